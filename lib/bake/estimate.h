/* estimate.h: seed 000's estimator for one sample point and its directions (no threads, no files). */
#ifndef VDBGI_ESTIMATE_H
#define VDBGI_ESTIMATE_H

#include "scene.h"
#include "tracer.h"

/*
 * An adaptive bake's pilot: a spherical Fibonacci set of this many rays at
 * every point; the rest of its rays, one set of a ladder of sizes (whole
 * pilots up to VDBGI_ADAPTIVE_FINE rays in all, doublings past it).
 */
#define VDBGI_ADAPTIVE_BATCH 32
#define VDBGI_ADAPTIVE_FINE 1024

#define VDBGI_EMISSION_NONE UINT32_MAX

#define VDBGI_MAX_BOUNCES 16

/*
 * Bounces traced when the count is left to convergence; the ones past them
 * ride on the last traced one (vdbgi_bake_params.tail). By the third
 * bounce the light's shape over a scene has settled, and each later bounce
 * is close to a fixed share of the one before (docs/lights.md measures it).
 */
#define VDBGI_TRACED_BOUNCES 3

/*
 * A light as the estimator uses it: the sun or a scene light, resolved.
 * rgb is in the estimator's units (E / pi): per unit cos(theta) for a
 * directional light, at 1 m for a point or spot light.
 */
typedef struct vdbgi_lamp {
    vdbgi_light_type type;
    float pos[3], to_light[3]; /* to_light: unit, towards a directional light */
    float axis[3];             /* a spot's unit direction of travel */
    float rgb[3];
    float inv_range4;            /* 1 / range^4, or 0 for none */
    float cos_outer, cone_scale; /* a spot: smooth step (cos - cos_outer) * cone_scale */
    bool is_sun;                 /* the command line's (or default) sun */
    bool is_sky;                 /* the sky map's sun (vdbgi_sky_sun) */
} vdbgi_lamp;

/* Resolved estimator settings (defaults applied, sun normalised). */
typedef struct vdbgi_bake_params {
    int rays;
    bool adaptive; /* rays a point by its pilot's spread (vdbgi_adaptive_scale) */
    float noise;
    int max_rays;
    double adaptive_scale; /* a point's rays: this times the square root of its pilot's spread */
    double adaptive_floor; /* added to that spread first (surface points: a pilot that saw no
                              spread may have missed a small bright patch) */
    float ray_dist, ambient, falloff, invalid_threshold;
    float sun_dir[3], sun_color[3], sky[3];
    bool sun_on;
    /* Which materials' emission lights the hits: 0 every one, m + 1 material m alone (a
       lightmap layer), VDBGI_EMISSION_NONE none. */
    uint32_t emission;
    vdbgi_sampling sampling;
    uint64_t seed;
    int threads;
    vdbgi_trace_method method;
    vdbgi_basis basis;
    vdbgi_model model;
    vdbgi_lights lights;
    /*
     * Bounces traced, or 0 until vdbgi_bounces_converge has chosen them from
     * converge (the share of the light below which the next bounce is not
     * worth it; 0 for a count given). tail: the light of the bounces past
     * the last traced one, as a multiple of its own, per channel (0: none).
     */
    int bounces;
    float converge, tail[3];
    const vdbgi_sky *sky_map;
    /* What lights the hits with a shadow ray each: the sun (when on), the sky map's sun, then
       the scene's lights. */
    vdbgi_lamp lamps[VDBGI_MAX_LIGHTS + 2];
    int lamp_count;
    int scene_lamps; /* of them, from the scene */
} vdbgi_bake_params;

/* desc (NULL: the defaults) for scene, whose lights it resolves. */
vdbgi_result vdbgi_bake_params_resolve(vdbgi_context *ctx, const vdbgi_bake_desc *desc,
                                       const vdbgi_scene *scene, vdbgi_bake_params *out);

/* What vdbgi_bounces_converge found. */
typedef struct vdbgi_bounce_plan {
    int bounces;       /* until the next would add less than converge of the light */
    int traced;        /* of them, traced: at most VDBGI_TRACED_BOUNCES */
    double last_share; /* what the last of the bounces added, a share of the light */
    double tail_share; /* the share of the light the untraced bounces carry */
} vdbgi_bounce_plan;

