/*
 * test_bake.c: the estimator matches seed 000's closed forms (a probe above a
 * plane, a probe inside a closed box), probes inside solids are invalid,
 * results do not depend on scale or thread count, and bad parameters, a
 * cancelling callback and failing allocations are refused cleanly.
 */
#define _POSIX_C_SOURCE 200809L
#include "test_util.h"
#include "vdbgi_bench.h"

#include <math.h>
#include <stdbool.h>

static const double rho = 0.5, ambient = 0.15;

/* Seed 000's estimator for a probe at height h over an infinite plane, sun at angle cos = ndotl. */
static double plane_closed_form(double h, double ray_dist, double falloff, double ndotl)
{
    double bracket = 1.0 - h / ray_dist;
    if (isfinite(falloff))
        bracket -= (h / falloff) * (atan(falloff / h) - atan(falloff / ray_dist));
    return rho * (ambient + ndotl) / 2.0 * bracket;
}

/* A plane of side 'size' at y = 0 (albedo rho) scaled by s, as a scene. */
static vdbgi_scene *plane_scene(vdbgi_context *ctx, float size)
{
    test_mesh m = {0};
    test_mesh_plane(&m, size, 0.0f);
    const vdbgi_mesh_desc d = test_mesh_desc(&m, (float)rho, 0);
    vdbgi_scene *s = NULL;
    CHECK_RESULT(ctx, vdbgi_scene_create(ctx, &d, 1, &s), VDBGI_OK);
    return s;
}

/* m's triangles (albedo rho), as a scene. */
static vdbgi_scene *mesh_scene(vdbgi_context *ctx, const test_mesh *m)
{
    const vdbgi_mesh_desc d = test_mesh_desc(m, (float)rho, 0);
    vdbgi_scene *s = NULL;
    CHECK_RESULT(ctx, vdbgi_scene_create(ctx, &d, 1, &s), VDBGI_OK);
    return s;
}

static vdbgi_bake_desc plane_desc(int rays, float ray_dist, float falloff, vdbgi_sampling sampling)
{
    const vdbgi_bake_desc d = {.rays = rays,
                               .ray_dist = ray_dist,
                               .ambient = (float)ambient,
                               .sun_dir = {0.0f, 1.0f, 0.0f},
                               .falloff = falloff,
                               .sampling = sampling};
    return d;
}

static void probe_above_plane_matches_closed_form_fibonacci(void)
{
    vdbgi_context *ctx = test_context();
    vdbgi_scene *s = plane_scene(ctx, 100.0f); /* > 2 x ray_dist across */
    const float heights[] = {0.25f, 1.0f, 3.0f, 10.0f};
    const float falloffs[] = {4.0f, 1.0f, INFINITY};
    for (size_t f = 0; f < 3; f++) {
        const vdbgi_bake_desc d = plane_desc(16384, 40.0f, falloffs[f], VDBGI_SAMPLING_FIBONACCI);
        float pts[4 * 3], rgb[4 * 3];
        for (int i = 0; i < 4; i++)
            pts[3 * i] = 0.123f, pts[3 * i + 1] = heights[i], pts[3 * i + 2] = -0.321f;
        CHECK_RESULT(ctx, vdbgi_scene_bake_points(s, &d, pts, 4, rgb, NULL), VDBGI_OK);
        for (int i = 0; i < 4; i++) {
            const double want = plane_closed_form(heights[i], 40.0, falloffs[f], 1.0);
            /* A Fibonacci set integrates this smooth-but-clipped integrand to ~1/N. */
            CHECK_NEAR(rgb[3 * i], want, 2e-3 * want + 2e-4);
            CHECK(rgb[3 * i] == rgb[3 * i + 1] && rgb[3 * i] == rgb[3 * i + 2]);
        }
    }
    vdbgi_scene_destroy(s);
    vdbgi_context_destroy(ctx);
}

/*
 * An emitting plane is the lit plane's closed form with its radiance in
 * place of rho (ambient + sun): a probe at distance h under a ceiling of
 * radiance Le (albedo 0, every other light off) reads Le / 2 x the bracket.
 */
static void probe_under_an_emitting_ceiling_matches_the_closed_form(void)
{
    vdbgi_context *ctx = test_context();
    test_mesh m = {0};
    const float a[3] = {-50, 0, -50}, b[3] = {50, 0, -50}, c[3] = {50, 0, 50}, d[3] = {-50, 0, 50};
    test_mesh_quad(&m, a, b, c, d); /* at y = 0, facing down */
    vdbgi_mesh_desc md = test_mesh_desc(&m, 0.0f, 0);
    const float le[3] = {3.0f, 2.0f, 1.0f};
    memcpy(md.emissive, le, sizeof(le));
    vdbgi_scene *s = NULL;
    CHECK_RESULT(ctx, vdbgi_scene_create(ctx, &md, 1, &s), VDBGI_OK);
    const float falloffs[2] = {4.0f, INFINITY};
    for (int f = 0; s && f < 2; f++) {
        vdbgi_bake_desc bd = plane_desc(16384, 40.0f, falloffs[f], VDBGI_SAMPLING_FIBONACCI);
        bd.ambient_is_set = 1;   /* with 0: no fill */
        bd.sun_color_is_set = 1; /* with (0,0,0): no sun */
        const float heights[3] = {0.5f, 2.0f, 8.0f};
        float pts[9], rgb[9];
        for (int i = 0; i < 3; i++)
            pts[3 * i] = 0.2f, pts[3 * i + 1] = -heights[i], pts[3 * i + 2] = 0.1f;
        CHECK_RESULT(ctx, vdbgi_scene_bake_points(s, &bd, pts, 3, rgb, NULL), VDBGI_OK);
        for (int i = 0; i < 3; i++) {
            const double h = heights[i], fo = falloffs[f];
            double bracket = 1.0 - h / 40.0;
            if (isfinite(fo))
                bracket -= (h / fo) * (atan(fo / h) - atan(fo / 40.0));
            for (int k = 0; k < 3; k++) {
                const double want = le[k] / 2.0 * bracket;
                CHECK_NEAR(rgb[3 * i + k], want, 2e-3 * want + 2e-4);
            }
        }
    }
    /* From above, the ceiling's back: no light. */
    const float above[3] = {0.2f, 1.0f, 0.1f};
    float rgb[3] = {1, 1, 1};
    vdbgi_bake_desc bd = plane_desc(1024, 40.0f, INFINITY, VDBGI_SAMPLING_FIBONACCI);
    bd.ambient_is_set = 1;   /* with 0: no fill */
    bd.sun_color_is_set = 1; /* with (0,0,0): no sun */
    CHECK_RESULT(ctx, vdbgi_scene_bake_points(s, &bd, above, 1, rgb, NULL), VDBGI_OK);
    CHECK(rgb[0] == 0.0f && rgb[1] == 0.0f && rgb[2] == 0.0f);
    vdbgi_scene_destroy(s);
    vdbgi_context_destroy(ctx);
}

static void probe_above_plane_matches_closed_form_random(void)
{
    vdbgi_context *ctx = test_context();
    vdbgi_scene *s = plane_scene(ctx, 100.0f);
    const int rays = 16384;
    const float heights[] = {0.5f, 2.0f, 8.0f};
    const vdbgi_bake_desc d = plane_desc(rays, 40.0f, 4.0f, VDBGI_SAMPLING_RANDOM);
    float pts[3 * 3], rgb[3 * 3];
    for (int i = 0; i < 3; i++)
        pts[3 * i] = 0.0f, pts[3 * i + 1] = heights[i], pts[3 * i + 2] = 0.0f;
    CHECK_RESULT(ctx, vdbgi_scene_bake_points(s, &d, pts, 3, rgb, NULL), VDBGI_OK);
    for (int i = 0; i < 3; i++) {
        const double want = plane_closed_form(heights[i], 40.0, 4.0, 1.0);
        /* Each ray adds at most rho (ambient + 1): 5 standard errors of such a mean. */
        const double sigma = rho * (ambient + 1.0) / 2.0 / sqrt((double)rays);
        CHECK_NEAR(rgb[3 * i], want, 5.0 * sigma);
    }
    vdbgi_scene_destroy(s);
    vdbgi_context_destroy(ctx);
}

