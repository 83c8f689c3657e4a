/* gifile.c: the .gi container (docs/format.md): header, indirection, atlas, gzip. */
#define _POSIX_C_SOURCE 200809L
#include "gifile.h"
#include "util.h"

#include <errno.h>
#include <libdeflate.h>
#include <math.h>
#include <stdio.h>
#include <string.h>
#include <sys/stat.h>
#include <zlib.h>

static const char gi_magic[8] = {'v', 'd', 'b', 'g', 'i', '.', 'g', 'i'};

static void write_header(const vdbgi_volume_info *in, uint8_t h[VDBGI_GI_HEADER_SIZE])
{
    memset(h, 0, VDBGI_GI_HEADER_SIZE);
    memcpy(h, gi_magic, 8);
    vdbgi_put_u32(h + 8, VDBGI_GI_VERSION);
    vdbgi_put_u32(h + 12, VDBGI_GI_HEADER_SIZE);
    vdbgi_put_u32(h + 16, (uint32_t)in->encoding);
    vdbgi_put_f32(h + 20, in->rgbm_range);
    for (int k = 0; k < 3; k++) {
        vdbgi_put_u32(h + 24 + 4 * k, in->indirection_dims[k]);
        vdbgi_put_u32(h + 36 + 4 * k, in->atlas_dims[k]);
        vdbgi_put_f32(h + 48 + 4 * k, in->box_min[k]);
        vdbgi_put_f32(h + 60 + 4 * k, in->box_max[k]);
    }
    vdbgi_put_f32(h + 72, in->spacing);
    vdbgi_put_u32(h + 76, in->max_level);
    for (int l = 0; l < 4; l++)
        vdbgi_put_u32(h + 80 + 4 * l, in->bricks[l]);
    vdbgi_put_u32(h + 96, (uint32_t)in->indirection_size);
    vdbgi_put_u32(h + 100, (uint32_t)in->atlas_size);
}

vdbgi_result vdbgi_gifile_alloc(vdbgi_volume *v)
{
    const vdbgi_volume_info *const in = &v->info;
    VDBGI_FAIL_IF(v->ctx, in->indirection_size > UINT32_MAX || in->atlas_size > UINT32_MAX,
                  VDBGI_ERR_OUT_OF_MEMORY, "textures of %zu + %zu bytes exceed the format's 4 GiB",
                  in->indirection_size, in->atlas_size);
    v->raw = vdbgi_calloc(v->ctx, VDBGI_GI_HEADER_SIZE + in->indirection_size + in->atlas_size, 1);
    if (!v->raw)
        return VDBGI_ERR_OUT_OF_MEMORY;
    v->indirection = v->raw + VDBGI_GI_HEADER_SIZE;
    v->atlas = v->indirection + in->indirection_size;
    return VDBGI_OK;
}

vdbgi_result vdbgi_gifile_encode(vdbgi_volume *v)
{
    vdbgi_context *const ctx = v->ctx;
    write_header(&v->info, v->raw);
    const size_t raw = VDBGI_GI_HEADER_SIZE + v->info.indirection_size + v->info.atlas_size;
    /* libdeflate: one call over the whole buffer, several times faster than zlib at level 6. */
    struct libdeflate_compressor *const c = libdeflate_alloc_compressor(6);
    VDBGI_FAIL_IF(ctx, !c, VDBGI_ERR_OUT_OF_MEMORY, "libdeflate: cannot start compression");
    const size_t cap = libdeflate_gzip_compress_bound(c, raw);
    uint8_t *const out = vdbgi_alloc(ctx, cap);
    const size_t written = out ? libdeflate_gzip_compress(c, v->raw, raw, out, cap) : 0;
    libdeflate_free_compressor(c);
    if (!written) {
        vdbgi_free(ctx, out);
        return out ? vdbgi_fail(ctx, VDBGI_ERR_BACKEND, "libdeflate: compression failed")
                   : VDBGI_ERR_OUT_OF_MEMORY;
    }
    vdbgi_free(ctx, v->file);
    v->file = out;
    v->info.file_size = written;
    return VDBGI_OK;
}

vdbgi_result vdbgi_volume_write(const vdbgi_volume *v, const char *path)
{
    VDBGI_FAIL_IF(v->ctx, !v->file, VDBGI_ERR_INVALID_ARG, "volume has no encoded file");
    return vdbgi_write_bytes_atomic(v->ctx, path, v->file, v->info.file_size);
}

