/*
 * vdbgi.h: the public C API of vdbgi, a baker of light-probe global illumination.
 *
 * Call order
 * ----------
 *   vdbgi_context *ctx;  vdbgi_context_create(NULL, &ctx);     allocator, log
 *   vdbgi_scene *scene;  vdbgi_scene_load(ctx, "world.glb", &scene);
 *   vdbgi_probes *pr;    vdbgi_probes_place(ctx, scene, &place_desc, &pr);
 *                        vdbgi_probes_bake(pr, scene, &bake_desc, &stats);
 *                        vdbgi_probes_write(pr, "world.vdb");
 *   vdbgi_probes_destroy(pr); vdbgi_scene_destroy(scene); vdbgi_context_destroy(ctx);
 *
 * Converting a bake into GPU bricks (seed 000's runtime format):
 *   vdbgi_probes_read(ctx, "world.vdb", &pr);
 *   vdbgi_volume *vol;   vdbgi_volume_build(ctx, pr, &convert_desc, &vol);
 *                        vdbgi_volume_write(vol, "world.gi.gz");
 *                        vdbgi_volume_sample(vol, xyz, rgb);   what the shader sees
 *
 * Every fallible call returns a vdbgi_result; on failure vdbgi_context_error()
 * holds a one-line message naming the value or file at fault. The library
 * never exits, aborts or prints: text reaches the user only through the log
 * callback given to the context.
 *
 * Threads: one thread at a time per context and per object made from it.
 * Distinct contexts are independent. The bake spreads its own work over
 * threads internally and calls the progress callback on the caller's thread.
 *
 * Units: world lengths are metres; colours are linear RGB; directions need
 * not be normalised unless stated. Names say units: _count is elements,
 * _size is bytes.
 *
 * Conventions
 * -----------
 * Names: vdbgi_<object>_<verb>, the object the first argument.
 * Descs: an all-zero desc means the defaults, and a field holding zero (every
 * component zero, for a vector) takes its default. Where zero is itself a
 * value one may want (no ambient fill, no margin, an origin at the world's
 * origin), the field has a companion <field>_is_set: set, the field is taken
 * as given, zero included. A mode is an enum or a flag whose zero is the
 * default, never a special value of a number.
 * Objects: read-only calls (writers included) take const objects; their
 * side figures come back through optional *_out pointers.
 * Bulk data: vdbgi_*_copy_* fills a caller's buffer; called with a NULL
 * buffer it returns the size needed, and with one too small it returns 0
 * and writes nothing.
 * Calls for benchmarks and debugging are declared in vdbgi_bench.h, which
 * gi-bench and the tests include; it is not installed.
 */
#ifndef VDBGI_H
#define VDBGI_H

#include <stddef.h>
#include <stdint.h>

