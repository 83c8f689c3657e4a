/* internal.h: declarations shared inside lib/ (never installed). */
#ifndef VDBGI_INTERNAL_H
#define VDBGI_INTERNAL_H

#include "vdbgi.h"

#include <stdarg.h>
#include <stdbool.h>

#ifdef __cplusplus
extern "C" {
#endif

#if defined(__GNUC__)
#define VDBGI_PRINTF(f, a) __attribute__((format(printf, f, a)))
#else
#define VDBGI_PRINTF(f, a)
#endif

struct vdbgi_context {
    void *(*alloc)(void *user, size_t size);
    void (*free)(void *user, void *ptr);
    void (*log)(void *user, vdbgi_log_level level, const char *message);
    void *user;
    char error[512];
};

/* Record a failure message on ctx and return code (for one-line returns). */
vdbgi_result vdbgi_fail(vdbgi_context *ctx, vdbgi_result code, const char *fmt, ...)
    VDBGI_PRINTF(3, 4);
void vdbgi_log(vdbgi_context *ctx, vdbgi_log_level level, const char *fmt, ...)
    VDBGI_PRINTF(3, 4);

/* Return error code with a message if cond holds (zstd's RETURN_ERROR_IF). */
#define VDBGI_FAIL_IF(ctx, cond, code, ...)                                                        \
    do {                                                                                           \
        if (cond)                                                                                  \
            return vdbgi_fail((ctx), (code), __VA_ARGS__);                                         \
    } while (0)

/* Forward a failure of call; the message is already on the context. */
#define VDBGI_TRY(call)                                                                            \
    do {                                                                                           \
        const vdbgi_result vdbgi_try_r_ = (call);                                                  \
        if (vdbgi_try_r_ != VDBGI_OK)                                                              \
            return vdbgi_try_r_;                                                                   \
    } while (0)

/* Allocation through the context's hooks. NULL on failure, message recorded. */
void *vdbgi_alloc(vdbgi_context *ctx, size_t size);
/* count * size bytes, zeroed; refuses (NULL) when the product would wrap. */
void *vdbgi_calloc(vdbgi_context *ctx, size_t count, size_t size);
void vdbgi_free(vdbgi_context *ctx, void *ptr);
char *vdbgi_strdup(vdbgi_context *ctx, const char *s);

/* Wall clock, seconds, monotonic. */
double vdbgi_now(void);
/* Online cores, at least 1. */
int vdbgi_core_count(void);
/*
 * Run fn(args + t * stride) for t in 0..n-1 (n <= 64): t > 0 on threads of
 * their own, t == 0 on this one, which also runs any whose thread did not
 * start. Returns when all are done.
 */
void vdbgi_run_threads(int n, void *(*fn)(void *), void *args, size_t stride);

/*
 * Write an output the safe way: write(ctx, tmp, user) fills a temporary
 * file "path.tmp-XXXXXX" made beside path, which is renamed over path if it
 * succeeds and removed if it fails. A failed write never leaves a partial
 * file nor touches an existing one. VDBGI_ERR_IO if the directory refuses.
 */
typedef vdbgi_result (*vdbgi_writer)(vdbgi_context *ctx, const char *tmp, const void *user);
vdbgi_result vdbgi_write_atomic(vdbgi_context *ctx, const char *path, vdbgi_writer write,
                                const void *user);

/* ---- scene.c ----------------------------------------------------------- */

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

/* ---- tracer.c: the only file that includes Embree ---------------------- */

typedef struct vdbgi_tracer vdbgi_tracer;

vdbgi_result vdbgi_tracer_create(vdbgi_context *ctx, const float *positions, size_t vertex_count,
                                 const uint32_t *indices, size_t triangle_count,
                                 vdbgi_tracer **out);
void vdbgi_tracer_destroy(vdbgi_tracer *tracer);

/*
 * A batch of rays sharing their extent. org and dir hold 3 floats per ray,
 * or one xyz for every ray when their stride is 0 (a probe's rays share an
 * origin; its shadow rays share the sun's direction).
 */
typedef struct vdbgi_ray_batch {
    const float *org;
    const float *dir;
    size_t org_stride, dir_stride; /* floats between rays: 3, or 0 for shared */
    float tnear, tfar;
    size_t count;
} vdbgi_ray_batch;

/* First hits: t (INFINITY for a miss), primitive and barycentrics. */
typedef struct vdbgi_hit {
    float t, u, v;
    uint32_t prim;
} vdbgi_hit;

/* Thread-safe after creation. scratch must hold vdbgi_tracer_scratch_size(count) bytes. */
size_t vdbgi_tracer_scratch_size(size_t count);
void vdbgi_tracer_intersect(const vdbgi_tracer *tracer, vdbgi_trace_method method,
                            const vdbgi_ray_batch *rays, vdbgi_hit *hits, void *scratch);
/* occluded[i] = 1 if ray i hits anything in (tnear, tfar). */
void vdbgi_tracer_occluded(const vdbgi_tracer *tracer, vdbgi_trace_method method,
                           const vdbgi_ray_batch *rays, unsigned char *occluded, void *scratch);
/* The first Embree error since creation, or VDBGI_OK (message recorded on ctx). */
vdbgi_result vdbgi_tracer_check(vdbgi_tracer *tracer);

/* ---- probes (placement.c, bake.c, vdb_shim.cpp) ------------------------ */

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

/* ---- field.c: the filled fine lattice, in OpenVDB's 8^3 leaves --------- */

#define VDBGI_LEAF_LOG2 3
#define VDBGI_LEAF_DIM 8
#define VDBGI_LEAF_VOXELS 512

/* One leaf: voxel (x, y, z) of the leaf is at offset x*64 + y*8 + z (VDB's order). */
typedef struct vdbgi_leaf {
    int32_t origin[3];                  /* multiple of 8, fine-lattice index */
    uint64_t mask[8];                   /* bit n of word n/64: voxel n holds a value */
    float rgb[VDBGI_LEAF_VOXELS][3];
} vdbgi_leaf;

typedef struct vdbgi_field {
    vdbgi_context *ctx;
    vdbgi_leaf *leaves;
    size_t leaf_count;
    uint32_t *table; /* open addressing: leaf index + 1, 0 = empty */
    size_t table_size;
} vdbgi_field;

/* Allocate room for leaf_count leaves (zeroed) and an empty lookup table. */
vdbgi_result vdbgi_field_alloc(vdbgi_context *ctx, size_t leaf_count, vdbgi_field *out);
/* Index the leaves by origin; call once they are filled in. */
void vdbgi_field_index(vdbgi_field *f);
void vdbgi_field_free(vdbgi_field *f);
/* The leaf holding fine point ijk, or NULL. */
const vdbgi_leaf *vdbgi_field_leaf(const vdbgi_field *f, const int32_t ijk[3]);
/* Value at fine point ijk; false where the field holds none. */
bool vdbgi_field_get(const vdbgi_field *f, const int32_t ijk[3], float rgb[3]);
/* The same, remembering the last leaf in *cache (start it at NULL; one per thread). */
bool vdbgi_field_get_cached(const vdbgi_field *f, const int32_t ijk[3], float rgb[3],
                            const vdbgi_leaf **cache);

static inline int32_t vdbgi_floor_div(int32_t a, int32_t b) /* b > 0 */
{
    return a >= 0 ? a / b : -((-a + b - 1) / b);
}

/* How vdbgi_vdb_fill spreads valid values (see docs/converter.md). */
typedef struct vdbgi_fill_params {
    float invalid_threshold; /* back-face fraction above which a probe is not a source */
    int cell_size;           /* fine probes per level-0 brick cell edge (4) */
    int margin_cells;        /* cells added around the cells holding probes (1) */
    int rim;                 /* fine points added around those cells for filtering (1) */
    float weights[3];        /* weight of a face, edge and corner neighbour */
    int max_iterations;      /* rings of spreading before giving up */
    bool darkest;            /* invalid probes take their darkest valued neighbour, not the
                                mean: a probe inside a wall then leaks no light to the dark side */
} vdbgi_fill_params;

/* The converter's fill for a (checked) vdbgi_fill choice: what bricks.c and bevy.c both use. */
vdbgi_fill_params vdbgi_fill_params_default(float invalid_threshold, vdbgi_fill fill);

/*
 * The field at fine position pos (lattice units, may be fractional):
 * trilinear over the 8 lattice points around it, renormalised over those
 * that hold a value. False when none does. cache as for vdbgi_field_get_cached.
 */
bool vdbgi_field_trilinear(const vdbgi_field *f, const double pos[3], float rgb[3],
                           const vdbgi_leaf **cache);

#ifdef __cplusplus
}
#endif

#endif /* VDBGI_INTERNAL_H */