/*
 * When bp's bounces are left to convergence, a pilot of surface receivers
 * spread over scene by area, traced VDBGI_MAX_BOUNCES deep, chooses them:
 * bp->bounces becomes the bounces to trace and bp->tail what the rest add.
 * Otherwise plan says bp's count. The same for every tile and thread count.
 */
vdbgi_result vdbgi_bounces_converge(vdbgi_context *ctx, const vdbgi_scene *scene,
                                    const vdbgi_tracer *tracer, vdbgi_bake_params *bp,
                                    vdbgi_bounce_plan *plan);

/*
 * What lamp l brings to a surface point pos of facing unit normal n,
 * unshadowed: f times l->rgb is its E / pi (the cosine, the inverse square,
 * the range window and the cone in f); and the shadow ray that decides it:
 * its unit direction and length. False when the lamp cannot light it.
 */
bool vdbgi_lamp_light(const vdbgi_lamp *l, const float pos[3], const float n[3], float *f,
                      float dir[3], float *dist);

/* The radiance a miss along unit direction d brings back. */
void vdbgi_miss_radiance(const vdbgi_bake_params *bp, const float d[3], float rgb[3]);

/* The L2 polynomial's terms 1..8 at unit direction d (term 0 is 1), and their weights. */
void vdbgi_sh2_terms(const float d[3], float p[8]);
extern const float vdbgi_sh2_weights[8];

/* Spherical Fibonacci set of n unit directions (3 floats each). */
void vdbgi_fibonacci_directions(int n, float *dirs);
/*
 * n directions over the +z hemisphere, cosine-weighted (a Fibonacci spiral on
 * the unit disk, lifted: Malley's method), so the mean of what they bring
 * back is E / pi.
 */
void vdbgi_hemisphere_directions(int n, float *dirs);
/* The +z set base (count directions) turned onto unit normal n, and about it when random. */
void vdbgi_hemisphere_turn(const float *base, int count, const float n[3], uint64_t stream,
                           bool random, float *out);
/* A sample point's random stream: from its lattice point (or index) and the seed only. */
/* base's n directions turned by the rotation of a point's stream into out (seed 000's
   set made random a probe at a time). */
void vdbgi_directions_rotate(uint64_t stream, const float *base, int n, float *out);
uint64_t vdbgi_point_stream(int32_t i, int32_t j, int32_t k, uint64_t seed);
/*
 * The pilot points: given a lattice (origin xyz, spacing, margin > 0), its
 * own valid probes, picked by hash over the whole band; for surface (a
 * lightmap's texels), points spread over the scene's surfaces by area (as
 * vdbgi_bounces_converge's), estimated over their hemispheres; for probes
 * given as points or with no margin, those lifted off the surfaces. Those mostly seeing back
 * faces are left out. The same for every tile and thread count.
 *
 * vdbgi_adaptive_scale, when bp is adaptive: sets bp->adaptive_scale (and
 * adaptive_floor), so that a point's rays, that times the square root of
 * its pilot's spread (plus the floor), give an error, as vdbgi_bake_noise
 * measures it, of bp->noise or up to 15 % under. vdbgi_bake_noise: the
 * error bp gives 256 points (spread over the whole scene as the 1024 of the
 * pilot are), each estimated twice (a fixed set under random rotations),
 * over their mean light.
 */
vdbgi_result vdbgi_adaptive_scale(vdbgi_context *ctx, const vdbgi_scene *scene,
                                  const vdbgi_tracer *tracer, const double lattice[5], bool surface,
                                  vdbgi_bake_params *bp);
vdbgi_result vdbgi_bake_noise(vdbgi_context *ctx, const vdbgi_scene *scene,
                              const vdbgi_tracer *tracer, const double lattice[5], bool surface,
                              const vdbgi_bake_params *bp, double *noise);
/*
 * The ladder's smallest set of at least n rays (max_rays less the pilot at
 * most): its size, and in *offset where it starts among
 * vdbgi_estimator_directions' sets.
 */
int vdbgi_adaptive_set(int n, int max_rays, int *offset);
/*
 * The directions bp's points share, allocated through ctx: the Fibonacci set
 * of bp->rays, or an adaptive bake's ladder of sets, over the sphere for
 * probes or the +z hemisphere for surface points (hemisphere); *count: the
 * most a point traces at once (what vdbgi_estimator_init takes).
 */
