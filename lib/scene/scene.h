/* scene.h: the triangle soup a scene loads into: positions, albedo, materials, textures. */
#ifndef VDBGI_SCENE_H
#define VDBGI_SCENE_H

#include "context.h"
#include "image_shim.h"

#ifdef __cplusplus
extern "C" {
#endif

/* The brightest emission a material may have (radiance, linear): a cap that keeps sums finite. */
#define VDBGI_MAX_EMISSION 1e6f

/* A material's texture, decoded and turned into linear values when loaded. */
typedef vdbgi_image vdbgi_texture;

typedef struct vdbgi_material {
    float base[3];        /* linear */
    int texture;          /* index into textures, -1 for none */
    float emissive[3];    /* radiance it emits, linear, strength included (0: none) */
    int emissive_texture; /* index into textures (sRGB decoded), -1 for none */
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
#define VDBGI_TRI_VARIES 2u   /* textured, or vertex colours differ: interpolate per hit */
#define VDBGI_TRI_EMISSIVE 4u /* its material emits light */

struct vdbgi_scene {
    vdbgi_context *ctx;
    size_t vertex_count, triangle_count, skipped_count;
    float *positions;  /* 3 per vertex */
    float *uvs;        /* 2 per vertex (0 where the mesh has none) */
    float *uvs1;       /* 2 per vertex: the second UV set (lightmaps), 0 where none */
    size_t uv1_count;  /* vertices that have one */
    float *colors;     /* 3 per vertex (1 where the mesh has none) */
    uint32_t *indices; /* 3 per triangle */
    vdbgi_tri *tris;
    vdbgi_material *materials;
    size_t material_count;
    vdbgi_texture *textures;
    size_t texture_count;
    float bounds_min[3], bounds_max[3];
    float ray_offset; /* the largest offset a hit gets: at the coordinate farthest out */
    char *name;
    vdbgi_light lights[VDBGI_MAX_LIGHTS];
    size_t light_count;
    double keep_boxes[VDBGI_MAX_KEEP_BOXES][6]; /* nodes named vdbgi_keep*: spaces, not geometry */
    size_t keep_box_count;
    size_t keep_node_count; /* such nodes, boxed or not (no vertex, or past the most boxes) */
};

/*
 * Building a scene (scene.c), for vdbgi_scene_create and the assimp import:
 * allocate the arrays (every vertex white, no texture), add triangles over
 * the vertices filled in, then finish (bounds, ray offset, triangle records).
 */
vdbgi_result vdbgi_scene_alloc(vdbgi_context *ctx, const char *name, size_t vertex_count,
                               size_t triangle_capacity, size_t material_count,
                               size_t texture_count, vdbgi_scene **out);
typedef enum { VDBGI_TRI_KEPT, VDBGI_TRI_NONFINITE, VDBGI_TRI_DEGENERATE } vdbgi_tri_status;
vdbgi_tri_status vdbgi_scene_add_triangle(vdbgi_scene *s, uint32_t a, uint32_t b, uint32_t c,
                                          uint32_t material);
vdbgi_result vdbgi_scene_finish(vdbgi_scene *s, size_t nonfinite_count);

/* Albedo of triangle prim at barycentrics (u, v) (Embree's: p = (1-u-v) v0 + u v1 + v v2). */
void vdbgi_scene_albedo(const vdbgi_scene *scene, uint32_t prim, float u, float v, float rgb[3]);
/*
 * Radiance triangle prim emits at (u, v) towards its front (both sides when
 * double-sided): the material's emissive colour times its emissive texture.
 */
void vdbgi_scene_emission(const vdbgi_scene *scene, uint32_t prim, float u, float v, float rgb[3]);
/*
 * Ray offsets follow the coordinates they guard, not the scene's extent: a
 * point rebuilt on a triangle from its barycentrics is good to a few ulps of
 * the triangle's largest vertex coordinate, so a ray leaves it 1e-5 of that
 * (about 80 ulps) off the face, 1 cm counting as the smallest magnitude. A
 * speck 1 km away changes nothing near the origin.
 */
#define VDBGI_RAY_OFFSET_REL 1e-5f
#define VDBGI_RAY_OFFSET_MIN_MAGNITUDE 0.01f

/* The offset a ray leaving triangle prim takes, metres. */
float vdbgi_scene_offset(const vdbgi_scene *scene, uint32_t prim);
/* Triangle prim's point at (u, v) into p; returns vdbgi_scene_offset there. */
float vdbgi_scene_hit_point(const vdbgi_scene *scene, uint32_t prim, float u, float v, float p[3]);
/* Area of triangle t, square metres. */
double vdbgi_scene_triangle_area(const vdbgi_scene *scene, size_t t);
/* (v1 - v0) x (v2 - v0) of triangle t: its front normal, twice its area long. */
void vdbgi_scene_triangle_cross(const vdbgi_scene *scene, size_t t, double c[3]);

#ifdef __cplusplus
}
#endif

#endif /* VDBGI_SCENE_H */
