/* gifile.h: the .gi container (docs/format.md): a header and a body, as bytes. */
#ifndef VDBGI_GIFILE_H
#define VDBGI_GIFILE_H

#include "context.h"

/* Versions 1 to 5 have 112 header bytes; versions 6 to 8 add the basis, 116. */
#define VDBGI_GI_HEADER_SIZE 112
#define VDBGI_GI_HEADER_MAX 116
/*
 * The versions (docs/format.md has the table): 1 the seed layout's textures,
 * 2 either layout's textures, 5 the compact layout packed with its bricks'
 * places, 6 version 5 with L2 terms (a basis field, then 24 bytes a stored
 * point), 7 version 6 with the terms predicted better, 8 version 7 with the
 * second band's terms one ratio for all three channels (what vdbgi writes).
 * 3 and 4 were older compact forms, refused.
 */
#define VDBGI_GI_VERSION 8
/* The L2 terms' bytes a stored point as the library holds them (8 terms x RGB, signed ratios
   to L0), and as versions 6 and 7 store them and their textures hold them. */
#define VDBGI_SH_BYTES 24
/* Version 8: terms 1-3 x RGB, then terms 4-8 one byte each (luminance), in the file and the
   GPU's textures (three RGBA8 and one RG8 a texel). */
#define VDBGI_SH_BYTES_LUMA2 14

/* The term bytes a stored point and a texel hold in a file of this version (6 to 8). */
static inline int vdbgi_term_bytes(uint32_t version)
{
    return version >= 8 ? VDBGI_SH_BYTES_LUMA2 : VDBGI_SH_BYTES;
}

/* Which of a point's 24 bytes (3 term + channel) term byte j of this version is:
   version 8's bytes 9..13 are terms 4..8's red byte, the one their three channels share. */
static inline int vdbgi_term_byte(uint32_t version, int j)
{
    return version >= 8 && j >= 9 ? 9 + 3 * (j - 9) : j;
}
/*
 * The layout field holds vdbgi_layout's numbers (1 seed, 2 compact). Two
 * older values are still read in version 2: 0 for the seed layout, and 3 for
 * the compact one (written while 2 meant the compact layout before the lift,
 * which is read alike: only what positions below a column's lowest brick
 * read differs).
 */
#define VDBGI_GI_LAYOUT_SEED_OLD 0
#define VDBGI_GI_LAYOUT_COMPACT_OLD 3
/* Version 5: each brick's first atlas texel, three u16 a brick. */
#define VDBGI_PLACEMENT_BYTES 6
/* Version 5: the most atlas texels a brick may bring (a brick is 125; a file's atlas is bounded). */
#define VDBGI_ATLAS_TEXELS_PER_BRICK 500
/* The compact atlas's largest side: a brick's first texel is 4 r + (a's two bits) <= 1023. */
#define VDBGI_ATLAS_MAX 1024
/* Cells of the indirection any lattice may have, however sparse: 16 M, about 500 MB to
   convert. Past it the converter takes at most 64 cells a valid probe, and a reader at
   most 4096 for every cell under a brick. */
#define VDBGI_SPARSE_CELLS (1 << 24)
/*
 * Sanity bounds (docs/format.md): the RGBM range a file may say (the writer
 * says 8); 65504, half floats' largest, is the most light a texel can carry
 * to a GPU anyway.
 */
#define VDBGI_GI_RANGE_MIN (1.0f / 65536.0f)
#define VDBGI_GI_RANGE_MAX 65504.0f

/*
 * The header of a volume's file: version 1 for the seed layout, 2 for the
 * compact layout's textures (packed 0), or packed, the version its payload
 * follows (5, or 6 to 8 with info->basis VDBGI_BASIS_SH2; info->stored_points
 * counts the stored values).
 * Returns its size in bytes.
 */
size_t vdbgi_gifile_header(const vdbgi_volume_info *info, uint32_t packed,
                           uint8_t h[VDBGI_GI_HEADER_MAX]);

/* Header (header_size bytes) and body gzip'd (libdeflate, level 6) into *out, allocated
   through ctx. */
vdbgi_result vdbgi_gifile_gzip(vdbgi_context *ctx, const uint8_t *h, size_t header_size,
                               const uint8_t *body, size_t body_size, uint8_t **out,
                               size_t *out_size);

/*
 * A .gi or .gi.gz in memory, its header checked (docs/format.md, "What
 * vdbgi_volume_read refuses", all but the body's own rules): the header into
 * *info (file_size the bytes given) and *version, and the body, the bytes
 * after the header, uncompressed, exactly as long as the header says, into
 * *body (allocated through ctx). Messages start with name.
 */
vdbgi_result vdbgi_gifile_parse(vdbgi_context *ctx, const char *name, const uint8_t *bytes,
                                size_t size, vdbgi_volume_info *info, uint32_t *version,
                                uint8_t **body, size_t *body_size);
/*
 * The same, without the copy: a plain .gi's body is moved to the front of
 * file, which *body then is (file from ctx's allocator: the caller frees
 * *body, and not file too). A gzip'd file is inflated into a block of its
 * own, as vdbgi_gifile_parse does, and a refused one is left as it was.
 */
vdbgi_result vdbgi_gifile_parse_in_place(vdbgi_context *ctx, const char *name, uint8_t *file,
                                         size_t file_size, vdbgi_volume_info *info,
                                         uint32_t *version, uint8_t **body, size_t *body_size);

/* A regular file's bytes, allocated through ctx. */
vdbgi_result vdbgi_gifile_slurp(vdbgi_context *ctx, const char *path, uint8_t **data, size_t *size);

#endif /* VDBGI_GIFILE_H */
