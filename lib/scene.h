/* scene.h: the triangle soup a scene loads into: positions, albedo, materials, textures. */
#ifndef VDBGI_SCENE_H
#define VDBGI_SCENE_H

#include "context.h"

#ifdef __cplusplus
extern "C" {
#endif

typedef struct vdbgi_texture {
    int width, height;
    float *rgba; /* linear, row 0 at the top (v = 1) */
} vdbgi_texture;

typedef struct vdbgi_material {
    float base[3];  /* linear */
    int texture;    /* index into textures, -1 for none */
    bool double_sided;
} vdbgi_material;

/* What a hit needs of its triangle, in one 32-byte record. */
typedef struct vdbgi_tri {
    float normal[3]; /* unit, counter-clockwise front */
    float albedo[3]; /* the albedo everywhere on it, unless VDBGI_TRI_VARIES */
    uint32_t material;
    uint32_t flags;
} vdbgi_tri;

#define VDBGI_TRI_DOUBLE_SIDED 1u
#define VDBGI_TRI_VARIES 2u /* textured, or vertex colours differ: interpolate per hit */

struct vdbgi_tracer;

struct vdbgi_scene {
    vdbgi_context *ctx;
    size_t vertex_count, triangle_count, skipped_count;
    float *positions;   /* 3 per vertex */
    float *uvs;         /* 2 per vertex (0 where the mesh has none) */
    float *colors;      /* 3 per vertex (1 where the mesh has none) */
    uint32_t *indices;  /* 3 per triangle */
    vdbgi_tri *tris;
    vdbgi_material *materials;
    size_t material_count;
    vdbgi_texture *textures;
    size_t texture_count;
    float bounds_min[3], bounds_max[3];
    float ray_offset;
    char *name;
    struct vdbgi_tracer *tracer;
};

/* Albedo of triangle prim at barycentrics (u, v) (Embree's: p = (1-u-v) v0 + u v1 + v v2). */
void vdbgi_scene_albedo(const vdbgi_scene *scene, uint32_t prim, float u, float v, float rgb[3]);
/* Area of triangle t, square metres. */
double vdbgi_scene_triangle_area(const vdbgi_scene *scene, size_t t);

#ifdef __cplusplus
}
#endif

#endif /* VDBGI_SCENE_H */