static void lattice_probes_above_plane_match_and_below_are_invalid(void)
{
    vdbgi_context *ctx = test_context();
    vdbgi_scene *s = plane_scene(ctx, 24.0f);
    const vdbgi_place_desc pd = {.spacing = 1.0, .margin = 3.0};
    vdbgi_probes *p = NULL;
    CHECK_RESULT(ctx, vdbgi_probes_place(ctx, s, &pd, &p), VDBGI_OK);
    const vdbgi_bake_desc bd = plane_desc(2048, 10.0f, 4.0f, VDBGI_SAMPLING_FIBONACCI);
    vdbgi_bake_stats st;
    CHECK_RESULT(ctx, vdbgi_probes_bake(p, s, &bd, &st), VDBGI_OK);
    vdbgi_probes_info info;
    vdbgi_probes_get_info(p, &info);
    /* Origin 0.5: over the plane, layers at y = +-0.5, +-1.5, +-2.5 in 24 x 24 columns. */
    size_t checked_above = 0, checked_below = 0, over = 0, over_invalid = 0;
    for (size_t i = 0; i < info.probe_count; i++) {
        int32_t ijk[3];
        float rgb[3], bf;
        vdbgi_probes_get(p, i, ijk, rgb, &bf);
        const double x = info.origin[0] + ijk[0], y = info.origin[1] + ijk[1],
                     z = info.origin[2] + ijk[2];
        if (fabs(x) < 12.0 && fabs(z) < 12.0) {
            over++;
            over_invalid += bf > info.invalid_threshold;
        }
        if (fabs(x) > 1.0 || fabs(z) > 1.0) /* centre columns: the plane reaches past ray_dist */
            continue;
        if (y > 0.0) {
            CHECK_NEAR(rgb[0], plane_closed_form(y, 10.0, 4.0, 1.0), 3e-3);
            CHECK(bf == 0.0f);
            checked_above++;
        } else {
            CHECK(bf == 1.0f); /* every hit is the back of the plane */
            checked_below++;
        }
    }
    CHECK(checked_above == 4 * 3 && checked_below == 4 * 3);
    CHECK(over == 24 * 24 * 6 && over_invalid == 24 * 24 * 3);
    CHECK(st.invalid_probe_count == info.invalid_count);
    CHECK(st.primary_ray_count == 2048u * info.probe_count);
    vdbgi_probes_destroy(p);
    vdbgi_scene_destroy(s);
    vdbgi_context_destroy(ctx);
}

/* A closed room of half-size r with inward faces; the sun outside it must not get in. */
static void closed_box_reads_albedo_times_ambient_at_any_scale(void)
{
    const float scales[] = {0.5f, 1000.0f}; /* a 1 m room and a 2 km one */
    for (int si = 0; si < 2; si++) {
        const float r = scales[si];
        vdbgi_context *ctx = test_context();
        test_mesh m = {0};
        const float lo[3] = {-r, -r, -r}, hi[3] = {r, r, r};
        test_mesh_box(&m, lo, hi, 1);
        const vdbgi_mesh_desc md = test_mesh_desc(&m, (float)rho, 0);
        vdbgi_scene *s = NULL;
        CHECK_RESULT(ctx, vdbgi_scene_create(ctx, &md, 1, &s), VDBGI_OK);
        float pts[3 * 3] = {0.0f,     0.0f,       0.0f,      0.9f * r,  -0.9f * r,
                            0.5f * r, -0.99f * r, 0.99f * r, -0.99f * r};
        float rgb[3 * 3], bf[3];
        for (int sun = 0; sun < 2; sun++) {
            vdbgi_bake_desc d = {
                .rays = 512, .ray_dist = 4.0f * r, .ambient = (float)ambient, .falloff = INFINITY};
            if (!sun)
                d.sun_color_is_set = 1; /* with (0,0,0): no sun */
            CHECK_RESULT(ctx, vdbgi_scene_bake_points(s, &d, pts, 3, rgb, bf), VDBGI_OK);
            for (int i = 0; i < 9; i++)
                CHECK_NEAR(rgb[i], rho * ambient, 1e-6);
            for (int i = 0; i < 3; i++)
                CHECK(bf[i] == 0.0f);
        }
        vdbgi_scene_destroy(s);
        vdbgi_context_destroy(ctx);
    }
}

static void plane_under_slanted_sun_has_no_self_shadow_at_any_scale(void)
{
    const float scales[] = {0.01f, 1.0f, 25.0f}; /* a 1 m plane, 100 m, 2.5 km */
    const float sun[3] = {0.4f, 0.8f, 0.3f};
    const double ndotl = 0.8 / sqrt(0.16 + 0.64 + 0.09);
    for (int si = 0; si < 3; si++) {
        const float k = scales[si];
        vdbgi_context *ctx = test_context();
        vdbgi_scene *s = plane_scene(ctx, 100.0f * k);
        vdbgi_bake_desc d = plane_desc(4096, 40.0f * k, 4.0f * k, VDBGI_SAMPLING_FIBONACCI);
        memcpy(d.sun_dir, sun, sizeof(sun));
        const float pts[3] = {0.1f * k, 1.5f * k, 0.2f * k};
        float rgb[3];
        CHECK_RESULT(ctx, vdbgi_scene_bake_points(s, &d, pts, 1, rgb, NULL), VDBGI_OK);
        const double want = plane_closed_form(1.5, 40.0, 4.0, ndotl);
        CHECK_NEAR(rgb[0], want, 4e-3 * want);
        vdbgi_scene_destroy(s);
        vdbgi_context_destroy(ctx);
    }
}

/* A closed box from -2 to 2 m on every axis, albedo 0.8, its faces outward. */
static vdbgi_scene *box_scene(vdbgi_context *ctx)
{
    test_mesh m = {0};
    const float lo[3] = {-2, -2, -2}, hi[3] = {2, 2, 2};
    test_mesh_box(&m, lo, hi, 0);
    const vdbgi_mesh_desc md = test_mesh_desc(&m, 0.8f, 0);
    vdbgi_scene *s = NULL;
    CHECK_RESULT(ctx, vdbgi_scene_create(ctx, &md, 1, &s), VDBGI_OK);
    return s;
}

static void probes_inside_a_solid_are_invalid(void)
{
    vdbgi_context *ctx = test_context();
    vdbgi_scene *s = box_scene(ctx);
    vdbgi_probes *p = NULL;
    const vdbgi_place_desc pd = {.spacing = 0.5};
    CHECK_RESULT(ctx, vdbgi_probes_place(ctx, s, &pd, &p), VDBGI_OK);
    CHECK_RESULT(ctx, vdbgi_probes_bake(p, s, NULL, NULL), VDBGI_OK);
    vdbgi_probes_info info;
    vdbgi_probes_get_info(p, &info);
    size_t inside = 0, outside = 0;
    for (size_t i = 0; i < info.probe_count; i++) {
        int32_t ijk[3];
        float bf;
        vdbgi_probes_get(p, i, ijk, NULL, &bf);
        int in = 1;
        for (int k = 0; k < 3; k++)
            in &= fabs(info.origin[k] + 0.5 * ijk[k]) < 2.0;
        if (in) {
            CHECK(bf == 1.0f);
            inside++;
        } else {
            CHECK(bf <= info.invalid_threshold);
            outside++;
        }
    }
    CHECK(inside == 8 * 8 * 8 && outside > 0);
    CHECK(info.invalid_count == inside);
    vdbgi_probes_destroy(p);
    vdbgi_scene_destroy(s);
    vdbgi_context_destroy(ctx);
}

/* A plane and two boxes, one of them double-sided: enough to exercise every branch. */
static vdbgi_scene *mixed_scene(vdbgi_context *ctx)
{
    static test_mesh ground, solid, open;
    memset(&ground, 0, sizeof(ground));
    memset(&solid, 0, sizeof(solid));
    memset(&open, 0, sizeof(open));
    test_mesh_plane(&ground, 12.0f, 0.0f);
    const float lo1[3] = {-3, 0, -2}, hi1[3] = {-1, 3, 2};
    const float lo2[3] = {1, 0.5f, -1}, hi2[3] = {3, 1.5f, 1};
    test_mesh_box(&solid, lo1, hi1, 0);
    test_mesh_box(&open, lo2, hi2, 0);
    const vdbgi_mesh_desc md[3] = {test_mesh_desc(&ground, 0.3f, 0),
                                   test_mesh_desc(&solid, 0.7f, 0), test_mesh_desc(&open, 0.5f, 1)};
    vdbgi_scene *s = NULL;
    CHECK_RESULT(ctx, vdbgi_scene_create(ctx, md, 3, &s), VDBGI_OK);
    return s;
}

