# A sample of `make fuzz` (tests/fuzz_damage.sh): 12 cuts and 40 seeded byte
# flips of an ambient-cube .vdb and its .gi.gz, through vdb-to-gi and
# gi-inspect under time and memory limits: each run reads or is refused in one
# line naming the file, and leaves no output.
CUTS=12 FLIPS=40 QUIET=1 BIN="$BIN" DATA="$DATA" sh "$ROOT/tests/fuzz_damage.sh"