vdbgi_result vdbgi_estimator_directions(vdbgi_context *ctx, const vdbgi_bake_params *bp,
                                        bool hemisphere, float **dirs, int *count);

/*
 * One thread's estimator: what it reads (set by the caller) and its scratch
 * for one point's rays (vdbgi_estimator_init, for a set of set_count
 * directions). One estimator per thread; the scene and tracer are shared.
 */
typedef struct vdbgi_estimator {
    const vdbgi_scene *scene;
    const vdbgi_tracer *tracer;
    const vdbgi_bake_params *bp;
    const float *base_dirs; /* from vdbgi_estimator_directions */
    bool shade;             /* false: rays and counts only (the bare benchmark loop) */
    bool cube;              /* also the ambient-cube sides */
    bool sh2;               /* also the L2 terms c1..c8 */
    /*
     * Light a hit surface receives besides the fill and the sun, as the
     * estimator's E / pi (a lightmap's previous pass), or NULL for none;
     * back says the ray met the triangle's back face.
     */
    void (*hit_light)(const void *user, const vdbgi_hit *hit, bool back, float rgb[3]);
    const void *hit_user;
    float *dir, *sorg;
    float *bdir; /* the bounces' directions, per path: dir holds the primaries' till the sums */
    float *sdir, *sdist;  /* per shadow ray: direction and length */
    float *sun_weight;    /* per shadow ray: what it adds when open, RGB */
    float *radiance;      /* per ray, RGB: what the ray brings back */
    uint32_t *shadow_ray; /* per shadow ray: the primary ray it continues */
    vdbgi_hit *hits;
    unsigned char *occluded;
    /*
     * The paths' current hits, per ray: the point on the surface (where the
     * lamps are read), the ray origin one offset off its lit side, that
     * offset, the facing normal and the path's throughput.
     */
    float *phit, *porg, *poff, *pnorm, *pweight;
    uint32_t *pray;
    uint64_t stream; /* the point's, for the bounces' random numbers */
    /*
     * When not NULL, VDBGI_MAX_BOUNCES + 1 RGB sums the rays' light is
     * added to by increment: 0 what the rays see (sky, emitters), k >= 1
     * what the k-th bounce adds (lamps at the k-th hit, what the ray leaving
     * it sees).
     */
    double *depth_light;
    void *scratch;
} vdbgi_estimator;

vdbgi_result vdbgi_estimator_init(vdbgi_context *ctx, vdbgi_estimator *e, int set_count);
void vdbgi_estimator_free(vdbgi_context *ctx, vdbgi_estimator *e);

/* What one point's rays gave. */
typedef struct vdbgi_estimate {
    float rgb[3];   /* irradiance (seed 000's mean radiance over the sphere) */
    float backface; /* fraction of hits on back faces */
    float stderr_;  /* standard error of the mean over channels */
    float cube[18]; /* six sides x RGB, vdbgi_side order, when e->cube */
    float sh[24];   /* L2 terms c1..c8 x RGB (VDBGI_SH2_TERMS), when e->sh2 */
    uint32_t rays;
    uint64_t hits, shadow;
} vdbgi_estimate;

/*
 * Estimate at world position pos over the whole sphere, with stream (from
 * vdbgi_point_stream) choosing the point's rotation for random and adaptive
 * sampling. Thread-safe for distinct estimators.
 */
void vdbgi_estimate_point(vdbgi_estimator *e, const float pos[3], uint64_t stream,
                          vdbgi_estimate *out);

/*
 * Estimate at a surface point pos with unit normal n over its hemisphere:
 * e->base_dirs must be vdbgi_estimator_directions' hemisphere sets, turned
 * about n by an angle from stream for random and adaptive sampling (an
 * adaptive point's second set by another). out->rgb is the cosine-weighted
 * mean radiance (irradiance over pi); backface as for probes.
 */
void vdbgi_estimate_hemisphere(vdbgi_estimator *e, const float pos[3], const float n[3],
                               uint64_t stream, vdbgi_estimate *out);

#endif /* VDBGI_ESTIMATE_H */