static void results_do_not_depend_on_thread_count(void)
{
    vdbgi_context *ctx = test_context();
    vdbgi_scene *s = mixed_scene(ctx);
    const vdbgi_place_desc pd = {.spacing = 0.5};
    for (int sampling = 0; sampling < 2; sampling++) {
        float *first_rgb = NULL, *first_bf = NULL;
        size_t n = 0;
        const int threads[] = {1, 2, 3, 7};
        for (int t = 0; t < 4; t++) {
            vdbgi_probes *p = NULL;
            CHECK_RESULT(ctx, vdbgi_probes_place(ctx, s, &pd, &p), VDBGI_OK);
            const vdbgi_bake_desc bd = {.rays = 64,
                                        .sampling = (vdbgi_sampling)sampling,
                                        .seed = 42,
                                        .threads = threads[t]};
            CHECK_RESULT(ctx, vdbgi_probes_bake(p, s, &bd, NULL), VDBGI_OK);
            vdbgi_probes_info info;
            vdbgi_probes_get_info(p, &info);
            if (t == 0) {
                n = info.probe_count;
                first_rgb = malloc(n * 3 * sizeof(float));
                first_bf = malloc(n * sizeof(float));
            }
            CHECK(info.probe_count == n);
            int same = 1;
            for (size_t i = 0; i < n && i < info.probe_count; i++) {
                float rgb[3], bf;
                vdbgi_probes_get(p, i, NULL, rgb, &bf);
                if (t == 0) {
                    memcpy(&first_rgb[3 * i], rgb, sizeof(rgb));
                    first_bf[i] = bf;
                } else {
                    same &= memcmp(&first_rgb[3 * i], rgb, sizeof(rgb)) == 0 &&
                            memcmp(&first_bf[i], &bf, sizeof(bf)) == 0;
                }
            }
            CHECK(same);
            vdbgi_probes_destroy(p);
        }
        free(first_rgb);
        free(first_bf);
    }
    vdbgi_scene_destroy(s);
    vdbgi_context_destroy(ctx);
}

static void random_sampling_differs_by_seed_and_probe(void)
{
    vdbgi_context *ctx = test_context();
    vdbgi_scene *s = mixed_scene(ctx);
    const float pts[6] = {0.2f, 0.7f, 0.1f, 0.2f, 0.7f, 0.1f};
    float a[6], b[6], fa[6];
    vdbgi_bake_desc d = {.rays = 16, .sampling = VDBGI_SAMPLING_RANDOM, .seed = 1};
    CHECK_RESULT(ctx, vdbgi_scene_bake_points(s, &d, pts, 2, a, NULL), VDBGI_OK);
    d.seed = 2;
    CHECK_RESULT(ctx, vdbgi_scene_bake_points(s, &d, pts, 2, b, NULL), VDBGI_OK);
    d.sampling = VDBGI_SAMPLING_FIBONACCI;
    CHECK_RESULT(ctx, vdbgi_scene_bake_points(s, &d, pts, 2, fa, NULL), VDBGI_OK);
    /* Same place, different stream (point index or seed): different rotation, different value. */
    CHECK(memcmp(&a[0], &a[3], 3 * sizeof(float)) != 0);
    CHECK(memcmp(&a[0], &b[0], 3 * sizeof(float)) != 0);
    /* The fixed set gives the same value at the same place. */
    CHECK(memcmp(&fa[0], &fa[3], 3 * sizeof(float)) == 0);
    vdbgi_scene_destroy(s);
    vdbgi_context_destroy(ctx);
}

static void sky_fills_misses_and_falloff_off_is_flat(void)
{
    vdbgi_context *ctx = test_context();
    vdbgi_scene *s = plane_scene(ctx, 100.0f);
    /* Far above the plane (beyond ray_dist) every ray misses: the value is the sky. */
    const vdbgi_bake_desc d = {.rays = 100, .ray_dist = 5.0f, .sky = {0.1f, 0.2f, 0.3f}};
    const float pts[3] = {0.0f, 20.0f, 0.0f};
    float rgb[3];
    CHECK_RESULT(ctx, vdbgi_scene_bake_points(s, &d, pts, 1, rgb, NULL), VDBGI_OK);
    CHECK_NEAR(rgb[0], 0.1, 1e-6);
    CHECK_NEAR(rgb[1], 0.2, 1e-6);
    CHECK_NEAR(rgb[2], 0.3, 1e-6);
    vdbgi_scene_destroy(s);
    vdbgi_context_destroy(ctx);
}

static void trace_methods_agree(void)
{
    vdbgi_context *ctx = test_context();
    vdbgi_scene *s = mixed_scene(ctx);
    const float pts[6] = {0.2f, 0.7f, 0.1f, -0.5f, 3.5f, 1.0f};
    float ref[6], rgb[6];
    vdbgi_bake_desc d = {.rays = 100, .trace_method = VDBGI_TRACE_SINGLE};
    CHECK_RESULT(ctx, vdbgi_scene_bake_points(s, &d, pts, 2, ref, NULL), VDBGI_OK);
    for (int m = VDBGI_TRACE_PACKET8; m <= VDBGI_TRACE_STREAM; m++) {
        d.trace_method = (vdbgi_trace_method)m;
        CHECK_RESULT(ctx, vdbgi_scene_bake_points(s, &d, pts, 2, rgb, NULL), VDBGI_OK);
        for (int i = 0; i < 6; i++)
            CHECK_NEAR(rgb[i], ref[i], 1e-6);
    }
    vdbgi_scene_destroy(s);
    vdbgi_context_destroy(ctx);
}

/*
 * The desc convention (vdbgi.h): a field holding zero takes its default; with
 * its _is_set flag, zero is taken as given; a value given is used with or
 * without the flag.
 */
static void zero_means_default_unless_flagged(void)
{
    vdbgi_context *ctx = test_context();
    vdbgi_scene *s = box_scene(ctx);
    /* With no margin, only the lattice points on the box's faces: 6 x 9 x 9 less the edges. */
    const vdbgi_place_desc descs[5] = {{.spacing = 0.5},
                                       {.spacing = 0.5, .margin_is_set = 1, .origin_is_set = 1},
                                       {.spacing = 0.5, .origin_is_set = 1},
                                       {.spacing = 0.5, .origin = {0.1, 0.0, 0.0}},
                                       {.spacing = 0.5, .margin = 1.0}};
    vdbgi_probes_info info[5];
    for (int i = 0; i < 5; i++) {
        vdbgi_probes *p = NULL;
        CHECK_RESULT(ctx, vdbgi_probes_place(ctx, s, &descs[i], &p), VDBGI_OK);
        if (p)
            vdbgi_probes_get_info(p, &info[i]);
        else
            memset(&info[i], 0, sizeof(info[i]));
        vdbgi_probes_destroy(p);
    }
    CHECK(info[0].margin == 2.0 && info[0].origin[0] == 0.25 && info[0].origin[1] == 0.25);
    CHECK(info[1].margin == 0.0 && info[1].probe_count == 9 * 9 * 9 - 7 * 7 * 7);
    CHECK(info[2].origin[0] == 0.0 && info[2].origin[1] == 0.0 && info[2].origin[2] == 0.0);
    CHECK(info[3].origin[0] == 0.1 && info[3].origin[1] == 0.0 && info[3].origin[2] == 0.0);
    CHECK(info[4].margin == 1.0 && info[4].probe_count < info[0].probe_count);
    vdbgi_scene_destroy(s);
    vdbgi_context_destroy(ctx);
}

/*
 * gi-bake --walkable: on a 20 m floor (y = 0) with an 8 m wall standing on it
 * (x = 0), the probes kept are those the rule keeps, worked out here by hand:
 * a lattice point stands over the floor when it is within the height above it
 * or a spacing under it (and over its extent); a probe is kept when it or one
 * of its 26 neighbours stands so. A keep box adds its probes; tiles keep what
 * the whole lattice keeps.
 */
static bool over_floor(double x, double y, double z, double height, double spacing)
{
    return fabs(x) < 10.0 && fabs(z) < 10.0 &&
           ((y > 0.0 && y <= height) || (y < 0.0 && y >= -spacing));
}

