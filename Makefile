# vdbgi: bake light-probe global illumination into OpenVDB grids and GPU bricks.
# `make list` shows the targets. config=release|debug|asan|ubsan|tsan, V=1 shows
# commands, WERROR=1 turns warnings into errors.

config ?= release
ifeq ($(SANITIZE),1)
config := asan
endif
BUILD := build/$(config)
PREFIX ?= /usr/local
DESTDIR ?=

PKG_CONFIG ?= pkg-config

ifeq ($(V),1)
Q :=
else
Q := @
endif

# ---- flags ------------------------------------------------------------------

WARN_C := -Wall -Wextra -Wshadow -Wstrict-prototypes -Wmissing-prototypes -Wundef \
          -Wpointer-arith -Wcast-qual -Wwrite-strings -Wvla -Wformat=2
WARN_CXX := -Wall -Wextra -Wshadow
ifeq ($(WERROR),1)
WARN_C += -Werror
WARN_CXX += -Werror
endif

OPT_release := -O2 -g
OPT_debug := -O0 -g
OPT_asan := -O1 -g -fno-omit-frame-pointer -fsanitize=address,undefined -fno-sanitize-recover=all
OPT_ubsan := -O1 -g -fno-omit-frame-pointer -fsanitize=undefined -fno-sanitize-recover=all
OPT_tsan := -O1 -g -fsanitize=thread
OPT := $(OPT_$(config))
ifeq ($(OPT),)
$(error unknown config '$(config)': use release, debug, asan, ubsan or tsan)
endif

# Dependencies. Evaluated lazily (=) so that `make deps` can install them first.
# Their -I become -isystem so our warnings do not fire inside their headers.
pkg_cflags = $(patsubst -I%,-isystem %,$(shell $(PKG_CONFIG) --cflags $(1) 2>/dev/null))
pkg_libs = $(shell $(PKG_CONFIG) --libs $(1) 2>/dev/null)
VDB_CFLAGS ?=
VDB_LIBS ?= -lopenvdb $(call pkg_libs,Imath tbb)
EMBREE_LIBS ?= -lembree3
OIIO_CFLAGS = $(call pkg_cflags,OpenImageIO)
OIIO_LIBS = $(call pkg_libs,OpenImageIO)
ASSIMP_CFLAGS = $(call pkg_cflags,assimp)
ASSIMP_LIBS = $(call pkg_libs,assimp)
# OpenImageIO is not among them: it lives in the image module, opened on first use.
DEP_LIBS = $(VDB_LIBS) $(EMBREE_LIBS) $(ASSIMP_LIBS) -ltinygltf -ldeflate -lz -ldl -lpthread -lm