/* ---- reading ---------------------------------------------------------------- */

static vdbgi_result parse_header(vdbgi_context *ctx, const char *path, const uint8_t *h,
                                 vdbgi_volume_info *info, size_t *header_size)
{
    VDBGI_FAIL_IF(ctx, memcmp(h, gi_magic, 8) != 0, VDBGI_ERR_FORMAT,
                  "%s: not a .gi file (bad magic)", path);
    const uint32_t version = vdbgi_get_u32(h + 8);
    VDBGI_FAIL_IF(ctx, version != VDBGI_GI_VERSION, VDBGI_ERR_FORMAT,
                  "%s: .gi version %u, this reader knows %d", path, version, VDBGI_GI_VERSION);
    *header_size = vdbgi_get_u32(h + 12);
    VDBGI_FAIL_IF(ctx, *header_size < VDBGI_GI_HEADER_SIZE || *header_size > 65536,
                  VDBGI_ERR_FORMAT, "%s: bad header size %zu", path, *header_size);
    memset(info, 0, sizeof(*info));
    const uint32_t enc = vdbgi_get_u32(h + 16);
    VDBGI_FAIL_IF(ctx, enc > 1, VDBGI_ERR_FORMAT, "%s: unknown encoding %u", path, enc);
    info->encoding = (vdbgi_encoding)enc;
    info->rgbm_range = vdbgi_get_f32(h + 20);
    VDBGI_FAIL_IF(ctx, !(info->rgbm_range > 0.0f) || !isfinite(info->rgbm_range), VDBGI_ERR_FORMAT,
                  "%s: bad RGBM range", path);
    size_t ind = 4, atlas = 4;
    for (int k = 0; k < 3; k++) {
        info->indirection_dims[k] = vdbgi_get_u32(h + 24 + 4 * k);
        info->atlas_dims[k] = vdbgi_get_u32(h + 36 + 4 * k);
        info->box_min[k] = vdbgi_get_f32(h + 48 + 4 * k);
        info->box_max[k] = vdbgi_get_f32(h + 60 + 4 * k);
        VDBGI_FAIL_IF(
            ctx, info->indirection_dims[k] < 1 || info->indirection_dims[k] > VDBGI_MAX_TEXTURE_DIM,
            VDBGI_ERR_FORMAT, "%s: bad indirection size", path);
        VDBGI_FAIL_IF(ctx,
                      info->atlas_dims[k] < VDBGI_BRICK_PADDED ||
                          info->atlas_dims[k] > 256 * VDBGI_BRICK_PADDED ||
                          info->atlas_dims[k] % VDBGI_BRICK_PADDED,
                      VDBGI_ERR_FORMAT, "%s: bad atlas size", path);
        VDBGI_FAIL_IF(ctx,
                      !isfinite(info->box_min[k]) || !isfinite(info->box_max[k]) ||
                          !(info->box_max[k] > info->box_min[k]),
                      VDBGI_ERR_FORMAT, "%s: bad volume box", path);
        ind *= info->indirection_dims[k];
        atlas *= info->atlas_dims[k];
    }
    info->spacing = vdbgi_get_f32(h + 72);
    info->max_level = vdbgi_get_u32(h + 76);
    VDBGI_FAIL_IF(ctx, info->max_level > 3, VDBGI_ERR_FORMAT, "%s: bad max level", path);
    for (int l = 0; l < 4; l++) {
        info->bricks[l] = vdbgi_get_u32(h + 80 + 4 * l);
        info->brick_count += info->bricks[l];
    }
    info->indirection_size = vdbgi_get_u32(h + 96);
    info->atlas_size = vdbgi_get_u32(h + 100);
    VDBGI_FAIL_IF(ctx, info->indirection_size != ind || info->atlas_size != atlas, VDBGI_ERR_FORMAT,
                  "%s: texture sizes disagree with their dimensions", path);
    return VDBGI_OK;
}

