/*
 * test_lightmap.c: lightmap bakes against closed forms. A wall over a lit
 * floor: the probes' plane form transposed to a texel. A closed box of
 * uniform albedo and fill: pass N holds the Nth partial sum of the
 * geometric series. A floor under an emitting ceiling. Layers that add up
 * to the map. The same bytes on one thread and on two, rays fixed or auto;
 * auto's rays where the light varies. And a plan that tells a bake's
 * atlases before it.
 */
#define _POSIX_C_SOURCE 200809L
#include "test_baked.h"

#include <math.h>
#include <string.h>

static void bake(vdbgi_context *ctx, const vdbgi_mesh_desc *meshes, size_t mesh_count,
                 const vdbgi_bake_desc *bd, float texel, const vdbgi_lightmap_params *lp, baked *b)
{
    vdbgi_scene *scene = NULL;
    CHECK_RESULT(ctx, vdbgi_scene_create(ctx, meshes, mesh_count, &scene), VDBGI_OK);
    bake_map(ctx, scene, bd, texel, lp, b);
}

/*
 * A wall texel at height h over an infinite floor of albedo rho, lit by an
 * overhead sun of 1 and the fill a, sky s, no falloff, rays of length R: the
 * floor's radiance rho (a + 1) reaches it along the directions that meet
 * the floor within R, d_y < -h/R, and the sky along the rest. Cosine-
 * weighted, those are the part y < -c of the unit disk (Malley), a share
 * F = (acos c - c sqrt(1 - c^2)) / pi, c = h / R, so
 * E = pi (rho (a + 1) F + s (1 - F)). Baked with bd (its sky, sun and R
 * set here); the worst relative error over the wall's texels, *k kept for
 * the caller to unbake.
 */
static double a_wall_over_a_lit_floor(vdbgi_context *ctx, vdbgi_bake_desc bd, float sky, baked *k)
{
    test_mesh floor = {0}, wall = {0};
    test_mesh_plane(&floor, 40.0f, 0.0f);
    const float a[3] = {0, 0, 2}, b[3] = {0, 0, -2}, c[3] = {0, 4, -2}, d[3] = {0, 4, 2};
    test_mesh_quad(&wall, a, b, c, d); /* facing +x */
    const vdbgi_mesh_desc meshes[2] = {test_mesh_desc(&floor, 0.5f, 0),
                                       test_mesh_desc(&wall, 0.8f, 0)};
    bd.ray_dist = 10.0f;
    bd.sun_dir[1] = 1.0f;
    bd.sun_color[0] = bd.sun_color[1] = bd.sun_color[2] = 1.0f;
    bd.sky[0] = bd.sky[1] = bd.sky[2] = sky;
    bd.falloff = INFINITY;
    bd.threads = 2;
    const vdbgi_lightmap_params lp = {.passes = 1, .rings = 3};
    bake(ctx, meshes, 2, &bd, 1.0f, &lp, k);
    double worst = 0.0;
    size_t checked = 0;
    for (size_t i = 0; k->map.rgb && i < k->map.texel_count; i++) {
        const int32_t t = k->tx.tri[i];
        if (t < 0 || k->scene->tris[t].normal[0] < 0.5f)
            continue; /* wall texels only */
        const double h = k->tx.pos[3 * i + 1], cc = h / 10.0, pi = 3.14159265358979;
        const double F = (acos(cc) - cc * sqrt(1.0 - cc * cc)) / pi;
        const double want = pi * (0.5 * (0.15 + 1.0) * F + sky * (1.0 - F));
        CHECK(k->map.valid[i]);
        for (int ch = 0; ch < 3; ch++)
            worst = fmax(worst, fabs(k->map.rgb[3 * i + (size_t)ch] - want) / want);
        checked++;
    }
    CHECK(checked >= 16);
    return worst;
}

