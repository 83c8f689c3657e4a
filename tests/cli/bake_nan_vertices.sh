# Triangles with non-finite vertices are skipped with a warning; the rest bakes.
printf 'v 0 0 0\nv 4 0 0\nv 4 0 -4\nv nan 0 0\nf 1 2 3\nf 1 2 4\n' > some.obj
"$BIN/gi-bake" some.obj -o out.vdb --spacing 1 --rays 8
