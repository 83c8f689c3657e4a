/*
 * volume_io.c: a volume to and from its .gi file. The file code (gifile.c)
 * sees a header and a body; which body, textures or the packed layout's
 * payload, and what a reader checks inside it, is decided here and in the
 * layouts (packed.c).
 */
#define _POSIX_C_SOURCE 200809L
#include "gifile.h"
#include "packed.h"
#include "util.h"

#include <errno.h>
#include <stdio.h>
#include <string.h>

/*
 * Every indirection texel must point at a whole brick inside the atlas, with a
 * level the file allows: a seed slot, or a compact brick's first texel (an
 * empty compact cell points at the block of zeros at the corner).
 */
static vdbgi_result check_indirection(vdbgi_context *ctx, const char *path, const vdbgi_volume *v)
{
    const vdbgi_volume_info *const info = &v->info;
    const bool compact = info->layout == VDBGI_LAYOUT_COMPACT;
    const uint8_t *const ind = v->tex.indirection;
    const uint32_t b = compact ? VDBGI_BRICK_COMPACT : VDBGI_BRICK_PADDED;
    for (size_t i = 0; i < info->indirection_size; i += 4) {
        const uint8_t *const t = &ind[i];
        bool inside = true;
        uint32_t level;
        if (compact) {
            level = t[3] & 3u;
            for (int k = 0; k < 3; k++)
                inside =
                    inside && 4u * t[k] + (t[3] >> (2 + 2 * k) & 3u) + b <= info->atlas_dims[k];
        } else {
            if (t[3] == 0)
                continue;
            level = t[3] - 1u;
            for (int k = 0; k < 3; k++)
                inside = inside && (t[k] + 1u) * b <= info->atlas_dims[k];
        }
        VDBGI_FAIL_IF(ctx, !inside || level > info->max_level, VDBGI_ERR_FORMAT,
                      "%s: indirection texel %zu points outside the atlas", path, i / 4);
    }
    return VDBGI_OK;
}

/* A volume from a parsed file: the body becomes its textures, or its payload rebuilt into them. */
static vdbgi_result from_body(vdbgi_context *ctx, const char *name, const vdbgi_volume_info *info,
                              uint32_t version, uint8_t *body, size_t body_size, vdbgi_volume **out)
{
    vdbgi_volume *const v = vdbgi_calloc(ctx, 1, sizeof(*v));
    if (!v) {
        vdbgi_free(ctx, body);
        return VDBGI_ERR_OUT_OF_MEMORY;
    }
    v->ctx = ctx;
    v->info = *info;
    vdbgi_result r;
    if (version >= 5) { /* packed: kept, so that it writes back as it came */
        v->payload = body;
        v->payload_size = body_size;
        v->version = version;
        r = vdbgi_pack_read(v, name);
    } else {
        vdbgi_textures_adopt(&v->tex, body, info->ind_dims, info->atlas_dims);
        r = check_indirection(ctx, name, v);
    }
    if (r != VDBGI_OK) {
        vdbgi_volume_destroy(v);
        return r;
    }
    *out = v;
    return VDBGI_OK;
}

static vdbgi_result read_bytes(vdbgi_context *ctx, const char *name, const uint8_t *bytes,
                               size_t size, vdbgi_volume **out)
{
    vdbgi_volume_info info;
    uint32_t version = 0;
    uint8_t *body = NULL;
    size_t body_size = 0;
    VDBGI_TRY(vdbgi_gifile_parse(ctx, name, bytes, size, &info, &version, &body, &body_size));
    VDBGI_TRY(from_body(ctx, name, &info, version, body, body_size, out));
    vdbgi_volume *const v = *out;
    vdbgi_result r;
    if (size >= 2 && bytes[0] == 0x1f && bytes[1] == 0x8b) { /* written back as it came */
        r = (v->file = vdbgi_alloc(ctx, size)) ? VDBGI_OK : VDBGI_ERR_OUT_OF_MEMORY;
        if (r == VDBGI_OK)
            memcpy(v->file, bytes, v->file_size = size);
    } else {
        r = vdbgi_volume_seal(v);
        v->info.file_size = size; /* the file read, as for a gzip'd one */
    }
    if (r != VDBGI_OK) {
        vdbgi_volume_destroy(v);
        *out = NULL;
    }
    return r;
}