static void a_wall_over_a_lit_floor_matches_the_closed_form(void)
{
    vdbgi_context *ctx = test_context();
    baked k;
    CHECK(a_wall_over_a_lit_floor(ctx, (vdbgi_bake_desc){.rays = 4096}, 0.0f, &k) < 0.005);
    unbake(&k);
    vdbgi_context_destroy(ctx);
}

/*
 * Inside a closed box of albedo rho 0.6 with fill a 0.3 and no sun, baked
 * with bd's rays (the light set here) over passes: pass N gives
 * pi rho a (1 - rho^N)/(1 - rho) at every texel, each valid. The worst
 * relative error, *k kept for the caller to unbake.
 */
static double in_a_closed_box(vdbgi_context *ctx, vdbgi_bake_desc bd, int passes, baked *k)
{
    test_mesh box = {0};
    const float lo[3] = {0, 0, 0}, hi[3] = {4, 4, 4};
    test_mesh_box(&box, lo, hi, 1);
    const vdbgi_mesh_desc mesh = test_mesh_desc(&box, 0.6f, 0);
    bd.ray_dist = 20.0f;
    bd.ambient = 0.3f;
    bd.sun_color_is_set = 1;
    bd.falloff = INFINITY;
    bd.threads = 2;
    const vdbgi_lightmap_params lp = {.passes = passes, .rings = 3};
    bake(ctx, &mesh, 1, &bd, 0.5f, &lp, k);
    const double want = 3.14159265358979 * 0.6 * 0.3 * (1.0 - pow(0.6, passes)) / 0.4;
    double worst = 0.0;
    size_t n = 0;
    for (size_t i = 0; k->map.rgb && i < k->map.texel_count; i++)
        if (k->tx.tri[i] >= 0) {
            CHECK(k->map.valid[i]);
            worst = fmax(worst, fabs(k->map.rgb[3 * i] - want) / want);
            n++;
        }
    CHECK(n > 0 && k->map.invalid_count == 0);
    return worst;
}

static void passes_add_the_terms_of_the_geometric_series(void)
{
    vdbgi_context *ctx = test_context();
    for (int passes = 1; passes <= 3; passes++) {
        baked k;
        CHECK(in_a_closed_box(ctx, (vdbgi_bake_desc){.rays = 64}, passes, &k) < 1e-5);
        unbake(&k);
    }
    vdbgi_context_destroy(ctx);
}

/*
 * Auto texels: the wall over the lit floor (above) under a grey sky,
 * within 1.5 % at a tight target, on more than the
 * pilot's 32 rays a texel and fewer than the cap; and in the closed box of
 * uniform fill, where every ray brings the same light, the pilot alone,
 * exactly the series' first term.
 */
static void auto_texels_spend_rays_where_the_light_varies(void)
{
    vdbgi_context *ctx = test_context();
    baked k;
    const vdbgi_bake_desc bd = {.adaptive = 1, .noise = 0.001f, .max_rays = 4096};
    CHECK(a_wall_over_a_lit_floor(ctx, bd, 0.1f, &k) < 0.015);
    CHECK(k.map.gathers > 0 && k.map.gathered > 40 * k.map.gathers &&
          k.map.gathered < 2048 * k.map.gathers);
    unbake(&k);

    CHECK(in_a_closed_box(ctx, (vdbgi_bake_desc){.adaptive = 1}, 1, &k) < 1e-5);
    CHECK(k.map.gathers > 0 && k.map.gathered == 32 * k.map.gathers);
    unbake(&k);
    vdbgi_context_destroy(ctx);
}

/* A 2 m box on an 8 m floor, albedo 0.7: the charts of several faces and sizes. */
static vdbgi_mesh_desc box_on_floor(test_mesh *m)
{
    test_mesh_plane(m, 8.0f, 0.0f);
    const float lo[3] = {-1, 0, -1}, hi[3] = {1, 2, 1};
    test_mesh_box(m, lo, hi, 0);
    return test_mesh_desc(m, 0.7f, 0);
}

