// gi-stream.js: a .gi or .gi.gz read as its bytes arrive, held to what its
// header declares and to a memory budget (docs/web.md, "Bounds"). The header is
// checked the moment its bytes are in; the .gi is then allocated once, at the
// size the header declares, if that fits the budget, and reading stops at the
// first byte past it. A gzip'd stream is unpacked a slice at a time, so a bomb
// unpacks at most one slice's worth (about 16 MB) past the bound before it is
// refused. No three.js here: it runs in a page, a worker and node.

// The most bytes a volume may unpack to (its .gi, and its textures as the reader
// makes them) unless the caller raises it: a page holds about four times this
// while it builds and uploads them. lib/vdbgi.h's VDBGI_VOLUME_BUDGET is the same.
export const MAX_BYTES = 32 << 20;

// Compressed bytes handed to the inflater at once: deflate unpacks at most about
// 1032 bytes from one, so no slice can unpack more than ~16.5 MB.
const SLICE = 16384;

const MAGIC = 'vdbgi.gi';
// A size for a message: 1.5 MiB, 12.0 KiB, 300 bytes.
const size = (n) => (n >= 1 << 20 ? `${(n / (1 << 20)).toFixed(1)} MiB` : n >= 1024 ? `${(n / 1024).toFixed(1)} KiB` : `${n} bytes`);
const printable = (b) => Array.from(b, (c) => (c >= 32 && c < 127 ? String.fromCharCode(c) : '.')).join('');

// What the first bytes say a file is, when it is not a .gi or a gzip stream:
// the mistakes a user makes, told before the rest of the file is read.
function notGi(first) {
  const text = printable(first);
  if (first[0] === 0x20 && text.startsWith(' BDV'))
    return 'an OpenVDB file (.vdb), not a .gi.gz: convert it first (vdb-to-gi probes.vdb -o probes.gi.gz)';
  if (text.startsWith('glTF'))
    return 'a binary glTF (.glb), not a .gi.gz: bake its light with gi-bake, then convert it with vdb-to-gi';
  if (/^\s*</.test(text))
    return `text beginning "${text.trim().slice(0, 24)}" (an HTML page?), not a .gi.gz: check the URL and the server`;
  return `not a .gi or .gi.gz file (it begins "${text.slice(0, 8)}")`;
}

// CRC-32 (IEEE, as gzip's trailer), table-driven, carried across calls.
let crcTable = null;
export function crc32(bytes, crc = 0) {
  if (!crcTable) {
    crcTable = new Uint32Array(256);
    for (let n = 0; n < 256; n++) {
      let c = n;
      for (let k = 0; k < 8; k++) c = c & 1 ? 0xedb88320 ^ (c >>> 1) : c >>> 1;
      crcTable[n] = c >>> 0;
    }
  }
  let c = ~crc;
  for (let i = 0; i < bytes.length; i++) c = crcTable[(c ^ bytes[i]) & 255] ^ (c >>> 8);
  return ~c >>> 0;
}

// The budget's refusal, or null: `total` bytes of .gi and `textureBytes` of textures.
export function overBudget(total, textureBytes, maxBytes) {
  const biggest = Math.max(total, textureBytes);
  if (biggest <= maxBytes) return null;
  return new Error(`the volume unpacks to ${size(biggest)} (${textureBytes} bytes of textures), past the ` +
    `${size(maxBytes)} budget: pass loadGi a larger maxBytes to load it`);
}

// Reads one file: push() its bytes as they come (any chunking), then end() for
// the .gi's bytes. `header(bytes)` parses a header from the .gi's first bytes
// (throwing on a bad one) and returns { headerSize, stored, textureBytes }; it is
// given `headerBytes` of them (fewer only if the file has no more). `trailerSize`,
// when the caller already holds the whole gzip file, is what its trailer says, so
// a header that disagrees is refused before anything more is unpacked.
export class GiStreamReader {
  constructor({ header, headerBytes, maxBytes = MAX_BYTES, trailerSize = null }) {
    if (!(maxBytes > 0)) throw new Error(`maxBytes must be a positive number of bytes (got ${maxBytes})`);
    this.parse = header;
    this.maxBytes = maxBytes;
    this.trailerSize = trailerSize;
    this.headerBytes = headerBytes;
    this.kind = null; // 'gi' or 'gzip', from the first bytes
    this.sniffed = new Uint8Array(0); // the file's first bytes until they tell its kind
    this.first = new Uint8Array(0); // the .gi's first bytes until its header is judged
    this.out = null; // the .gi, allocated at the size its header declares
    this.at = 0;
    this.total = 0;
    this.packed = 0; // gzip'd bytes given to the inflater
    this.tail = new Uint8Array(8); // the last 8 of them: the trailer, at the end
    this.crc = 0;
    this.failure = null;
    this.closing = false;
    this.cut = null; // what the inflater said when the stream ended early
    this.inflateMs = 0;
    this.busy = false; // a push() or end() is running
  }

