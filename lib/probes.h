/* probes.h: the probe object: lattice, per-probe values, metadata; resolved bake settings. */
#ifndef VDBGI_PROBES_H
#define VDBGI_PROBES_H

#include "context.h"

#ifdef __cplusplus
extern "C" {
#endif

typedef enum vdbgi_meta_type {
    VDBGI_META_STRING,
    VDBGI_META_INT,    /* int64 */
    VDBGI_META_DOUBLE, /* double, may be inf */
    VDBGI_META_VEC3    /* 3 floats */
} vdbgi_meta_type;

typedef struct vdbgi_meta {
    char name[48];
    vdbgi_meta_type type;
    char text[208]; /* VDBGI_META_STRING */
    int64_t i;
    double d;
    float v[3];
    char line[256]; /* "name=value", kept current by the setters */
} vdbgi_meta;

#define VDBGI_META_CAPACITY 40

struct vdbgi_probes {
    vdbgi_context *ctx;
    double spacing, margin, origin[3];
    size_t count;
    int32_t *ijk;     /* 3 per probe */
    float *rgb;       /* 3 per probe, NULL until baked or read */
    float *backface;  /* per probe */
    float *cube;      /* 18 per probe (6 sides x RGB, vdbgi_side order), or NULL */
    float *stderr_;   /* per probe: standard error of the value, or NULL (not baked) */
    uint32_t *rays;   /* per probe: rays traced, or NULL (every probe had desc->rays) */
    float invalid_threshold;
    size_t invalid_count;
    vdbgi_meta meta[VDBGI_META_CAPACITY];
    size_t meta_count;
};

vdbgi_result vdbgi_probes_alloc(vdbgi_context *ctx, size_t count, bool with_values,
                                vdbgi_probes **out);
void vdbgi_meta_set_string(vdbgi_probes *probes, const char *name, const char *value);
void vdbgi_meta_set_int(vdbgi_probes *probes, const char *name, int64_t value);
void vdbgi_meta_set_double(vdbgi_probes *probes, const char *name, double value);
void vdbgi_meta_set_vec3(vdbgi_probes *probes, const char *name, const float value[3]);
const vdbgi_meta *vdbgi_meta_find(const vdbgi_probes *probes, const char *name);

/* Resolved estimator settings (defaults applied, sun normalised). */
typedef struct vdbgi_bake_params {
    int rays;
    bool adaptive;   /* rays in batches until the noise target or max_rays */
    float noise;
    int max_rays;
    float ray_dist, ambient, falloff, invalid_threshold;
    float sun_dir[3], sun_color[3], sky[3];
    bool sun_on;
    vdbgi_sampling sampling;
    uint64_t seed;
    int threads;
    vdbgi_trace_method method;
    vdbgi_basis basis;
} vdbgi_bake_params;

vdbgi_result vdbgi_bake_params_resolve(vdbgi_context *ctx, const vdbgi_bake_desc *desc,
                                       vdbgi_bake_params *out);

#ifdef __cplusplus
}
#endif

#endif /* VDBGI_PROBES_H */