static void the_same_bytes_on_one_thread_and_two(void)
{
    vdbgi_context *ctx = test_context();
    test_mesh m = {0};
    const vdbgi_mesh_desc mesh = box_on_floor(&m);
    for (int adaptive = 0; adaptive < 2; adaptive++) {
        baked k[2];
        for (int t = 0; t < 2; t++) {
            const vdbgi_bake_desc bd = {.rays = adaptive ? 0 : 32,
                                        .adaptive = adaptive,
                                        .noise = 0.05f,
                                        .sampling = VDBGI_SAMPLING_RANDOM,
                                        .threads = t + 1};
            const vdbgi_lightmap_params lp = {.passes = 2, .direct = true, .rings = 3};
            bake(ctx, &mesh, 1, &bd, 0.25f, &lp, &k[t]);
        }
        CHECK(k[0].map.rgb && k[1].map.rgb &&
              memcmp(k[0].map.rgb, k[1].map.rgb, 3 * k[0].map.texel_count * sizeof(float)) == 0);
        CHECK(k[0].map.gathered == k[1].map.gathered);
        unbake(&k[0]);
        unbake(&k[1]);
    }
    vdbgi_context_destroy(ctx);
}

/*
 * A floor texel under an emitting ceiling of radiance Le at height h (albedo
 * 0, so nothing bounces), rays of length R, no falloff, every other light
 * off: the ceiling is met along directions with d_y > h/R, the disk's
 * r^2 < 1 - c^2 under Malley's method, so E = pi Le (1 - c^2), c = h / R.
 */
static void a_floor_under_an_emitting_ceiling_matches_the_closed_form(void)
{
    vdbgi_context *ctx = test_context();
    test_mesh floor = {0}, ceiling = {0};
    test_mesh_plane(&floor, 4.0f, 0.0f);
    const float a[3] = {-60, 3, -60}, b[3] = {60, 3, -60}, c[3] = {60, 3, 60}, d[3] = {-60, 3, 60};
    test_mesh_quad(&ceiling, a, b, c, d); /* facing down */
    vdbgi_mesh_desc meshes[2] = {test_mesh_desc(&floor, 0.5f, 0),
                                 test_mesh_desc(&ceiling, 0.0f, 0)};
    const float le[3] = {2.0f, 1.0f, 0.5f};
    memcpy(meshes[1].emissive, le, sizeof(le));
    const vdbgi_bake_desc bd = {.rays = 4096,
                                .ray_dist = 6.0f,
                                .ambient_is_set = 1,
                                .sun_color_is_set = 1,
                                .falloff = INFINITY,
                                .threads = 2};
    const vdbgi_lightmap_params lp = {.passes = 2, .rings = 3};
    baked k;
    bake(ctx, meshes, 2, &bd, 0.5f, &lp, &k);
    const double cc = 3.0 / 6.0, open = 1.0 - cc * cc;
    double worst = 0.0;
    size_t checked = 0;
    for (size_t i = 0; k.map.rgb && i < k.map.texel_count; i++) {
        const int32_t t = k.tx.tri[i];
        if (t < 0 || k.scene->tris[t].normal[1] < 0.5f)
            continue; /* floor texels only */
        CHECK(k.map.valid[i]);
        for (int ch = 0; ch < 3; ch++) {
            const double want = 3.14159265358979 * le[ch] * open;
            worst = fmax(worst, fabs(k.map.rgb[3 * i + (size_t)ch] - want) / want);
        }
        checked++;
    }
    CHECK(checked >= 16);
    CHECK(worst < 0.005);
    unbake(&k);
    vdbgi_context_destroy(ctx);
}

/*
 * Light adds: with --layers each light (sun, ambient, sky, each emissive
 * material) gets a map of its own, and they sum to the map a bake with all
 * of them on gives, texel by texel, through every pass.
 */
