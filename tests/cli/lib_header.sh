# vdbgi.h and vdbgi_bench.h compile alone as C99 and as C++ with strict warnings, and
# declare no C++.
printf '#include "vdbgi.h"\nint main(void) { return vdbgi_version_string()[0] == 0; }\n' > a.c
cp a.c a.cpp
cc -std=c99 -Wall -Wextra -pedantic -Werror -I"$ROOT/lib" a.c -c -o a.o && echo "C99 ok"
c++ -std=c++11 -Wall -Wextra -pedantic -Werror -I"$ROOT/lib" a.cpp -c -o b.o && echo "C++ ok"
grep -q 'include <\(openvdb\|OpenImageIO\|embree\|assimp\)' "$ROOT/lib/vdbgi.h" || echo "no third-party headers"
printf '#include "vdbgi_bench.h"\nint main(void) { return vdbgi_version_string()[0] == 0; }\n' > b.c
cp b.c b.cpp
cc -std=c99 -Wall -Wextra -pedantic -Werror -I"$ROOT/lib" b.c -c -o c.o && echo "bench C99 ok"
c++ -std=c++11 -Wall -Wextra -pedantic -Werror -I"$ROOT/lib" b.cpp -c -o d.o && echo "bench C++ ok"
