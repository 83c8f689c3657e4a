# run: early (among the slowest, so started first)
# assimp's own test corpus (Debian's assimp-testmodels, which make deps installs):
# every model, the broken ones in invalid/ among them, is baked by gi-bake or
# refused in one line of its own, within 20 s and 2 GB each (one ray a probe, at most
# 200 000 probes: the import and the checks are what is tested, not the bake).
# Lines assimp prints itself (its OpenDDL parser writes to stderr, and Debian's
# assimp 5.2 gives no way to catch it) are listed apart. Counts go to stderr, as
# they follow the package's version.
models=/usr/share/assimp/models
if [ ! -d "$models" ]; then
    echo "assimp-testmodels missing (make deps installs it)"
    exit 77
fi
. "$ROOT/tests/cli/hostile.inc"
hostile_limit 2000
# Under make asan the corpus tests the importers' memory errors, not leaks: assimp's
# own importers leak on some of its models (AMF, LWO, IRR, OpenGEX, RAW), and
# LeakSanitizer's tracer crashes at exit after the IQM one. Our leaks are the other
# tests' to find.
case "$BIN" in */asan/*) export ASAN_OPTIONS="${ASAN_OPTIONS:+$ASAN_OPTIONS:}detect_leaks=0" ;; esac
find "$models" -type f | LC_ALL=C sort |
    grep -viE '\.(png|jpe?g|tga|bmp|dds|tiff?|gif|pcx|psd|hdr|ktx|txt|md|bin|mtl|glsl|xsd|cfg|mat|shader|material|skin|h|cpp)$' > list
n=0
: > report
while read -r f; do
    n=$((n + 1))
    ($limit; timeout 20 "$BIN/gi-bake" "$f" -o "out$n.vdb" -q --rays 1 --max-probes 200000) >/dev/null 2>err
    rc=$?
    foreign=$(grep -vc '^gi-bake: ' err)
    left=$(ls out$n.* 2>/dev/null | wc -l)
    run_outcome gi-bake $rc $left
    [ $outcome = baked ] && [ $left -ne 1 ] && outcome=odd # a bake leaves its .vdb
    if [ $outcome != odd ]; then
        echo $outcome >> report
    else
        echo "${f#$models/}: exit $rc, $own line(s) of its own, $left output(s): $(head -n 1 err)"
    fi
    [ $foreign -eq 0 ] || echo "assimp printed itself on ${f#$models/}: $(grep -v '^gi-bake: ' err | head -n 1)"
    rm -f out$n.*
done < list
echo "$n models: $(grep -c baked report) baked, $(grep -c refused report) refused" >&2
echo "every model baked or refused in one line: $([ $(wc -l < report) -eq $n ] && echo yes || echo no)"