static void layers_add_up_to_the_whole_map(void)
{
    vdbgi_context *ctx = test_context();
    test_mesh ground = {0}, lamp = {0}, box = {0};
    test_mesh_plane(&ground, 8.0f, 0.0f);
    const float lo[3] = {-1, 0, -1}, hi[3] = {1, 2, 1};
    test_mesh_box(&box, lo, hi, 0);
    const float a[3] = {2, 0.5f, -1}, b[3] = {2, 0.5f, 1}, c[3] = {2, 1.5f, 1},
                d[3] = {2, 1.5f, -1};
    test_mesh_quad(&lamp, a, b, c, d); /* facing -x, towards the box */
    vdbgi_mesh_desc meshes[3] = {test_mesh_desc(&ground, 0.6f, 0), test_mesh_desc(&lamp, 0.2f, 0),
                                 test_mesh_desc(&box, 0.7f, 0)};
    meshes[1].emissive[0] = 4.0f, meshes[1].emissive[1] = 3.0f;
    vdbgi_scene *scene = NULL;
    CHECK_RESULT(ctx, vdbgi_scene_create(ctx, meshes, 3, &scene), VDBGI_OK);
    vdbgi_lightmap_desc desc = {.texel = 0.25f,
                                .size = 128,
                                .passes = 3,
                                .direct = 1,
                                .bake = {.rays = 32, .sky = {0.2f, 0.3f, 0.5f}, .threads = 2}};
    vdbgi_lightmap_result *whole = NULL, *split = NULL;
    vdbgi_lightmap_stats st;
    CHECK_RESULT(ctx, vdbgi_lightmap_bake_scene(ctx, scene, &desc, &whole, NULL), VDBGI_OK);
    desc.layers = 1;
    CHECK_RESULT(ctx, vdbgi_lightmap_bake_scene(ctx, scene, &desc, &split, &st), VDBGI_OK);
    CHECK(st.layers == 4);
    static const char *const want[4] = {"sun", "ambient", "sky", "emissive1"};
    const vdbgi_lightmap *const m = whole ? vdbgi_lightmap_result_map(whole, 0, NULL) : NULL;
    const vdbgi_lightmap *layer[4] = {NULL};
    for (size_t l = 0; split && l < 4; l++) {
        const char *name = NULL;
        layer[l] = vdbgi_lightmap_result_map(split, l + 1, &name);
        CHECK(layer[l] && name && strcmp(name, want[l]) == 0);
    }
    CHECK(split && vdbgi_lightmap_result_map(split, 5, NULL) == NULL);
    double worst = 0.0, peak = 0.0, least = INFINITY;
    size_t n = 0;
    for (size_t i = 0; m && layer[3] && i < m->texel_count; i++) {
        if (!m->valid[i])
            continue;
        for (int k = 0; k < 3; k++) {
            double sum = 0.0;
            for (int l = 0; l < 4; l++)
                sum += layer[l]->rgb[3 * i + (size_t)k];
            worst = fmax(worst, fabs(sum - m->rgb[3 * i + (size_t)k]));
            peak = fmax(peak, m->rgb[3 * i + (size_t)k]);
        }
        n++;
    }
    /* Every layer lights something. */
    for (int l = 0; l < 4 && layer[3]; l++) {
        double most = 0.0;
        for (size_t i = 0; i < 3 * layer[l]->texel_count; i++)
            most = fmax(most, layer[l]->rgb[i]);
        least = fmin(least, most);
    }
    CHECK(n > 100 && peak > 0.0 && least > 0.01 * peak);
    CHECK(worst <= 1e-5 * peak);
    vdbgi_lightmap_result_destroy(whole);
    vdbgi_lightmap_result_destroy(split);
    vdbgi_scene_destroy(scene);
    vdbgi_context_destroy(ctx);
}

/*
 * vdbgi_lightmap_plan unwraps as the bake does: the same charts, atlases,
 * edge and texels at each texel size, default and fixed atlas sizes, one
 * atlas or several (the box's faces at 0.02 m overflow 64 texels).
 */
