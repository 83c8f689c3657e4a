/* volume.h: the volume object: its textures, its file bytes, and what its build kept. */
#ifndef VDBGI_VOLUME_H
#define VDBGI_VOLUME_H

#include "sampler.h"
#include "textures.h"

struct vdbgi_volume {
    vdbgi_context *ctx;
    vdbgi_volume_info info;
    vdbgi_textures tex; /* what the GPU gets */
    uint8_t *payload;   /* compact layout: the file's body (level bytes, placement, values) */
    size_t payload_size;
    uint32_t version; /* the file version the payload follows: 5, or 6 to 8 with L2 terms */
    uint8_t *file;    /* the gzip'd .gi a write writes, made once the volume is whole */
    size_t file_size;
    /* Only from vdbgi_volume_build: */
    struct vdbgi_field *filled; /* convert/field.h; NULL unless built whole */
    double lattice_origin[3];   /* world position of fine index (0,0,0) */
    int32_t origin_cell[3];     /* absolute level-0 cell of indirection texel (0,0,0) */
    float mean_rgb[3];          /* mean of the valid probes */
};

/*
 * The colour of the level view for a brick level 0..3, or -1 for no brick:
 * linear RGB, 3 floats (the web viewer's DebugView.LEVEL and levels.png from
 * vdbgi_volume_write_slices).
 */
const float *vdbgi_level_colour(int level);

/*
 * Makes the gzip'd file a write writes, from the header and the body, once the
 * volume is whole (built, or read from a plain .gi), so that writers are pure
 * copies of a volume that no longer changes. Sets info.file_size.
 */
vdbgi_result vdbgi_volume_seal(vdbgi_volume *v);

/* The textures and uniforms of a volume, as the sampler takes them. */
vdbgi_volume_view vdbgi_volume_view_of(const vdbgi_volume *v);

/*
 * The runtime's indirection (docs/format.md): two texels a column (its run,
 * and where the run starts in the list), then the runs' texels, in a 2D
 * texture at most VDBGI_COLUMNS_ROW texels wide. Writes it to out unless NULL
 * or shorter than capacity (then returns 0); returns its bytes, 0 (dims 0)
 * above VDBGI_COLUMNS_ROW^2 texels.
 */
size_t vdbgi_volume_columns(const vdbgi_volume *v, uint8_t *out, size_t capacity, uint32_t dims[2]);

/*
 * vdbgi_volume_build_regions with halo points read either side of a region
 * (VDBGI_REGION_HALO); fewer than the fill reaches give other bytes, which
 * is how a test shows the halo matters.
 */
vdbgi_result vdbgi_volume_build_regions_halo(vdbgi_context *ctx, vdbgi_probe_file *file,
                                             int32_t region_points, int halo,
                                             const vdbgi_convert_desc *desc, vdbgi_volume **out);

#endif /* VDBGI_VOLUME_H */
