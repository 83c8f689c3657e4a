# An independent JavaScript loader (tests/js/gi_loader.mjs: node, DecompressionStream)
# agrees with the C sampler (gi-inspect --at) at 400 points, for both encodings and
# both brick layouts; it reads the indirection as the runtime's columns, which it
# builds to the size the C library reports. The C reader built to WebAssembly (the
# worker's) rebuilds every packed file's textures as the JavaScript one does.
"$BIN/gi-bake" -q "$DATA/world.glb" -o world.vdb --spacing 1 --rays 32 >/dev/null
for run in rgbm,seed rgb9e5,seed rgbm,compact rgb9e5,compact; do
    "$BIN/vdb-to-gi" -q world.vdb -o w.gi.gz --encoding ${run%,*} --layout ${run#*,} --eps 0.2
    # Points spread over the world box and a little beyond it (clamp to edge).
    set -- $(awk 'BEGIN { s = 12345; for (i = 0; i < 400; i++) {
        s = (s * 1103515245 + 12345) % 2147483648; x = s / 2147483648 * 60 - 30;
        s = (s * 1103515245 + 12345) % 2147483648; y = s / 2147483648 * 16 - 2;
        s = (s * 1103515245 + 12345) % 2147483648; z = s / 2147483648 * 60 - 30;
        printf "--at %.4f,%.4f,%.4f ", x, y, z } }')
    "$BIN/gi-inspect" w.gi.gz "$@" > inspect.txt
    node "$ROOT/tests/js/check_loader.mjs" w.gi.gz inspect.txt | sed 's/([0-9]* lit)/(lit)/'
    grep '^runtime' inspect.txt
done
# At 0.5 m the runtime's columns texture has more than one row: the same 400 points
# through the loader's row and column arithmetic.
"$BIN/gi-bake" -q "$DATA/world.glb" -o fine.vdb --rays 16 >/dev/null
"$BIN/vdb-to-gi" -q fine.vdb -o f.gi.gz
"$BIN/gi-inspect" f.gi.gz "$@" > inspect.txt
node "$ROOT/tests/js/check_loader.mjs" f.gi.gz inspect.txt | sed 's/([0-9]* lit)/(lit)/'
grep '^runtime' inspect.txt
# A server that sends the file with Content-Encoding: gzip hands the page the .gi
# unpacked (the browser undid the gzip): the loader reads that body alike.
gzip -dc f.gi.gz > f.gi
node "$ROOT/tests/js/check_loader.mjs" f.gi inspect.txt | sed 's/([0-9]* lit)/(lit)/'
# A packed (version 5) file: the JavaScript reader rebuilds the textures the C reader
# rebuilds, byte for byte, with few and with many level seams to stitch.
for run in rgbm,0.2 rgb9e5,0.2 rgbm,5 rgb9e5,5; do
    "$BIN/vdb-to-gi" -q world.vdb -o w.gi.gz --encoding ${run%,*} --eps ${run#*,}
    "$BIN/gi-inspect" w.gi.gz --textures textures.gi > inspect.txt
    grep '^bricks' inspect.txt | sed 's/^/  /'
    node "$ROOT/tests/js/check_textures.mjs" w.gi.gz textures.gi
    node "$ROOT/tests/js/check_wasm.mjs" w.gi.gz
done
# L2 terms (version 8, its second band in luminance; 7, every term in colour; and 6 as
# older runtimes read them): the JavaScript reader rebuilds the term textures (six, or
# version 8's four; stitched texels too, at eps 5) and reads them with a
# normal as the C sampler does; the same points read without it disagree, so the terms
# are what is compared.
"$BIN/gi-bake" -q "$DATA/world.glb" -o sh.vdb --spacing 1 --rays 32 --basis sh2 >/dev/null
for run in rgbm,0.2,7 rgb9e5,5,6 rgb9e5,5,7 rgbm,0.2,8 rgb9e5,5,8; do
    version=${run##*,} run=${run%,*}
    "$BIN/vdb-to-gi" -q sh.vdb -o s.gi.gz --encoding ${run%,*} --eps ${run#*,} --gi-version $version
    echo "version $(gzip -dc s.gi.gz | od -An -tu4 -j8 -N4 | tr -d ' ')"
    "$BIN/gi-inspect" s.gi.gz "$@" --normal 0.3,-0.8,0.5 > inspect.txt
    node "$ROOT/tests/js/check_loader.mjs" s.gi.gz inspect.txt 0.3,-0.8,0.5 | sed 's/([0-9]* lit)/(lit)/'
    node "$ROOT/tests/js/check_wasm.mjs" s.gi.gz
done
# The worker's reader (the C one built to WebAssembly) at the defaults a user bakes and
# converts with (0.5 m, the version the converter chooses), and the L2 file of them.
"$BIN/gi-bake" -q "$DATA/world.glb" -o fine_sh.vdb --rays 16 --basis sh2 >/dev/null
"$BIN/vdb-to-gi" -q fine_sh.vdb -o fs.gi.gz
node "$ROOT/tests/js/check_wasm.mjs" f.gi.gz fs.gi.gz
node "$ROOT/tests/js/check_loader.mjs" s.gi.gz inspect.txt | sed 's/[0-9]* channels of 400 points disagree.*/channels disagree without the normal/'