static void a_plan_tells_the_bake_atlases(void)
{
    vdbgi_context *ctx = test_context();
    test_mesh m = {0};
    const vdbgi_mesh_desc mesh = box_on_floor(&m);
    vdbgi_scene *scene = NULL;
    CHECK_RESULT(ctx, vdbgi_scene_create(ctx, &mesh, 1, &scene), VDBGI_OK);
    static const struct {
        float texel;
        int size;
    } cases[] = {{0.5f, 0}, {0.25f, 0}, {0.1f, 0}, {0.25f, 64}, {0.02f, 64}};
    size_t several = 0;
    for (size_t c = 0; scene && c < sizeof(cases) / sizeof(cases[0]); c++) {
        const vdbgi_lightmap_desc d = {.texel = cases[c].texel,
                                       .size = cases[c].size,
                                       .passes = 1,
                                       .bake = {.rays = 4, .model = VDBGI_MODEL_SEED}};
        vdbgi_lightmap_stats plan, got;
        vdbgi_lightmap_result *res = NULL;
        CHECK_RESULT(ctx, vdbgi_lightmap_plan(ctx, scene, &d, &plan), VDBGI_OK);
        CHECK_RESULT(ctx, vdbgi_lightmap_bake_scene(ctx, scene, &d, &res, &got), VDBGI_OK);
        CHECK(plan.charts == got.charts && plan.atlases == got.atlases &&
              plan.atlas_size == got.atlas_size && plan.texels == got.texels &&
              fabs(plan.utilisation - got.utilisation) < 1e-12 && plan.samples == 0);
        several += plan.atlases > 1;
        vdbgi_lightmap_result_destroy(res);
    }
    CHECK(several > 0);
    /* Past the ray limit (texels x rays x passes), the plan refuses as the bake does. */
    const vdbgi_lightmap_desc heavy = {
        .texel = 0.02f, .passes = 16, .bake = {.rays = 1000000, .model = VDBGI_MODEL_SEED}};
    vdbgi_lightmap_stats st;
    vdbgi_lightmap_result *res = NULL;
    CHECK_RESULT(ctx, vdbgi_lightmap_plan(ctx, scene, &heavy, &st), VDBGI_ERR_OUT_OF_MEMORY);
    CHECK(strstr(vdbgi_context_error(ctx), "G rays") != NULL);
    CHECK_RESULT(ctx, vdbgi_lightmap_bake_scene(ctx, scene, &heavy, &res, &st),
                 VDBGI_ERR_OUT_OF_MEMORY);
    vdbgi_lightmap_result_destroy(res);
    /*
     * Auto's rays are counted at what the noise asks (256 a texel at the default, 4x that at
     * half of it), not at its cap: a map of 3-10 M texels plans at the default and is refused
     * at --noise 0.025, where every texel may take the 1,024 the cap allows.
     */
    vdbgi_lightmap_desc many = {
        .texel = 0.004f, .passes = 3, .bake = {.adaptive = 1, .model = VDBGI_MODEL_SEED}};
    CHECK_RESULT(ctx, vdbgi_lightmap_plan(ctx, scene, &many, &st), VDBGI_OK);
    printf("  %.2f M texels\n", st.texels * 1e-6);
    CHECK(st.texels > 8e9 / (3.0 * 1024) && st.texels < 8e9 / (3.0 * 256));
    many.bake.noise = 0.025f;
    CHECK_RESULT(ctx, vdbgi_lightmap_plan(ctx, scene, &many, &st), VDBGI_ERR_OUT_OF_MEMORY);
    CHECK(strstr(vdbgi_context_error(ctx), "G rays") != NULL);
    vdbgi_scene_destroy(scene);
    vdbgi_context_destroy(ctx);
}

int main(void)
{
    RUN(a_plan_tells_the_bake_atlases);
    RUN(a_floor_under_an_emitting_ceiling_matches_the_closed_form);
    RUN(layers_add_up_to_the_whole_map);
    RUN(a_wall_over_a_lit_floor_matches_the_closed_form);
    RUN(passes_add_the_terms_of_the_geometric_series);
    RUN(the_same_bytes_on_one_thread_and_two);
    RUN(auto_texels_spend_rays_where_the_light_varies);
    return CHECK_EXIT();
}