static void walkable_keeps_the_space_over_floors(void)
{
    vdbgi_context *ctx = test_context();
    static test_mesh floor_, wall;
    memset(&floor_, 0, sizeof(floor_));
    memset(&wall, 0, sizeof(wall));
    test_mesh_plane(&floor_, 20.0f, 0.0f);
    const float a[3] = {0, 0, -5}, b[3] = {0, 0, 5}, c[3] = {0, 8, 5}, d[3] = {0, 8, -5};
    test_mesh_quad(&wall, a, b, c, d);
    const vdbgi_mesh_desc md[2] = {test_mesh_desc(&floor_, 0.5f, 0),
                                   test_mesh_desc(&wall, 0.5f, 1)};
    vdbgi_scene *s = NULL;
    CHECK_RESULT(ctx, vdbgi_scene_create(ctx, md, 2, &s), VDBGI_OK);
    const double spacing = 0.5, height = 2.0;
    const double box[1][6] = {{0.5, 5.0, -1.0, 1.5, 6.0, 1.0}}; /* up the wall, over no floor */
    vdbgi_probes *all = NULL, *kept = NULL, *boxed = NULL;
    const vdbgi_place_desc every = {.spacing = spacing, .margin = 2.0};
    const vdbgi_place_desc walk = {.spacing = spacing, .margin = 2.0, .walkable_height = height};
    const vdbgi_place_desc only_box = {
        .spacing = spacing, .margin = 2.0, .keep_boxes = box, .keep_box_count = 1};
    CHECK_RESULT(ctx, vdbgi_probes_place(ctx, s, &every, &all), VDBGI_OK);
    CHECK_RESULT(ctx, vdbgi_probes_place(ctx, s, &walk, &kept), VDBGI_OK);
    CHECK_RESULT(ctx, vdbgi_probes_place(ctx, s, &only_box, &boxed), VDBGI_OK);
    if (all && kept && boxed) {
        vdbgi_probes_info ia, ik, ib;
        vdbgi_probes_get_info(all, &ia);
        vdbgi_probes_get_info(kept, &ik);
        vdbgi_probes_get_info(boxed, &ib);
        size_t want = 0, in_box = 0, j = 0, wrong = 0;
        for (size_t i = 0; i < ia.probe_count; i++) {
            int32_t ijk[3];
            vdbgi_probes_get(all, i, ijk, NULL, NULL);
            double pos[3];
            for (int k = 0; k < 3; k++)
                pos[k] = ia.origin[k] + spacing * ijk[k];
            bool keep = false;
            for (int n = 0; n < 27; n++)
                keep |=
                    over_floor(pos[0] + spacing * (n % 3 - 1), pos[1] + spacing * (n / 3 % 3 - 1),
                               pos[2] + spacing * (n / 9 - 1), height, spacing);
            in_box += pos[0] >= box[0][0] && pos[1] >= box[0][1] && pos[2] >= box[0][2] &&
                      pos[0] <= box[0][3] && pos[1] <= box[0][4] && pos[2] <= box[0][5];
            if (!keep)
                continue;
            want++;
            /* Both lists keep the placement's order. */
            int32_t got[3] = {0, 0, 0};
            if (j < ik.probe_count)
                vdbgi_probes_get(kept, j++, got, NULL, NULL);
            wrong += memcmp(got, ijk, sizeof(got)) != 0;
        }
        CHECK(want > 1000 && want < ia.probe_count && ik.probe_count == want && wrong == 0);
        CHECK(in_box > 0 && ib.probe_count == in_box);
        /* Two tiles of it keep the whole lattice's probes. */
        size_t tiled = 0;
        for (int t = 0; t < 2; t++) {
            vdbgi_probes *tile = NULL;
            vdbgi_place_desc td = walk;
            td.tile_index = t;
            td.tile_count = 2;
            CHECK_RESULT(ctx, vdbgi_probes_place(ctx, s, &td, &tile), VDBGI_OK);
            if (tile) {
                vdbgi_probes_info it;
                vdbgi_probes_get_info(tile, &it);
                tiled += it.probe_count;
            }
            vdbgi_probes_destroy(tile);
        }
        CHECK(tiled == want);
    }
    const vdbgi_place_desc bad = {.spacing = spacing, .walkable_height = -1.0};
    vdbgi_probes *none = NULL;
    CHECK_RESULT(ctx, vdbgi_probes_place(ctx, s, &bad, &none), VDBGI_ERR_INVALID_ARG);
    vdbgi_probes_destroy(all);
    vdbgi_probes_destroy(kept);
    vdbgi_probes_destroy(boxed);
    vdbgi_scene_destroy(s);
    vdbgi_context_destroy(ctx);
}

static void bare_trace_counts_the_same_rays(void)
{
    vdbgi_context *ctx = test_context();
    vdbgi_scene *s = mixed_scene(ctx);
    vdbgi_probes *p = NULL;
    CHECK_RESULT(ctx, vdbgi_probes_place(ctx, s, NULL, &p), VDBGI_OK);
    const vdbgi_bake_desc d = {.rays = 32};
    vdbgi_bake_stats bake, bare;
    CHECK_RESULT(ctx, vdbgi_probes_bake(p, s, &d, &bake), VDBGI_OK);
    CHECK_RESULT(ctx, vdbgi_probes_trace_bare(p, s, &d, &bare), VDBGI_OK);
    CHECK(bake.primary_ray_count == bare.primary_ray_count);
    CHECK(bake.shadow_ray_count == bare.shadow_ray_count && bake.shadow_ray_count > 0);
    CHECK(bake.hit_count == bare.hit_count);
    vdbgi_probes_destroy(p);
    vdbgi_scene_destroy(s);
    vdbgi_context_destroy(ctx);
}

static void bad_bake_parameters_are_refused(void)
{
    vdbgi_context *ctx = test_context();
    vdbgi_scene *s = mixed_scene(ctx);
    const float pt[3] = {0, 1, 0};
    float rgb[3];
    vdbgi_bake_desc bad[14];
    memset(bad, 0, sizeof(bad));
    bad[0].rays = -2;
    bad[1].rays = 2000000;
    bad[2].ray_dist = -1.0f;
    bad[3].ambient = -0.5f;
    bad[4].sun_dir[0] = NAN;
    bad[5].sun_color[1] = -1.0f;
    bad[6].falloff = -4.0f;
    bad[7].sky[2] = INFINITY;
    bad[8].sampling = (vdbgi_sampling)7;
    bad[9].threads = -2;
    bad[10].invalid_threshold = 1.5f;
    bad[11].trace_method = (vdbgi_trace_method)9;
    bad[12].ambient = -1.0f; /* a mistyped negative is no default */
    bad[13].basis = (vdbgi_basis)3;
    for (int i = 0; i < 14; i++) {
        CHECK_RESULT(ctx, vdbgi_scene_bake_points(s, &bad[i], pt, 1, rgb, NULL),
                     VDBGI_ERR_INVALID_ARG);
        CHECK(strlen(vdbgi_context_error(ctx)) > 0);
    }
    const float nan_pt[3] = {0, NAN, 0};
    CHECK_RESULT(ctx, vdbgi_scene_bake_points(s, NULL, nan_pt, 1, rgb, NULL),
                 VDBGI_ERR_INVALID_ARG);

    vdbgi_probes *p = (vdbgi_probes *)1;
    const vdbgi_place_desc badp[4] = {
        {.spacing = -1.0}, {.spacing = NAN}, {.margin = -3.0}, {.spacing = 1e-9}};
    for (int i = 0; i < 4; i++) {
        CHECK_RESULT(ctx, vdbgi_probes_place(ctx, s, &badp[i], &p), VDBGI_ERR_INVALID_ARG);
        CHECK(p == NULL);
        p = (vdbgi_probes *)1;
    }
    /* Too many probes: refused up front, naming the count and the memory. */
    const vdbgi_place_desc many = {.spacing = 0.05, .max_probes = 1000};
    CHECK_RESULT(ctx, vdbgi_probes_place(ctx, s, &many, &p), VDBGI_ERR_OUT_OF_MEMORY);
    CHECK(strstr(vdbgi_context_error(ctx), "probes") && strstr(vdbgi_context_error(ctx), "GiB"));
    /* Just over the limit: the exact count decides. */
    const vdbgi_place_desc tight = {.spacing = 0.5, .max_probes = 10};
    CHECK_RESULT(ctx, vdbgi_probes_place(ctx, s, &tight, &p), VDBGI_ERR_OUT_OF_MEMORY);
    CHECK(strstr(vdbgi_context_error(ctx), "above the limit of 10") != NULL);
    CHECK(p == NULL);
    vdbgi_scene_destroy(s);
    vdbgi_context_destroy(ctx);
}

static int cancel_at_half(void *user, float done)
{
    int *const calls = user;
    (*calls)++;
    return done >= 0.5f;
}

static void progress_is_reported_and_can_cancel(void)
{
    vdbgi_context *ctx = test_context();
    vdbgi_scene *s = mixed_scene(ctx);
    vdbgi_probes *p = NULL;
    CHECK_RESULT(ctx, vdbgi_probes_place(ctx, s, NULL, &p), VDBGI_OK);
    int calls = 0;
    vdbgi_bake_desc d = {
        .rays = 16, .threads = 1, .progress = cancel_at_half, .progress_user = &calls};
    CHECK_RESULT(ctx, vdbgi_probes_bake(p, s, &d, NULL), VDBGI_ERR_CANCELLED);
    CHECK(calls >= 1 && calls <= 101);
    vdbgi_probes_info info;
    vdbgi_probes_get_info(p, &info);
    CHECK(!info.baked); /* a cancelled bake leaves no half-written values */
    vdbgi_probes_destroy(p);
    vdbgi_scene_destroy(s);
    vdbgi_context_destroy(ctx);
}

