# Every damaged file of tests/hostile (vdb, gi, js, lightmap; copied from the reports
# that found them or written by hand) is refused (a .vdb converted whole and region by region): exit 1 within 20 s under a 4 GB
# address-space limit, one line on stderr naming the file, no output left; node's
# loader refuses the js files alike. The originals still convert, and a
# texture that is a device or claims 20000^2 pixels is a warning, not a hang or
# 6 GB, in gi-bake and gi-lightmap, as a base colour or as emission. Prints what it checked and every deviation.
H="$ROOT/tests/hostile"
. "$ROOT/tests/cli/hostile.inc"
hostile_limit 4000
runs=0
bad=0
check() { # expect (refuse|accept), file, command...
    expect=$1 f=$2
    shift 2
    ($limit; timeout 20 "$@") >/dev/null 2>err
    rc=$?
    lines=$(wc -l < err)
    left=$(ls out.* 2>/dev/null | wc -l)
    runs=$((runs + 1))
    if [ "$expect" = refuse ]; then
        if [ $rc != 1 ] || [ "$lines" != 1 ] || ! grep -q "$(basename "$f")" err || [ "$left" != 0 ]; then
            echo "NOT REFUSED CLEANLY: $(basename "$f") by $(basename "$1"): exit $rc, $lines lines, $left outputs left"
            head -n 3 err
            bad=$((bad + 1))
        fi
    elif [ $rc != 0 ]; then
        echo "NOT ACCEPTED: $(basename "$f") by $(basename "$1"): exit $rc"
        bad=$((bad + 1))
    fi
    rm -f out.*
}
for f in "$H"/vdb/*.vdb; do
    case "$(basename "$f")" in
    ORIGINAL*) expect=accept ;;
    *) expect=refuse ;;
    esac
    check $expect "$f" "$BIN/vdb-to-gi" "$f" -o out.gi.gz -q
    # Region by region: the same checks at open, then OpenVDB's clipped reads.
    check $expect "$f" "$BIN/vdb-to-gi" "$f" -o out.gi.gz -q --region 32
    # A long thin lattice is a valid file: only its conversion is refused.
    [ "$(basename "$f")" = bbox_long_line.vdb ] && expect=accept
    check $expect "$f" "$BIN/gi-inspect" "$f"
done
for f in "$H"/gi/*.gi.gz "$H"/js/*.gi.gz; do
    case "$(basename "$f")" in ORIGINAL*) expect=accept ;; *) expect=refuse ;; esac
    check $expect "$f" "$BIN/gi-inspect" "$f"
done
# The lightmapper's own: work past its budget, only NaN geometry.
for f in "$H"/lightmap/*.obj; do
    check refuse "$f" "$BIN/gi-lightmap" "$f" -o out.glb -q
done
echo "$bad of the runs deviated"
for f in "$H"/scenes/*.obj; do
    ($limit; timeout 20 "$BIN/gi-bake" "$f" -o out.vdb --spacing 2 --rays 8) >/dev/null 2>err
    echo "$(basename "$f"): exit $?, $(sed -e 's/^gi-bake: warning: //' -e "s|$H/||g" err)"
    rm -f out.*
done
# The JavaScript loader, in node under the same limits: the files for it (declared
# sizes that would unpack far more than the file) refused with the C reader's words.
for f in "$H"/js/*.gi.gz; do
    echo "node $(basename "$f"): $($limit; timeout 20 node "$ROOT/tests/js/read_gi.mjs" "$f" 2>&1)"
done
# And the worker's reader, the C one built to WebAssembly, behind the same header checks
# (without the address-space limit: V8 reserves WebAssembly memory's guard regions in it).
for f in "$H"/gi/*.gi.gz "$H"/js/*.gi.gz; do
    echo "WebAssembly $(basename "$f"): $(timeout 20 node "$ROOT/tests/js/check_wasm.mjs" "$f" 2>&1 | sed 's/^WebAssembly //')"
done
# The same scenes through gi-lightmap; and their textures as emission (map_Ke), through both.
for f in "$H"/scenes/*.obj; do
    ($limit; timeout 20 "$BIN/gi-lightmap" "$f" -o out.glb --size 64 --texel 0.5) >/dev/null 2>err
    echo "gi-lightmap $(basename "$f"): exit $?, $(sed -e 's/^gi-lightmap: warning: //' -e "s|$H/||g" err)"
    rm -f out.*
    cp "$H"/scenes/*.png .
    sed 's/^map_Kd/Ke 1 1 1\nmap_Ke/' "$H/scenes/$(sed -n 's/^mtllib //p' "$f")" > ke.mtl
    sed 's/^mtllib .*/mtllib ke.mtl/' "$f" > ke.obj
    ($limit; timeout 20 "$BIN/gi-bake" ke.obj -o out.vdb --spacing 2 --rays 8) >/dev/null 2>err
    echo "emissive $(basename "$f"), gi-bake: exit $?, $(sed 's/^gi-bake: warning: //' err)"
    ($limit; timeout 20 "$BIN/gi-lightmap" ke.obj -o out.glb --size 64 --texel 0.5) >/dev/null 2>err
    echo "emissive $(basename "$f"), gi-lightmap: exit $?, $(sed 's/^gi-lightmap: warning: //' err)"
    rm -f out.* ke.* ./*.png
done
