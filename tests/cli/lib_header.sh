# vdbgi.h compiles alone as C99 and as C++ with strict warnings, and declares no C++.
printf '#include "vdbgi.h"\nint main(void) { return vdbgi_version_string()[0] == 0; }\n' > a.c
cp a.c a.cpp
cc -std=c99 -Wall -Wextra -pedantic -Werror -I"$ROOT/lib" a.c -c -o a.o && echo "C99 ok"
c++ -std=c++11 -Wall -Wextra -pedantic -Werror -I"$ROOT/lib" a.cpp -c -o b.o && echo "C++ ok"
grep -q 'include <\(openvdb\|OpenImageIO\|embree\|assimp\)' "$ROOT/lib/vdbgi.h" || echo "no third-party headers"