/* Every allocation the pipeline makes may fail: each failure is reported and nothing leaks. */
static void failing_allocations_are_reported_without_leaks(void)
{
    test_mesh m = {0};
    test_mesh_plane(&m, 4.0f, 0.0f);
    const vdbgi_mesh_desc md = test_mesh_desc(&m, 0.5f, 0);
    int succeeded = 0;
    for (long n = 0; n < 200 && !succeeded; n++) {
        test_alloc a = {0, n, 0};
        const vdbgi_context_desc cd = {.alloc = test_alloc_fn, .free = test_free_fn, .user = &a};
        vdbgi_context *ctx = NULL;
        vdbgi_result r = vdbgi_context_create(&cd, &ctx);
        vdbgi_scene *s = NULL;
        vdbgi_probes *p = NULL;
        if (r == VDBGI_OK)
            r = vdbgi_scene_create(ctx, &md, 1, &s);
        if (r == VDBGI_OK)
            r = vdbgi_probes_place(ctx, s, NULL, &p);
        const vdbgi_bake_desc bd = {.rays = 8, .threads = 2};
        if (r == VDBGI_OK)
            r = vdbgi_probes_bake(p, s, &bd, NULL);
        CHECK(r == VDBGI_OK || r == VDBGI_ERR_OUT_OF_MEMORY);
        if (r != VDBGI_OK && p) {
            vdbgi_probes_info info;
            vdbgi_probes_get_info(p, &info);
            CHECK(!info.baked);
        }
        succeeded = r == VDBGI_OK;
        vdbgi_probes_destroy(p);
        vdbgi_scene_destroy(s);
        vdbgi_context_destroy(ctx);
        CHECK(a.live == 0);
    }
    CHECK(succeeded);
}

/* Seed 000's estimator seen by a surface facing down at the plane (cosine-weighted, normalised). */
static double plane_facing_down_closed_form(double h, double ray_dist, double falloff)
{
    /* 2 int_{h/R}^1 rho (a + 1) mu^3 / (mu^2 + c^2) dmu with c = h / falloff. */
    const double m0 = h / ray_dist, c2 = isfinite(falloff) ? (h / falloff) * (h / falloff) : 0.0;
    return rho * (ambient + 1.0) * ((1.0 - m0 * m0) - c2 * log((1.0 + c2) / (m0 * m0 + c2)));
}

static void ambient_cube_above_a_plane_matches_closed_form(void)
{
    vdbgi_context *ctx = test_context();
    vdbgi_scene *s = plane_scene(ctx, 24.0f);
    const vdbgi_place_desc pd = {.spacing = 1.0, .margin = 2.0};
    vdbgi_probes *p = NULL;
    CHECK_RESULT(ctx, vdbgi_probes_place(ctx, s, &pd, &p), VDBGI_OK);
    const float falloffs[2] = {4.0f, INFINITY};
    for (int f = 0; f < 2; f++) {
        vdbgi_bake_desc bd = plane_desc(4096, 10.0f, falloffs[f], VDBGI_SAMPLING_FIBONACCI);
        bd.basis = VDBGI_BASIS_AMBIENT_CUBE;
        CHECK_RESULT(ctx, vdbgi_probes_bake(p, s, &bd, NULL), VDBGI_OK);
        vdbgi_probes_info info;
        vdbgi_probes_get_info(p, &info);
        CHECK(info.basis == VDBGI_BASIS_AMBIENT_CUBE);
        size_t checked = 0;
        for (size_t i = 0; i < info.probe_count; i++) {
            int32_t ijk[3];
            float cube[6][3];
            vdbgi_probes_get(p, i, ijk, NULL, NULL);
            const double x = info.origin[0] + ijk[0], y = info.origin[1] + ijk[1],
                         z = info.origin[2] + ijk[2];
            if (fabs(x) > 1.0 || fabs(z) > 1.0 || y < 0.0)
                continue;
            CHECK_RESULT(ctx, vdbgi_probes_get_cube(p, i, cube), VDBGI_OK);
            const double down = plane_facing_down_closed_form(y, 10.0, falloffs[f]);
            CHECK_NEAR(cube[VDBGI_SIDE_NY][0], down, 4e-3 * down);
            CHECK(cube[VDBGI_SIDE_PY][0] == 0.0f); /* facing the black sky */
            /* Sideways: between the two, and the same on all four sides. */
            for (int side = VDBGI_SIDE_PX; side <= VDBGI_SIDE_NZ; side++) {
                if (side == VDBGI_SIDE_PY || side == VDBGI_SIDE_NY)
                    continue;
                CHECK(cube[side][0] > 0.0f && cube[side][0] < down);
                CHECK_NEAR(cube[side][0], cube[VDBGI_SIDE_PX][0], 0.01 * cube[VDBGI_SIDE_PX][0]);
            }
            checked++;
        }
        CHECK(checked == 4 * 2);
    }
    vdbgi_probes_destroy(p);
    vdbgi_scene_destroy(s);
    vdbgi_context_destroy(ctx);
}

static void ambient_cube_in_uniform_surroundings_agrees_and_keeps_the_scalar(void)
{
    vdbgi_context *ctx = test_context();
    test_mesh m = {0};
    const float lo[3] = {-2, -2, -2}, hi[3] = {2, 2, 2};
    test_mesh_box(&m, lo, hi, 1);
    vdbgi_scene *const s = mesh_scene(ctx, &m);
    vdbgi_probes *p = NULL;
    const vdbgi_place_desc pd = {.spacing = 0.5};
    CHECK_RESULT(ctx, vdbgi_probes_place(ctx, s, &pd, &p), VDBGI_OK);
    vdbgi_bake_desc bd = {.rays = 300, .falloff = INFINITY, .sampling = VDBGI_SAMPLING_RANDOM};
    CHECK_RESULT(ctx, vdbgi_probes_bake(p, s, &bd, NULL), VDBGI_OK);
    vdbgi_probes_info info;
    vdbgi_probes_get_info(p, &info);
    float *const scalar = malloc(info.probe_count * 3 * sizeof(float));
    for (size_t i = 0; i < info.probe_count; i++)
        vdbgi_probes_get(p, i, NULL, &scalar[3 * i], NULL);
    float cube[6][3];
    CHECK_RESULT(ctx, vdbgi_probes_get_cube(p, 0, cube), VDBGI_ERR_INVALID_ARG);
    bd.basis = VDBGI_BASIS_AMBIENT_CUBE;
    CHECK_RESULT(ctx, vdbgi_probes_bake(p, s, &bd, NULL), VDBGI_OK);
    size_t inside = 0;
    int same = 1;
    for (size_t i = 0; i < info.probe_count; i++) {
        int32_t ijk[3];
        float rgb[3], bf;
        vdbgi_probes_get(p, i, ijk, rgb, &bf);
        same &= memcmp(rgb, &scalar[3 * i], sizeof(rgb)) == 0;
        int in = 1;
        for (int k = 0; k < 3; k++)
            in &= fabs(info.origin[k] + 0.5 * ijk[k]) < 1.9;
        if (!in)
            continue;
        /* Every ray hits a wall of albedo rho lit by ambient alone: every side reads rho x ambient. */
        vdbgi_probes_get_cube(p, i, cube);
        for (int side = 0; side < 6; side++)
            CHECK_NEAR(cube[side][1], rho * ambient, 1e-6);
        inside++;
    }
    CHECK(same); /* the scalar keeps its bits */
    CHECK(inside > 100);
    free(scalar);
    vdbgi_probes_destroy(p);
    vdbgi_scene_destroy(s);
    vdbgi_context_destroy(ctx);
}

/*
 * L2 probes over a plane lit from above, falloff off: uniform radiance L from
 * below (out to ray_dist), black sky. A surface facing down reads the plane's
 * full value, one facing up nothing, one facing sideways about half: the sphere's
 * mean (the scalar basis) reads half for all three. At the probes, the
 * sampler returns what the terms say for any normal.
 */
