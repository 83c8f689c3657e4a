# --help on stdout with exit 0, --version, for the converter and the inspector.
"$BIN/vdb-to-gi" --help | head -n 1
"$BIN/vdb-to-gi" --help | grep -c '^      --\(eps\|max-level\|criterion\|encoding\|slices\|stats\) '
"$BIN/vdb-to-gi" --version
"$BIN/gi-inspect" --help | head -n 1
"$BIN/gi-inspect" --version
