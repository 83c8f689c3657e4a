# OpenImageIO lives in a module opened only when an image is read or written:
# with no module to be found, --help, an untextured bake and a conversion
# without images still work, what needs images fails with one clear line, and a
# texture it cannot read is a warning, as a missing texture file is.
export VDBGI_IMAGE_MODULE=/nonexistent/libvdbgi_image.so
printf 'v -2 0 2\nv 2 0 2\nv 2 0 -2\nv -2 0 -2\nf 1 2 3 4\n' > plane.obj
"$BIN/gi-bake" --help | head -n 1
"$BIN/gi-bake" -q plane.obj -o plane.vdb --spacing 1 --rays 16 >/dev/null; echo "bake $?"
"$BIN/vdb-to-gi" -q plane.vdb -o plane.gi.gz; echo "convert $?"
"$BIN/vdb-to-gi" -q plane.vdb -o other.gi.gz --slices slices 2>err; echo "slices $? $(cat err)"
printf 'newmtl t\nmap_Kd t.png\n' > t.mtl
printf 'mtllib t.mtl\nv -2 0 2\nv 2 0 2\nv 2 0 -2\nv -2 0 -2\nvt 0 0\nvt 1 0\nvt 1 1\nvt 0 1\nusemtl t\nf 1/1 2/2 3/3 4/4\n' > t.obj
cp "$DATA/floor.png" t.png
"$BIN/gi-bake" t.obj -o t.vdb --spacing 1 --rays 16 2>err >/dev/null; echo "textured $? $(cat err)"
unset VDBGI_IMAGE_MODULE
"$BIN/gi-bake" t.obj -o t.vdb --spacing 1 --rays 16 | grep "^scene"