static void sh2_above_a_plane_reads_each_side(void)
{
    vdbgi_context *ctx = test_context();
    vdbgi_scene *s = plane_scene(ctx, 24.0f);
    const vdbgi_place_desc pd = {.spacing = 1.0, .margin = 2.0};
    vdbgi_probes *p = NULL;
    CHECK_RESULT(ctx, vdbgi_probes_place(ctx, s, &pd, &p), VDBGI_OK);
    vdbgi_bake_desc bd = plane_desc(4096, 10.0f, INFINITY, VDBGI_SAMPLING_FIBONACCI);
    bd.basis = VDBGI_BASIS_SH2;
    CHECK_RESULT(ctx, vdbgi_probes_bake(p, s, &bd, NULL), VDBGI_OK);
    vdbgi_probes_info info;
    vdbgi_probes_get_info(p, &info);
    CHECK(info.basis == VDBGI_BASIS_SH2);
    static const float normals[6][3] = {{0, -1, 0}, {0, 1, 0},       {1, 0, 0},
                                        {0, 0, -1}, {0.6f, 0, 0.8f}, {-0.8f, 0, 0.6f}};
    size_t checked = 0;
    double scalar_worst = 0.0;
    for (size_t i = 0; i < info.probe_count; i++) {
        int32_t ijk[3];
        float sh[VDBGI_SH2_TERMS][3], e[6][3], got[6][3], pos[6][3];
        vdbgi_probes_get(p, i, ijk, NULL, NULL);
        const double x = info.origin[0] + ijk[0], y = info.origin[1] + ijk[1],
                     z = info.origin[2] + ijk[2];
        if (fabs(x) > 1.0 || fabs(z) > 1.0 || y < 0.0)
            continue;
        CHECK_RESULT(ctx, vdbgi_probes_get_sh2(p, i, sh), VDBGI_OK);
        /* Rays end at ray_dist: the plane fills a cone of half-angle a about straight down. */
        const double down = plane_facing_down_closed_form(y, 10.0, INFINITY);
        const double a = acos(y / 10.0), L = rho * (ambient + 1.0);
        const double side = L * (a - sin(a) * cos(a)) / 3.14159265358979;
        for (int n = 0; n < 6; n++) {
            vdbgi_sh2_eval(sh, normals[n], e[n]);
            pos[n][0] = (float)x, pos[n][1] = (float)y, pos[n][2] = (float)z;
        }
        /* L2's own truncation of the cone's edge: within 2.5 %. */
        CHECK_NEAR(e[0][0], down, 0.025 * down);
        CHECK_NEAR(e[1][0], 0.0, 0.025 * down);
        for (int n = 2; n < 6; n++)
            CHECK_NEAR(e[n][0], side, 0.025 * down);
        /* The scalar is the sphere's mean: half of the plane's value whichever way a surface faces. */
        scalar_worst = fmax(scalar_worst, fabs(sh[0][0] - down) / down);
        CHECK_RESULT(ctx, vdbgi_probes_sample_points(p, 6, pos[0], normals[0], 0.0f, got[0], NULL),
                     VDBGI_OK);
        for (int n = 0; n < 6; n++)
            CHECK_NEAR(got[n][0], e[n][0], 1e-6);
        checked++;
    }
    CHECK(checked == 4 * 2);
    CHECK(scalar_worst > 0.4);
    vdbgi_probes_destroy(p);
    vdbgi_scene_destroy(s);
    vdbgi_context_destroy(ctx);
}

/*
 * Probes hold their L2 terms as half-float ratios to L0 (probes.h): each term
 * reads within a half's rounding of the same estimate in floats at the same
 * point (2^-11 of itself, and the float division and product, or where the
 * ratio is below the halves' normal range 2^-25 of L0), channel by channel
 * under coloured light (a term scaled by another channel's L0 would be off
 * by the colours' ratio). Terms held exactly would prove nothing: most must
 * differ.
 */
/*
 * Bounces trace their own directions: the directional sides of a probe whose
 * rays turn with it (a random rotation, auto) must come out as the fixed set's
 * do, under the physical model's bounces too. Their directions once went into
 * the primaries' buffer, which the sides then read: 3x off with a sky.
 */
static void rotated_rays_keep_their_directions_through_bounces(void)
{
    vdbgi_context *ctx = test_context();
    test_mesh m = {0};
    test_mesh_plane(&m, 12.0f, 0.0f);
    const float lo[3] = {-1, 0, -1}, hi[3] = {1, 2, 1};
    test_mesh_box(&m, lo, hi, 0);
    const vdbgi_mesh_desc md = test_mesh_desc(&m, 0.6f, 0);
    vdbgi_scene *s = NULL;
    CHECK_RESULT(ctx, vdbgi_scene_create(ctx, &md, 1, &s), VDBGI_OK);
    const vdbgi_place_desc pd = {.spacing = 1.0, .margin = 1.5};
    vdbgi_probes *p[3] = {NULL, NULL, NULL};
    for (int way = 0; way < 3; way++) {
        const vdbgi_bake_desc bd = {.rays = way < 2 ? 4096 : 0,
                                    .adaptive = way == 2,
                                    .max_rays = way == 2 ? 4096 : 0,
                                    .noise = way == 2 ? 0.001f : 0.0f,
                                    .sampling =
                                        way ? VDBGI_SAMPLING_RANDOM : VDBGI_SAMPLING_FIBONACCI,
                                    .basis = VDBGI_BASIS_AMBIENT_CUBE,
                                    .model = VDBGI_MODEL_PHYSICAL,
                                    .bounces = 2,
                                    .sky = {0.4f, 0.5f, 0.7f}};
        CHECK_RESULT(ctx, vdbgi_probes_place(ctx, s, &pd, &p[way]), VDBGI_OK);
        CHECK_RESULT(ctx, vdbgi_probes_bake(p[way], s, &bd, NULL), VDBGI_OK);
    }
    vdbgi_probes_info info = {0};
    if (p[0])
        vdbgi_probes_get_info(p[0], &info);
    double worst[3] = {0.0, 0.0, 0.0};
    size_t compared = 0;
    for (size_t i = 0; p[1] && p[2] && i < info.probe_count; i++) {
        float bf, cube[3][6][3];
        vdbgi_probes_get(p[0], i, NULL, NULL, &bf);
        if (bf > info.invalid_threshold)
            continue;
        for (int way = 0; way < 3; way++)
            vdbgi_probes_get_cube(p[way], i, cube[way]);
        for (int side = 0; side < 6; side++)
            for (int way = 1; way < 3; way++) {
                const double a = cube[0][side][2], b = cube[way][side][2];
                worst[way] = fmax(worst[way], fabs(b - a) / fmax(a, 1e-3));
            }
        compared++;
    }
    CHECK(compared > 100);
    CHECK(worst[1] < 0.05 && worst[2] < 0.05);
    for (int way = 0; way < 3; way++)
        vdbgi_probes_destroy(p[way]);
    vdbgi_scene_destroy(s);
    vdbgi_context_destroy(ctx);
}

static void sh2_probes_hold_each_term_to_half_precision(void)
{
    vdbgi_context *ctx = test_context();
    test_mesh m = {0};
    test_mesh_plane(&m, 8.0f, 0.0f);
    const float lo[3] = {-1, 0, -1}, hi[3] = {0.5f, 1.5f, 1};
    test_mesh_box(&m, lo, hi, 0);
    vdbgi_scene *const s = mesh_scene(ctx, &m);
    vdbgi_probes *p = NULL;
    const vdbgi_place_desc pd = {.spacing = 0.5};
    CHECK_RESULT(ctx, vdbgi_probes_place(ctx, s, &pd, &p), VDBGI_OK);
    const vdbgi_bake_desc bd = {.rays = 64,
                                .sun_dir = {0.3f, 1.0f, 0.2f},
                                .sun_color = {3.0f, 1.0f, 0.25f},
                                .sky = {0.02f, 0.05f, 0.2f},
                                .basis = VDBGI_BASIS_SH2};
    CHECK_RESULT(ctx, vdbgi_probes_bake(p, s, &bd, NULL), VDBGI_OK);
    vdbgi_probes_info info;
    vdbgi_probes_get_info(p, &info);
    float *const at = calloc(info.probe_count, 3 * sizeof(float));
    float *const want = calloc(info.probe_count, 27 * sizeof(float));
    CHECK(at && want);
    for (size_t i = 0; at && i < info.probe_count; i++) {
        int32_t ijk[3];
        vdbgi_probes_get(p, i, ijk, NULL, NULL);
        for (int k = 0; k < 3; k++) /* as the bake places it */
            at[3 * i + k] = (float)(info.origin[k] + info.spacing * ijk[k]);
    }
    CHECK_RESULT(ctx, vdbgi_scene_bake_points_sh2(s, &bd, at, info.probe_count, want), VDBGI_OK);
    size_t worse = 0, differ = 0, terms = 0;
    for (size_t i = 0; want && i < info.probe_count; i++) {
        float sh[VDBGI_SH2_TERMS][3];
        vdbgi_probes_get_sh2(p, i, sh);
        for (int t = 0; t < VDBGI_SH2_TERMS; t++)
            for (int k = 0; k < 3; k++) {
                const float w = want[27 * i + 3 * t + k];
                const float c0 = want[27 * i + k];
                worse += !(fabsf(sh[t][k] - w) <=
                           ldexpf(fabsf(w), -11) * (1.0f + ldexpf(1.0f, -21)) + ldexpf(c0, -25));
                differ += sh[t][k] != w;
                terms += t > 0 && w != 0.0f;
            }
    }
    CHECK(worse == 0);
    CHECK(terms > 1000 && differ > terms / 2);
    free(at);
    free(want);
    vdbgi_probes_destroy(p);
    vdbgi_scene_destroy(s);
    vdbgi_context_destroy(ctx);
}

