# Every global symbol libvdbgi.a defines starts with vdbgi_ (C++ template instances
# from the OpenVDB/OIIO headers are weak and unique symbols, so they are left aside).
nm -g --defined-only "$BIN/../libvdbgi.a" | awk 'NF == 3 && $2 ~ /^[TDBRGS]$/ { print $3 }' |
    grep -v '^vdbgi_' | sort | head -20
nm -g --defined-only "$BIN/../libvdbgi.a" | awk 'NF == 3 && $2 == "T" && $3 ~ /^vdbgi_/ { n++ } END { print (n > 20 ? "many" : "few") " vdbgi_ functions" }'
