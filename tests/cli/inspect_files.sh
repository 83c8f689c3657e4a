# gi-inspect reads a .vdb (metadata, --at) and a .gi.gz; it refuses a cut or damaged
# .gi.gz with one line and exit 1, never reading past the end.
"$BIN/gi-bake" -q "$DATA/room.obj" -o room.vdb --rays 16 >/dev/null
"$BIN/vdb-to-gi" -q room.vdb -o room.gi.gz
"$BIN/gi-inspect" room.vdb --at 0,1.5,0 | grep -E '^(probes|meta +(scene|rays)=|at )' | sed 's/-> .*/-> rgb/'
"$BIN/gi-inspect" room.gi.gz --at 0,1.5,0 | grep -E '^(encoding|at )' | sed 's/-> .*/-> rgb/'
size=$(wc -c < room.gi.gz)
head -c $((size / 2)) room.gi.gz > cut.gi.gz
"$BIN/gi-inspect" cut.gi.gz >/dev/null 2>err; echo "exit $? $(cat err)"
cp room.gi.gz flip.gi.gz
printf '\377\377\377\377' | dd of=flip.gi.gz bs=1 seek=$((size / 2)) conv=notrunc 2>/dev/null
"$BIN/gi-inspect" flip.gi.gz >/dev/null 2>err; echo "exit $? lines $(wc -l < err)"
head -c $((size - 8)) room.gi.gz > notrailer.gi.gz
"$BIN/gi-inspect" notrailer.gi.gz >/dev/null 2>err; echo "exit $? $(cat err)"
{ cat room.gi.gz; printf 'junk'; } > junk.gi.gz
"$BIN/gi-inspect" junk.gi.gz >/dev/null 2>err; echo "exit $? $(cat err)"
head -c 20 room.gi.gz > tiny.gi.gz
"$BIN/gi-inspect" tiny.gi.gz >/dev/null 2>err; echo "exit $? $(cat err)"
"$BIN/gi-inspect" room.vdb --at 500,500,500 >/dev/null 2>err; echo "exit $? $(cat err)"