/* In a closed box lit only by the fill every direction brings the same light: E(n) is flat. */
static void sh2_in_uniform_surroundings_is_flat_and_thread_independent(void)
{
    vdbgi_context *ctx = test_context();
    test_mesh m = {0};
    const float lo[3] = {-2, -2, -2}, hi[3] = {2, 2, 2};
    test_mesh_box(&m, lo, hi, 1);
    const vdbgi_mesh_desc md = test_mesh_desc(&m, (float)rho, 0);
    vdbgi_scene *s = NULL;
    CHECK_RESULT(ctx, vdbgi_scene_create(ctx, &md, 1, &s), VDBGI_OK);
    vdbgi_probes *p = NULL, *q = NULL;
    const vdbgi_place_desc pd = {.spacing = 0.5};
    CHECK_RESULT(ctx, vdbgi_probes_place(ctx, s, &pd, &p), VDBGI_OK);
    CHECK_RESULT(ctx, vdbgi_probes_place(ctx, s, &pd, &q), VDBGI_OK);
    vdbgi_bake_desc bd = {.rays = 1024,
                          .falloff = INFINITY,
                          .sampling = VDBGI_SAMPLING_RANDOM,
                          .basis = VDBGI_BASIS_SH2,
                          .threads = 1};
    CHECK_RESULT(ctx, vdbgi_probes_bake(p, s, &bd, NULL), VDBGI_OK);
    bd.threads = 3;
    CHECK_RESULT(ctx, vdbgi_probes_bake(q, s, &bd, NULL), VDBGI_OK);
    vdbgi_probes_info info;
    vdbgi_probes_get_info(p, &info);
    size_t inside = 0;
    int same = 1;
    float worst = 0.0f;
    for (size_t i = 0; i < info.probe_count; i++) {
        int32_t ijk[3];
        float a[VDBGI_SH2_TERMS][3], b[VDBGI_SH2_TERMS][3];
        vdbgi_probes_get(p, i, ijk, NULL, NULL);
        vdbgi_probes_get_sh2(p, i, a);
        vdbgi_probes_get_sh2(q, i, b);
        same &= memcmp(a, b, sizeof(a)) == 0;
        int in = 1;
        for (int k = 0; k < 3; k++)
            in &= fabs(info.origin[k] + 0.5 * ijk[k]) < 1.9;
        if (!in)
            continue;
        for (int n = 0; n < 26; n++) { /* the 26 directions to a cube's faces, edges, corners */
            const int c = n < 13 ? n : n + 1; /* 13 is the centre */
            const int d[3] = {c % 3 - 1, c / 3 % 3 - 1, c / 9 - 1};
            const float len = sqrtf((float)(d[0] * d[0] + d[1] * d[1] + d[2] * d[2]));
            const float nrm[3] = {d[0] / len, d[1] / len, d[2] / len};
            float e[3];
            vdbgi_sh2_eval(a, nrm, e);
            worst = fmaxf(worst, fabsf(e[1] - (float)(rho * ambient)));
        }
        inside++;
    }
    CHECK(same); /* any thread count, the same bits */
    CHECK(inside > 100);
    CHECK(worst < 0.01f * (float)(rho * ambient));
    vdbgi_probes_destroy(p);
    vdbgi_probes_destroy(q);
    vdbgi_scene_destroy(s);
    vdbgi_context_destroy(ctx);
}

static void adaptive_rays_stop_early_where_light_is_even(void)
{
    vdbgi_context *ctx = test_context();
    /* A closed room, sun off, no falloff: every ray of an inside probe brings the same value. */
    test_mesh walls = {0}, pillar = {0};
    const float lo[3] = {-3, -3, -3}, hi[3] = {3, 3, 3};
    const float plo[3] = {1.0f, -3.0f, 1.0f}, phi[3] = {1.4f, 3.0f, 1.4f};
    test_mesh_box(&walls, lo, hi, 1);
    test_mesh_box(&pillar, plo, phi, 0);
    const vdbgi_mesh_desc md[2] = {test_mesh_desc(&walls, 0.5f, 0),
                                   test_mesh_desc(&pillar, 0.9f, 0)};
    vdbgi_scene *s = NULL;
    CHECK_RESULT(ctx, vdbgi_scene_create(ctx, md, 1, &s), VDBGI_OK);
    vdbgi_probes *p = NULL;
    const vdbgi_place_desc pd = {.spacing = 1.0, .margin = 8.0};
    CHECK_RESULT(ctx, vdbgi_probes_place(ctx, s, &pd, &p), VDBGI_OK);
    vdbgi_bake_desc d = {.adaptive = 1, .falloff = INFINITY, .threads = 1};
    d.sun_color_is_set = 1; /* with (0,0,0): no sun */
    vdbgi_bake_stats st;
    CHECK_RESULT(ctx, vdbgi_probes_bake(p, s, &d, &st), VDBGI_OK);
    vdbgi_probes_info info;
    vdbgi_probes_get_info(p, &info);
    for (size_t i = 0; i < info.probe_count; i++) {
        float se;
        uint32_t rays;
        float bf;
        vdbgi_probes_get(p, i, NULL, NULL, &bf);
        vdbgi_probes_get_noise(p, i, &se, &rays);
        if (bf == 0.0f)
            CHECK(se < 1e-6f && rays == 32); /* the pilot alone: it saw no spread */
    }
    CHECK(st.primary_ray_count < 32u * info.probe_count + 32u * info.invalid_count * 32u);
    vdbgi_probes_destroy(p);
    vdbgi_scene_destroy(s);
    /* With the pillar the light varies: probes take from the pilot alone to 6x it and more (7x
       when measured), the same on any thread count. */
    CHECK_RESULT(ctx, vdbgi_scene_create(ctx, md, 2, &s), VDBGI_OK);
    vdbgi_probes *q[2] = {NULL, NULL};
    d.sun_color[0] = d.sun_color[1] = d.sun_color[2] =
        0.0f; /* the sun on: its shadow of the pillar varies the most */
    d.max_rays = 512;
    d.noise = 0.01f;
    for (int t = 0; t < 2; t++) {
        CHECK_RESULT(ctx, vdbgi_probes_place(ctx, s, &pd, &q[t]), VDBGI_OK);
        d.threads = t + 1;
        CHECK_RESULT(ctx, vdbgi_probes_bake(q[t], s, &d, NULL), VDBGI_OK);
    }
    uint32_t most = 0, least = UINT32_MAX;
    int same = 1;
    vdbgi_probes_get_info(q[0], &info);
    for (size_t i = 0; i < info.probe_count; i++) {
        float a[3], b[3], sa, sb;
        uint32_t ra, rb;
        vdbgi_probes_get(q[0], i, NULL, a, NULL);
        vdbgi_probes_get(q[1], i, NULL, b, NULL);
        vdbgi_probes_get_noise(q[0], i, &sa, &ra);
        vdbgi_probes_get_noise(q[1], i, &sb, &rb);
        same &= memcmp(a, b, sizeof(a)) == 0 && sa == sb && ra == rb;
        most = ra > most ? ra : most;
        least = ra < least ? ra : least;
        CHECK(ra >= 32 && ra <= 512 && ra % 32 == 0);
    }
    CHECK(same && most >= 6 * 32 && least == 32);
    /*
     * The target is the noise the bake then measures and reports, met from under (within 15 %
     * when the cap allows): half of it takes more than twice the rays past the pilots (a
     * Fibonacci set's error falls faster than independent rays', whose 4x it would be).
     */
    d.max_rays = 1 << 16;
    d.threads = 0;
    uint64_t spent[2];
    double noise[2];
    for (int t = 0; t < 2; t++) {
        d.noise = t ? 0.007f : 0.01f;
        CHECK_RESULT(ctx, vdbgi_probes_bake(q[0], s, &d, &st), VDBGI_OK);
        spent[t] = st.primary_ray_count - 32u * st.probe_count; /* past the pilots */
        noise[t] = st.noise;
        CHECK(st.noise <= d.noise && st.noise > 0.5 * d.noise);
    }
    CHECK(spent[1] > 2 * spent[0] && noise[1] < noise[0]);
    const vdbgi_bake_desc fixed = {.adaptive = 1};
    CHECK_RESULT(ctx, vdbgi_probes_trace_bare(q[0], s, &fixed, &st), VDBGI_ERR_INVALID_ARG);
    const vdbgi_bake_desc bad[4] = {{.adaptive = 1, .noise = -1.0f},
                                    {.adaptive = 1, .max_rays = 10},
                                    {.rays = -7},
                                    {.adaptive = 1, .rays = 64}};
    for (int i = 0; i < 4; i++)
        CHECK_RESULT(ctx, vdbgi_probes_bake(q[0], s, &bad[i], NULL), VDBGI_ERR_INVALID_ARG);
    vdbgi_probes_destroy(q[0]);
    vdbgi_probes_destroy(q[1]);
    vdbgi_scene_destroy(s);
    vdbgi_context_destroy(ctx);
}