  // Bytes of the file, raw or gzip'd as it was sent. Await each push() before the next
  // (or end()): the inflater takes one slice at a time.
  async push(chunk) {
    this.enter();
    try {
      await this.pushNow(chunk);
    } finally {
      this.busy = false;
    }
  }

  enter() {
    if (this.busy) throw new Error('GiStreamReader: push() or end() called while another is pending (await each)');
    this.busy = true;
  }

  async pushNow(chunk) {
    if (this.failure) throw this.failure;
    if (!this.kind) {
      // Two bytes tell gzip; anything else must begin with the .gi's magic.
      const have = concat(this.sniffed, chunk);
      const gzip = have.length >= 2 && have[0] === 0x1f && have[1] === 0x8b;
      if (!gzip && have.length < MAGIC.length) {
        this.sniffed = have;
        return;
      }
      chunk = have;
      if (gzip) this.startInflate();
      else if (printable(have.subarray(0, MAGIC.length)) === MAGIC) this.kind = 'gi';
      else throw this.refuse(notGi(have.subarray(0, 32)));
    }
    if (this.kind === 'gi') return this.take(chunk);
    // A slice at a time: a write resolves once its output is queued, and the next
    // waits until the pump has taken all of it (TransformStream's backpressure).
    let start = now();
    for (let i = 0; i < chunk.length && !this.failure; i += SLICE) {
      const slice = chunk.subarray(i, i + SLICE);
      this.keepTail(slice);
      await this.writer.write(slice).catch((e) => this.inflaterFailed(e));
      // Writes resolve as microtasks: a large chunk would otherwise be one long task.
      if (now() - start > SLICE_MS) {
        this.inflateMs += now() - start;
        await yieldToPage();
        start = now();
      }
    }
    this.inflateMs += now() - start;
    if (this.failure) throw this.failure;
  }

  // The .gi's bytes, whole, once the file has ended.
  async end() {
    this.enter();
    try {
      return await this.endNow();
    } finally {
      this.busy = false;
    }
  }

  async endNow() {
    if (this.failure) throw this.failure;
    if (!this.kind) throw this.refuse(this.sniffed.length ? notGi(this.sniffed) : 'empty: no bytes at all');
    if (this.kind === 'gzip') {
      const t = now();
      this.closing = true;
      await this.writer.close().catch((e) => { this.cut ??= e; });
      await this.pump;
      // A stream that stops early: said as where, once the header was read, with the
      // inflater's own words (the browser's less its DOM preamble).
      const said = String(this.cut?.message).replace(/^Failed to execute '[^']*' on '[^']*': /, '');
      if (this.cut && this.out && !this.failure)
        throw this.refuse(this.at < this.total
          ? `cut short: the .gi ends at byte ${this.at} of the ${this.total} its header declares ` +
            `(the gzip stream stops after ${this.packed} bytes: ${said})`
          : `cut short: the gzip stream stops after ${this.packed} bytes, before its trailer (${said})`);
      if (this.cut) this.inflaterFailed(this.cut);
      this.inflateMs += now() - t;
      if (this.failure) throw this.failure;
    }
    if (!this.out) {
      // Fewer bytes than a header wants: judged as they are (the parser says what is short).
      const first = this.first;
      this.first = new Uint8Array(0);
      this.judge(first);
      this.take(first);
    }
    if (this.at < this.total)
      throw this.refuse(`cut short: the .gi ends at byte ${this.at} of the ${this.total} its header declares` +
        (this.kind === 'gzip' ? ` (after ${this.packed} gzip'd bytes)` : ''));
    if (this.kind === 'gzip') {
      // DecompressionStream may stop at the end of the first gzip member and ignore
      // what follows: the file's last 8 bytes must be that member's trailer.
      const dv = new DataView(this.tail.buffer);
      if (dv.getUint32(4, true) !== this.total >>> 0 || dv.getUint32(0, true) !== this.crc)
        throw this.refuse('bytes after the gzip stream');
    }
    return this.out;
  }

