# The .vdb opens in vdb_print: two grids, the lattice transform, the bake settings.
# room.obj is closed and has no lamp: dark under the default physical model, lit by the
# seed model's ambient fill.
"$BIN/gi-bake" -q "$DATA/room.obj" -o room.vdb --spacing 0.25 --rays 16 --model seed >/dev/null
vdb_print -l -m room.vdb | grep -E '^Name:|Type:|voxel size|Number of active voxels|^  (ambient|falloff|rays|sampling|scene|spacing|sun_dir|triangles|probes|margin|origin):|\[0.125, 0.125, 0.125, 1\]'