#ifdef __cplusplus
extern "C" {
#endif

#if defined(VDBGI_BUILDING) && defined(__GNUC__)
#define VDBGI_API __attribute__((visibility("default")))
#else
#define VDBGI_API
#endif

#define VDBGI_VERSION_MAJOR 0
#define VDBGI_VERSION_MINOR 1
#define VDBGI_VERSION_PATCH 0

/* Results. Numbered by hand; a value is never reused or renumbered. */
typedef enum vdbgi_result {
    VDBGI_OK = 0,
    VDBGI_ERR_INVALID_ARG = 1,   /* a parameter is out of range: fix the call */
    VDBGI_ERR_OUT_OF_MEMORY = 2, /* an allocation failed, or the job would need too much */
    VDBGI_ERR_IO = 3,            /* a file could not be opened, read, written or renamed */
    VDBGI_ERR_FORMAT = 4,        /* a file was read but its contents are not usable */
    VDBGI_ERR_BACKEND = 5,       /* Embree, OpenVDB, OpenImageIO or assimp failed */
    VDBGI_ERR_CANCELLED = 6      /* the progress callback asked to stop */
} vdbgi_result;

typedef enum vdbgi_log_level {
    VDBGI_LOG_ERROR = 1,
    VDBGI_LOG_WARNING = 2,
    VDBGI_LOG_INFO = 3,
    VDBGI_LOG_DEBUG = 4
} vdbgi_log_level;

/* Fixed text for a result code, e.g. "invalid argument". Never NULL. */
VDBGI_API const char *vdbgi_result_string(vdbgi_result result);

/* The library version as "MAJOR.MINOR.PATCH". */
VDBGI_API const char *vdbgi_version_string(void);

/* ------------------------------------------------------------------------ */
/* Context: allocator, log, last error.                                      */

typedef struct vdbgi_context vdbgi_context;

/*
 * How a context allocates and reports. A NULL desc, or NULL fields, mean
 * malloc/free and no log.
 *   alloc, free: both or neither. alloc returns memory aligned for any type
 *                (like malloc) or NULL; free accepts NULL. Used for every
 *                allocation vdbgi itself makes; the libraries it calls
 *                allocate on their own.
 *   log:         receives warnings and information, one line per call,
 *                no trailing newline. May be called from the caller's thread
 *                only. Errors are not logged: they are returned.
 *   user:        passed back to the three callbacks.
 *   memory_limit: the most bytes vdbgi may hold at once (0: no limit). An
 *                allocation that would pass it fails with
 *                VDBGI_ERR_OUT_OF_MEMORY and a message naming the limit, so
 *                a job too big for its machine (or its scheduler's memory
 *                request) ends with one line instead of being killed.
 *                Counts vdbgi's own allocations and the grids OpenVDB holds
 *                while a .vdb is read or merged; not a scene importer's.
 *   volume_budget: the most bytes a .gi read with this context may unpack to,
 *                its body and its runtime textures each (0: VDBGI_VOLUME_BUDGET;
 *                SIZE_MAX: no bound). A volume past it is refused from its
 *                header, VDBGI_ERR_OUT_OF_MEMORY, before anything is allocated.
 */
typedef struct vdbgi_context_desc {
    void *(*alloc)(void *user, size_t size);
    void (*free)(void *user, void *ptr);
    void (*log)(void *user, vdbgi_log_level level, const char *message);
    void *user;
    size_t memory_limit;
    size_t volume_budget;
} vdbgi_context_desc;

/*
 * Create a context. desc may be NULL. On failure *out is NULL and the result
 * says why (there is no context to hold a message).
 */
VDBGI_API vdbgi_result vdbgi_context_create(const vdbgi_context_desc *desc, vdbgi_context **out);

/* Destroy a context; NULL is a no-op. Every object made from it must be gone. */
VDBGI_API void vdbgi_context_destroy(vdbgi_context *ctx);

/*
 * The message of the last failure on this context: lower case, one line, no
 * trailing period, e.g. "probe spacing must be > 0 (got -1)". Empty when
 * nothing has failed. Owned by the context; valid until its next call.
 */
VDBGI_API const char *vdbgi_context_error(const vdbgi_context *ctx);

/* The most bytes the context held at once so far (what memory_limit counts). */
VDBGI_API size_t vdbgi_context_memory_peak(const vdbgi_context *ctx);

/*
 * Check that path could be written as an output (its directory exists and
 * accepts a new file) without touching path itself: lets an app fail before
 * a long bake rather than after it. VDBGI_ERR_IO names the reason.
 */
VDBGI_API vdbgi_result vdbgi_output_check(vdbgi_context *ctx, const char *path);

/*
 * Write size bytes to path the way the library writes every output: into a
 * temporary file beside it, checked to the last write and fsync, then
 * renamed over path. A failure leaves no file and never touches an existing
 * one. For the apps' own outputs (statistics).
 */
VDBGI_API vdbgi_result vdbgi_context_write_file(vdbgi_context *ctx, const char *path,
                                                const void *data, size_t size);

/*
 * Hold outputs (hold non-zero): every file written on ctx from now on is
 * complete and synced under its temporary name, and replaces nothing until
 * vdbgi_context_commit_outputs renames them all; vdbgi_context_discard_outputs
 * (or destroying the context) removes them. A run that writes several files
 * then leaves all of them or none. Writing one path twice while held fails.
 */
VDBGI_API void vdbgi_context_hold_outputs(vdbgi_context *ctx, int hold);
VDBGI_API vdbgi_result vdbgi_context_commit_outputs(vdbgi_context *ctx);
VDBGI_API void vdbgi_context_discard_outputs(vdbgi_context *ctx);

/*
 * Remove the temporary file of every write in progress, in any context.
 * Async-signal-safe: for a SIGINT or SIGTERM handler, which should then let
 * the signal end the process. Outputs are written to "OUT.tmp-PID-XXXXXX"
 * and renamed when complete; one left by a killed process is removed by the
 * next write of OUT.
 */
VDBGI_API void vdbgi_remove_temporaries(void);

/* ------------------------------------------------------------------------ */
/* Scene: a triangle soup with a material per triangle, and its ray tracer.  */

typedef struct vdbgi_scene vdbgi_scene;

/*
 * Load any format assimp reads (.glb, .gltf, .obj + .mtl, .fbx, ...). Node
 * transforms are applied and polygons triangulated. Albedo at a point is the
 * material's base colour (glTF baseColorFactor, OBJ Kd, both taken as linear)
 * times its base-colour texture at the point's UV (sRGB-decoded; files beside
 * the scene or embedded in .glb) times the vertex colour where present.
 * Triangles with a non-finite vertex are skipped with a warning; degenerate
 * (zero-area) ones are skipped silently. A node whose name begins with
 * "vdbgi_keep" (and what is under it) is no geometry but a box: the world
 * bounds of its vertices, a space what moves uses (vdbgi_scene_keep_boxes:
 * the first VDBGI_MAX_KEEP_BOXES with a vertex; vdbgi_scene_info counts the
 * nodes too). Fails with VDBGI_ERR_IO for a missing
 * or unreadable file, VDBGI_ERR_FORMAT for a file assimp rejects or one with no
 * usable triangle. Builds the Embree BVH before returning.
 */
VDBGI_API vdbgi_result vdbgi_scene_load(vdbgi_context *ctx, const char *path, vdbgi_scene **out);

/*
 * One mesh of a scene built from memory (tests, generated worlds).
 *   positions:      xyz per vertex, vertex_count * 3 floats, world space.
 *   indices:        three per triangle, each < vertex_count.
 *   albedo:         linear RGB of the whole mesh, each in [0, 1].
 *   double_sided:   non-zero if both faces are front faces; otherwise the
 *                   front is the counter-clockwise side (right-handed normal
 *                   (v1 - v0) x (v2 - v0)), as in glTF.
 * Inputs are copied; they need only live for the call.
 */
typedef struct vdbgi_mesh_desc {
    const float *positions;
    size_t vertex_count;
    const uint32_t *indices;
    size_t triangle_count;
    float albedo[3];
    int double_sided;
    float emissive[3]; /* radiance its front emits, linear, 0..1e6 (0: none); lights the scene */
} vdbgi_mesh_desc;

/* Build a scene from meshes in memory; same checks and result codes as load. */
VDBGI_API vdbgi_result vdbgi_scene_create(vdbgi_context *ctx, const vdbgi_mesh_desc *meshes,
                                          size_t mesh_count, vdbgi_scene **out);

/* Destroy a scene; NULL is a no-op. */
VDBGI_API void vdbgi_scene_destroy(vdbgi_scene *scene);

typedef struct vdbgi_scene_info {
    size_t triangle_count;         /* triangles kept and traced */
    size_t skipped_triangle_count; /* dropped: non-finite or zero-area */
    size_t material_count;
    size_t texture_count;
    float bounds_min[3], bounds_max[3]; /* of the kept triangles, metres */
    float ray_offset;       /* largest ray offset (1e-5 of the farthest coordinate), m */
    const char *name;       /* file name without directories */
    size_t light_count;     /* punctual lights (vdbgi_scene_get_lights) */
    size_t keep_box_count;  /* boxes of nodes named vdbgi_keep* (vdbgi_scene_keep_boxes) */
    size_t keep_node_count; /* such nodes: more than the boxes when some have no vertex, or
                               past VDBGI_MAX_KEEP_BOXES */
} vdbgi_scene_info;

/* Describe a scene. Strings belong to the scene. */
VDBGI_API void vdbgi_scene_get_info(const vdbgi_scene *scene, vdbgi_scene_info *info);

/*
 * A punctual light, as glTF's KHR_lights_punctual has it (the loader reads
 * them, with their nodes' transforms, from every format assimp gives lights
 * for). Radiometric as the bake is: a point or spot light of colour I lights
 * a surface at distance d, at angle theta to its normal, with irradiance
 * E = I cos(theta) / d^2 (times the range window and the spot's cone); a
 * directional light with E = I cos(theta).
 *   position:   world metres (point, spot).
 *   direction:  the way the light travels (directional, spot), non-zero.
 *   color:      colour times intensity, linear, each in 0..1e6 (glTF:
 *               candela for point and spot, lux for directional).
 *   range:      glTF's window: E is multiplied by
 *               clamp(1 - (d/range)^4, 0, 1); 0 for none.
 *   inner_cone, outer_cone: a spot's angles from its axis, radians,
 *               0 <= inner <= outer <= pi/2; between them E falls off as
 *               glTF's reference does (a smooth step in cos, squared).
 */
typedef enum vdbgi_light_type {
    VDBGI_LIGHT_DIRECTIONAL = 1,
    VDBGI_LIGHT_POINT = 2,
    VDBGI_LIGHT_SPOT = 3
} vdbgi_light_type;

typedef struct vdbgi_light {
    vdbgi_light_type type;
    float position[3];
    float direction[3];
    float color[3];
    float range;
    float inner_cone, outer_cone;
    char name[64]; /* for messages; may be empty */
} vdbgi_light;

/* Most lights a scene may hold: each costs a shadow ray per hit. */
#define VDBGI_MAX_LIGHTS 64

/*
 * Add count lights to a scene (copied; directions normalised). A light that
 * is not finite, has a colour outside 0..1e6, a spot's outer angle below its
 * inner one, or would take the scene past VDBGI_MAX_LIGHTS is refused with
 * VDBGI_ERR_INVALID_ARG naming it, and none of them is added.
 */
VDBGI_API vdbgi_result vdbgi_scene_add_lights(vdbgi_scene *scene, const vdbgi_light *lights,
                                              size_t count);
/* The scene's lights (owned by the scene) into *lights; returns their count. */
VDBGI_API size_t vdbgi_scene_get_lights(const vdbgi_scene *scene, const vdbgi_light **lights);

/*
 * The boxes of the scene's vdbgi_keep nodes (min x, y, z, max x, y, z,
 * metres; owned by the scene) into *boxes, for vdbgi_place_desc.keep_boxes;
 * returns their count.
 */
VDBGI_API size_t vdbgi_scene_keep_boxes(const vdbgi_scene *scene, const double (**boxes)[6]);

/*
 * An environment: an equirectangular (2:1) image of the radiance arriving
 * from each direction, +y up, u = 0.5 looking down -z at rotation 0 (the
 * layout of a .hdr or .exr "latlong" map), read through the image module.
 */
typedef struct vdbgi_sky vdbgi_sky;

/*
 * Load path as a sky: its texels times intensity (> 0), turned by rotation
 * degrees about +y. Refused by name: a missing or unreadable file, one that
 * is not an image, not 2:1, larger than the image module decodes, or whose
 * texels (times intensity) are negative, not finite or above 1e6.
 */
VDBGI_API vdbgi_result vdbgi_sky_load(vdbgi_context *ctx, const char *path, float intensity,
                                      float rotation, vdbgi_sky **out);
VDBGI_API void vdbgi_sky_destroy(vdbgi_sky *sky);
/* A hash of the sky's texels and settings, for the bake's metadata. */
VDBGI_API uint64_t vdbgi_sky_hash(const vdbgi_sky *sky);
/* The radiance arriving from unit direction d (towards the sky), bilinear; without its sun. */
VDBGI_API void vdbgi_sky_radiance(const vdbgi_sky *sky, const float d[3], float rgb[3]);
/*
 * The map's sun, taken out of it at load: texels over 50 times the mean
 * radiance of the rest of the map, that hold at least 1 % of its light
 * within 5 degrees of their centre, keep 50 times that mean, and the rest
 * of their light becomes
 * a directional light (unit dir towards it, in the world; rgb the
 * irradiance it gives a surface facing it) that the bake traces a shadow
 * ray to, like a scene's sun. 0 (and nothing taken out) for a map without
 * one, else 1.
 */
VDBGI_API int vdbgi_sky_sun(const vdbgi_sky *sky, float dir[3], float rgb[3]);

/*
 * Receivers: point_count points on the scene's surfaces, each triangle chosen
 * with probability proportional to its area and the point uniform on it,
 * then moved `offset` metres along the triangle's front normal (where a
 * runtime lookup of a vertex or fragment would sample). Written as 3 floats
 * each into points; the same seed gives the same points.
 */
VDBGI_API vdbgi_result vdbgi_scene_sample_surface(const vdbgi_scene *scene, size_t point_count,
                                                  float offset, uint64_t seed, float *points);

/* ------------------------------------------------------------------------ */
/* Probes: the lattice near surfaces, its irradiance and validity.           */

typedef struct vdbgi_probes vdbgi_probes;

/*
 * Which probes exist. Probe ijk stands at origin + spacing * ijk. All-zero
 * means the defaults.
 *   spacing:     lattice step, metres, > 0. 0 == 0.5.
 *   margin:      a probe exists if its true distance to the nearest triangle
 *                is at most this, metres, >= 0. 0 == 4 * spacing (one
 *                level-0 brick); margin_is_set with 0 for no margin.
 *   origin:      world position of probe (0,0,0). (0,0,0) without
 *                origin_is_set == half a spacing on every axis, so floors at
 *                whole multiples of the spacing fall between probes rather
 *                than on them.
 *   max_probes:  refuse larger lattices. 0 == 50 000 000.
 *   tile_index, tile_count: place only tile tile_index (0-based) of
 *                tile_count (2..4096; 0 or 1: the whole lattice): slabs
 *                across x, cut between OpenVDB leaves (8 probes) where the
 *                surfaces' area crosses each tile_count-th of the whole, so
 *                the tiles hold about as many probes each; a tile places
 *                its slab alone, from the triangles that can reach it. Every
 *                probe's value depends only on its ijk, so the tiles' bakes
 *                merged (vdbgi_probes_merge) equal the whole bake.
 *   walkable_height: > 0, metres: keep only the probes the space above
 *                walkable surfaces reads (when statics take a lightmap and
 *                the volume serves what moves): those whose ray straight
 *                down meets, within this height, a triangle facing up within
 *                45 degrees of +y (either way up when double-sided), and
 *                those one spacing or less under such a triangle. 0: every
 *                probe near a surface. At most 1000.
 *   keep_boxes, keep_box_count: boxes (min x, y, z, max x, y, z, metres)
 *                whose probes are kept too (with walkable_height 0, only
 *                theirs); at most VDBGI_MAX_KEEP_BOXES.
 */
typedef struct vdbgi_place_desc {
    double spacing;
    double margin;
    int margin_is_set;
    double origin[3];
    int origin_is_set;
    uint64_t max_probes;
    int tile_index, tile_count;
    double walkable_height;
    const double (*keep_boxes)[6];
    size_t keep_box_count;
} vdbgi_place_desc;

/* Most boxes vdbgi_place_desc.keep_boxes names. */
#define VDBGI_MAX_KEEP_BOXES 64

/* Most tiles a lattice is cut into. */
#define VDBGI_MAX_TILES 4096

/*
 * Merge the .vdb files of a tiled bake (gi-bake --tile I/N, one file a tile,
 * any order) into the whole lattice's .vdb at path, with OpenVDB's tree
 * merge: the result holds every probe of the one-machine bake with the same
 * values. Each tile is read with every check of vdbgi_probes_read, then
 * refused by name (VDBGI_ERR_FORMAT, nothing written) when it is not a tile,
 * belongs to another bake (any setting, the scene or the lattice differs),
 * is of another tile count, is given twice, holds probes outside its range
 * or overlaps another; and the set when a tile is missing or their slabs
 * leave a gap. The whole's metadata is the tiles' without
 * the tile keys, with probes, invalid_probes and bake_seconds summed.
 */
VDBGI_API vdbgi_result vdbgi_probes_merge(vdbgi_context *ctx, const char *const *paths,
                                          size_t count, const char *path);

/* Bytes the library holds per probe while baking, for memory estimates. */
#define VDBGI_BYTES_PER_PROBE 64

/*
 * Find the probes within the margin of the scene's triangles, using
 * OpenVDB's mesh-to-volume unsigned distance. The probe order is the VDB
 * tree order (leaf by leaf), fixed for a given scene and desc. Fails with
 * VDBGI_ERR_INVALID_ARG for a non-positive or non-finite spacing or margin,
 * and with VDBGI_ERR_OUT_OF_MEMORY, stating the count and memory, when the
 * lattice would hold more than max_probes probes.
 */
VDBGI_API vdbgi_result vdbgi_probes_place(vdbgi_context *ctx, const vdbgi_scene *scene,
                                          const vdbgi_place_desc *desc, vdbgi_probes **out);

typedef enum vdbgi_sampling {
    VDBGI_SAMPLING_FIBONACCI = 0, /* one spherical Fibonacci set for every probe (seed 000) */
    VDBGI_SAMPLING_RANDOM = 1     /* that set under a random rotation per probe */
} vdbgi_sampling;

typedef enum vdbgi_basis {
    VDBGI_BASIS_SCALAR = 0,       /* one colour per probe (seed 000) */
    VDBGI_BASIS_AMBIENT_CUBE = 1, /* also six colours, one per axis direction (Bevy, HL2) */
    VDBGI_BASIS_SH2 = 2           /* also eight colours: L2 spherical harmonics (vdbgi_sh2_eval) */
} vdbgi_basis;

/*
 * The L2 basis, stored cosine-convolved as the polynomial a reader evaluates:
 *
 *   E(n) / pi = max(0, c0 + c1 x + c2 y + c3 z + c4 xy + c5 yz + c6 (3z^2 - 1)
 *                        + c7 xz + c8 (x^2 - y^2))
 *
 * for a unit normal n = (x, y, z) in world axes, per channel. c0 is the
 * scalar value (the mean over the sphere); with radiance L over N rays of
 * directions d, c_k = w_k * sum(L * p_k(d)) / N with p_k the k-th term above
 * and w = 2, 2, 2, 15/4, 15/4, 5/16, 15/4, 15/16 (the band's SH constant
 * squared, times 4 pi, times its cosine lobe's A_l / pi: 1, 2/3, 1/4). The
 * units are the estimator's: E / pi, so uniform radiance L gives L for
 * every n. The .vdb holds c1..c8 as grids irradiance_sh1 .. irradiance_sh8.
 */
#define VDBGI_SH2_TERMS 9

/*
 * Ambient-cube sides, in the order vdbgi_probes_get_cube returns them and
 * with the grid names the .vdb uses: irradiance_px, _nx, _py, _ny, _pz, _nz.
 * Side s is what a surface facing that direction receives: the
 * cosine-weighted mean over its hemisphere of the rays' radiance, normalised
 * over the directions actually traced, so uniform radiance L gives exactly L.
 */
typedef enum vdbgi_side {
    VDBGI_SIDE_PX = 0,
    VDBGI_SIDE_NX = 1,
    VDBGI_SIDE_PY = 2,
    VDBGI_SIDE_NY = 3,
    VDBGI_SIDE_PZ = 4,
    VDBGI_SIDE_NZ = 5
} vdbgi_side;

typedef enum vdbgi_trace_method {
    VDBGI_TRACE_AUTO = 0,     /* the fastest measured on this build (see docs/performance.md) */
    VDBGI_TRACE_SINGLE = 1,   /* rtcIntersect1 / rtcOccluded1, one ray at a time */
    VDBGI_TRACE_PACKET8 = 2,  /* rtcIntersect8 / rtcOccluded8 */
    VDBGI_TRACE_PACKET16 = 3, /* rtcIntersect16 / rtcOccluded16 */
    VDBGI_TRACE_STREAM = 4    /* rtcIntersect1M / rtcOccluded1M over a probe's rays */
} vdbgi_trace_method;

/*
 * The irradiance estimator of seed 000. All-zero means the defaults:
 *   rays:        directions per probe, 1..1 000 000. 0 == 128. Must be 0
 *                when adaptive.
 *   adaptive:    0: every probe takes `rays` directions. 1: rays by each
 *                probe's spread: a 32-ray Fibonacci set under the probe's
 *                random rotation, then, as that set's spread s (the standard
 *                deviation of its rays) asks, one more Fibonacci set under
 *                another, of about k sqrt(s) rays less the 32 (whole 32s up
 *                to 1024 in all, doublings past), the two blended by their
 *                sizes^1.5. k comes from a pilot of 1024 of the lattice's
 *                valid probes (spread over the whole band, whatever the
 *                tile; where the margin is unknown, a file's probes,
 *                points lifted off the surfaces), then is fitted until the
 *                error measured at 256 (each
 *                baked twice, as vdbgi_bake_stats.noise is but under
 *                rotations of their own) is noise x their mean light, or
 *                at most 15 % under, as far as max_rays and six
 *                measurements allow. The same in any tile and on any
 *                thread count.
 *   noise:       the target of adaptive, relative, > 0. 0 == VDBGI_NOISE.
 *   max_rays:    the cap of adaptive, a power of two, 64..2^20. 0 == 1024.
 *   ray_dist:    longest ray, metres, > 0. 0 == 40.
 *   ambient:     fill light added at every hit, 0..1e6. 0 == 0.15;
 *                ambient_is_set with 0 for no fill.
 *   sun_dir:     direction towards the sun. (0,0,0) == (0.4, 0.8, 0.3).
 *                Normalised by the bake.
 *   sun_color:   sun radiance, linear RGB in 0..1e6. (0,0,0) == (1,1,1);
 *                sun_color_is_set with (0,0,0) turns the sun off. Under the
 *                physical model a scene whose own lights are used gets no
 *                default sun: only a sun_dir or sun_color given adds one.
 *   falloff:     distance weight 1 / (1 + (d/falloff)^2), metres, > 0.
 *                0 == 4; INFINITY turns the falloff off.
 *   sky:         what a miss contributes, linear RGB in 0..1e6. (0,0,0) == black.
 *   sampling:    direction set, see vdbgi_sampling.
 *   seed:        random seed of VDBGI_SAMPLING_RANDOM; every probe's stream
 *                is derived from its ijk and this seed.
 *   threads:     worker threads, 0 == every online core. Results do not
 *                depend on it.
 *   invalid_threshold: a probe whose back-face fraction (back-face hits over
 *                all hits) exceeds this is invalid. 0 == 0.25.
 *   trace_method: Embree query shape, see vdbgi_trace_method.
 *   lights:      see vdbgi_lights.
 *   model:       see vdbgi_model. VDBGI_MODEL_PHYSICAL refuses an ambient
 *                or a falloff that is given. The apps (gi-bake, gi-lightmap)
 *                default to VDBGI_MODEL_PHYSICAL; zero here stays the seed's,
 *                whose closed forms this API's users hold their code to.
 *   bounces:     1..16: a hit's outgoing light also carries what arrives
 *                there after bounces - 1 more reflections, traced further
 *                along one cosine-weighted ray per bounce (the ambient fill
 *                and the falloff apply at the first hit only). 0 == the
 *                model's default: 1 for the seed model; for the physical
 *                model, until the next bounce would add less than converge
 *                of the light (a pilot of surface points finds how many;
 *                the first three are traced, and the third carries the
 *                rest in proportion; the stats say what).
 *   converge:    see bounces; (0, 1), 0 == VDBGI_CONVERGE. Only with
 *                bounces 0.
 *   sky_map:     the radiance of a miss, in place of sky (which must then be
 *                black); NULL for none. Must outlive the bake.
 *   basis:       VDBGI_BASIS_AMBIENT_CUBE adds six directional colours per
 *                probe from the same rays (see vdbgi_side), VDBGI_BASIS_SH2
 *                eight L2 terms (see VDBGI_SH2_TERMS); the scalar value keeps
 *                its meaning and its bits.
 *   progress:    called on the caller's thread with the fraction done, at
 *                most about 100 times; a non-zero return stops the bake with
 *                VDBGI_ERR_CANCELLED. May be NULL.
 */
/*
 * The share of the light the next bounce (or pass) must add for the count
 * to go on, by default. Past the third the bounces are not traced, so a
 * smaller share costs nothing: 0.2 % leaves the light within 1 % of a
 * converged path tracer's in a closed room, where 1 % left 1.4-1.8 % out
 * (docs/lights.md).
 */
#define VDBGI_CONVERGE 0.002f

/*
 * The noise an adaptive bake (probes or texels) aims for by default, and the
 * apps' default: 5 % of the light, the error of 4.2-4.9 % measured against a
 * 16,384-ray bake on the bundled world and the interior, where the apps' fixed
 * counts left 6.4-8.8 % (probes, 128 rays) and 11-13 % (texels, 64 rays);
 * docs/performance.md, "Rays by default".
 */
#define VDBGI_NOISE 0.05f

/* Which of the scene's punctual lights light the hits. */
typedef enum vdbgi_lights {
    VDBGI_LIGHTS_SCENE = 0, /* all of them; its directional lights stand in for the
                               default sun (a sun_dir given replaces them) */
    VDBGI_LIGHTS_OFF = 1    /* none: the sun and the sky only, as before lights */
} vdbgi_lights;

/* The light model. */
typedef enum vdbgi_model {
    VDBGI_MODEL_SEED = 0,    /* seed 000's: the ambient fill and the distance falloff */
    VDBGI_MODEL_PHYSICAL = 1 /* neither: only the lights, emission, the sky and bounces */
} vdbgi_model;

typedef struct vdbgi_bake_desc {
    int rays;
    int adaptive;
    float noise;
    int max_rays;
    float ray_dist;
    float ambient;
    int ambient_is_set;
    float sun_dir[3];
    float sun_color[3];
    int sun_color_is_set;
    float falloff;
    float sky[3];
    vdbgi_sampling sampling;
    uint64_t seed;
    int threads;
    float invalid_threshold;
    vdbgi_trace_method trace_method;
    vdbgi_basis basis;
    vdbgi_lights lights;
    vdbgi_model model;
    int bounces;
    float converge;
    const vdbgi_sky *sky_map;
    int (*progress)(void *user, float done);
    void *progress_user;
} vdbgi_bake_desc;

typedef struct vdbgi_bake_stats {
    uint64_t probe_count;
    uint64_t primary_ray_count;
    uint64_t shadow_ray_count; /* towards the sun and lights; with bounces, theirs too */
    uint64_t hit_count;
    uint64_t invalid_probe_count;
    double seconds; /* wall time of the bake call */
    int threads;    /* worker threads used */
    /* Bounces: until converged (or as given), of them traced, the share of the light the last
       added, and the share the untraced ones carry. */
    int bounces, bounces_traced;
    double last_share, tail_share;
    /*
     * The error the bake's settings give 256 of the lattice's valid
     * probes, picked by hash over the whole band (whatever the tile; keep
     * boxes and --walkable not applied; without a margin, points lifted
     * off the surfaces), over their mean light: each
     * estimated twice under rotations of its own, the RMS of the difference over
     * sqrt 2 (a fixed Fibonacci set measured under random rotations, which
     * it beats by ~15 %). 0 for an unshaded bake.
     */
    double noise;
} vdbgi_bake_stats;

/*
 * Bake every probe: its irradiance (mean over the rays of the hit's albedo
 * times (ambient + max(0, n.sun) sun_color [if the sun is visible from the
 * hit]) / (1 + (d/falloff)^2), or sky for a miss) and its back-face fraction.
 * stats may be NULL. The result depends only on the scene, the lattice and
 * desc (not on threads or timing). The scene must be the one the probes were
 * placed on.
 */
VDBGI_API vdbgi_result vdbgi_probes_bake(vdbgi_probes *probes, const vdbgi_scene *scene,
                                         const vdbgi_bake_desc *desc, vdbgi_bake_stats *stats);

/*
 * The estimator at arbitrary points of the scene, for receivers and tests.
 * Writes point_count * 3 floats to rgb and, if backface is not NULL,
 * point_count back-face fractions. Random sampling seeds point i from
 * (i, 0, 0).
 */
VDBGI_API vdbgi_result vdbgi_scene_bake_points(const vdbgi_scene *scene,
                                               const vdbgi_bake_desc *desc, const float *points,
                                               size_t point_count, float *rgb, float *backface);

/*
 * Write an OpenVDB file: a Vec3s grid "irradiance" (linear RGB), a float
 * grid "validity" (back-face fraction; above the stored invalid_threshold
 * means invalid), a float grid "stderr" (each probe's standard error), a
 * float grid "rays" (whole numbers) when the count was adaptive (earlier
 * files held it as Int32, which pyopenvdb cannot open; still read), six
 * Vec3s grids with
 * ambient cubes, all with a linear transform of voxel size = spacing and
 * translation = origin, and the bake settings, scene name, triangle count,
 * probe count and bake time as metadata of both grids. The file is written
 * to a temporary name beside path and renamed when complete: a failure never
 * leaves a partial file nor replaces an existing one.
 */
VDBGI_API vdbgi_result vdbgi_probes_write(const vdbgi_probes *probes, const char *path);

/*
 * Read a file written by vdbgi_probes_write (or any VDB file with a Vec3s
 * grid "irradiance"; a missing "validity" grid means every probe is valid).
 */
VDBGI_API vdbgi_result vdbgi_probes_read(vdbgi_context *ctx, const char *path, vdbgi_probes **out);

/*
 * The same file read a z range at a time, for a conversion region by region
 * (vdbgi_volume_build_regions): open checks every grid's bytes once and
 * holds no probe; read gives the probes with z0 <= k < z1 (perhaps none), in
 * the order vdbgi_probes_read gives them, with its checks of the values. A
 * read's memory is counted once it is read, not estimated before; a file
 * changed since open is refused, and after a failed read the file is not
 * to be read again. extent is the index box (inclusive, whole 8-point
 * leaves) holding every probe.
 */
typedef struct vdbgi_probe_file vdbgi_probe_file;
VDBGI_API vdbgi_result vdbgi_probe_file_open(vdbgi_context *ctx, const char *path,
                                             vdbgi_probe_file **out);
VDBGI_API void vdbgi_probe_file_extent(const vdbgi_probe_file *file, int32_t lo[3], int32_t hi[3]);
VDBGI_API vdbgi_result vdbgi_probe_file_read(vdbgi_probe_file *file, int32_t z0, int32_t z1,
                                             vdbgi_probes **out);
/* Close the file; NULL is a no-op. */
VDBGI_API void vdbgi_probe_file_close(vdbgi_probe_file *file);

/* Destroy probes; NULL is a no-op. */
VDBGI_API void vdbgi_probes_destroy(vdbgi_probes *probes);

typedef struct vdbgi_probes_info {
    size_t probe_count;
    size_t invalid_count;           /* 0 until baked */
    double spacing;                 /* metres */
    double margin;                  /* metres */
    double origin[3];               /* world position of ijk (0,0,0) */
    int32_t ijk_min[3], ijk_max[3]; /* inclusive bounds of the probes */
    float invalid_threshold;        /* back-face fraction above which a probe is invalid */
    int baked;                      /* non-zero once values are present */
    vdbgi_basis basis;              /* which directional grids the probes hold */
    int tile_index, tile_count;     /* a tile (vdbgi_place_desc), or 0, 0 for a whole lattice */
    int32_t tile_x[2];              /* the range of i a tile holds, [begin, end) */
} vdbgi_probes_info;

VDBGI_API void vdbgi_probes_get_info(const vdbgi_probes *probes, vdbgi_probes_info *info);

/*
 * Probe number index (0 <= index < probe_count): its lattice coordinate,
 * irradiance and back-face fraction. Any output pointer may be NULL.
 * Returns VDBGI_ERR_INVALID_ARG for an index out of range.
 */
VDBGI_API vdbgi_result vdbgi_probes_get(const vdbgi_probes *probes, size_t index, int32_t ijk[3],
                                        float rgb[3], float *backface);

/*
 * The baked field at world position pos: trilinear interpolation of the
 * eight probes around it, over those that exist and are valid (weights
 * renormalised). Returns VDBGI_ERR_INVALID_ARG, rgb zero, when none of the
 * eight is. Scans every probe: meant for inspection, not for loops.
 */
VDBGI_API vdbgi_result vdbgi_probes_sample(const vdbgi_probes *probes, const float pos[3],
                                           float rgb[3]);

/*
 * Every probe at once into the caller's arrays: ijk (3 int32 a probe), rgb
 * (3 floats) and backface (1 float), each NULL to skip, for capacity
 * probes. Returns the probe count when all three are NULL (the size query),
 * else the probes copied: the count, or 0, writing nothing, when capacity is
 * smaller.
 */
VDBGI_API size_t vdbgi_probes_copy(const vdbgi_probes *probes, int32_t *ijk, float *rgb,
                                   float *backface, size_t capacity);

/*
 * Probe number index's standard error (of its value, the mean over channels,
 * estimated from the spread of its rays) and the rays it took. Either
 * pointer may be NULL. VDBGI_ERR_INVALID_ARG out of range.
 */
VDBGI_API vdbgi_result vdbgi_probes_get_noise(const vdbgi_probes *probes, size_t index,
                                              float *stderr_out, uint32_t *rays_out);

/*
 * Probe number index's ambient cube, six RGB colours in vdbgi_side order.
 * VDBGI_ERR_INVALID_ARG for an index out of range or probes baked (or read)
 * without the ambient-cube basis.
 */
VDBGI_API vdbgi_result vdbgi_probes_get_cube(const vdbgi_probes *probes, size_t index,
                                             float cube[6][3]);

/*
 * Probe number index's L2 terms c0..c8 (VDBGI_SH2_TERMS colours; c0 is its
 * irradiance). VDBGI_ERR_INVALID_ARG for an index out of range or probes
 * baked (or read) without the L2 basis.
 */
VDBGI_API vdbgi_result vdbgi_probes_get_sh2(const vdbgi_probes *probes, size_t index,
                                            float sh[VDBGI_SH2_TERMS][3]);

/* E(n) / pi of L2 terms sh (as VDBGI_SH2_TERMS above) for unit normal n, clamped at 0. */
VDBGI_API void vdbgi_sh2_eval(const float sh[VDBGI_SH2_TERMS][3], const float n[3], float rgb[3]);

/*
 * The baked field at count world positions pos (3 floats each) as a surface
 * with unit normal normals[i] (3 floats each; NULL: no normal) receives it.
 * A surface's reading (normal_bias > 0) first moves the point normal_bias
 * metres along its normal, and weighs each of the eight probes around it,
 * beside its trilinear weight, by ((1 + cos)/2)^2 + 0.05 of the angle
 * between the normal and the direction to the probe: a probe behind the
 * surface sees its other side. A character's (0) reads where it is, with
 * trilinear weights alone. Over the valid ones among
 * the eight (weights renormalised) each basis term is interpolated, then
 * evaluated for the normal: the L2 polynomial, the ambient cube's
 * n^2-weighted sides, or the scalar whatever the normal (and without
 * normals, which is vdbgi_probes_sample). E / pi into rgb (3 floats each);
 * valid[i] (may be NULL) says whether any of the eight was valid, rgb zero
 * where none was. Builds a lookup of its own: meant for batches.
 */
VDBGI_API vdbgi_result vdbgi_probes_sample_points(const vdbgi_probes *probes, size_t count,
                                                  const float *pos, const float *normals,
                                                  float normal_bias, float *rgb,
                                                  unsigned char *valid);

/*
 * Metadata stored with the grids, as "name=value" text, index 0..n-1; NULL
 * past the end. Owned by the probes.
 */
VDBGI_API const char *vdbgi_probes_metadata(const vdbgi_probes *probes, size_t index);

/* ------------------------------------------------------------------------ */
/* Volume: adaptive bricks, atlas and indirection (the .gi file).            */

typedef struct vdbgi_volume vdbgi_volume;

typedef enum vdbgi_encoding {
    VDBGI_ENCODING_RGBM = 0,  /* rgba8: colour = rgb * a * range (seed 000, range 8) */
    VDBGI_ENCODING_RGB9E5 = 1 /* WebGPU rgb9e5ufloat: shared 5-bit exponent, 9-bit mantissas */
} vdbgi_encoding;

/*
 * How a brick lies in the atlas (docs/format.md). Both keep 4^3 probes a brick
 * and one indirection texel per level-0 cell. The numbers are the ones the
 * .gi file's layout field, web/gi-format.js and the shaders use; 0 asks for
 * the default, which a volume never reports.
 */
typedef enum vdbgi_layout {
    VDBGI_LAYOUT_DEFAULT = 0, /* what vdb-to-gi writes: VDBGI_LAYOUT_COMPACT */
    VDBGI_LAYOUT_SEED = 1,    /* seed 000's, for its shader unmodified: 6^3 texels, a coarse
                                probe at the centre of its 2^L block, a one-texel apron on
                                every side */
    VDBGI_LAYOUT_COMPACT = 2  /* 5^3 texels: a coarse probe at a corner of its 2^L block, so
                                the filter needs a border on the + side only (Unreal's
                                volumetric lightmap); where a coarser brick adjoins, a
                                brick's face takes its interpolated values, so levels meet
                                without a step; neighbours along x and z share their
                                border planes in the atlas */
} vdbgi_layout;

typedef enum vdbgi_criterion {
    VDBGI_CRITERION_AUTO = 0,   /* the default: VDBGI_CRITERION_INTERP (see docs/converter.md) */
    VDBGI_CRITERION_RANGE = 1,  /* keep a block coarse if its colour range <= eps (seed 000) */
    VDBGI_CRITERION_INTERP = 2, /* ... or if its brick's trilinear interpolation reproduces
                                   every fine probe it covers within eps */
    VDBGI_CRITERION_RMSE = 3    /* ... or if that interpolation's RMSE over the fine probes
                                   it covers is within eps (Unreal's volumetric lightmap) */
} vdbgi_criterion;

typedef enum vdbgi_fill {
    VDBGI_FILL_AUTO = 0,   /* the default: VDBGI_FILL_DARKEST */
    VDBGI_FILL_MEAN = 1,   /* an invalid or absent probe takes the weighted mean of its
                               valued neighbours */
    VDBGI_FILL_DARKEST = 2 /* ... except an invalid probe whose two face neighbours along
                               one axis both hold values (inside a wall thinner than the
                               spacing), which takes its darkest neighbour (least r+g+b):
                               a fraction of the light leaks into dark rooms, at no
                               measurable cost in the open (docs/stability.md) */
} vdbgi_fill;

/* What a volume keeps of the probes' L2 terms. */
typedef enum vdbgi_terms {
    VDBGI_TERMS_KEEP = 0, /* the terms, where the probes have them (.gi version 7) */
    VDBGI_TERMS_DROP = 1  /* the scalar alone, as seed 000 (version 5) */
} vdbgi_terms;

/*
 * How to coarsen and encode. All-zero means the defaults:
 *   eps:        tolerance, relative to the mean irradiance of the valid
 *               probes (so one value suits dim and bright scenes): a block's
 *               largest channel difference must be <= eps * mean. >= 0.
 *               0 == 0.1; eps_is_set with 0 never coarsens a varying block.
 *   max_level:  largest brick level, 0..3 (a level-L brick spans 4 x 2^L
 *               probes). 0 == 3; max_level_is_set with 0 for level-0 bricks
 *               only.
 *   criterion:  see vdbgi_criterion.
 *   encoding:   see vdbgi_encoding.
 *   noise_sigmas: sampling-noise allowance, in standard errors (the bake's
 *               "stderr" grid): a block's range is discounted by twice this
 *               many times its noisiest valid probe's standard error, and the
 *               interpolation test allows it once. >= 0. 0 == 1 for random
 *               and adaptive bakes (the estimate assumes independent rays and
 *               overstates a rotated Fibonacci set's error 1.9-2.4x:
 *               docs/stability.md) and 0 for the fixed Fibonacci set, whose
 *               error is a shared bias, not noise; noise_sigmas_is_set with 0
 *               for none.
 *   fill:       see vdbgi_fill.
 *   progress:   as vdbgi_bake_desc's; may be NULL.
 *   threads:    worker threads, 0 == every online core. The bytes do not
 *               depend on it.
 *   layout:     see vdbgi_layout (0: the compact layout).
 *   terms:      see vdbgi_terms: whether a volume of the compact layout
 *               carries the probes' L2 terms when they have them
 *               (VDBGI_BASIS_SH2; .gi version 8 or 7, see gi_version; read
 *               with a normal: vdbgi_volume_sample_normal). The seed layout holds the
 *               scalar only.
 *   gi_version: a volume with L2 terms: 8, terms 4-8 one ratio for all
 *               channels, their luminance's (14 bytes a texel on the GPU);
 *               7, every term's three channels (24 bytes a texel); 6 is
 *               7 for runtimes from before version 7 (the same textures, a
 *               larger file); 0 chooses: 8 where its second band moves the
 *               probes' readings by at most VDBGI_LUMA2_TOLERANCE
 *               (info.luma2_error), else 7. Other values, or 6 to 8 for a
 *               volume without terms, are VDBGI_ERR_INVALID_ARG.
 *   term_bits:  L2 terms: the bits of each signed ratio byte kept, 4..8
 *               (0: VDBGI_TERM_BITS); 8 keeps all, each bit fewer doubles
 *               the step to which a ratio is rounded, and shrinks the file.
 *               The textures and readers stay as they are. A volume
 *               without terms has nothing to round (no error).
 */
/*
 * The most luma2_error (vdbgi_volume_info) with which vdbgi_convert_desc's gi_version 0
 * writes version 8, from gi-bench truth at 0.5 m (docs/directional.md, "The second band
 * in luminance"): the interior's 3.0 % cost its characters 0.3 points against the
 * hemisphere truth, the 200 m world's 3.9 % 1.0, the bundled world's 4.5-6.3 % 1.9.
 */
#define VDBGI_LUMA2_TOLERANCE 0.04

typedef struct vdbgi_convert_desc {
    float eps;
    int eps_is_set;
    float noise_sigmas;
    int noise_sigmas_is_set;
    int max_level;
    int max_level_is_set;
    vdbgi_criterion criterion;
    vdbgi_encoding encoding;
    vdbgi_fill fill;
    int (*progress)(void *user, float done);
    void *progress_user;
    int threads;
    vdbgi_layout layout;
    vdbgi_terms terms;
    int gi_version;
    int term_bits;
} vdbgi_convert_desc;

/*
 * The default bits of an L2 ratio: a step of 4/127 of a term's range. On the
 * bundled world at 0.5 m it takes a third off the file for 0.5 points of
 * surface error against the hemisphere truth (docs/directional.md): the
 * bake's noise in the ratios is larger than the step.
 */
#define VDBGI_TERM_BITS 6

/* The RGBM range: colours up to this are encoded, brighter ones clamp. */
#define VDBGI_RGBM_RANGE 8.0f
/*
 * What a .gi may unpack to by default, its body and its textures (indirection,
 * atlas and, for L2, six term textures of the atlas's size) each: a browser holds
 * about four times this while it builds and uploads them. The web loader's
 * MAX_BYTES is the same.
 */
#define VDBGI_VOLUME_BUDGET ((size_t)32 << 20)
/* The largest 3D texture dimension WebGPU guarantees; the atlas stays within it. */
#define VDBGI_MAX_TEXTURE_DIM 2048
/* The runtime's indirection is at most this many texels a side (WebGL2's 2D minimum). */
#define VDBGI_COLUMNS_ROW 2048

/* The .gi file's texel encodings (docs/format.md), for tools that write or read texels. */

/*
 * RGBM with multiplier range `range`: M = ceil(255 max(r,g,b)/range)/255,
 * rgb = round(255 c / (M range))/255. Rounding M up keeps every channel in
 * [0, 1], so decoding lands within half a step (M range / 510) of the input.
 * Negative and NaN channels encode as 0; colours brighter than range clamp
 * (the return value is then non-zero).
 */
VDBGI_API int vdbgi_rgbm_encode(const float rgb[3], float range, uint8_t out[4]);
VDBGI_API void vdbgi_rgbm_decode(const uint8_t in[4], float range, float rgb[3]);

/*
 * RGB9E5 (EXT_texture_shared_exponent, WebGPU rgb9e5ufloat): 9-bit
 * mantissas, one 5-bit exponent, bias 15; r in bits 0-8, g 9-17, b 18-26,
 * exponent 27-31. Largest value 65408; relative error <= 2^-9 of the
 * largest channel. Negative and NaN channels encode as 0; larger values clamp
 * (the return value is then non-zero).
 */
VDBGI_API int vdbgi_rgb9e5_encode(const float rgb[3], uint32_t *out);
VDBGI_API void vdbgi_rgb9e5_decode(uint32_t in, float rgb[3]);

/*
 * Build the bricked volume of baked probes: fill invalid and absent probes
 * from valid neighbours, coarsen top-down by desc's criterion, pack the atlas
 * and the indirection texture, encode, and measure the error of what the
 * shader will sample against the filled field at every valid probe. The
 * probes are only read. Fails with VDBGI_ERR_INVALID_ARG for a bad desc,
 * VDBGI_ERR_FORMAT for probes with no value or no valid probe, and
 * VDBGI_ERR_OUT_OF_MEMORY, saying what to change, when the atlas or the
 * indirection would exceed VDBGI_MAX_TEXTURE_DIM texels on an axis.
 */
VDBGI_API vdbgi_result vdbgi_volume_build(vdbgi_context *ctx, const vdbgi_probes *probes,
                                          const vdbgi_convert_desc *desc, vdbgi_volume **out);

/*
 * The same volume, to the same bytes, built region by region: slabs of
 * region_points lattice points along z (a multiple of VDBGI_REGION_STEP),
 * each read with VDBGI_REGION_HALO points either side, filled, coarsened
 * and sampled, then dropped. What stays whole is the lattice's cells and
 * bricks (a few bytes a 64-probe cell) and the volume itself (its textures
 * and payload). The file is read four times (statistics, bricks, values,
 * error figures). The volume holds no filled field: vdbgi_volume_write_slices
 * refuses it. Refused where the whole build is not: probes, valid or not,
 * spanning more than the indirection can hold along an axis.
 */
#define VDBGI_REGION_STEP 32
#define VDBGI_REGION_HALO 16
VDBGI_API vdbgi_result vdbgi_volume_build_regions(vdbgi_context *ctx, vdbgi_probe_file *file,
                                                  int32_t region_points,
                                                  const vdbgi_convert_desc *desc,
                                                  vdbgi_volume **out);

/*
 * Write the .gi file (docs/format.md), gzip-compressed, through a temporary
 * file renamed when complete: the seed layout as header, indirection bytes
 * and atlas bytes (version 1); the compact layout packed, each probe once
 * (version 5), its textures rebuilt by the reader. The gzip happens here
 * (the first write or vdbgi_volume_write_memory), not in the build; the
 * bytes are kept for the next.
 */
VDBGI_API vdbgi_result vdbgi_volume_write(const vdbgi_volume *volume, const char *path);

/*
 * Write the runtime textures as they go to the GPU, uncompressed: header,
 * indirection bytes, atlas bytes (version 1, or 2 for the compact layout),
 * for an engine that uploads them as they are and for comparing readers.
 */
VDBGI_API vdbgi_result vdbgi_volume_write_textures(const vdbgi_volume *volume, const char *path);

/*
 * Read a .gi file (gzip'd or not). Every size is checked against the header
 * and the data; a truncated or corrupted file is VDBGI_ERR_FORMAT, and
 * nothing is read past the end of the data.
 */
VDBGI_API vdbgi_result vdbgi_volume_read(vdbgi_context *ctx, const char *path, vdbgi_volume **out);

/*
 * vdbgi_volume_read for a file already in memory: size bytes at data,
 * gzip'd or not, borrowed for the call only. The same checks and refusals;
 * messages name `name` (NULL: "memory") where the file reader names the
 * path.
 */
VDBGI_API vdbgi_result vdbgi_volume_read_memory(vdbgi_context *ctx, const void *data, size_t size,
                                                const char *name, vdbgi_volume **out);

/*
 * The bytes vdbgi_volume_write writes (the gzip'd .gi): their count into
 * *size, and into buffer (capacity bytes) unless it is NULL (a size query).
 * VDBGI_ERR_INVALID_ARG, nothing written, when capacity is smaller than
 * *size; VDBGI_ERR_OUT_OF_MEMORY when the file cannot be made. The file is
 * gzip'd by the first write or size query and kept with the volume; a volume
 * read from a file writes back the same bytes as vdb-to-gi wrote.
 */
VDBGI_API vdbgi_result vdbgi_volume_write_memory(const vdbgi_volume *volume, void *buffer,
                                                 size_t capacity, size_t *size);

VDBGI_API void vdbgi_volume_destroy(vdbgi_volume *volume);

typedef struct vdbgi_volume_info {
    vdbgi_encoding encoding;
    vdbgi_layout layout;
    vdbgi_basis basis; /* VDBGI_BASIS_SCALAR, or VDBGI_BASIS_SH2: L2 terms beside the atlas */
    float rgbm_range;
    float spacing;                /* finest probe spacing, metres */
    float box_min[3], box_max[3]; /* world box the indirection covers, metres */
    uint32_t ind_dims[3];         /* level-0 cells */
    uint32_t atlas_dims[3];       /* texels */
    uint32_t max_level;
    uint32_t bricks[4]; /* kept bricks per level */
    uint32_t brick_count;
    size_t indirection_size, atlas_size; /* bytes, uncompressed */
    size_t file_size;                    /* bytes of the file read, or that a write writes */
    size_t dense_rgba8_size;             /* a dense RGBA8 grid over the probes' box */
    /* Filled in by vdbgi_volume_build only (0 after vdbgi_volume_read): */
    size_t probe_count, valid_count, filled_count, unreached_count;
    size_t fallback_count;       /* texels (seed layout) or stored points (compact) the fill
                                    left without a value: their brick's block mean */
    size_t clamped_count;        /* texels whose colour exceeded the RGBM range */
    double mean_irradiance;      /* over valid probes and channels */
    double rmse, p99, max_error; /* sampled field vs filled field at valid probes, absolute */
    double seconds;              /* wall time of the build */
    size_t stored_points;        /* compact layout: probe values the file stores, each once */
    /* The runtime's indirection, as vdbgi's shaders upload it instead of the 3D one
       (docs/format.md): a 2D RGBA8 texture; size 0 above VDBGI_COLUMNS_ROW^2 texels. */
    uint32_t columns_dims[2];
    size_t columns_size; /* bytes; the GPU holds columns_size + atlas_size + sh_size */
    size_t sh_size;      /* L2 terms: 14 bytes an atlas texel (version 8: three RGBA8 and one RG8
                            snorm textures) or 24 (6 and 7: six RGBA8), or 0 */
    int term_bits;       /* L2 terms, build only: the bits of each ratio byte kept (desc's) */
    /* L2 terms, build only: how far version 8's second band (in luminance) moves the valid
       probes' readings from every term in colour: RMS over 14 normals (axes, diagonals) and
       the channels, over the mean reading. */
    double luma2_error;
} vdbgi_volume_info;

VDBGI_API void vdbgi_volume_get_info(const vdbgi_volume *volume, vdbgi_volume_info *info);

/*
 * The runtime textures into the caller's buffer, as the .gi file holds them
 * (docs/format.md): indirection_size or atlas_size bytes. With a NULL
 * buffer, returns the size needed; else the bytes copied, or 0 (nothing
 * written) when capacity is smaller.
 */
VDBGI_API size_t vdbgi_volume_copy_indirection(const vdbgi_volume *volume, void *buffer,
                                               size_t capacity);
VDBGI_API size_t vdbgi_volume_copy_atlas(const vdbgi_volume *volume, void *buffer, size_t capacity);

/*
 * The runtime's indirection (docs/format.md "The runtime's indirection"): the
 * 3D indirection's non-empty runs of cells along y, one list for all
 * columns, in a 2D RGBA8 texture of columns_dims texels; what vdbgi's web
 * runtime uploads. Same convention as above (0 also when the volume is too
 * large for it).
 */
VDBGI_API size_t vdbgi_volume_copy_columns(const vdbgi_volume *volume, void *buffer,
                                           size_t capacity);

/*
 * The value the runtime shader of seed 000 computes at world position pos:
 * NEAREST indirection read, level and slot decode, local coordinates,
 * trilinear atlas read with the texel-centre convention and clamp-to-edge,
 * decode. Outside the box the coordinates clamp like the textures do; an
 * empty cell reads black, except, in the compact layout, below a column's
 * lowest brick, which reads that brick's bottom plane (the lift,
 * docs/format.md).
 */
VDBGI_API void vdbgi_volume_sample(const vdbgi_volume *volume, const float pos[3], float rgb[3]);

/*
 * What a surface with unit normal n reads at pos, E(n) / pi: with L2 terms,
 * the L0 colour and the eight terms' ratios to it, each read as
 * vdbgi_volume_sample reads the atlas (one trilinear weight set), then
 * c0 (1 + sum r_k p_k(n)) clamped at 0 a channel (docs/format.md, "Version
 * 6"); a scalar volume reads what vdbgi_volume_sample does. The caller moves
 * pos off its surface as it sees fit (the runtime: half a spacing).
 */
VDBGI_API void vdbgi_volume_sample_normal(const vdbgi_volume *volume, const float pos[3],
                                          const float n[3], float rgb[3]);

typedef enum vdbgi_axis { VDBGI_AXIS_X = 0, VDBGI_AXIS_Y = 1, VDBGI_AXIS_Z = 2 } vdbgi_axis;

/*
 * Slice images for people, through OpenImageIO, into directory dir (made if
 * missing), one pixel per probe of the lattice plane nearest world
 * coordinate `at` across `axis`: the baked probes (baked.*: black where
 * there is none), the field the bricks give, read through the sampler
 * (bricks.*), its difference from the filled field (difference.*, times
 * 10), the brick level of each cell (levels.png: black empty, red level 0,
 * yellow 1, green 2, blue 3), and the atlas's z layers side by side
 * (atlas.*). PNG files are exposed by `exposure` stops and sRGB-encoded; EXR
 * files hold linear values. probes must be those the volume was built from;
 * a volume from vdbgi_volume_read has no filled field and is refused.
 */
VDBGI_API vdbgi_result vdbgi_volume_write_slices(const vdbgi_volume *volume,
                                                 const vdbgi_probes *probes, vdbgi_axis axis,
                                                 double at, float exposure, const char *dir);

/* ------------------------------------------------------------------------ */
/* Bevy irradiance volumes: dense grids of ambient cubes (seeds 001, 002).   */

typedef struct vdbgi_bevy vdbgi_bevy;

typedef enum vdbgi_bevy_format {
    VDBGI_BEVY_RGBA16F = 0, /* Rgba16Float texels, alpha 1 */
    VDBGI_BEVY_RGB9E5 = 1   /* Rgb9e5Ufloat texels */
} vdbgi_bevy_format;

/*
 * The dense voxel grid of a Bevy irradiance volume. All-zero means defaults:
 *   resolution:  voxels per axis, each >= 1. (0,0,0) == from voxel_size.
 *   voxel_size:  metres, > 0, used when resolution is 0. 0 == 4 x spacing.
 *   box_min/max: world box the volume covers, inside the baked bounds.
 *                Both (0,0,0) without box_is_set == the baked bounds (the
 *                probes' box plus half a spacing on every side).
 *   fill:        as vdbgi_convert_desc's; one choice of neighbour a probe,
 *                the darkest by the sum over all six sides, for every side.
 *   threads:     worker threads, 0 == every online core (same bytes).
 * Texture limits: layout 1 is (Rx, 2Ry, 3Rz) texels, each at most 2048;
 * layout 2 is 3Rx x 2RyRz texels, each at most 8192.
 */
typedef struct vdbgi_bevy_desc {
    int resolution[3];
    double voxel_size;
    double box_min[3], box_max[3];
    int box_is_set;
    vdbgi_fill fill;
    int threads;
} vdbgi_bevy_desc;

/*
 * Resample baked ambient cubes onto the dense grid: the six sides are filled
 * from valid probes as the converter fills (docs/converter.md), read trilinearly
 * at every voxel centre, and voxels with no filled point around them take
 * the mean of their valued grid neighbours, ring by ring. Fails with
 * VDBGI_ERR_INVALID_ARG for probes without ambient cubes, a box outside the
 * baked bounds, a zero or oversized resolution.
 */
VDBGI_API vdbgi_result vdbgi_bevy_build(vdbgi_context *ctx, const vdbgi_probes *probes,
                                        const vdbgi_bevy_desc *desc, vdbgi_bevy **out);

/*
 * A volume from memory: cube holds, for voxel (x, y, z) at index
 * (z*Ry + y)*Rx + x, six RGB colours in vdbgi_side order (18 floats). Copied.
 */
VDBGI_API vdbgi_result vdbgi_bevy_create(vdbgi_context *ctx, const float *cube,
                                         const int resolution[3], const double box_min[3],
                                         const double box_max[3], vdbgi_bevy **out);

VDBGI_API void vdbgi_bevy_destroy(vdbgi_bevy *volume);

typedef struct vdbgi_bevy_info {
    int resolution[3];
    double box_min[3], box_max[3];
    double center[3], size[3]; /* the light probe's Transform: translation, scale */
    size_t ktx2_texels;        /* Rx * 2Ry * 3Rz */
} vdbgi_bevy_info;

VDBGI_API void vdbgi_bevy_get_info(const vdbgi_bevy *volume, vdbgi_bevy_info *info);

/*
 * Layout 1 (Bevy's IrradianceVolume, seed 001): a 3D texture (Rx, 2Ry, 3Rz)
 * where side S of voxel (x, y, z) sits at s = x, t = y (+Ry for +X, +Y, +Z),
 * p = z (+Rz for Y sides, +2Rz for Z sides), in a KTX2 file. NaN and
 * negative colours are written as 0; colours beyond the format clamp, and
 * *clamped_count_out (may be NULL) says how many did.
 */
VDBGI_API vdbgi_result vdbgi_bevy_write_ktx2(const vdbgi_bevy *volume, const char *path,
                                             vdbgi_bevy_format format, size_t *clamped_count_out);

/*
 * Layout 2 (bevy-baked-gi, seed 002): a linear RGBA8 PNG of 3x2-texel cells,
 * cell i = (z*Ry + y)*Rx + x at texel (3 (i mod Rx), 2 floor(i / Rx)), the
 * upper row +X +Y +Z, the lower -X -Y -Z, each colour in the 8-bit shared
 * exponent encoding C = 2^(255A - 128) (R, G, B). No sRGB conversion.
 * *clamped_count_out (may be NULL): colours beyond the encoding's range.
 */
VDBGI_API vdbgi_result vdbgi_bevy_write_baked_gi(const vdbgi_bevy *volume, const char *path,
                                                 size_t *clamped_count_out);

/*
 * The volume's placement as JSON (resolution, box, the Transform's
 * translation and scale, the texture's name and layout), for the app that
 * spawns the LightProbe.
 */
VDBGI_API vdbgi_result vdbgi_bevy_write_json(const vdbgi_bevy *volume, const char *path,
                                             const char *texture, const char *layout);

/* ---- surface lightmaps (seed 004) ------------------------------------------ */

typedef struct vdbgi_lightmap_result vdbgi_lightmap_result;

/*
 * A lightmap bake of a whole scene. All-zero means the defaults.
 *   texel:    metres a texel edge, > 0. 0 == 0.25.
 *   size:     atlas edge in texels, 16..16384. More atlases when the
 *             charts do not fit one; a chart larger than one shrinks. 0 ==
 *             the smallest multiple of 32 texels that holds every chart on
 *             one atlas, or atlases of 1024 when one of 1024 cannot (a scene
 *             with its own second UV set: 1024).
 *   passes:   reflections, 1..VDBGI_LIGHTMAP_MAX_PASSES: pass k lights the
 *             hits with pass k-1's map, so every source's light reaches a
 *             texel over at most that many. 0 == the model's default: under
 *             the physical model until the next pass would add less than
 *             converge of the light, as gi-bake's bounces 0 counts them (at
 *             most three passes swept, the third's light carrying the
 *             rest); under the seed model 2 (seed 004's: its fill stands in
 *             for the rest).
 *   converge: with passes 0, that share, in (0, 1). 0 == VDBGI_CONVERGE.
 *   direct:   non-zero: the map holds the texel's own sun too (fully
 *             baked); else bounced light only, the lights staying on at
 *             runtime (seed 004's default).
 *   ao_dist:  > 0: an ambient-occlusion map instead, the open fraction of
 *             the cosine-weighted hemisphere within this many metres.
 *   layers:   non-zero: besides the map, one map per light that is on (sun,
 *             ambient fill, sky, each emissive material; at most
 *             VDBGI_LIGHTMAP_MAX_LAYERS), each baked with that light alone,
 *             so a game can dim or switch them and add them at runtime;
 *             they sum to the map. Not with ao_dist.
 *   bake:     the light model and sampling, as for probes (rays 0 == 64).
 *             Adaptive: each texel's rays by its pilot's spread, the scale
 *             from points on the surfaces (not for AO). Emissive materials
 *             light the scene.
 * A scene whose every mesh has a second UV set inside [0, 1] with no
 * overlapping triangles keeps it (texel ignored); otherwise a warning says
 * why not, and the scene is unwrapped anew.
 */
typedef struct vdbgi_lightmap_desc {
    float texel;
    int size;
    int passes;
    float converge;
    int direct;
    float ao_dist;
    int layers; /* non-zero: also one map per light (seed 004's layers), which sum to the map */
    float chart_angle; /* degrees a chart's triangles may turn from its first, (0, 90); 0 == 15 */
    vdbgi_bake_desc bake;
} vdbgi_lightmap_desc;

#define VDBGI_LIGHTMAP_MAX_LAYERS 16
#define VDBGI_LIGHTMAP_MAX_PASSES 16
/* Most atlas texels a lightmap takes (about 60 bytes each while baking: 1 GB). */
#define VDBGI_LIGHTMAP_MAX_TEXELS (1 << 24)
/*
 * Most hemisphere rays it plans, texels x rays x passes (minutes on a few
 * cores): an adaptive bake counted at 256 rays a texel at VDBGI_NOISE,
 * scaled as noise^-2 within 32..max_rays (a bake at its cap traces more).
 */
#define VDBGI_LIGHTMAP_MAX_RAYS 8e9

typedef struct vdbgi_lightmap_stats {
    int kept_uv1;  /* the scene's own second UV set was usable and kept */
    size_t layers; /* maps per light (0 without layers) */
    size_t charts, atlases;
    int atlas_size;     /* each atlas's edge, texels */
    size_t texels;      /* atlas texels, all pages */
    size_t samples;     /* texels that sample a triangle */
    size_t invalid;     /* samples inside geometry or behind back faces (filled in) */
    double utilisation; /* chart texels over atlas texels */
    int passes;         /* swept */
    double last_share;  /* of the map's light, the last pass's (0 for AO); until converged,
                           the last of the bounces' */
    int bounces;        /* until converged: the passes the light needs (0 otherwise) */
    double tail_share;  /* until converged: the share of the light the passes not swept carry */
    double pass_seconds[16];
    double seconds; /* the whole bake, unwrap included */
    unsigned long long rays;
    double gather_rays; /* a sample's rays over its hemisphere in a pass, on average (no AO) */
    double noise;       /* the error a pass's gather leaves, over the light: 256 points on the
                           surfaces each gathered twice (a fixed set under random turns), after
                           the timing (0 for AO) */
} vdbgi_lightmap_stats;

/* Unwrap scene, rasterise its texels and bake them; stats (may be NULL) says how it went. */
VDBGI_API vdbgi_result vdbgi_lightmap_bake_scene(vdbgi_context *ctx, const vdbgi_scene *scene,
                                                 const vdbgi_lightmap_desc *desc,
                                                 vdbgi_lightmap_result **out,
                                                 vdbgi_lightmap_stats *stats);
VDBGI_API void vdbgi_lightmap_result_destroy(vdbgi_lightmap_result *result);

/*
 * The atlases desc's unwrap takes, without a texel baked: into stats, the
 * charts, atlases, atlas_size, texels (atlas texels, all pages),
 * utilisation and kept_uv1 of vdbgi_lightmap_bake_scene with the same desc
 * (the rest 0), in the time of the unwrap alone. For choosing a texel size
 * (gi-lightmap --budget). The limits on atlases, texels and rays are the
 * bake's: past them, VDBGI_ERR_OUT_OF_MEMORY with the bake's message.
 */
VDBGI_API vdbgi_result vdbgi_lightmap_plan(vdbgi_context *ctx, const vdbgi_scene *scene,
                                           const vdbgi_lightmap_desc *desc,
                                           vdbgi_lightmap_stats *stats);

/*
 * Write the bake: the scene as a binary glTF at path (its second UV set,
 * and per material the 8-bit map on TEXCOORD_1: an AO map as the core
 * occlusionTexture, a lightmap in the material's extras, docs/lightmap.md),
 * and beside it, for a lightmap, each atlas's irradiance as half floats
 * (path without ".glb", then ".lightmap0.exr", ".lightmap1.exr", ...).
 */
/* The .glb's size in bytes into *glb_size unless it is NULL. */
VDBGI_API vdbgi_result vdbgi_lightmap_write(const vdbgi_lightmap_result *result, const char *path,
                                            size_t *glb_size);

/*
 * Pictures for people, into directory dir (made if missing), per atlas N:
 * mapN.png, the map as the .glb holds it (sRGB, E / scale; AO as grey), and
 * chartsN.png, each chart in a colour of its own, gutters black, and the
 * samples found inside geometry (filled from their neighbours) red.
 */
VDBGI_API vdbgi_result vdbgi_lightmap_write_slices(const vdbgi_lightmap_result *result,
                                                   const char *dir);

#ifdef __cplusplus
}
#endif

#endif /* VDBGI_H */
