/*
 * gifile.c: the .gi container (docs/format.md): a header and a body to bytes
 * and back, gzip on the way out, every size checked on the way in. What the
 * body holds (textures, or the packed layout's payload) is the volume's and
 * the layouts' business, not this file's.
 */
#define _POSIX_C_SOURCE 200809L
#include "gifile.h"
#include "lattice.h"
#include "sampler.h" /* the brick sizes: the atlas's limits */
#include "util.h"

#include <errno.h>
#include <libdeflate.h>
#include <math.h>
#include <stdio.h>
#include <string.h>
#include <sys/stat.h>
#include <zlib.h>

static const char gi_magic[8] = {'v', 'd', 'b', 'g', 'i', '.', 'g', 'i'};

/* Versions 6 to 8 hold L2 terms: a basis field ends their 116-byte header. */
static bool holds_terms(uint32_t version)
{
    return version >= 6 && version <= 8;
}

size_t vdbgi_gifile_header(const vdbgi_volume_info *in, uint32_t packed,
                           uint8_t h[VDBGI_GI_HEADER_MAX])
{
    memset(h, 0, VDBGI_GI_HEADER_MAX);
    memcpy(h, gi_magic, 8);
    /*
     * Seed-layout files stay version 1, byte for byte (their layout field is
     * reserved, 0); the compact layout is packed (5, or 6 to 8 with L2 terms,
     * as its payload was written), or version 2 as textures.
     */
    const bool compact = in->layout == VDBGI_LAYOUT_COMPACT;
    const bool sh = holds_terms(packed) && in->basis == VDBGI_BASIS_SH2;
    const size_t size = sh ? VDBGI_GI_HEADER_MAX : VDBGI_GI_HEADER_SIZE;
    vdbgi_put_u32(h + 8, compact ? (packed ? packed : 2) : 1);
    vdbgi_put_u32(h + 12, (uint32_t)size);
    vdbgi_put_u32(h + 16, (uint32_t)in->encoding);
    vdbgi_put_f32(h + 20, in->rgbm_range);
    for (int k = 0; k < 3; k++) {
        vdbgi_put_u32(h + 24 + 4 * k, in->ind_dims[k]);
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
    vdbgi_put_u32(h + 104, compact ? VDBGI_LAYOUT_COMPACT : 0);
    if (packed)
        vdbgi_put_u32(h + 108, (uint32_t)in->stored_points);
    if (sh)
        vdbgi_put_u32(h + 112, VDBGI_BASIS_SH2);
    return size;
}

vdbgi_result vdbgi_gifile_gzip(vdbgi_context *ctx, const uint8_t *h, size_t header_size,
                               const uint8_t *body, size_t body_size, uint8_t **out,
                               size_t *out_size)
{
    *out = NULL;
    *out_size = 0;
    uint8_t *const in = vdbgi_alloc(ctx, header_size + body_size);
    /* libdeflate: one call over the whole buffer, several times faster than zlib at level 6. */
    struct libdeflate_compressor *const z = libdeflate_alloc_compressor(6);
    const size_t capacity = z ? libdeflate_gzip_compress_bound(z, header_size + body_size) : 0;
    uint8_t *const gz = z ? vdbgi_alloc(ctx, capacity) : NULL;
    size_t written = 0;
    if (in && gz) {
        memcpy(in, h, header_size);
        memcpy(in + header_size, body, body_size);
        written = libdeflate_gzip_compress(z, in, header_size + body_size, gz, capacity);
    }
    libdeflate_free_compressor(z);
    vdbgi_free(ctx, in);
    if (!written) {
        vdbgi_free(ctx, gz);
        return in && gz ? vdbgi_fail(ctx, VDBGI_ERR_BACKEND, "libdeflate: compression failed")
                        : VDBGI_ERR_OUT_OF_MEMORY;
    }
    *out = gz;
    *out_size = written;
    return VDBGI_OK;
}

/* ---- reading ---------------------------------------------------------------- */

/* The magic, the version and the layout field (docs/format.md's table of versions): the layout. */
static vdbgi_result parse_version(vdbgi_context *ctx, const char *path, const uint8_t *h,
                                  vdbgi_layout *layout)
{
    VDBGI_FAIL_IF(ctx, memcmp(h, gi_magic, 8) != 0, VDBGI_ERR_FORMAT,
                  "%s: not a .gi file (bad magic)", path);
    const uint32_t version = vdbgi_get_u32(h + 8);
    VDBGI_FAIL_IF(ctx, version < 1 || version > VDBGI_GI_VERSION, VDBGI_ERR_FORMAT,
                  "%s: .gi version %u, this reader knows 1..%d", path, version, VDBGI_GI_VERSION);
    /*
     * Version 1 is the seed layout (its field is reserved, 0); version 2 says
     * which; version 5 is the packed compact layout. Versions 3 and 4 were
     * older compact forms: in 5^3 slots, and packed with placement left to
     * the reader. Versions 6 to 8 are version 5 with L2 terms.
     */
    VDBGI_FAIL_IF(ctx, version == 3 || version == 4, VDBGI_ERR_FORMAT,
                  "%s: an older vdbgi's compact layout (.gi version %u): convert the .vdb again",
                  path, version);
    const uint32_t field = vdbgi_get_u32(h + 104);
    const bool compact = field == VDBGI_LAYOUT_COMPACT || field == VDBGI_GI_LAYOUT_COMPACT_OLD;
    const bool seed = field == VDBGI_LAYOUT_SEED || field == VDBGI_GI_LAYOUT_SEED_OLD;
    VDBGI_FAIL_IF(ctx,
                  version == 1   ? field != 0
                  : version >= 5 ? field != VDBGI_LAYOUT_COMPACT
                                 : !compact && !seed,
                  VDBGI_ERR_FORMAT, "%s: unknown brick layout %u for version %u", path, field,
                  version);
    *layout = compact ? VDBGI_LAYOUT_COMPACT : VDBGI_LAYOUT_SEED;
    return VDBGI_OK;
}

/*
 * The box against the lattice it spans: a spacing the lattice may have, an
 * extent of 4 x ind_dims spacings on every axis (to 1e-3, plus 2^-20 of the
 * largest corner for the corners' rounding), and corners the lattice's
 * origin and index range can reach. Legal numbers that no writer makes and
 * that would move or lose the light are refused here.
 */
static vdbgi_result check_box(vdbgi_context *ctx, const char *path, const vdbgi_volume_info *info)
{
    const double s = info->spacing;
    VDBGI_FAIL_IF(ctx, !(s >= VDBGI_MIN_SPACING && s <= VDBGI_MAX_SPACING), VDBGI_ERR_FORMAT,
                  "%s: spacing %g m is outside %g..%g", path, s, VDBGI_MIN_SPACING,
                  VDBGI_MAX_SPACING);
    for (int k = 0; k < 3; k++) {
        const double lo = info->box_min[k], hi = info->box_max[k];
        const double corner = fmax(fabs(lo), fabs(hi)), extent = hi - lo;
        const double want = 4.0 * info->ind_dims[k] * s;
        VDBGI_FAIL_IF(ctx, corner > VDBGI_MAX_ORIGIN + VDBGI_MAX_INDEX * s, VDBGI_ERR_FORMAT,
                      "%s: box_min/box_max reach %g m, past what a lattice of spacing %g m can",
                      path, corner, s);
        VDBGI_FAIL_IF(ctx, fabs(extent - want) > 1e-3 * want + 0x1p-20 * corner, VDBGI_ERR_FORMAT,
                      "%s: the box is %g m on %c, where ind_dims (%u) x 4 x spacing (%g m) is %g m",
                      path, extent, "xyz"[k], info -> ind_dims[k], s, want);
    }
    return VDBGI_OK;
}

static vdbgi_result parse_header(vdbgi_context *ctx, const char *path, const uint8_t *h,
                                 vdbgi_volume_info *info, size_t *header_size,
                                 uint64_t *stored_size)
{
    vdbgi_layout layout = VDBGI_LAYOUT_DEFAULT;
    VDBGI_TRY(parse_version(ctx, path, h, &layout));
    const uint32_t version = vdbgi_get_u32(h + 8);
    const bool compact = layout == VDBGI_LAYOUT_COMPACT;
    *header_size = vdbgi_get_u32(h + 12);
    const bool terms = holds_terms(version);
    const size_t least_header = terms ? VDBGI_GI_HEADER_MAX : VDBGI_GI_HEADER_SIZE;
    VDBGI_FAIL_IF(ctx, *header_size < least_header || *header_size > 65536, VDBGI_ERR_FORMAT,
                  "%s: bad header size %zu", path, *header_size);
    memset(info, 0, sizeof(*info));
    /* Versions 6 to 8 say their basis: L2 is the only one they hold (5 and older: the scalar). */
    VDBGI_FAIL_IF(ctx, terms && vdbgi_get_u32(h + 112) != VDBGI_BASIS_SH2, VDBGI_ERR_FORMAT,
                  "%s: unknown basis %u", path, vdbgi_get_u32(h + 112));
    info->basis = terms ? VDBGI_BASIS_SH2 : VDBGI_BASIS_SCALAR;
    const uint32_t enc = vdbgi_get_u32(h + 16);
    VDBGI_FAIL_IF(ctx, enc > 1, VDBGI_ERR_FORMAT, "%s: unknown encoding %u", path, enc);
    info->encoding = (vdbgi_encoding)enc;
    info->layout = layout;
    /* The seed layout's atlas is whole 6^3 slots, 256 an axis; the compact one's texels are free. */
    const uint32_t b = compact ? 1 : VDBGI_BRICK_PADDED,
                   lo = compact ? VDBGI_BRICK_COMPACT : VDBGI_BRICK_PADDED,
                   hi = compact ? VDBGI_ATLAS_MAX : 256 * VDBGI_BRICK_PADDED;
    info->rgbm_range = vdbgi_get_f32(h + 20);
    VDBGI_FAIL_IF(
        ctx, !(info->rgbm_range >= VDBGI_GI_RANGE_MIN && info->rgbm_range <= VDBGI_GI_RANGE_MAX),
        VDBGI_ERR_FORMAT, "%s: rgbm_range %g is outside %g..%g", path, (double)info->rgbm_range,
        (double)VDBGI_GI_RANGE_MIN, (double)VDBGI_GI_RANGE_MAX);
    size_t ind = 4, atlas = 4;
    for (int k = 0; k < 3; k++) {
        info->ind_dims[k] = vdbgi_get_u32(h + 24 + 4 * k);
        info->atlas_dims[k] = vdbgi_get_u32(h + 36 + 4 * k);
        info->box_min[k] = vdbgi_get_f32(h + 48 + 4 * k);
        info->box_max[k] = vdbgi_get_f32(h + 60 + 4 * k);
        VDBGI_FAIL_IF(ctx, info->ind_dims[k] < 1 || info->ind_dims[k] > VDBGI_MAX_TEXTURE_DIM,
                      VDBGI_ERR_FORMAT, "%s: bad indirection size", path);
        VDBGI_FAIL_IF(
            ctx, info->atlas_dims[k] < lo || info->atlas_dims[k] > hi || info->atlas_dims[k] % b,
            VDBGI_ERR_FORMAT, "%s: bad atlas size", path);
        VDBGI_FAIL_IF(ctx,
                      !isfinite(info->box_min[k]) || !isfinite(info->box_max[k]) ||
                          !(info->box_max[k] > info->box_min[k]),
                      VDBGI_ERR_FORMAT, "%s: box_min/box_max on %c: not finite, or not ordered",
                      path, "xyz"[k]);
        ind *= info->ind_dims[k];
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
    VDBGI_FAIL_IF(ctx, version < 5 && vdbgi_get_u32(h + 108) != 0, VDBGI_ERR_FORMAT,
                  "%s: reserved header field is not 0", path);
    /* Versions 5 to 7 store the level bytes, the placement and the points, not the textures. */
    const bool packed = version >= 5;
    info->stored_points = packed ? vdbgi_get_u32(h + 108) : 0;
    /*
     * Every brick stores inner points no other brick reads and no stitching
     * touches: 27 at levels 0 and 1, at least 8 at level 2 and 1 at level 3
     * (a coarse block may reach past the stored grid). So the bricks, and the
     * atlas built for them, are bounded by what the file holds.
     */
    const uint64_t least = 27 * ((uint64_t)info->bricks[0] + info->bricks[1]) +
                           8 * (uint64_t)info->bricks[2] + info->bricks[3];
    VDBGI_FAIL_IF(ctx, packed && least > info->stored_points, VDBGI_ERR_FORMAT,
                  "%s: the header's bricks need at least %llu stored points, it has %zu", path,
                  (unsigned long long)least, info->stored_points);
    /*
     * The converter's indirection covers its valid probes' cells and a margin:
     * past 16 M cells, at most 64 a valid probe, so at most 4096 for every
     * cell a brick covers. A header declaring 10^9 empty cells (1 GB of level
     * bytes from a 1 MB file, then a 4 GB texture) is refused before either.
     */
    const uint64_t cells = ind / 4, covered = info->bricks[0] + 8ull * info->bricks[1] +
                                              64ull * info->bricks[2] + 512ull * info->bricks[3];
    VDBGI_FAIL_IF(ctx, packed && cells > VDBGI_SPARSE_CELLS && cells > 4096 * covered,
                  VDBGI_ERR_FORMAT,
                  "%s: %llu cells of the indirection for %llu under bricks (more than 4096 a "
                  "brick's cell, and more than %d): too sparse a volume",
                  path, (unsigned long long)cells, (unsigned long long)covered, VDBGI_SPARSE_CELLS);
    /* The placement table's bound, from the header's counts: before the budget weighs the atlas. */
    VDBGI_FAIL_IF(ctx,
                  packed && (uint64_t)atlas / 4 >
                                VDBGI_ATLAS_TEXELS_PER_BRICK * ((uint64_t)info->brick_count + 1),
                  VDBGI_ERR_FORMAT,
                  "%s: a %ux%ux%u atlas for %u bricks (at most %d texels a brick)", path,
                  info->atlas_dims[0], info->atlas_dims[1], info->atlas_dims[2], info->brick_count,
                  VDBGI_ATLAS_TEXELS_PER_BRICK);
    VDBGI_TRY(check_box(ctx, path, info));
    *stored_size = packed ? ind / 4 + VDBGI_PLACEMENT_BYTES * (uint64_t)info->brick_count +
                                (4 + (terms ? (uint64_t)vdbgi_term_bytes(version) : 0)) *
                                    (uint64_t)info->stored_points
                          : ind + atlas;
    return VDBGI_OK;
}

/* Deflate expands at most about 1032:1; with gzip's framing no honest file goes past this. */
#define VDBGI_GZIP_MAX_RATIO 1100

/* The whole file in memory: its real size bounds everything read from it. */
vdbgi_result vdbgi_gifile_slurp(vdbgi_context *ctx, const char *path, uint8_t **data, size_t *size)
{
    *data = NULL;
    *size = 0;
    FILE *const f = fopen(path, "rb");
    VDBGI_FAIL_IF(ctx, !f, VDBGI_ERR_IO, "%s: cannot open: %s", path, strerror(errno));
    struct stat st;
    if (fstat(fileno(f), &st) != 0 || st.st_size < 0) {
        fclose(f);
        return vdbgi_fail(ctx, VDBGI_ERR_IO, "%s: cannot read: %s", path, strerror(errno));
    }
    const size_t n = (size_t)st.st_size;
    uint8_t *const b = vdbgi_alloc(ctx, n ? n : 1);
    const bool ok = b && fread(b, 1, n, f) == n;
    fclose(f);
    if (!ok) {
        vdbgi_free(ctx, b);
        return b ? vdbgi_fail(ctx, VDBGI_ERR_IO, "%s: cannot read", path) : VDBGI_ERR_OUT_OF_MEMORY;
    }
    *data = b;
    *size = n;
    return VDBGI_OK;
}

/* The first bytes of a gzip stream, up to out_size, inflated no further: how many it gave. */
static size_t gunzip_prefix(const uint8_t *in, size_t in_size, uint8_t *out, size_t out_size)
{
    z_stream zs;
    memset(&zs, 0, sizeof(zs));
    if (inflateInit2(&zs, 16 + MAX_WBITS) != Z_OK)
        return 0;
    zs.next_in = (Bytef *)(uintptr_t)in;
    zs.avail_in = (uInt)(in_size > UINT32_MAX ? UINT32_MAX : in_size);
    zs.next_out = out;
    zs.avail_out = (uInt)out_size;
    int z = Z_OK;
    while (zs.avail_out > 0 && z == Z_OK)
        z = inflate(&zs, Z_SYNC_FLUSH);
    inflateEnd(&zs);
    return out_size - zs.avail_out;
}

/*
 * Every size comes from the header and is checked before anything is
 * allocated for it: against its dimensions, then against what the bytes can
 * hold (their count, times deflate's largest ratio). The gzip stream must
 * decompress to exactly the header's size with its CRC and length right,
 * and nothing may follow it.
 */
static vdbgi_result parse_file(vdbgi_context *ctx, const char *path, const uint8_t *file,
                               size_t file_size, uint8_t *in_place, vdbgi_volume_info *info,
                               uint32_t *version, uint8_t **body, size_t *body_size)
{
    uint8_t *raw = NULL;
    *body = NULL;
    *body_size = 0;
    const bool gz = file_size >= 18 && file[0] == 0x1f && file[1] == 0x8b;
    uint8_t h[VDBGI_GI_HEADER_MAX] = {0};
    size_t header_size = 0;
    vdbgi_result r = VDBGI_OK;
    const size_t got = gz ? gunzip_prefix(file, file_size, h, sizeof(h))
                          : (file_size < sizeof(h) ? file_size : sizeof(h));
    if (!gz)
        memcpy(h, file, got);
    /* The first 112 bytes say the version; a basis (versions 6 to 8) follows them. */
    const size_t want =
        got >= 12 && holds_terms(vdbgi_get_u32(h + 8)) ? VDBGI_GI_HEADER_MAX : VDBGI_GI_HEADER_SIZE;
    if (got < want) {
        r = vdbgi_fail(ctx, VDBGI_ERR_FORMAT, "%s: %s", path,
                       gz ? "damaged gzip data, or too short to be a .gi file"
                          : "too short to be a .gi file");
        goto done;
    }
    uint64_t stored = 0;
    if ((r = parse_header(ctx, path, h, info, &header_size, &stored)) != VDBGI_OK)
        goto done;
    const uint64_t total = (uint64_t)header_size + stored;
    if (gz ? total > (uint64_t)file_size * VDBGI_GZIP_MAX_RATIO : total != file_size) {
        r = vdbgi_fail(ctx, VDBGI_ERR_FORMAT,
                       "%s: the header's %llu bytes of textures cannot come from a %zu-byte file",
                       path, (unsigned long long)total, file_size);
        goto done;
    }
    if (gz && (uint32_t)total != vdbgi_get_u32(file + file_size - 4)) {
        r = vdbgi_fail(ctx, VDBGI_ERR_FORMAT,
                       "%s: cut short or damaged (the gzip trailer says %u bytes, the header %llu)",
                       path, vdbgi_get_u32(file + file_size - 4), (unsigned long long)total);
        goto done;
    }
    /* The budget: what the body and the textures built from it would take. */
    /* Terms: 24 bytes a texel in every version, as the readers rebuild them (version 8's
       14 are packed from them). */
    const uint64_t textures = (uint64_t)info->indirection_size +
                              (uint64_t)info->atlas_size * (info->basis == VDBGI_BASIS_SH2 ? 7 : 1);
    const uint64_t biggest = textures > total ? textures : total;
    if (biggest > ctx->volume_budget) {
        r = vdbgi_fail(ctx, VDBGI_ERR_OUT_OF_MEMORY,
                       "%s: the volume unpacks to %.1f MiB (%llu bytes of textures), past the "
                       "%.1f MiB volume budget",
                       path, (double)biggest / (1 << 20), (unsigned long long)textures,
                       (double)ctx->volume_budget / (1 << 20));
        goto done;
    }
    if (in_place && !gz)
        raw = in_place;
    else if (!(raw = vdbgi_alloc(ctx, (size_t)total))) {
        r = VDBGI_ERR_OUT_OF_MEMORY;
        goto done;
    }
    if (gz) {
        struct libdeflate_decompressor *const d = libdeflate_alloc_decompressor();
        size_t in_used = 0, out_got = 0;
        const enum libdeflate_result dr =
            d ? libdeflate_gzip_decompress_ex(d, file, file_size, raw, (size_t)total, &in_used,
                                              &out_got)
              : LIBDEFLATE_BAD_DATA;
        libdeflate_free_decompressor(d);
        if (dr != LIBDEFLATE_SUCCESS || out_got != total || in_used != file_size) {
            r = vdbgi_fail(ctx, VDBGI_ERR_FORMAT, "%s: %s", path,
                           dr == LIBDEFLATE_SUCCESS && in_used != file_size
                               ? "data after the gzip stream"
                           : dr == LIBDEFLATE_SUCCESS || dr == LIBDEFLATE_SHORT_OUTPUT
                               ? "textures end early"
                               : "damaged gzip data (its CRC, length or stream is wrong)");
            goto done;
        }
    } else if (raw != file) {
        memcpy(raw, file, (size_t)total);
    }
    /* The body to the front: it is what the caller keeps (as textures, or a payload). */
    memmove(raw, raw + header_size, (size_t)stored);
    info->file_size = file_size;
    *version = vdbgi_get_u32(h + 8);
    *body = raw;
    *body_size = (size_t)stored;
    raw = NULL;
done:
    if (raw != in_place)
        vdbgi_free(ctx, raw);
    return r;
}

vdbgi_result vdbgi_gifile_parse(vdbgi_context *ctx, const char *path, const uint8_t *file,
                                size_t file_size, vdbgi_volume_info *info, uint32_t *version,
                                uint8_t **body, size_t *body_size)
{
    return parse_file(ctx, path, file, file_size, NULL, info, version, body, body_size);
}

vdbgi_result vdbgi_gifile_parse_in_place(vdbgi_context *ctx, const char *path, uint8_t *file,
                                         size_t file_size, vdbgi_volume_info *info,
                                         uint32_t *version, uint8_t **body, size_t *body_size)
{
    return parse_file(ctx, path, file, file_size, file, info, version, body, body_size);
}