/* Every indirection texel must point at a slot of the atlas with a level the file allows. */
static vdbgi_result check_indirection(vdbgi_context *ctx, const char *path, const vdbgi_volume *v)
{
    const vdbgi_volume_info *const info = &v->info;
    const uint32_t slots[3] = {info->atlas_dims[0] / 6, info->atlas_dims[1] / 6,
                               info->atlas_dims[2] / 6};
    for (size_t i = 0; i < info->indirection_size; i += 4) {
        const uint8_t *const t = &v->indirection[i];
        if (t[3] == 0)
            continue;
        VDBGI_FAIL_IF(
            ctx,
            t[0] >= slots[0] || t[1] >= slots[1] || t[2] >= slots[2] || t[3] > info->max_level + 1,
            VDBGI_ERR_FORMAT, "%s: indirection texel %zu points outside the atlas", path, i / 4);
    }
    return VDBGI_OK;
}

vdbgi_result vdbgi_volume_read(vdbgi_context *ctx, const char *path, vdbgi_volume **out)
{
    VDBGI_FAIL_IF(ctx, !out, VDBGI_ERR_INVALID_ARG, "no output pointer given");
    *out = NULL;
    VDBGI_TRY(vdbgi_input_check(ctx, path));
    /* gzread reads gzip'd and plain files alike, and checks the gzip CRC at the end. */
    gzFile gz = gzopen(path, "rb");
    VDBGI_FAIL_IF(ctx, !gz, VDBGI_ERR_IO, "%s: cannot open: %s", path,
                  errno ? strerror(errno) : "out of memory");
    vdbgi_result r = VDBGI_OK;
    vdbgi_volume *v = NULL;
    uint8_t h[VDBGI_GI_HEADER_SIZE];
    const int got = gzread(gz, h, sizeof(h));
    if (got != (int)sizeof(h)) {
        r = vdbgi_fail(ctx, VDBGI_ERR_FORMAT, "%s: %s", path,
                       got < 0 ? "damaged gzip data" : "too short to be a .gi file");
        goto done;
    }
    vdbgi_volume_info info;
    size_t header_size = 0;
    if ((r = parse_header(ctx, path, h, &info, &header_size)) != VDBGI_OK)
        goto done;
    /* Skip header fields added by later minor versions. */
    for (size_t skip = header_size - sizeof(h); skip > 0; skip--)
        if (gzgetc(gz) < 0) {
            r = vdbgi_fail(ctx, VDBGI_ERR_FORMAT, "%s: truncated header", path);
            goto done;
        }
    if (!(v = vdbgi_calloc(ctx, 1, sizeof(*v)))) {
        r = VDBGI_ERR_OUT_OF_MEMORY;
        goto done;
    }
    v->ctx = ctx;
    v->info = info;
    if ((r = vdbgi_gifile_alloc(v)) != VDBGI_OK)
        goto done;
    const struct {
        uint8_t *p;
        size_t n;
        const char *what;
    } parts[2] = {{v->indirection, info.indirection_size, "indirection"},
                  {v->atlas, info.atlas_size, "atlas"}};
    for (int i = 0; i < 2; i++) {
        size_t done_bytes = 0;
        while (done_bytes < parts[i].n) {
            const size_t chunk =
                parts[i].n - done_bytes > (1u << 30) ? (1u << 30) : parts[i].n - done_bytes;
            const int n = gzread(gz, parts[i].p + done_bytes, (unsigned)chunk);
            if (n <= 0) {
                int zerr = 0;
                const char *const msg = gzerror(gz, &zerr);
                r = vdbgi_fail(ctx, VDBGI_ERR_FORMAT, "%s: %s ends early (%zu of %zu bytes)%s%s",
                               path, parts[i].what, done_bytes, parts[i].n, n < 0 ? ": " : "",
                               n < 0 ? msg : "");
                goto done;
            }
            done_bytes += (size_t)n;
        }
    }
    /* Nothing may follow the atlas, and the gzip trailer (CRC, length) must check out. */
    uint8_t extra;
    const int tail = gzread(gz, &extra, 1);
    if (tail != 0) {
        int zerr = 0;
        const char *const msg = gzerror(gz, &zerr);
        r = vdbgi_fail(ctx, VDBGI_ERR_FORMAT, "%s: %s", path,
                       tail > 0 ? "data after the atlas" : msg);
        goto done;
    }
    r = check_indirection(ctx, path, v);
done:
    gzclose(gz);
    if (r != VDBGI_OK) {
        vdbgi_volume_destroy(v);
        return r;
    }
    struct stat st;
    v->info.file_size = stat(path, &st) == 0 ? (size_t)st.st_size : 0;
    *out = v;
    return VDBGI_OK;
}