vdbgi_result vdbgi_volume_read(vdbgi_context *ctx, const char *path, vdbgi_volume **out)
{
    VDBGI_FAIL_IF(ctx, !out, VDBGI_ERR_INVALID_ARG, "no output pointer given");
    *out = NULL;
    VDBGI_TRY(vdbgi_input_check(ctx, path));
    uint8_t *file = NULL;
    size_t file_size = 0;
    VDBGI_TRY(vdbgi_gifile_slurp(ctx, path, &file, &file_size));
    const vdbgi_result r = read_bytes(ctx, path, file, file_size, out);
    vdbgi_free(ctx, file);
    return r;
}

vdbgi_result vdbgi_volume_read_memory(vdbgi_context *ctx, const void *data, size_t size,
                                      const char *name, vdbgi_volume **out)
{
    VDBGI_FAIL_IF(ctx, !out, VDBGI_ERR_INVALID_ARG, "no output pointer given");
    *out = NULL;
    VDBGI_FAIL_IF(ctx, !data && size, VDBGI_ERR_INVALID_ARG, "no bytes given");
    return read_bytes(ctx, name ? name : "memory", data, size, out);
}

/* ---- writing ----------------------------------------------------------------------------- */

vdbgi_result vdbgi_volume_seal(vdbgi_volume *v)
{
    VDBGI_FAIL_IF(v->ctx, !v->payload && !v->tex.indirection, VDBGI_ERR_INVALID_ARG,
                  "volume has nothing to write");
    uint8_t h[VDBGI_GI_HEADER_MAX];
    const size_t header_size = vdbgi_gifile_header(&v->info, v->payload ? v->version : 0, h);
    const uint8_t *const body = v->payload ? v->payload : v->tex.indirection;
    const size_t body_size =
        v->payload ? v->payload_size : v->info.indirection_size + v->info.atlas_size;
    vdbgi_free(v->ctx, v->file);
    v->file = NULL;
    VDBGI_TRY(vdbgi_gifile_gzip(v->ctx, h, header_size, body, body_size, &v->file, &v->file_size));
    v->info.file_size = v->file_size;
    return VDBGI_OK;
}

vdbgi_result vdbgi_volume_write(const vdbgi_volume *v, const char *path)
{
    return vdbgi_write_bytes_atomic(v->ctx, path, v->file, v->file_size);
}

vdbgi_result vdbgi_volume_write_memory(const vdbgi_volume *v, void *buffer, size_t capacity,
                                       size_t *size)
{
    *size = v->file_size;
    VDBGI_FAIL_IF(v->ctx, buffer && capacity < *size, VDBGI_ERR_INVALID_ARG,
                  "a buffer of %zu bytes for a %zu-byte file", capacity, *size);
    if (buffer)
        memcpy(buffer, v->file, *size);
    return VDBGI_OK;
}

typedef struct texture_file {
    const vdbgi_volume *v;
    uint8_t header[VDBGI_GI_HEADER_MAX];
} texture_file;

static vdbgi_result write_textures(vdbgi_context *ctx, const char *tmp, const void *user)
{
    const texture_file *const tf = user;
    const vdbgi_volume *const v = tf->v;
    FILE *const f = fopen(tmp, "wb");
    VDBGI_FAIL_IF(ctx, !f, VDBGI_ERR_IO, "%s: cannot write: %s", tmp, strerror(errno));
    const size_t body = v->info.indirection_size + v->info.atlas_size;
    const bool ok = fwrite(tf->header, 1, VDBGI_GI_HEADER_SIZE, f) == VDBGI_GI_HEADER_SIZE &&
                    fwrite(v->tex.indirection, 1, body, f) == body;
    const int saved = errno;
    if (fclose(f) != 0 || !ok)
        return vdbgi_fail(ctx, VDBGI_ERR_IO, "%s: cannot write: %s", tmp,
                          strerror(ok ? errno : saved));
    return VDBGI_OK;
}

vdbgi_result vdbgi_volume_write_textures(const vdbgi_volume *v, const char *path)
{
    VDBGI_FAIL_IF(v->ctx, !v->tex.atlas, VDBGI_ERR_INVALID_ARG, "volume has no textures");
    VDBGI_FAIL_IF(v->ctx, v->info.basis != VDBGI_BASIS_SCALAR, VDBGI_ERR_INVALID_ARG,
                  "the textures' file (version 2) holds no L2 terms: convert with the scalar "
                  "basis for it");
    texture_file tf = {.v = v};
    vdbgi_gifile_header(&v->info, 0, tf.header);
    return vdbgi_write_atomic(v->ctx, path, write_textures, &tf);
}
