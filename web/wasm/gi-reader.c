/*
 * gi-reader.c: lib/'s reader of a packed .gi (versions 5 to 8), built to
 * WebAssembly for web/gi-wasm.js, which the decoding worker runs in place of
 * gi-packed.js's rebuild (the same bytes in less time: docs/web.md, "The
 * WebAssembly reader").
 *
 * gi_read takes a whole inflated .gi (the browser inflates with
 * DecompressionStream) and does what volume_io.c's read of it does: every
 * header check, then the plan, its checks and the textures rebuilt
 * (vdbgi_pack_read). The page copies out the indirection, the atlas and the
 * L2 terms (24 signed bytes a texel, vdbgi_term_byte's order), which it
 * splits into its term textures as it copies them. One volume at a time: a
 * read frees the one before. Fresh memory is much of a first read's time (a
 * first touch of a page costs about as much as the work on it), so the
 * file's bytes become the body in place, and are not copied.
 */
#include "gifile.h"
#include "packed.h"
#include "volume.h"

#define EXPORT(name) __attribute__((export_name(#name)))

static vdbgi_context *ctx;
static vdbgi_volume *vol;

static void volume_free(vdbgi_volume *v)
{
    if (!v)
        return;
    vdbgi_textures_free(v->ctx, &v->tex);
    vdbgi_free(v->ctx, v->payload);
    vdbgi_free(v->ctx, v);
}

EXPORT(gi_free) void gi_free(void)
{
    volume_free(vol);
    vol = NULL;
}

/* n bytes for a .gi (through the context's allocator, which the body's block must come from). */
EXPORT(gi_alloc) void *gi_alloc(size_t n)
{
    /* No budget of its own: the page's (loadGi's maxBytes) held the header to its own. */
    const vdbgi_context_desc desc = {.volume_budget = SIZE_MAX};
    if (!ctx && vdbgi_context_create(&desc, &ctx) != VDBGI_OK)
        return NULL;
    return vdbgi_alloc(ctx, n);
}

/* The .gi's size bytes at data, from gi_alloc, which this takes: 0 when read, else a
   vdbgi_result, and gi_error() says why. */
EXPORT(gi_read) int gi_read(uint8_t *data, size_t size)
{
    gi_free();
    if (!ctx || !data)
        return VDBGI_ERR_INVALID_ARG;
    vdbgi_volume_info info;
    uint32_t version = 0;
    uint8_t *body = NULL;
    size_t body_size = 0;
    const char *const name = "the .gi";
    vdbgi_result r =
        vdbgi_gifile_parse_in_place(ctx, name, data, size, &info, &version, &body, &body_size);
    if (body != data)
        vdbgi_free(ctx, data);
    if (r != VDBGI_OK)
        return r;
    if (version < 5) { /* textures as they are: gi-format.js checks them in place */
        vdbgi_free(ctx, body);
        return vdbgi_fail(ctx, VDBGI_ERR_FORMAT, "version %u is not packed", version);
    }
    vdbgi_volume *const v = vdbgi_calloc(ctx, 1, sizeof(*v));
    if (!v) {
        vdbgi_free(ctx, body);
        return VDBGI_ERR_OUT_OF_MEMORY;
    }
    *v = (vdbgi_volume){
        .ctx = ctx, .info = info, .payload = body, .payload_size = body_size, .version = version};
    r = vdbgi_pack_read(v, name);
    if (r != VDBGI_OK) {
        volume_free(v);
        return r;
    }
    vol = v;
    return VDBGI_OK;
}

EXPORT(gi_error) const char *gi_error(void)
{
    return ctx ? vdbgi_context_error(ctx) : "no context";
}

EXPORT(gi_atlas) const uint8_t *gi_atlas(void)
{
    return vol ? vol->tex.atlas : NULL;
}

EXPORT(gi_atlas_size) size_t gi_atlas_size(void)
{
    return vol ? vol->info.atlas_size : 0;
}

EXPORT(gi_indirection) const uint8_t *gi_indirection(void)
{
    return vol ? vol->tex.indirection : NULL;
}

EXPORT(gi_indirection_size) size_t gi_indirection_size(void)
{
    return vol ? vol->info.indirection_size : 0;
}

EXPORT(gi_stored_points) size_t gi_stored_points(void)
{
    return vol ? vol->info.stored_points : 0;
}

/* The L2 terms, 24 a texel, or NULL. */
EXPORT(gi_terms) const int8_t *gi_terms(void)
{
    return vol ? vol->tex.sh : NULL;
}
