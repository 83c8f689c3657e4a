/*
 * giwasm.c: the measured entry points. gi_read(data, size) takes the bytes of
 * an already-inflated .gi (versions 5..7: the packed layout the web runtime
 * loads), and does what lib/format/volume_io.c's read_bytes + from_body do for
 * it (vdbgi_gifile_parse: every header check, the body copied out; then
 * vdbgi_pack_read: the plan, its checks, and the textures rebuilt), except the
 * vdbgi_volume_seal that read_bytes runs on a non-gzip input (it re-gzips the
 * file so that a write can write it back: no use to a browser).
 * gi_prepare() then makes what gi-gpu.js's prepareTextures makes: the
 * runtime's indirection columns (vdbgi_volume_columns) and the L2 terms as six
 * RGBA8 textures of unsigned bytes (q ^ 0x80).
 */
#include "gifile.h"
#include "packed.h"
#include "volume.h"

#include <stdlib.h>
#include <string.h>

#ifdef __EMSCRIPTEN__
#include <emscripten.h>
#define EXPORT EMSCRIPTEN_KEEPALIVE
#else
#define EXPORT
#endif

static vdbgi_context *ctx;
static vdbgi_volume *vol;
static uint8_t *columns;
static size_t columns_size;
static uint32_t columns_dims[2];
static uint8_t *sh_tex[6];

static void volume_free(vdbgi_volume *v)
{
    if (!v)
        return;
    vdbgi_textures_free(v->ctx, &v->tex);
    vdbgi_free(v->ctx, v->payload);
    vdbgi_free(v->ctx, v->file);
    vdbgi_free(v->ctx, v);
}

EXPORT void gi_free(void)
{
    volume_free(vol);
    vol = NULL;
    free(columns);
    columns = NULL;
    columns_size = 0;
    for (int i = 0; i < 6; i++) {
        free(sh_tex[i]);
        sh_tex[i] = NULL;
    }
}

EXPORT void *gi_alloc(size_t n)
{
    return malloc(n);
}
EXPORT void gi_dealloc(void *p)
{
    free(p);
}

/* 0 OK, else a vdbgi_result; gi_error() says why. */
EXPORT int gi_read(const uint8_t *data, size_t size)
{
    gi_free();
    if (!ctx && vdbgi_context_create(NULL, &ctx) != VDBGI_OK)
        return VDBGI_ERR_OUT_OF_MEMORY;
    vdbgi_volume_info info;
    uint32_t version = 0;
    uint8_t *body = NULL;
    size_t body_size = 0;
    const char *name = "memory";
    vdbgi_result r = vdbgi_gifile_parse(ctx, name, data, size, &info, &version, &body, &body_size);
    if (r != VDBGI_OK)
        return r;
    if (version < 5) { /* only the packed layout is measured */
        vdbgi_free(ctx, body);
        return vdbgi_fail(ctx, VDBGI_ERR_FORMAT, "version %u: not measured here", version);
    }
    vdbgi_volume *const v = vdbgi_calloc(ctx, 1, sizeof(*v));
    if (!v) {
        vdbgi_free(ctx, body);
        return VDBGI_ERR_OUT_OF_MEMORY;
    }
    v->ctx = ctx;
    v->info = info;
    v->payload = body;
    v->payload_size = body_size;
    v->version = version;
    r = vdbgi_pack_read(v, name);
    if (r != VDBGI_OK) {
        volume_free(v);
        return r;
    }
    v->info.file_size = size;
    vol = v;
    return VDBGI_OK;
}

/* The GPU-ready arrays, as gi-gpu.js's prepareTextures: 0 OK. */
EXPORT int gi_prepare(void)
{
    if (!vol)
        return VDBGI_ERR_INVALID_ARG;
    columns_size = vdbgi_volume_columns(vol, NULL, 0, columns_dims);
    if (!columns_size)
        return vdbgi_fail(ctx, VDBGI_ERR_FORMAT, "the runtime's indirection is too large");
    columns = malloc(columns_size);
    if (!columns || vdbgi_volume_columns(vol, columns, columns_size, columns_dims) != columns_size)
        return VDBGI_ERR_OUT_OF_MEMORY;
    if (vol->tex.sh) {
        const size_t texels = vdbgi_texels(vol->info.atlas_dims);
        for (int i = 0; i < 6; i++)
            if (!(sh_tex[i] = malloc(4 * texels)))
                return VDBGI_ERR_OUT_OF_MEMORY;
        /* term byte j of a texel (24 a texel) -> texture j >> 2, component j & 3, as q + 128 */
        const uint8_t *s = (const uint8_t *)vol->tex.sh;
        uint32_t *w[6];
        for (int i = 0; i < 6; i++)
            w[i] = (uint32_t *)sh_tex[i];
        for (size_t t = 0; t < texels; t++, s += 24)
            for (int i = 0; i < 6; i++) {
                uint32_t x;
                memcpy(&x, s + 4 * i, 4);
                w[i][t] = x ^ 0x80808080u;
            }
    }
    return VDBGI_OK;
}

EXPORT const char *gi_error(void)
{
    return ctx ? vdbgi_context_error(ctx) : "no context";
}
EXPORT const uint8_t *gi_atlas(void)
{
    return vol ? vol->tex.atlas : NULL;
}
EXPORT size_t gi_atlas_size(void)
{
    return vol ? vol->info.atlas_size : 0;
}
EXPORT const uint8_t *gi_indirection(void)
{
    return vol ? vol->tex.indirection : NULL;
}
EXPORT size_t gi_indirection_size(void)
{
    return vol ? vol->info.indirection_size : 0;
}
EXPORT const uint8_t *gi_columns(void)
{
    return columns;
}
EXPORT size_t gi_columns_size(void)
{
    return columns_size;
}
EXPORT uint32_t gi_columns_dim(int k)
{
    return columns_dims[k & 1];
}
EXPORT const uint8_t *gi_sh(int i)
{
    return i >= 0 && i < 6 ? sh_tex[i] : NULL;
}
EXPORT const uint32_t *gi_atlas_dims(void)
{
    return vol ? vol->info.atlas_dims : NULL;
}
