# Every global symbol libvdbgi.a defines starts with vdbgi_ (C++ template instances
# from the OpenVDB/OIIO headers are weak and unique symbols, so they are left aside;
# so are AddressSanitizer's __odr_asan.* indicators of globals, under make asan).
nm -g --defined-only "$BIN/../libvdbgi.a" | awk 'NF == 3 && $2 ~ /^[TDBRGS]$/ { print $3 }' |
    grep -v -e '^vdbgi_' -e '^__odr_asan\.vdbgi_' | sort | head -20
nm -g --defined-only "$BIN/../libvdbgi.a" | awk 'NF == 3 && $2 == "T" && $3 ~ /^vdbgi_/ { n++ } END { print (n > 20 ? "many" : "few") " vdbgi_ functions" }'
