# loadGi over HTTP from an unlucky server (issue 47, items 4 and 5; tests/js/check_fetch.mjs):
# progress events, a default timeout for a response that stops, and every refusal naming
# the URL and what happened.
[ -d "$ROOT/web/node_modules/three" ] || { echo "web/node_modules missing (make deps installs it)"; exit 77; }
"$BIN/gi-bake" -q "$DATA/room.obj" -o room.vdb --spacing 1 --rays 16 >/dev/null
"$BIN/vdb-to-gi" -q room.vdb -o room.gi.gz
node "$ROOT/tests/js/check_fetch.mjs" room.gi.gz
