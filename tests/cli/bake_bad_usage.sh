# Usage errors: one line naming the problem, a hint, exit 2, and no output file.
for args in "--frobnicate" "data.glb" "-o out.vdb" "a.glb b.glb -o out.vdb" \
            "s.glb -o out.vdb --spacing 0" "s.glb -o out.vdb --spacing -1" \
            "s.glb -o out.vdb --spacing abc" "s.glb -o out.vdb --rays 0" \
            "s.glb -o out.vdb --rays -5" "s.glb -o out.vdb --ray-dist 0" \
            "s.glb -o out.vdb --falloff -2" "s.glb -o out.vdb --sun 0,0,0" \
            "s.glb -o out.vdb --sun 1,2" "s.glb -o out.vdb --sky 1,nan,0" \
            "s.glb -o out.vdb --sampling sobol" "s.glb -o out.vdb --threads 0" \
            "s.glb -o out.vdb --max-probes 0" "s.glb -o out.vdb --margin -1" \
            "s.glb -o out.vdb --ambient -0.1" "s.glb -o out.vdb --rays" \
            "s.glb -o out.vdb --bounces 0" "s.glb -o out.vdb --bounces 1000" \
            "s.glb -o out.vdb --model pbr" "s.glb -o out.vdb --lights maybe" \
            "s.glb -o out.vdb --sky-intensity -1" "s.glb -o out.vdb --sky-rotation inf" \
            "s.glb -o out.vdb --walkable 0" "s.glb -o out.vdb --keep-box 1,2,3" \
            "s.glb -o out.vdb --keep-box 0,0,0,1,-1,1"; do
    # shellcheck disable=SC2086
    "$BIN/gi-bake" $args 2>err
    echo "$? $(head -n 1 err)"
    [ "$(wc -l <err)" -eq 2 ] || echo "  expected two lines on stderr"
done
ls
