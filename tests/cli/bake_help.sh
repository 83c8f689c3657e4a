# --help prints usage on stdout and exits 0; --version names the library version.
"$BIN/gi-bake" --help
"$BIN/gi-bake" --version
