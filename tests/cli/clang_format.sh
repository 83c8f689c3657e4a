# The tree is formatted as .clang-format says (`make format` applies it).
cd "$ROOT" || exit 1
n=0
for f in lib/*.h lib/*/*.c lib/*/*.h lib/*/*.cpp apps/*.c apps/*.h tests/*.c tests/*.h web/wasm/*.c \
    web/wasm/include/*.h; do
    clang-format "$f" | cmp -s "$f" - || { echo "not formatted: $f"; n=$((n + 1)); }
done
echo "$n files not formatted"
