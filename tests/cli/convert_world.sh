# The bundled world end to end: bake, convert with slices and JSON statistics, read back.
"$BIN/gi-bake" -q "$DATA/world.glb" -o world.vdb --spacing 1 --rays 32 >/dev/null
"$BIN/vdb-to-gi" world.vdb -o world.gi.gz --slices slices --stats stats.json >out.txt || exit 1
sed -n 's/^\([a-z]*\) .*/\1/p' out.txt | tr '\n' ' '; echo
gzip -t world.gi.gz && echo "gzip -t: ok"
/usr/bin/python3 - <<'PY'
import json
s = json.load(open("stats.json"))
print("json:", sorted(s)[:6], "...")
print("bricks add up:", sum(s["bricks_per_level"]) == s["bricks"])
print("sizes:", s["atlas_bytes"] == 4 * s["atlas_dims"][0] * s["atlas_dims"][1] * s["atlas_dims"][2],
      s["raw_bytes"] == s["atlas_bytes"] + s["indirection_bytes"], s["gzip_bytes"] < s["raw_bytes"])
print("columns:", s["columns_bytes"] == 4 * s["columns_dims"][0] * s["columns_dims"][1],
      0 < s["columns_bytes"] < s["indirection_bytes"], s["vram_bytes"] == s["atlas_bytes"] + s["columns_bytes"])
print("error below 2% of the mean:", s["rmse_relative"] < 0.02)
PY
for f in baked bricks difference atlas; do
    echo "$f: $(iinfo "slices/$f.png" | grep -o '3 channel, uint8 png')"
    iinfo "slices/$f.exr" | grep -o '3 channel, half openexr'
done
iinfo slices/levels.png | grep -o '3 channel, uint8 png'
"$BIN/gi-inspect" world.gi.gz | cut -c1-12 | tr -s ' ' | tr '\n' '|'; echo