# -ffp-contract=off: no fused multiply-adds, so float results are the same on every CPU and
# compiler (the packed .gi's JavaScript reader rebuilds the C one's bytes, docs/format.md).
# lib/ is one folder a stage (lib/README.md); file names are unique across them, so a
# source names a header by its file name alone and tests/cli/lib_layers.sh holds the rule.
LIB_DIRS := $(sort $(dir $(wildcard lib/*/)))
LIB_INC := -Ilib $(LIB_DIRS:%/=-I%)
ALL_CFLAGS = -std=c11 $(WARN_C) $(OPT) -ffp-contract=off -MMD -MP -fvisibility=hidden -DVDBGI_BUILDING \
             -DVDBGI_MODULE_DIR='"$(PREFIX)/lib/vdbgi"' $(ASSIMP_CFLAGS) $(call pkg_cflags,stb) \
             $(CFLAGS)
# No -fvisibility=hidden for the C++ shims: OpenVDB's registries rely on its template
# statics being shared with libopenvdb.so, and initialize() crashes when they are hidden.
ALL_CXXFLAGS = -std=c++17 $(WARN_CXX) $(OPT) -MMD -MP -DVDBGI_BUILDING \
               $(VDB_CFLAGS) $(call pkg_cflags,Imath tbb) $(OIIO_CFLAGS) $(CXXFLAGS)
ALL_LDFLAGS = $(OPT) $(LDFLAGS)

# ---- sources ----------------------------------------------------------------

LIB_C := $(wildcard lib/*/*.c)
# The OpenImageIO shim is not among them: it is a module of its own.
LIB_CXX := $(filter-out lib/shim/image_shim.cpp,$(wildcard lib/shim/*.cpp))
LIB_OBJ := $(LIB_C:%.c=$(BUILD)/%.o) $(LIB_CXX:%.cpp=$(BUILD)/%.o)
LIB_A := $(BUILD)/libvdbgi.a
# The OpenImageIO shim as a module of its own (lib/shim/image.c opens it).
IMAGE_MODULE := $(BUILD)/lib/vdbgi/libvdbgi_image.so
IMAGE_OBJ := $(BUILD)/lib/shim/image_shim.pic.o

APP_NAMES := gi-bake vdb-to-gi gi-inspect gi-bench gi-lightmap gi-merge
APPS := $(APP_NAMES:%=$(BUILD)/bin/%)
# The web runtime's reader (web/gi-wasm.js): lib/'s rebuild of a packed .gi built to
# WebAssembly with clang and wasi-libc, with web/wasm's entry points, one-thread
# run_threads and gzip stand-ins (the browser inflates), written beside the worker's
# scripts as a module of base64 (web/README.md). The same bytes from every config.
# -D_Float16=__fp16: clang 14 has no _Float16 on wasm32; util.c's half floats are the
# baker's, not the reader's, and the linker drops them.
WASM_CC ?= clang
WASM_SRC := $(addprefix lib/,core/context.c core/util.c core/encode.c format/gifile.c \
            format/packed.c format/pack_rebuild.c format/textures.c format/sampler.c \
            format/volume_access.c convert/pack_place.c) $(wildcard web/wasm/*.c)
WASM := $(BUILD)/web/gi-reader.wasm
WASM_JS := web/gi-reader-wasm.js
WASM_FLAGS := --target=wasm32-wasi -O2 -std=c11 $(WARN_C) -Wno-missing-prototypes -ffp-contract=off \
              -DVDBGI_BUILDING -D_Float16=__fp16 -Iweb/wasm/include $(LIB_INC) \
              -mexec-model=reactor -Wl,--no-entry -Wl,--strip-all

# gi-bench is for measuring vdbgi itself: built, never installed.
INSTALL_APPS := $(filter-out %/gi-bench,$(APPS))
CLI_OBJ := $(BUILD)/apps/cli.o

TEST_SRC := $(wildcard tests/test_*.c)
TESTS := $(TEST_SRC:tests/%.c=$(BUILD)/tests/%)

DEB_PACKAGES := gcc g++ make pkg-config libopenvdb-dev libboost-dev libimath-dev libtbb-dev \
                libembree-dev libopenimageio-dev libassimp-dev zlib1g-dev libdeflate-dev libopenvdb-tools \
                python3 python3-openvdb python3-numpy openimageio-tools gnuplot-nox clang-format chromium libstb-dev \
                libtinygltf-dev assimp-testmodels slurmctld slurmd slurm-client munge \
                clang lld wasi-libc libclang-rt-dev-wasm32

# Keep object files of apps and tests (make would delete them as intermediates).
.SECONDARY:

.PHONY: all lib apps tests web check demo bench bench-scale chart deps asan fuzz install uninstall clean format list view pictures

## all: build the library, the apps and the web runtime's WebAssembly reader (default)
all: lib apps web

lib: $(LIB_A) $(IMAGE_MODULE)
apps: $(APPS)
tests: $(TESTS)
web: $(WASM_JS)

$(BUILD)/lib/%.o: lib/%.c Makefile
	@mkdir -p $(@D)
	@$(if $(Q),echo "  CC      $<")
	$(Q)$(CC) $(ALL_CFLAGS) $(LIB_INC) -c $< -o $@

$(BUILD)/lib/%.o: lib/%.cpp Makefile
	@mkdir -p $(@D)
	@$(if $(Q),echo "  CXX     $<")
	$(Q)$(CXX) $(ALL_CXXFLAGS) $(LIB_INC) -c $< -o $@

# The installed module directory is compiled into image.o: rebuild it when PREFIX changes.
PREFIX_STAMP := $(BUILD)/prefix$(subst /,_,$(PREFIX)).stamp
$(BUILD)/lib/shim/image.o: $(PREFIX_STAMP)
$(PREFIX_STAMP):
	@mkdir -p $(@D) && rm -f $(BUILD)/prefix*.stamp && touch $@

$(IMAGE_OBJ): lib/shim/image_shim.cpp Makefile
	@mkdir -p $(@D)
	@$(if $(Q),echo "  CXX     $<")
	$(Q)$(CXX) $(ALL_CXXFLAGS) $(LIB_INC) -fPIC -c $< -o $@

$(IMAGE_MODULE): $(IMAGE_OBJ)
	@mkdir -p $(@D)
	@$(if $(Q),echo "  LINK    $@")
	$(Q)$(CXX) $(ALL_LDFLAGS) -shared $^ $(OIIO_LIBS) -o $@

$(LIB_A): $(LIB_OBJ)
	@$(if $(Q),echo "  AR      $@")
	$(Q)rm -f $@ && ar rcs $@ $^

$(BUILD)/apps/%.o: apps/%.c
	@mkdir -p $(@D)
	@$(if $(Q),echo "  CC      $<")
	$(Q)$(CC) $(ALL_CFLAGS) -Ilib -c $< -o $@

# Objects first, the library after them all (gi-bench's subcommands add objects).
$(BUILD)/bin/%: $(BUILD)/apps/%.o $(CLI_OBJ) $(LIB_A) | $(IMAGE_MODULE)
	@mkdir -p $(@D)
	@$(if $(Q),echo "  LINK    $@")
	$(Q)$(CXX) $(ALL_LDFLAGS) $(filter %.o,$^) $(filter %.a,$^) $(DEP_LIBS) -o $@

$(WASM): $(WASM_SRC) $(wildcard lib/*.h lib/*/*.h web/wasm/include/*.h) Makefile
	@mkdir -p $(@D)
	@$(if $(Q),echo "  WASM    $@")
	$(Q)$(WASM_CC) $(WASM_FLAGS) $(WASM_SRC) -o $@

$(WASM_JS): $(WASM)
	@$(if $(Q),echo "  BASE64  $@")
	$(Q)tmp=$@.$$$$.tmp; \
	  echo "// gi-reader-wasm.js: made by make from web/wasm (gi-wasm.js loads it); not edited by hand." > $$tmp && \
	  printf 'export default "' >> $$tmp && base64 -w0 $< >> $$tmp && echo '";' >> $$tmp && \
	  mv $$tmp $@ || { rm -f $$tmp; exit 1; }

# vdb-to-gi's report of a conversion is a file of its own.
$(BUILD)/bin/vdb-to-gi: $(BUILD)/apps/convert_report.o $(BUILD)/apps/budget.o
# --budget's parsing and measured curves, shared by gi-bake, gi-lightmap and vdb-to-gi.
$(BUILD)/bin/gi-bake $(BUILD)/bin/gi-lightmap: $(BUILD)/apps/budget.o

# gi-bench is one file a subcommand (apps/bench_*.c).
BENCH_OBJ := $(patsubst apps/%.c,$(BUILD)/apps/%.o,$(wildcard apps/bench_*.c))
$(BUILD)/bin/gi-bench: $(BENCH_OBJ)

$(BUILD)/tests/%.o: tests/%.c
	@mkdir -p $(@D)
	@$(if $(Q),echo "  CC      $<")
	$(Q)$(CC) $(ALL_CFLAGS) $(LIB_INC) -Itests -c $< -o $@

$(BUILD)/tests/%: $(BUILD)/tests/%.o $(LIB_A) | $(IMAGE_MODULE)
	@$(if $(Q),echo "  LINK    $@")
	$(Q)$(CXX) $(ALL_LDFLAGS) $^ $(DEP_LIBS) -o $@

-include $(LIB_OBJ:.o=.d) $(IMAGE_OBJ:.o=.d) $(CLI_OBJ:.o=.d) $(BENCH_OBJ:.o=.d) $(APP_NAMES:%=$(BUILD)/apps/%.d) \
         $(BUILD)/apps/convert_report.d $(BUILD)/apps/budget.d \
         $(TEST_SRC:tests/%.c=$(BUILD)/tests/%.d)

## deps: install the Debian packages vdbgi needs (only those missing)
deps:
	@if ! command -v dpkg-query >/dev/null 2>&1; then \
	    echo "deps: not a Debian system; install OpenVDB, Embree 3, OpenImageIO, assimp, TBB, zlib, libdeflate, and clang with lld and wasi-libc (the web runtime's reader) yourself"; \
	    exit 0; \
	fi; \
	missing=""; \
	for p in $(DEB_PACKAGES); do \
	    dpkg-query -W -f='$${Status}' $$p 2>/dev/null | grep -q 'ok installed' || missing="$$missing $$p"; \
	done; \
	command -v node >/dev/null 2>&1 || missing="$$missing nodejs"; \
	command -v npm >/dev/null 2>&1 || missing="$$missing npm"; \
	if [ -n "$$missing" ]; then \
	    sudo=""; [ "$$(id -u)" = 0 ] || sudo=sudo; \
	    echo "deps: installing$$missing"; \
	    $$sudo apt-get update -qq && \
	    DEBIAN_FRONTEND=noninteractive $$sudo apt-get install -y -qq --no-install-recommends $$missing; \
	fi; \
	if [ ! -d tests/js/node_modules/ktx-parse ] || [ ! -d tests/js/node_modules/gltf-validator ] || \
	   [ ! -d tests/js/node_modules/potpack ]; then \
	    echo "deps: npm install (tests/js: ktx-parse and gltf-validator, independent readers; potpack, seed 004's packer)"; \
	    (cd tests/js && npm install --no-audit --no-fund --loglevel=error >/dev/null); \
	fi; \
	if [ ! -d web/node_modules/three ] || [ ! -d web/node_modules/puppeteer-core ] || \
	   [ ! -d web/node_modules/three-0.165 ] || [ ! -d web/node_modules/three-0.175 ] || \
	   [ ! -d web/node_modules/three-0.183 ] || [ ! -d web/node_modules/esbuild ] || \
	   [ ! -d web/node_modules/typescript ] || [ ! -d web/node_modules/@types/three ] || \
	   [ ! -d web/node_modules/vite ] || [ ! -d web/node_modules/@react-three/fiber ] || \
	   [ ! -d web/node_modules/react-dom ] || [ ! -d web/node_modules/@types/react ]; then \
	    echo "deps: npm ci (web: three, the oldest threes we claim, esbuild and vite for the README's builds, typescript and @types/three for the types, React and React Three Fiber for vdbgi/react, and puppeteer-core to drive Debian's chromium)"; \
	    (cd web && npm ci --no-audit --no-fund --loglevel=error >/dev/null); \
	fi

## check: install what is missing, build, run every test; ends with "N passed, N failed"
check:
	$(Q)$(MAKE) --no-print-directory deps
	$(Q)$(MAKE) --no-print-directory all tests
	$(Q)BUILD=$(BUILD) JOBS=$(JOBS) sh tests/run.sh

## asan: the test suite under AddressSanitizer and UBSan (same as SANITIZE=1 make check)
asan:
	$(Q)LSAN_OPTIONS=suppressions=$(CURDIR)/tests/lsan.supp:print_suppressions=0 $(MAKE) --no-print-directory config=asan check

## fuzz: cut and flip bytes of a real .vdb and .gi.gz, read each under limits; deviations kept
fuzz:
	$(Q)$(MAKE) --no-print-directory all
	$(Q)BUILD=$(BUILD) sh tests/fuzz_damage.sh

## demo: install what is missing, build, bake the bundled world and convert it
demo:
	$(Q)$(MAKE) --no-print-directory deps
	$(Q)$(MAKE) --no-print-directory all
	@mkdir -p out
	$(BUILD)/bin/gi-bake data/world.glb -o out/world.vdb
	$(BUILD)/bin/vdb-to-gi out/world.vdb -o out/world.gi.gz --slices out/slices --stats out/world.json
	$(BUILD)/bin/gi-lightmap data/world.glb -o out/world-lit.glb
	@echo
	@echo "demo: out/world.vdb      baked probes (vdb_print -l out/world.vdb, or Blender)"
	@echo "      out/world.gi.gz    bricks for the runtime (gi-inspect out/world.gi.gz --at 0,1,0)"
	@echo "      out/world.json     conversion statistics"
	@echo "      out/slices/*.png   the baked field, the bricks, their difference, levels, atlas"
	@echo "      out/world-lit.glb  the world with its lightmap (any glTF viewer; docs/lightmap.md)"
	@echo "      make view          serves web/viewer.html on 127.0.0.1: the lit world, its GI on the character"

## view: serve the viewer on 127.0.0.1 (PORT=8080) with the demo's lightmapped world and volume, or drop files on it
PORT ?= 8080
view:
	$(Q)$(MAKE) --no-print-directory deps
	@scene=/data/world.glb; [ -f out/world-lit.glb ] && scene=/out/world-lit.glb; \
	 if [ -f out/world.gi.gz ]; then q="scene=$$scene&gi=/out/world.gi.gz"; \
	 else echo "view: no out/world.gi.gz yet (make demo makes it); drop a .glb and a .gi.gz on the page"; q=""; fi; \
	 node web/serve.mjs --port $(PORT) $${q:+--query "$$q"}

## bench: bake throughput against bare Embree, conversion size/error/time (build/bench/bench.md)
bench:
	$(Q)$(MAKE) --no-print-directory deps
	$(Q)$(MAKE) --no-print-directory all
	$(Q)BUILD=$(BUILD) sh tests/bench.sh

## bench-scale: tiles of the 200 m world and the 4x world step by step (docs/scale.md, ten minutes)
bench-scale:
	$(Q)$(MAKE) --no-print-directory all
	$(Q)BUILD=$(BUILD) sh tests/scale.sh

## chart: sweep rays, eps and spacing, redraw docs/img/chart_*.png, stability table (two minutes)
chart:
	$(Q)$(MAKE) --no-print-directory deps
	$(Q)$(MAKE) --no-print-directory all $(BUILD)/tests/test_stability
	$(Q)BUILD=$(BUILD) sh tests/chart.sh

## pictures: the README's pictures from the demo's outputs (slices enlarged, the viewer with GI off and on)
pictures:
	$(Q)$(MAKE) --no-print-directory demo
	$(Q)sh tests/pictures.sh

## install: vdbgi.h, libvdbgi.a, the image module, vdbgi.pc and the apps under $(DESTDIR)$(PREFIX)
install: lib apps
	install -d $(DESTDIR)$(PREFIX)/include $(DESTDIR)$(PREFIX)/lib/pkgconfig \
	    $(DESTDIR)$(PREFIX)/lib/vdbgi $(DESTDIR)$(PREFIX)/bin
	install -m 644 lib/vdbgi.h $(DESTDIR)$(PREFIX)/include/
	install -m 644 $(LIB_A) $(DESTDIR)$(PREFIX)/lib/
	install -m 755 $(IMAGE_MODULE) $(DESTDIR)$(PREFIX)/lib/vdbgi/
	sed -e 's|@PREFIX@|$(PREFIX)|' -e 's|@VERSION@|$(shell sed -n 's/^#define VDBGI_VERSION_\(MAJOR\|MINOR\|PATCH\) //p' lib/vdbgi.h | paste -sd.)|' \
	    lib/vdbgi.pc.in > $(DESTDIR)$(PREFIX)/lib/pkgconfig/vdbgi.pc
	install -m 755 $(INSTALL_APPS) $(DESTDIR)$(PREFIX)/bin/

## uninstall: remove what install put there
uninstall:
	rm -f $(DESTDIR)$(PREFIX)/include/vdbgi.h $(DESTDIR)$(PREFIX)/lib/libvdbgi.a \
	      $(DESTDIR)$(PREFIX)/lib/vdbgi/libvdbgi_image.so \
	      $(DESTDIR)$(PREFIX)/lib/pkgconfig/vdbgi.pc $(INSTALL_APPS:$(BUILD)/bin/%=$(DESTDIR)$(PREFIX)/bin/%)
	-rmdir $(DESTDIR)$(PREFIX)/lib/vdbgi 2>/dev/null

## clean: remove build outputs
clean:
	rm -rf build out $(WASM_JS)

## format: apply .clang-format to every C and C++ source
format:
	clang-format -i lib/*.h lib/*/*.c lib/*/*.h lib/*/*.cpp apps/*.c apps/*.h tests/*.c tests/*.h \
	    web/wasm/*.c web/wasm/include/*.h

## list: show these targets
list:
	@sed -n 's/^## //p' $(MAKEFILE_LIST)
