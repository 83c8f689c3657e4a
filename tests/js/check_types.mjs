// check_types.mjs: each entry point's .d.ts declares what its module exports, no more and
// no less (the names, read with TypeScript's checker against node's import of the module),
// and each runtime class's public methods and accessors. Types a .d.ts adds for callers
// (interfaces, aliases) are not values and are left out of the comparison.
import { createRequire } from 'node:module';

const require = createRequire(new URL('../../web/', import.meta.url));
const ts = require('typescript');
const web = new URL('../../web/', import.meta.url).pathname;
const entries = { '.': 'vdbgi', './webgpu': 'vdbgi-webgpu', './format': 'gi-format', './lightmap-layers': 'lightmap-layers',
  './react': 'vdbgi-react', './probe-grid': 'gi-probe-grid' };

const program = ts.createProgram(Object.values(entries).map((f) => `${web}${f}.d.ts`),
  { strict: true, noEmit: true, module: ts.ModuleKind.ESNext, moduleResolution: ts.ModuleResolutionKind.Bundler,
    target: ts.ScriptTarget.ES2022, types: [], typeRoots: [`${web}node_modules/@types`] });
const checker = program.getTypeChecker();
// A class's own and inherited instance members, by name (private ones too: declared as internal).
const members = (type) => type.getProperties().map((p) => p.name);
let failed = 0;
for (const [entry, file] of Object.entries(entries)) {
  const source = program.getSourceFile(`${web}${file}.d.ts`);
  const declared = new Map();
  for (const s of checker.getExportsOfModule(checker.getSymbolAtLocation(source))) {
    const target = s.flags & ts.SymbolFlags.Alias ? checker.getAliasedSymbol(s) : s;
    if (target.flags & ts.SymbolFlags.Value) declared.set(s.name, target);
  }
  const mod = await import(`${web}${file}.js`);
  const actual = Object.keys(mod).sort();
  const missing = actual.filter((n) => !declared.has(n));
  const extra = [...declared.keys()].filter((n) => !(n in mod));
  // Classes: the public methods and accessors of an instance's prototype chain.
  const classes = [];
  for (const [name, symbol] of declared) {
    if (!(symbol.flags & ts.SymbolFlags.Class)) continue;
    const typed = new Set(members(checker.getDeclaredTypeOfSymbol(symbol)));
    const names = new Set();
    for (let p = mod[name].prototype; p && p !== Object.prototype; p = Object.getPrototypeOf(p))
      for (const n of Object.getOwnPropertyNames(p)) if (n !== 'constructor' && !n.startsWith('_')) names.add(n);
    const untyped = [...names].filter((n) => !typed.has(n));
    if (untyped.length) classes.push(`${name} lacks ${untyped.join(', ')}`);
  }
  const ok = !missing.length && !extra.length && !classes.length;
  if (!ok) failed++;
  console.log(`${ok ? 'ok' : 'FAILED'}: vdbgi${entry === '.' ? '' : entry.slice(1)}: ${actual.length} exports typed` +
    (missing.length ? `; untyped: ${missing.join(', ')}` : '') + (extra.length ? `; typed but absent: ${extra.join(', ')}` : '') +
    (classes.length ? `; ${classes.join('; ')}` : ''));
}
process.exit(failed ? 1 : 0);
