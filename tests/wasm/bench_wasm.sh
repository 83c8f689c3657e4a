#!/bin/sh
# bench_wasm.sh: `make bench-wasm` (issue 40, item 1: measure before choosing). Would a
# WebAssembly build of the C reader rebuild a .gi's textures faster than the JavaScript the
# worker runs? Builds lib/'s reader (gifile, packed, pack_rebuild, textures; gzip stubbed:
# the browser inflates with DecompressionStream) with Debian's emscripten into a standalone
# .wasm (giwasm.c's entry points), then on the bundled world's scalar and L2 volumes,
# inflated: checks that the JS, WASM and native C textures are the same bytes, and times
# the first (cold) run in fresh node processes and warm runs alternating in one
# (bench.mjs), and the native build (native_bench.c). Needs: apt install emscripten.
set -eu
ROOT=$(cd "$(dirname "$0")/../.." && pwd)
BUILD=${BUILD:-build/release}
HERE=$ROOT/tests/wasm
OUT=$ROOT/build/wasm
if ! command -v emcc >/dev/null; then
    echo "bench-wasm: no emcc (apt install emscripten)" >&2
    exit 2
fi
mkdir -p "$OUT/native"
cd "$OUT"
# Debian's emcc runs its tools with node; a newer node finds Debian's acorn through NODE_PATH.
export NODE_PATH=/usr/share/nodejs
"$ROOT/$BUILD/bin/gi-bake" -q "$ROOT/data/world.glb" -o w.vdb --basis sh2
"$ROOT/$BUILD/bin/vdb-to-gi" -q w.vdb -o world_sh2.gi.gz
"$ROOT/$BUILD/bin/vdb-to-gi" -q w.vdb -o world.gi.gz --basis scalar
gunzip -c world_sh2.gi.gz >world_sh2.gi
gunzip -c world.gi.gz >world.gi
INC="-I$HERE/stub -I$ROOT/lib $(for d in "$ROOT"/lib/*/; do printf -- '-I%s ' "$d"; done)"
CF="-std=c11 -ffp-contract=off -DVDBGI_BUILDING"
SRCS="$(for f in core/context core/util core/encode core/threads core/files format/gifile \
    format/packed format/pack_rebuild format/textures format/sampler format/volume_access \
    convert/pack_place; do printf '%s ' "$ROOT/lib/$f.c"; done) $HERE/stub/gzip_stub.c"
EXPORTS='["_gi_read","_gi_prepare","_gi_free","_gi_alloc","_gi_dealloc","_gi_error","_gi_atlas","_gi_atlas_size","_gi_indirection","_gi_indirection_size","_gi_columns","_gi_columns_size","_gi_columns_dim","_gi_sh"]'
# util.c's half floats (the baker's) use _Float16, which clang 14 refuses on wasm32.
# shellcheck disable=SC2086
emcc -O3 $CF $INC -D_Float16=__fp16 "$HERE/giwasm.c" $SRCS --no-entry -sSTANDALONE_WASM \
    -sALLOW_MEMORY_GROWTH=1 -sINITIAL_MEMORY=16MB -sEXPORTED_FUNCTIONS="$EXPORTS" -o gi.wasm
echo "gi.wasm: $(stat -c %s gi.wasm) bytes, $(gzip -9c gi.wasm | wc -c) gzip'd"
# shellcheck disable=SC2086
for f in "$HERE/giwasm.c" "$HERE/native_bench.c" $SRCS; do
    gcc -O2 $CF $INC -c "$f" -o "native/$(basename "$f" .c).o"
done
gcc native/*.o -Wl,--wrap=vdbgi_core_count -o native/bench1 -lm -lpthread
for f in world_sh2 world; do
    native/bench1 $f.gi native/$f >/dev/null
    node "$HERE/bench.mjs" check $f.gi gi.wasm native/$f
done
for f in world_sh2 world; do
    echo "== $f.gi ($(stat -c %s $f.gi) bytes inflated)"
    for _ in 1 2 3 4 5; do
        node "$HERE/bench.mjs" js $f.gi
        node "$HERE/bench.mjs" wasm $f.gi gi.wasm
    done
    node "$HERE/bench.mjs" both $f.gi gi.wasm
    echo "native, one thread, freed memory kept:"
    MALLOC_MMAP_THRESHOLD_=1000000000 MALLOC_TRIM_THRESHOLD_=1000000000 native/bench1 $f.gi
done