  // Stop reading (the caller's abort): the inflater is let go, later calls throw `reason`.
  cancel(reason = new Error('cancelled')) {
    this.stop(reason);
  }

  startInflate() {
    const ds = new DecompressionStream('gzip');
    this.writer = ds.writable.getWriter();
    this.reader = ds.readable.getReader();
    this.kind = 'gzip';
    // One reader for the whole stream: each unpacked chunk goes straight to take().
    this.pump = (async () => {
      try {
        for (;;) {
          const { done, value } = await this.reader.read();
          if (done || this.failure) break;
          this.take(value);
        }
      } catch (e) {
        // While closing, end() says what a stream that stops early means.
        if (this.closing) this.cut ??= e;
        else this.inflaterFailed(e);
      }
    })();
  }

  keepTail(slice) {
    this.packed += slice.length;
    if (slice.length >= 8) this.tail.set(slice.subarray(slice.length - 8));
    else {
      this.tail.copyWithin(0, slice.length);
      this.tail.set(slice, 8 - slice.length);
    }
  }

  stop(e) {
    if (this.failure) return;
    this.failure = e;
    // The inflater, if it was made (DecompressionStream may be missing or refuse).
    this.reader?.cancel(e).catch(() => {});
    this.writer?.abort(e).catch(() => {});
  }

  refuse(message) {
    const e = new Error(message);
    this.stop(e);
    return this.failure;
  }

  // What the inflater threw (the first failure wins: ours, when we stopped it).
  inflaterFailed(e) {
    if (this.failure) return;
    this.stop(new Error(`not a gzip'd .gi file, or damaged near gzip'd byte ${this.packed} (${e.message})`, { cause: e }));
  }

  // Bytes of the .gi itself, in order.
  take(bytes) {
    if (!this.out) {
      this.first = concat(this.first, bytes);
      if (this.first.length < this.headerBytes) return;
      this.judge(this.first);
      bytes = this.first;
      this.first = new Uint8Array(0);
    }
    if (this.at + bytes.length > this.total)
      throw this.refuse(`holds more than the ${this.total} bytes its header declares (byte ${this.total + 1} follows)`);
    this.out.set(bytes, this.at);
    this.at += bytes.length;
    if (this.kind === 'gzip') this.crc = crc32(bytes, this.crc);
  }

  // The header from the .gi's first bytes: refused, or the .gi allocated at its declared size.
  judge(first) {
    let h;
    try {
      h = this.parse(first);
    } catch (e) {
      this.stop(e);
      throw e;
    }
    const total = h.headerSize + h.stored;
    if (this.trailerSize !== null && total !== this.trailerSize)
      throw this.refuse(`cut short or damaged (the gzip trailer says ${this.trailerSize} bytes, the header ${total})`);
    const over = overBudget(total, h.textureBytes, this.maxBytes);
    if (over) {
      this.stop(over);
      throw over;
    }
    this.total = total;
    this.out = new Uint8Array(total);
  }
}

export const now = () => (typeof performance !== 'undefined' ? performance.now() : Date.now());
// A new task: the scheduler's yield where there is one, else a timer. The reader and the
// rebuild give the page back this way every SLICE_MS of work, so no task runs much longer.
// A message, not a timer: background tabs hold timers back to a second.
export const yieldToPage = () => {
  if (globalThis.scheduler?.yield) return globalThis.scheduler.yield();
  if (typeof MessageChannel === 'undefined') return new Promise((resolve) => setTimeout(resolve, 0));
  return new Promise((resolve) => {
    const channel = new MessageChannel();
    channel.port1.onmessage = () => {
      channel.port1.close();
      resolve();
    };
    channel.port2.postMessage(0);
  });
};
export const SLICE_MS = 20;

function concat(a, b) {
  if (!a.length) return b;
  const c = new Uint8Array(a.length + b.length);
  c.set(a);
  c.set(b, a.length);
  return c;
}