static void standard_error_tracks_the_actual_error(void)
{
    /* Above the plane the closed form is the truth: the stored standard error should bound the
       actual error of random sampling, without overstating it by an order of magnitude. */
    vdbgi_context *ctx = test_context();
    vdbgi_scene *s = plane_scene(ctx, 24.0f);
    const vdbgi_place_desc pd = {.spacing = 0.5, .margin = 2.0};
    vdbgi_probes *p = NULL;
    CHECK_RESULT(ctx, vdbgi_probes_place(ctx, s, &pd, &p), VDBGI_OK);
    const vdbgi_bake_desc d = plane_desc(64, 10.0f, 4.0f, VDBGI_SAMPLING_RANDOM);
    CHECK_RESULT(ctx, vdbgi_probes_bake(p, s, &d, NULL), VDBGI_OK);
    vdbgi_probes_info info;
    vdbgi_probes_get_info(p, &info);
    double err2 = 0.0, se2 = 0.0;
    size_t n = 0;
    for (size_t i = 0; i < info.probe_count; i++) {
        int32_t ijk[3];
        float rgb[3], se;
        vdbgi_probes_get(p, i, ijk, rgb, NULL);
        vdbgi_probes_get_noise(p, i, &se, NULL);
        const double x = info.origin[0] + 0.5 * ijk[0], y = info.origin[1] + 0.5 * ijk[1],
                     z = info.origin[2] + 0.5 * ijk[2];
        if (y < 0.0 || fabs(x) > 1.5 || fabs(z) > 1.5) /* the plane reaches past ray_dist */
            continue;
        const double want = plane_closed_form(y, 10.0, 4.0, 1.0);
        err2 += (rgb[0] - want) * (rgb[0] - want);
        se2 += (double)se * se;
        n++;
    }
    const double ratio = sqrt(err2 / se2);
    CHECK(n == 6 * 6 * 4);
    CHECK(ratio > 0.1 && ratio < 1.0);
    vdbgi_probes_destroy(p);
    vdbgi_scene_destroy(s);
    vdbgi_context_destroy(ctx);
}

/*
 * The noise a bake prints is its lattice's error: on a plane with three
 * blocks under a low sun, with 1 m probes to a 4 m margin and 0.5 m ones
 * to 2 m, the noise printed for 32 random rays is within 15 % of the RMSE,
 * over the mean, of every valid probe against a 1,024-ray bake of the same
 * probes (1.02 and 1.00 of it when written). Measured at points lifted off
 * the surfaces it was 1.26 and 1.16 of it here, and 0.64-0.72 on the
 * bundled world: they stood where a plane's probes do, never round a
 * block's edges.
 */
static void printed_noise_is_the_lattice_error(void)
{
    vdbgi_context *ctx = test_context();
    test_mesh ground = {0}, blocks[3];
    memset(blocks, 0, sizeof(blocks));
    test_mesh_plane(&ground, 16.0f, 0.0f);
    const float at[3][2] = {{-4.0f, -3.0f}, {2.0f, 1.0f}, {-1.0f, 4.0f}};
    vdbgi_mesh_desc md[4] = {test_mesh_desc(&ground, 0.6f, 0)};
    for (int b = 0; b < 3; b++) {
        const float lo[3] = {at[b][0], 0.0f, at[b][1]};
        const float hi[3] = {at[b][0] + 2.0f, 3.0f, at[b][1] + 1.5f};
        test_mesh_box(&blocks[b], lo, hi, 0);
        md[b + 1] = test_mesh_desc(&blocks[b], 0.8f, 0);
    }
    vdbgi_scene *s = NULL;
    CHECK_RESULT(ctx, vdbgi_scene_create(ctx, md, 4, &s), VDBGI_OK);
    /* 1 m probes to 4 m, and the defaults' proportion at 0.5 m: 2 m. */
    const vdbgi_place_desc pds[2] = {{.spacing = 1.0, .margin = 4.0},
                                     {.spacing = 0.5, .margin = 2.0}};
    for (int c = 0; c < 2; c++) {
        vdbgi_probes *p[2] = {NULL, NULL};
        vdbgi_bake_stats st;
        for (int t = 0; t < 2; t++) {
            const vdbgi_bake_desc d = {.rays = t ? 1024 : 32,
                                       .sampling = VDBGI_SAMPLING_RANDOM,
                                       .sun_dir = {0.5f, 0.4f, 0.3f},
                                       .sky = {0.3f, 0.4f, 0.6f}};
            CHECK_RESULT(ctx, vdbgi_probes_place(ctx, s, &pds[c], &p[t]), VDBGI_OK);
            CHECK_RESULT(ctx, vdbgi_probes_bake(p[t], s, &d, t ? NULL : &st), VDBGI_OK);
        }
        vdbgi_probes_info info;
        vdbgi_probes_get_info(p[0], &info);
        double sq = 0.0, mean = 0.0;
        size_t n = 0;
        for (size_t i = 0; i < info.probe_count; i++) {
            float a[3], b[3], bf;
            vdbgi_probes_get(p[0], i, NULL, a, &bf);
            vdbgi_probes_get(p[1], i, NULL, b, NULL);
            if (bf > info.invalid_threshold)
                continue;
            for (int k = 0; k < 3; k++)
                sq += ((double)a[k] - b[k]) * ((double)a[k] - b[k]), mean += b[k];
            n++;
        }
        const double rmse = n ? sqrt(sq / (3.0 * (double)n)) / (mean / (3.0 * (double)n)) : 0.0;
        CHECK(n > 1000 && rmse > 0.01);
        CHECK(st.noise > 0.85 * rmse && st.noise < 1.15 * rmse);
        vdbgi_probes_destroy(p[0]);
        vdbgi_probes_destroy(p[1]);
    }
    vdbgi_scene_destroy(s);
    vdbgi_context_destroy(ctx);
}

int main(void)
{
    RUN(probe_above_plane_matches_closed_form_fibonacci);
    RUN(probe_under_an_emitting_ceiling_matches_the_closed_form);
    RUN(probe_above_plane_matches_closed_form_random);
    RUN(lattice_probes_above_plane_match_and_below_are_invalid);
    RUN(closed_box_reads_albedo_times_ambient_at_any_scale);
    RUN(plane_under_slanted_sun_has_no_self_shadow_at_any_scale);
    RUN(probes_inside_a_solid_are_invalid);
    RUN(results_do_not_depend_on_thread_count);
    RUN(random_sampling_differs_by_seed_and_probe);
    RUN(sky_fills_misses_and_falloff_off_is_flat);
    RUN(trace_methods_agree);
    RUN(zero_means_default_unless_flagged);
    RUN(walkable_keeps_the_space_over_floors);
    RUN(bare_trace_counts_the_same_rays);
    RUN(bad_bake_parameters_are_refused);
    RUN(progress_is_reported_and_can_cancel);
    RUN(failing_allocations_are_reported_without_leaks);
    RUN(ambient_cube_above_a_plane_matches_closed_form);
    RUN(ambient_cube_in_uniform_surroundings_agrees_and_keeps_the_scalar);
    RUN(sh2_above_a_plane_reads_each_side);
    RUN(sh2_in_uniform_surroundings_is_flat_and_thread_independent);
    RUN(sh2_probes_hold_each_term_to_half_precision);
    RUN(rotated_rays_keep_their_directions_through_bounces);
    RUN(adaptive_rays_stop_early_where_light_is_even);
    RUN(standard_error_tracks_the_actual_error);
    RUN(printed_noise_is_the_lattice_error);
    return CHECK_EXIT();
}
