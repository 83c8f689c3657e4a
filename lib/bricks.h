/* bricks.h: the volume object shared by bricks.c, gifile.c and slices.c. */
#ifndef VDBGI_BRICKS_H
#define VDBGI_BRICKS_H

#include "internal.h"
#include "sampler.h"

struct vdbgi_volume {
    vdbgi_context *ctx;
    vdbgi_volume_info info;
    uint8_t *raw;         /* the uncompressed .gi: header, indirection, atlas */
    uint8_t *indirection; /* info.indirection_size bytes inside raw */
    uint8_t *atlas;       /* info.atlas_size bytes inside raw */
    uint8_t *file;        /* the gzip'd .gi bytes */
    /* Only from vdbgi_volume_build: */
    vdbgi_field filled;
    double lattice_origin[3]; /* world position of fine index (0,0,0) */
    int32_t origin_cell[3];   /* absolute level-0 cell of indirection texel (0,0,0) */
    float mean_rgb[3];        /* mean of the valid probes */
};

/* The textures and uniforms of a volume, as the sampler takes them. */
vdbgi_volume_view vdbgi_volume_view_of(const vdbgi_volume *v);

/* gifile.c: allocate v->raw for info's texture sizes and point indirection and atlas into it. */
vdbgi_result vdbgi_gifile_alloc(vdbgi_volume *v);
/* gifile.c: write the header into v->raw and gzip the whole into v->file. */
vdbgi_result vdbgi_gifile_encode(vdbgi_volume *v);

#define VDBGI_GI_HEADER_SIZE 112
#define VDBGI_GI_VERSION 1

#endif /* VDBGI_BRICKS_H */
