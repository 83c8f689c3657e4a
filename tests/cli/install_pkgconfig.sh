# make install into a staging root; a program built with nothing but
# `pkg-config --cflags --libs vdbgi` then links and bakes; gi-bench is not installed.
config=$(basename "$(dirname "$BIN")")
env -u MAKEFLAGS -u MAKELEVEL make -s -C "$ROOT" --no-print-directory install config="$config" \
    DESTDIR="$PWD/stage" PREFIX=/usr/local >/dev/null 2>err || { echo "install failed"; cat err; }
ls stage/usr/local/bin stage/usr/local/include stage/usr/local/lib/vdbgi
cat > t.c <<'C'
#include <stdio.h>
#include <vdbgi.h>

int main(void)
{
    static const float pos[12] = {-2, 0, 2, 2, 0, 2, 2, 0, -2, -2, 0, -2};
    static const uint32_t idx[6] = {0, 1, 2, 0, 2, 3};
    const vdbgi_mesh_desc mesh = {pos, 4, idx, 2, {0.5f, 0.5f, 0.5f}, 0};
    vdbgi_context *ctx = NULL;
    vdbgi_scene *scene = NULL;
    vdbgi_probes *probes = NULL;
    const vdbgi_place_desc place = {.spacing = 1.0};
    const vdbgi_bake_desc bake = {.rays = 16};
    if (vdbgi_context_create(NULL, &ctx) || vdbgi_scene_create(ctx, &mesh, 1, &scene) ||
        vdbgi_probes_place(ctx, scene, &place, &probes) ||
        vdbgi_probes_bake(probes, scene, &bake, NULL)) {
        printf("failed: %s\n", vdbgi_context_error(ctx));
        return 1;
    }
    vdbgi_probes_info info;
    vdbgi_probes_get_info(probes, &info);
    printf("vdbgi %s baked %zu probes\n", vdbgi_version_string(), info.probe_count);
    vdbgi_probes_destroy(probes);
    vdbgi_scene_destroy(scene);
    vdbgi_context_destroy(ctx);
    return 0;
}
C
export PKG_CONFIG_PATH="$PWD/stage/usr/local/lib/pkgconfig" PKG_CONFIG_SYSROOT_DIR="$PWD/stage"
case "$config" in asan) san="-fsanitize=address,undefined" ;; ubsan) san="-fsanitize=undefined" ;; *) san="" ;; esac
cc -std=c11 $san t.c $(pkg-config --cflags --libs vdbgi) -o t && ./t
