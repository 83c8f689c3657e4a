/*
 * gltf_shim.h: C interface to the only code that includes tinygltf
 * (Debian's libtinygltf-dev): a scene with its lightmap UVs and maps, as a
 * binary glTF in memory. No tinygltf type crosses it.
 */
#ifndef VDBGI_GLTF_SHIM_H
#define VDBGI_GLTF_SHIM_H

#include "context.h"

#ifdef __cplusplus
extern "C" {
#endif

/* One primitive: count unindexed vertices from first, one material. */
typedef struct vdbgi_gltf_primitive {
    uint32_t first, count, material;
} vdbgi_gltf_primitive;

typedef struct vdbgi_gltf_material {
    float base[3];         /* linear baseColorFactor */
    int base_texture;      /* image index (sRGB PNG, TEXCOORD_0), or -1 */
    float emissive[3];     /* linear; past 1 through KHR_materials_emissive_strength */
    int emissive_texture;  /* image index (sRGB PNG, TEXCOORD_0), or -1 */
    int map;               /* image index of its lightmap or AO map (TEXCOORD_1), or -1 */
    const int *layer_maps; /* image index of each layer's map (layer_count), or NULL */
    bool double_sided;
} vdbgi_gltf_material;

typedef struct vdbgi_gltf_image {
    const uint8_t *png;
    size_t size;
} vdbgi_gltf_image;

typedef struct vdbgi_gltf_desc {
    size_t vertex_count;
    const float *positions, *normals, *uv0, *uv1; /* 3, 3, 2, 2 floats a vertex; uv0 may be NULL */
    const float *colors;                          /* 3 floats a vertex (COLOR_0), or NULL */
    const vdbgi_gltf_primitive *primitives;
    size_t primitive_count;
    const vdbgi_gltf_material *materials;
    size_t material_count;
    const vdbgi_gltf_image *images;
    size_t image_count;
    bool ao;         /* maps are occlusion: occlusionTexture, texCoord 1 */
    float map_scale; /* lightmaps: E = map (linear) x map_scale, in extras */
    size_t layer_count;
    const char *const *layer_names;
    const float *layer_scales;
    const char *generator;
} vdbgi_gltf_desc;

/* The .glb's bytes into *out (through ctx's allocator: vdbgi_free) and *size. */
vdbgi_result vdbgi_gltf_encode(vdbgi_context *ctx, const vdbgi_gltf_desc *d, uint8_t **out,
                               size_t *size);

/* A glTF material as the file has it: what the import needs to find it again. */
typedef struct vdbgi_gltf_material_info {
    char name[64];     /* empty when unnamed or longer */
    float emissive[3]; /* emissiveFactor */
    float base[3];     /* baseColorFactor's RGB */
    float strength;    /* KHR_materials_emissive_strength, 1 without it */
} vdbgi_gltf_material_info;

/*
 * The materials of the glTF file at path (by its name: .gltf or .glb) into
 * *out (through ctx's allocator), *count of them; a file of another kind
 * gives none. VDBGI_ERR_FORMAT when a glTF file does not parse. Its images
 * are not decoded.
 */
vdbgi_result vdbgi_gltf_materials(vdbgi_context *ctx, const char *path,
                                  vdbgi_gltf_material_info **out, size_t *count);

/*
 * The range of each KHR_lights_punctual light of the glTF at path, in the
 * file's order (0 for none), which Debian's assimp 5.2 drops, into *out
 * (through ctx's allocator); a file of another kind gives none.
 * VDBGI_ERR_FORMAT when a glTF file does not parse.
 */
vdbgi_result vdbgi_gltf_light_ranges(vdbgi_context *ctx, const char *path, float **out,
                                     size_t *count);

#ifdef __cplusplus
}
#endif

#endif /* VDBGI_GLTF_SHIM_H */
