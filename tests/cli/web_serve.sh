# web/serve.mjs serves GET and HEAD only, to its own loopback Host (no DNS
# rebinding), from the repository only web/, data/, out/ and tests/web/, never a
# dotfile (.git) or a path out of a root, and no symlink that leads out of one.
mkdir files
echo ok > files/ok.txt
echo secret > outside.txt
ln -s "$PWD/outside.txt" files/out.txt
# Then the raw requests of tests/hostile/http, each as its bytes.
node "$ROOT/tests/js/check_serve.mjs" "$PWD/files" "$ROOT/tests/hostile/http"
