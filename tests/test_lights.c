/*
 * test_lights.c: the scene's own light against closed forms. A point light
 * over a plane gives E = I cos^3(theta) / h^2 (times glTF's range window);
 * a spot's cone cuts it off past its outer angle; a uniform sky map gives
 * E = pi L on a plane and, to a probe above it, L / 2 plus the plane's
 * rho L / 2 (one bounce carries the sky as far as a lamp); a sky map's sun
 * becomes a lamp without changing what a plane receives; in a closed box of
 * albedo rho whose walls emit Le, a probe after N bounces and a texel after
 * N passes both read Le (1 + rho + ... + rho^N), and bounces until
 * converged stop where that series says. Lamps are read at the true
 * hit: a probe over a lit plane is each ray's closed form, and a speck 1 km
 * away or a triangle 1000 km away changes nothing near the origin. Bad lights, skies and
 * settings are refused by name; bounces give the same bits on any thread
 * count; a glTF's lights arrive with their nodes' transforms and ranges,
 * and its sun stands in for the default one.
 */
#define _POSIX_C_SOURCE 200809L
#include "estimate.h"
#include "image_shim.h"
#include "probes.h"
#include "test_baked.h"

#include <math.h>
#include <stdio.h>

#define PI_D 3.14159265358979323846

static vdbgi_scene *plane_scene(vdbgi_context *ctx, float size, float albedo)
{
    test_mesh m = {0};
    test_mesh_plane(&m, size, 0.0f);
    const vdbgi_mesh_desc md = test_mesh_desc(&m, albedo, 0);
    vdbgi_scene *s = NULL;
    CHECK_RESULT(ctx, vdbgi_scene_create(ctx, &md, 1, &s), VDBGI_OK);
    return s;
}

/* A plane as plane_scene's, and when far > 0 a 1 cm speck that far out along +x. */
static vdbgi_scene *plane_and_speck(vdbgi_context *ctx, float size, float albedo, float far)
{
    test_mesh m = {0}, speck = {0};
    test_mesh_plane(&m, size, 0.0f);
    const float a[3] = {far, 0, 0.01f}, b[3] = {far + 0.01f, 0, 0.01f}, c[3] = {far + 0.01f, 0, 0},
                d[3] = {far, 0, 0};
    test_mesh_quad(&speck, a, b, c, d);
    const vdbgi_mesh_desc md[2] = {test_mesh_desc(&m, albedo, 0),
                                   test_mesh_desc(&speck, albedo, 0)};
    vdbgi_scene *s = NULL;
    CHECK_RESULT(ctx, vdbgi_scene_create(ctx, md, far > 0.0f ? 2 : 1, &s), VDBGI_OK);
    return s;
}

/* Only the lamps: no sun, no fill, no falloff. */
static const vdbgi_bake_desc lamps_only = {
    .rays = 16, .model = VDBGI_MODEL_PHYSICAL, .sun_color_is_set = 1, .threads = 2};

/* The plane test below, with a speck far metres out when far > 0. */
static void point_light_over_plane(float far)
{
    vdbgi_context *ctx = test_context();
    vdbgi_scene *s = plane_and_speck(ctx, 16.0f, 0.5f, far);
    const float h = 3.0f, range = 7.0f;
    const vdbgi_light lamp = {.type = VDBGI_LIGHT_POINT,
                              .position = {1.0f, h, -0.5f},
                              .color = {20.0f, 10.0f, 5.0f},
                              .range = range,
                              .name = "lamp"};
    CHECK_RESULT(ctx, vdbgi_scene_add_lights(s, &lamp, 1), VDBGI_OK);
    const vdbgi_lightmap_params lp = {.passes = 1, .direct = true, .rings = 3};
    baked k;
    size_t inside = 0, outside = 0;
    double worst = 0.0;
    if (s && bake_map(ctx, s, &lamps_only, 0.5f, &lp, &k)) {
        for (size_t i = 0; i < k.map.texel_count; i++) {
            if (k.tx.tri[i] < 0 || k.tx.tri[i] > 1) /* the plane's two triangles */
                continue;
            const float *const p = &k.tx.pos[3 * i];
            const double dx = p[0] - 1.0, dy = h, dz = p[2] + 0.5; /* on the plane, y = 0 */
            const double d = sqrt(dx * dx + dy * dy + dz * dz), q = pow(d / range, 4.0);
            const double window = q < 1.0 ? 1.0 - q : 0.0;
            for (int c = 0; c < 3; c++) {
                const double want = lamp.color[c] * dy / (d * d * d) * window;
                const double got = k.map.rgb[3 * i + (size_t)c];
                if (window == 0.0)
                    CHECK(got == 0.0);
                else
                    worst = fmax(worst, fabs(got - want) / (want + 1e-3 * lamp.color[c]));
            }
            inside += window > 0.0, outside += window == 0.0;
        }
        unbake(&k);
    }
    CHECK(inside > 100 && outside > 100);
    CHECK(worst < 1e-4);
    vdbgi_context_destroy(ctx);
}

/* A fully baked plane under a point light h = 3 m up: E = I h / d^3, inside the range. */
static void a_point_light_over_a_plane_gives_the_inverse_square_cosine(void)
{
    for (int far = 0; far <= 1000; far += 1000)
        point_light_over_plane((float)far);
}

/*
 * A probe over a plane under a lamp: each Fibonacci ray that meets the plane
 * brings rho I cos / (pi d^2) from its true hit, so the probe is that sum,
 * closed form ray by ray, to 1e-5; and the same with a speck 1 km away. (Read
 * where the shadow ray starts, 1e-5 of the scene's extent off the plane, it
 * was 0.1 % high, and 0.8 % with the speck.)
 */
static void a_lamp_is_read_at_the_true_hit_with_or_without_a_far_speck(void)
{
    vdbgi_context *ctx = test_context();
    const float rho = 0.5f, at[3] = {0.2f, 0.6f, 0.1f}, half = 8.0f;
    const vdbgi_light lamp = {
        .type = VDBGI_LIGHT_POINT, .position = {0.7f, 2.0f, -0.4f}, .color = {20.0f, 20.0f, 20.0f}};
    enum { N = 512 };
    float dirs[3 * N];
    vdbgi_fibonacci_directions(N, dirs);
    double want = 0.0;
    for (int i = 0; i < N; i++) {
        const float *const d = &dirs[3 * i];
        if (!(d[1] < 0.0f))
            continue;
        const double t = -at[1] / (double)d[1];
        const double hit[3] = {at[0] + t * d[0], 0.0, at[2] + t * d[2]};
        if (fabs(hit[0]) > half || fabs(hit[2]) > half)
            continue;
        const double l[3] = {lamp.position[0] - hit[0], lamp.position[1],
                             lamp.position[2] - hit[2]};
        const double dist = sqrt(l[0] * l[0] + l[1] * l[1] + l[2] * l[2]);
        want += rho * lamp.color[0] / PI_D * l[1] / (dist * dist * dist);
    }
    want /= N;
    vdbgi_bake_desc bd = lamps_only;
    bd.rays = N;
    bd.ray_dist = 100.0f;
    for (int far = 0; far <= 1000; far += 1000) {
        vdbgi_scene *s = plane_and_speck(ctx, 2.0f * half, rho, (float)far);
        if (!s)
            break;
        CHECK_RESULT(ctx, vdbgi_scene_add_lights(s, &lamp, 1), VDBGI_OK);
        float rgb[3];
        CHECK_RESULT(ctx, vdbgi_scene_bake_points(s, &bd, at, 1, rgb, NULL), VDBGI_OK);
        CHECK_NEAR(rgb[0], want, 1e-5 * want);
        vdbgi_scene_destroy(s);
    }
    vdbgi_context_destroy(ctx);
}

/*
 * A room lit by a lamp, alone and with one triangle 1000 km away: the far
 * triangle's rays keep their offsets (10 m) to itself, so the room's probes
 * and lightmap read as the room alone. (With offsets from the scene's
 * extent, every ray in the room started 10 m off its wall and the room baked
 * black.)
 */
static void a_triangle_1000_km_away_leaves_a_room_as_it_was(void)
{
    vdbgi_context *ctx = test_context();
    test_mesh room = {0}, far = {0};
    const float lo[3] = {-3, 0, -2}, hi[3] = {3, 3, 2};
    test_mesh_box(&room, lo, hi, 1);
    const float a[3] = {1e6f, 0, 10}, b[3] = {1e6f + 10, 0, 10}, c[3] = {1e6f + 10, 0, 0},
                d[3] = {1e6f, 0, 0};
    test_mesh_quad(&far, a, b, c, d);
    const vdbgi_mesh_desc md[2] = {test_mesh_desc(&room, 0.6f, 0), test_mesh_desc(&far, 0.6f, 0)};
    const vdbgi_light lamp = {
        .type = VDBGI_LIGHT_POINT, .position = {0.5f, 2.5f, 0.3f}, .color = {20.0f, 20.0f, 20.0f}};
    const float at[12] = {0, 1, 0, -2, 0.5f, 1, 2.5f, 2.5f, -1.5f, 1, 0.2f, 1.8f};
    vdbgi_bake_desc bd = lamps_only;
    bd.rays = 256;
    bd.bounces = 2;
    float probes[2][12];
    double mean[2] = {0.0, 0.0};
    for (int with_far = 0; with_far < 2; with_far++) {
        vdbgi_scene *s = NULL;
        CHECK_RESULT(ctx, vdbgi_scene_create(ctx, md, 1 + (size_t)with_far, &s), VDBGI_OK);
        if (!s)
            break;
        CHECK_RESULT(ctx, vdbgi_scene_add_lights(s, &lamp, 1), VDBGI_OK);
        CHECK_RESULT(ctx, vdbgi_scene_bake_points(s, &bd, at, 4, probes[with_far], NULL), VDBGI_OK);
        vdbgi_bake_desc lbd = bd;
        lbd.rays = 64;
        lbd.bounces = 0;
        const vdbgi_lightmap_params lp = {.passes = 2, .rings = 3};
        baked k;
        if (bake_map(ctx, s, &lbd, 0.25f, &lp, &k)) {
            size_t n = 0;
            for (size_t i = 0; i < k.map.texel_count; i++)
                if (k.tx.tri[i] >= 0 && k.tx.tri[i] < 12) /* the room's triangles */
                    mean[with_far] += k.map.rgb[3 * i], n++;
            mean[with_far] /= (double)(n ? n : 1);
            unbake(&k);
        } else {
            vdbgi_scene_destroy(s);
        }
    }
    CHECK(mean[0] > 0.1);
    CHECK_NEAR(mean[1], mean[0], 0.01 * mean[0]);
    for (int i = 0; i < 12; i++)
        CHECK_NEAR(probes[1][i], probes[0][i], 0.01 * probes[0][i] + 1e-6);
    vdbgi_context_destroy(ctx);
}

/* A spot straight down: full inside its inner angle, glTF's smooth step between, 0 past outer. */
static void a_spots_cone_ends_at_its_outer_angle(void)
{
    vdbgi_context *ctx = test_context();
    vdbgi_scene *s = plane_scene(ctx, 16.0f, 0.5f);
    const float h = 4.0f, inner = 0.3f, outer = 0.6f;
    const vdbgi_light spot = {.type = VDBGI_LIGHT_SPOT,
                              .position = {0.0f, h, 0.0f},
                              .direction = {0.0f, -2.0f, 0.0f},
                              .color = {30.0f, 30.0f, 30.0f},
                              .inner_cone = inner,
                              .outer_cone = outer};
    CHECK_RESULT(ctx, vdbgi_scene_add_lights(s, &spot, 1), VDBGI_OK);
    const vdbgi_lightmap_params lp = {.passes = 1, .direct = true, .rings = 3};
    baked k;
    size_t lit = 0, penumbra = 0, dark = 0;
    double worst = 0.0;
    if (s && bake_map(ctx, s, &lamps_only, 0.25f, &lp, &k)) {
        for (size_t i = 0; i < k.map.texel_count; i++) {
            if (k.tx.tri[i] < 0)
                continue;
            const float *const p = &k.tx.pos[3 * i];
            const double dy = h - p[1], d = sqrt(p[0] * p[0] + dy * dy + p[2] * p[2]);
            const double c = dy / d; /* cos of the angle from the spot's axis */
            const double t = fmin((c - cos(outer)) / (cos(inner) - cos(outer)), 1.0);
            const double cone = t > 0.0 ? t * t : 0.0;
            const double want = 30.0 * dy / (d * d * d) * cone, got = k.map.rgb[3 * i];
            if (cone == 0.0) {
                CHECK(got == 0.0);
                dark++;
                continue;
            }
            worst = fmax(worst, fabs(got - want) / (30.0 / (h * h)));
            lit += cone == 1.0, penumbra += cone < 1.0;
        }
        unbake(&k);
    }
    CHECK(lit > 50 && penumbra > 50 && dark > 100);
    CHECK(worst < 1e-3);
    vdbgi_context_destroy(ctx);
}

/* A 2:1 EXR of one colour, or two: west (u < 0.5) and east halves. */
static bool write_sky(vdbgi_context *ctx, const char *path, int w, int h, const float west[3],
                      const float east[3])
{
    float *const px = calloc((size_t)w * (size_t)h * 3, sizeof(float));
    for (int y = 0; y < h; y++)
        for (int x = 0; x < w; x++)
            memcpy(&px[3 * ((size_t)y * (size_t)w + (size_t)x)], x < w / 2 ? west : east,
                   3 * sizeof(float));
    const vdbgi_result r = vdbgi_image_write(ctx, path, w, h, 3, px, true);
    free(px);
    return r == VDBGI_OK;
}

/* E = pi L on an open plane; a probe above it sees L over half its sphere, and the plane. */
static void a_uniform_sky_map_lights_a_plane_and_a_probe(void)
{
    vdbgi_context *ctx = test_context();
    const float L[3] = {0.5f, 0.25f, 1.0f};
    vdbgi_sky *sky = NULL;
    CHECK(write_sky(ctx, tmp_path("sky.exr"), 64, 32, L, L));
    CHECK_RESULT(ctx, vdbgi_sky_load(ctx, tmp_path("sky.exr"), 2.0f, 30.0f, &sky), VDBGI_OK);
    if (!sky) {
        vdbgi_context_destroy(ctx);
        return;
    }
    vdbgi_scene *s = plane_scene(ctx, 2000.0f, 0.6f);
    vdbgi_bake_desc bd = lamps_only;
    bd.sky_map = sky;
    bd.rays = 256;
    bd.ray_dist = 1e5f;
    const vdbgi_lightmap_params lp = {.passes = 1, .rings = 3};
    baked k;
    if (s && bake_map(ctx, s, &bd, 100.0f, &lp, &k)) {
        size_t n = 0;
        for (size_t i = 0; i < k.map.texel_count; i++)
            if (k.tx.tri[i] >= 0 && fabsf(k.tx.pos[3 * i]) < 300 &&
                fabsf(k.tx.pos[3 * i + 2]) < 300)
                for (int c = 0; c < 3; c++, n++)
                    CHECK_NEAR(k.map.rgb[3 * i + (size_t)c], PI_D * 2.0 * L[c], 1e-3 * PI_D * 2.0);
        CHECK(n > 0);
        unbake(&k);
    }
    /*
     * The probe, 1 m up: the upper half reads 2L, the lower the plane's rho 2L, at one
     * bounce as at two (the plane sees only the sky).
     */
    s = plane_scene(ctx, 2000.0f, 0.6f);
    const float at[3] = {0.0f, 1.0f, 0.0f};
    bd.rays = 4096;
    for (int bounces = 1; s && bounces <= 2; bounces++) {
        bd.bounces = bounces;
        float rgb[3];
        CHECK_RESULT(ctx, vdbgi_scene_bake_points(s, &bd, at, 1, rgb, NULL), VDBGI_OK);
        for (int c = 0; c < 3; c++) {
            /* Half the sphere sees the sky; of the other half, the part past 1e5 m is sky too. */
            const double want = 2.0 * L[c] * (0.5 + 0.6 * 0.5);
            CHECK_NEAR(rgb[c], want, 0.01 * want);
        }
    }
    vdbgi_scene_destroy(s);
    vdbgi_sky_destroy(sky);
    vdbgi_context_destroy(ctx);
}

/* u = 0.5 looks down -z and u grows towards +x; a rotation turns the map about +y. */
static void a_sky_maps_directions_follow_the_latlong_layout(void)
{
    vdbgi_context *ctx = test_context();
    const float west[3] = {1, 0, 0}, east[3] = {0, 1, 0};
    CHECK(write_sky(ctx, tmp_path("halves.exr"), 64, 32, west, east));
    vdbgi_sky *sky = NULL, *turned = NULL;
    CHECK_RESULT(ctx, vdbgi_sky_load(ctx, tmp_path("halves.exr"), 1.0f, 0.0f, &sky), VDBGI_OK);
    CHECK_RESULT(ctx, vdbgi_sky_load(ctx, tmp_path("halves.exr"), 1.0f, 180.0f, &turned), VDBGI_OK);
    if (sky && turned) {
        const float px[3] = {1, 0, 0}, nx[3] = {-1, 0, 0};
        float a[3], b[3], c[3], d[3];
        vdbgi_sky_radiance(sky, px, a);
        vdbgi_sky_radiance(sky, nx, b);
        vdbgi_sky_radiance(turned, px, c);
        vdbgi_sky_radiance(turned, nx, d);
        CHECK(a[1] == 1.0f && a[0] == 0.0f && b[0] == 1.0f && b[1] == 0.0f);
        CHECK(c[0] == 1.0f && c[1] == 0.0f && d[1] == 1.0f && d[0] == 0.0f);
        CHECK(vdbgi_sky_hash(sky) != vdbgi_sky_hash(turned));
    }
    vdbgi_sky_destroy(sky);
    vdbgi_sky_destroy(turned);
    vdbgi_context_destroy(ctx);
}

/* A 256 x 128 map of radiance bg, and 2 x 2 texels of sun at columns 127-128, rows 42-43. */
static bool write_sun_sky(vdbgi_context *ctx, const char *path, float bg, float sun, bool band)
{
    const int w = 256, h = 128;
    float *const px = calloc((size_t)w * h * 3, sizeof(float));
    for (int y = 0; y < h; y++)
        for (int x = 0; x < w; x++) {
            const bool in_sun = band ? y == 60 : (x == 127 || x == 128) && (y == 42 || y == 43);
            for (int k = 0; k < 3; k++)
                px[3 * ((size_t)y * w + (size_t)x) + (size_t)k] = in_sun ? sun : bg;
        }
    const vdbgi_result r = vdbgi_image_write(ctx, path, w, h, 3, px, true);
    free(px);
    return r == VDBGI_OK;
}

/*
 * A sky map's sun is taken out as a lamp: its direction (turned with the
 * map), its irradiance (the patch's light over 50 times the rest's mean),
 * and a plane under it, fully baked, gets the whole map's irradiance. A
 * uniform map and a bright band round the horizon keep their light.
 */
static void a_sky_maps_sun_becomes_a_lamp(void)
{
    vdbgi_context *ctx = test_context();
    CHECK(write_sun_sky(ctx, tmp_path("sun.exr"), 0.5f, 60000.0f, false));
    CHECK(write_sun_sky(ctx, tmp_path("band.exr"), 0.5f, 60000.0f, true));
    vdbgi_sky *sky = NULL, *band = NULL, *flat = NULL;
    CHECK_RESULT(ctx, vdbgi_sky_load(ctx, tmp_path("sun.exr"), 1.0f, 90.0f, &sky), VDBGI_OK);
    CHECK_RESULT(ctx, vdbgi_sky_load(ctx, tmp_path("band.exr"), 1.0f, 0.0f, &band), VDBGI_OK);
    CHECK(write_sun_sky(ctx, tmp_path("flat.exr"), 0.5f, 0.5f, false));
    CHECK_RESULT(ctx, vdbgi_sky_load(ctx, tmp_path("flat.exr"), 1.0f, 0.0f, &flat), VDBGI_OK);
    float dir[3], e[3];
    CHECK(band && !vdbgi_sky_sun(band, dir, e));
    CHECK(flat && !vdbgi_sky_sun(flat, dir, e));
    if (!sky || !vdbgi_sky_sun(sky, dir, e)) {
        CHECK(false);
    } else {
        /* Map frame: the patch's centre 43/128 of the way down, looking down -z; turned a
           quarter about +y, it looks along +x. */
        const double theta = 43.0 / 128.0 * PI_D, omega = (2.0 * PI_D / 256) * (PI_D / 128);
        CHECK_NEAR(dir[0], sin(theta), 1e-3);
        CHECK_NEAR(dir[1], cos(theta), 1e-3);
        CHECK_NEAR(dir[2], 0.0, 1e-3);
        double want = 0.0, exact = PI_D * 0.5; /* the whole map over an up-facing plane */
        for (int row = 42; row <= 43; row++) {
            const double t = (row + 0.5) / 128.0 * PI_D;
            want += 2.0 * (60000.0 - 50.0 * 0.5) * omega * sin(t);
            exact += 2.0 * (60000.0 - 0.5) * omega * sin(t) * cos(t);
        }
        CHECK_NEAR(e[0], want, 1e-4 * want);
        vdbgi_scene *s = plane_scene(ctx, 200.0f, 0.5f);
        vdbgi_bake_desc bd = lamps_only;
        bd.sky_map = sky;
        bd.rays = 4096;
        bd.ray_dist = 1e5f;
        const vdbgi_lightmap_params lp = {.passes = 1, .direct = true, .rings = 3};
        baked k;
        if (s && bake_map(ctx, s, &bd, 20.0f, &lp, &k)) {
            size_t n = 0;
            for (size_t i = 0; i < k.map.texel_count; i++)
                if (k.tx.tri[i] >= 0 && fabsf(k.tx.pos[3 * i]) < 30 &&
                    fabsf(k.tx.pos[3 * i + 2]) < 30) {
                    CHECK_NEAR(k.map.rgb[3 * i], exact, 0.005 * exact);
                    n++;
                }
            CHECK(n > 0);
            unbake(&k);
        }
    }
    vdbgi_sky_destroy(sky);
    vdbgi_sky_destroy(band);
    vdbgi_sky_destroy(flat);
    vdbgi_context_destroy(ctx);
}

#define FURNACE_RHO 0.7f
#define FURNACE_LE 0.4f

/* A closed 4 x 3 x 5 m box, faces inward, of albedo FURNACE_RHO emitting FURNACE_LE. */
static vdbgi_mesh_desc furnace(test_mesh *box)
{
    const float lo[3] = {0, 0, 0}, hi[3] = {4, 3, 5};
    test_mesh_box(box, lo, hi, 1);
    vdbgi_mesh_desc md = test_mesh_desc(box, FURNACE_RHO, 0);
    md.emissive[0] = md.emissive[1] = md.emissive[2] = FURNACE_LE;
    return md;
}

/*
 * The furnace: a closed box whose walls (albedo rho) emit Le. A probe after
 * N bounces, and a texel after N passes, read Le (1 + rho + ... + rho^N):
 * the emitters seen, then N reflections of them, as far as a lamp's light
 * goes; exactly, since every ray of every path meets the same light.
 */
static void the_furnace_sums_the_series_for_probes_and_texels(void)
{
    vdbgi_context *ctx = test_context();
    const float rho = FURNACE_RHO, le = FURNACE_LE;
    test_mesh box = {0};
    const vdbgi_mesh_desc md = furnace(&box);
    vdbgi_bake_desc bd = lamps_only;
    bd.rays = 64;
    const float at[3] = {1.3f, 1.1f, 2.7f};
    double last = 0.0;
    for (int n = 1; n <= 4; n++) {
        const double want = le * (1.0 - pow(rho, n + 1)) / (1.0 - rho);
        vdbgi_scene *s = NULL;
        CHECK_RESULT(ctx, vdbgi_scene_create(ctx, &md, 1, &s), VDBGI_OK);
        if (!s)
            break;
        bd.bounces = n;
        float probe[3];
        CHECK_RESULT(ctx, vdbgi_scene_bake_points(s, &bd, at, 1, probe, NULL), VDBGI_OK);
        CHECK_NEAR(probe[0], want, 1e-5 * want);
        CHECK(probe[0] > last && probe[0] < le / (1.0f - rho)); /* grows, never past the limit */
        last = probe[0];
        bd.bounces = 0;
        const vdbgi_lightmap_params lp = {.passes = n, .rings = 3};
        baked k;
        if (bake_map(ctx, s, &bd, 0.5f, &lp, &k)) {
            double worst = 0.0;
            for (size_t i = 0; i < k.map.texel_count; i++)
                if (k.tx.tri[i] >= 0)
                    worst = fmax(worst, fabs(k.map.rgb[3 * i] / PI_D - want) / want);
            CHECK(worst < 1e-5);
            unbake(&k);
        } else {
            vdbgi_scene_destroy(s);
        }
    }
    vdbgi_context_destroy(ctx);
}

/*
 * Passes until converged, in the furnace: the k-th pass adds Le rho^k, so
 * the light needs the first n passes whose next term is under the share
 * asked; three are swept and the third's increment carries the rest, so
 * every texel reads Le (1 + ... + rho^n), as a probe does.
 */
static void passes_until_converged_stop_where_the_series_says(void)
{
    vdbgi_context *ctx = test_context();
    const double rho = FURNACE_RHO, le = FURNACE_LE;
    test_mesh box = {0};
    const vdbgi_mesh_desc md = furnace(&box);
    vdbgi_bake_desc bd = lamps_only;
    bd.rays = 64;
    static const float targets[3] = {0.1f, 0.01f, 0.001f};
    for (int t = 0; t < 3; t++) {
        int n = 1;
        double sum = 1.0 + rho;
        while (n < 16 && pow(rho, n + 1) > targets[t] * (sum + pow(rho, n + 1)))
            sum += pow(rho, ++n);
        vdbgi_scene *s = NULL;
        CHECK_RESULT(ctx, vdbgi_scene_create(ctx, &md, 1, &s), VDBGI_OK);
        const vdbgi_lightmap_params lp = {.passes = 0, .converge = targets[t], .rings = 3};
        baked k;
        if (s && bake_map(ctx, s, &bd, 0.5f, &lp, &k)) {
            CHECK(k.map.bounces == n && k.map.passes == (n < 3 ? n : 3));
            CHECK_NEAR(k.map.last_share, pow(rho, n) / sum, 1e-6);
            double worst = 0.0;
            for (size_t i = 0; i < k.map.texel_count; i++)
                if (k.tx.tri[i] >= 0)
                    worst = fmax(worst, fabs(k.map.rgb[3 * i] / PI_D - le * sum) / (le * sum));
            CHECK(worst < 1e-5);
            unbake(&k);
        }
    }
    /* A share outside (0, 1) is refused. */
    vdbgi_scene *s = NULL;
    CHECK_RESULT(ctx, vdbgi_scene_create(ctx, &md, 1, &s), VDBGI_OK);
    if (s) {
        vdbgi_lightmap_desc ld = {.passes = 0, .converge = 1.5f, .bake = bd};
        vdbgi_lightmap_result *res = NULL;
        CHECK_RESULT(ctx, vdbgi_lightmap_bake_scene(ctx, s, &ld, &res, NULL),
                     VDBGI_ERR_INVALID_ARG);
        CHECK(res == NULL);
        vdbgi_scene_destroy(s);
    }
    vdbgi_context_destroy(ctx);
}

/*
 * Bounces until converged, in the furnace: the k-th bounce adds Le rho^k
 * (exactly, at every receiver of the pilot), so the count stops at the
 * first n whose next term is under the share asked, and every probe reads
 * Le (1 + ... + rho^n) though only three bounces are traced: the third
 * carries the rest. The stats say so.
 */
static void bounces_until_converged_stop_where_the_series_says(void)
{
    vdbgi_context *ctx = test_context();
    const double rho = FURNACE_RHO, le = FURNACE_LE;
    test_mesh box = {0};
    const vdbgi_mesh_desc md = furnace(&box);
    static const float targets[3] = {0.1f, 0.01f, 0.002f};
    for (int t = 0; t < 3; t++) {
        int n = 1;
        double sum = 1.0 + rho;
        while (n < 16 && pow(rho, n + 1) > targets[t] * (sum + pow(rho, n + 1)))
            sum += pow(rho, ++n);
        double rest = 0.0;
        for (int k = 4; k <= n; k++)
            rest += pow(rho, k);
        vdbgi_scene *s = NULL;
        vdbgi_probes *p = NULL;
        CHECK_RESULT(ctx, vdbgi_scene_create(ctx, &md, 1, &s), VDBGI_OK);
        const vdbgi_place_desc pd = {.spacing = 1.0, .margin = 0.9};
        if (s)
            CHECK_RESULT(ctx, vdbgi_probes_place(ctx, s, &pd, &p), VDBGI_OK);
        vdbgi_bake_desc bd = lamps_only;
        bd.rays = 32;
        bd.converge = targets[t];
        vdbgi_bake_stats st = {0};
        if (p)
            CHECK_RESULT(ctx, vdbgi_probes_bake(p, s, &bd, &st), VDBGI_OK);
        CHECK(st.bounces == n);
        CHECK(st.bounces_traced == (n < 3 ? n : 3));
        CHECK_NEAR(st.last_share, pow(rho, n) / sum, 1e-6);
        CHECK_NEAR(st.tail_share, rest / sum, 1e-6);
        double worst = 0.0;
        size_t inside = 0;
        for (size_t i = 0; p && i < p->count; i++)
            if (p->backface[i] == 0.0f) {
                worst = fmax(worst, fabs(p->rgb[3 * i] - le * sum) / (le * sum));
                inside++;
            }
        CHECK(inside > 20);
        CHECK(worst < 1e-5);
        if (worst >= 1e-5)
            fprintf(stderr, "share %g: %d bounces, worst %g\n", (double)targets[t], n, worst);
        vdbgi_probes_destroy(p);
        vdbgi_scene_destroy(s);
    }
    /* A share outside (0, 1), or one with a count given, is refused. */
    vdbgi_scene *s = NULL;
    CHECK_RESULT(ctx, vdbgi_scene_create(ctx, &md, 1, &s), VDBGI_OK);
    const float at[3] = {1, 1, 1};
    float rgb[3];
    vdbgi_bake_desc bd = lamps_only;
    bd.converge = 1.5f;
    CHECK_RESULT(ctx, vdbgi_scene_bake_points(s, &bd, at, 1, rgb, NULL), VDBGI_ERR_INVALID_ARG);
    CHECK(strstr(vdbgi_context_error(ctx), "converged share must be in (0, 1)") != NULL);
    bd.converge = 0.05f;
    bd.bounces = 2;
    CHECK_RESULT(ctx, vdbgi_scene_bake_points(s, &bd, at, 1, rgb, NULL), VDBGI_ERR_INVALID_ARG);
    CHECK(strstr(vdbgi_context_error(ctx), "for bounces until converged") != NULL);
    vdbgi_scene_destroy(s);
    vdbgi_context_destroy(ctx);
}

/* Bounces, lamps and a sky on one thread and three: the same bits. */
static void bounces_give_the_same_bits_on_any_thread_count(void)
{
    vdbgi_context *ctx = test_context();
    test_mesh m = {0};
    const float lo[3] = {-2, 0, -2}, hi[3] = {2, 2, 2};
    test_mesh_plane(&m, 20.0f, 0.0f);
    test_mesh_box(&m, lo, hi, 0);
    const vdbgi_mesh_desc md = test_mesh_desc(&m, 0.6f, 0);
    const vdbgi_light lamps[2] = {
        {.type = VDBGI_LIGHT_POINT, .position = {4, 3, 1}, .color = {40, 30, 20}},
        {.type = VDBGI_LIGHT_SPOT,
         .position = {-4, 5, 0},
         .direction = {0.5f, -1, 0},
         .color = {90, 90, 90},
         .inner_cone = 0.2f,
         .outer_cone = 0.7f}};
    vdbgi_scene *scene = NULL;
    vdbgi_probes *p1 = NULL, *p3 = NULL;
    CHECK_RESULT(ctx, vdbgi_scene_create(ctx, &md, 1, &scene), VDBGI_OK);
    if (!scene) {
        vdbgi_context_destroy(ctx);
        return;
    }
    CHECK_RESULT(ctx, vdbgi_scene_add_lights(scene, lamps, 2), VDBGI_OK);
    const vdbgi_place_desc pd = {.spacing = 1.0};
    CHECK_RESULT(ctx, vdbgi_probes_place(ctx, scene, &pd, &p1), VDBGI_OK);
    CHECK_RESULT(ctx, vdbgi_probes_place(ctx, scene, &pd, &p3), VDBGI_OK);
    vdbgi_bake_desc bd = {.rays = 32,
                          .bounces = 3,
                          .model = VDBGI_MODEL_PHYSICAL,
                          .sky = {0.2f, 0.3f, 0.5f},
                          .sampling = VDBGI_SAMPLING_RANDOM,
                          .threads = 1};
    vdbgi_bake_stats s1, s3;
    CHECK_RESULT(ctx, vdbgi_probes_bake(p1, scene, &bd, &s1), VDBGI_OK);
    bd.threads = 3;
    CHECK_RESULT(ctx, vdbgi_probes_bake(p3, scene, &bd, &s3), VDBGI_OK);
    if (p1 && p3) {
        CHECK(p1->count == p3->count && p1->count > 100);
        CHECK(memcmp(p1->rgb, p3->rgb, p1->count * 3 * sizeof(float)) == 0);
        CHECK(s1.shadow_ray_count == s3.shadow_ray_count);
        /* The bounces and lamps did something: more light than one bounce of the sky alone. */
        double sum = 0.0;
        for (size_t i = 0; i < p1->count; i++)
            sum += p1->rgb[3 * i];
        CHECK(sum / (double)p1->count > 0.2 * 0.5);
    }
    /* Until converged: the pilot sums in its receivers' order, so the count and the bits
       are the same too. */
    bd.bounces = 0;
    bd.threads = 1;
    CHECK_RESULT(ctx, vdbgi_probes_bake(p1, scene, &bd, &s1), VDBGI_OK);
    bd.threads = 3;
    CHECK_RESULT(ctx, vdbgi_probes_bake(p3, scene, &bd, &s3), VDBGI_OK);
    if (p1 && p3) {
        CHECK(s1.bounces == s3.bounces && s1.bounces >= 2);
        CHECK(s1.tail_share == s3.tail_share && s1.last_share == s3.last_share);
        CHECK(memcmp(p1->rgb, p3->rgb, p1->count * 3 * sizeof(float)) == 0);
    }
    vdbgi_probes_destroy(p1);
    vdbgi_probes_destroy(p3);
    vdbgi_scene_destroy(scene);
    vdbgi_context_destroy(ctx);
}

/* A glTF's lights: assimp's, placed by their nodes, with the range read from the file. */
static void a_gltfs_lights_arrive_with_their_nodes_and_ranges(void)
{
    static const char gltf[] =
        "{\"asset\": {\"version\": \"2.0\"}, \"extensionsUsed\": [\"KHR_lights_punctual\"],"
        " \"extensions\": {\"KHR_lights_punctual\": {\"lights\": ["
        "  {\"type\": \"point\", \"color\": [1, 0.5, 0.25], \"intensity\": 10, \"range\": 7},"
        "  {\"type\": \"spot\", \"intensity\": 20, \"spot\": {\"innerConeAngle\": 0.3, "
        "\"outerConeAngle\": 0.6}},"
        "  {\"type\": \"directional\", \"intensity\": 3}]}},"
        " \"buffers\": [{\"byteLength\": 62, \"uri\": \"data:application/octet-stream;base64,"
        "AACgwAAAAAAAAKDAAACgQAAAAAAAAKDAAACgQAAAAAAAAKBAAACgwAAAAAAAAKBAAAACAAEAAAADAAIAAAA=\"}],"
        " \"bufferViews\": [{\"buffer\": 0, \"byteLength\": 48}, {\"buffer\": 0, \"byteOffset\": "
        "48, "
        "\"byteLength\": 12}],"
        " \"accessors\": [{\"bufferView\": 0, \"componentType\": 5126, \"count\": 4, \"type\": "
        "\"VEC3\","
        " \"min\": [-5, 0, -5], \"max\": [5, 0, 5]},"
        " {\"bufferView\": 1, \"componentType\": 5123, \"count\": 6, \"type\": \"SCALAR\"}],"
        " \"meshes\": [{\"primitives\": [{\"attributes\": {\"POSITION\": 0}, \"indices\": 1}]}],"
        " \"nodes\": [{\"mesh\": 0},"
        " {\"name\": \"lamp\", \"translation\": [1, 2, 3], \"extensions\": "
        "{\"KHR_lights_punctual\": "
        "{\"light\": 0}}},"
        " {\"name\": \"arm\", \"translation\": [0, 4, 0], \"children\": [3]},"
        " {\"name\": \"torch\", \"rotation\": [-0.7071068, 0, 0, 0.7071068], \"extensions\": "
        "{\"KHR_lights_punctual\": {\"light\": 1}}},"
        " {\"name\": \"sun\", \"rotation\": [-0.7071068, 0, 0, 0.7071068], \"extensions\": "
        "{\"KHR_lights_punctual\": {\"light\": 2}}}],"
        " \"scenes\": [{\"nodes\": [0, 1, 2, 4]}], \"scene\": 0}";
    vdbgi_context *ctx = test_context();
    FILE *f = fopen(tmp_path("lights.gltf"), "w");
    fputs(gltf, f);
    fclose(f);
    vdbgi_scene *s = NULL;
    CHECK_RESULT(ctx, vdbgi_scene_load(ctx, tmp_path("lights.gltf"), &s), VDBGI_OK);
    const vdbgi_light *l = NULL;
    if (s && vdbgi_scene_get_lights(s, &l) == 3) {
        CHECK(l[0].type == VDBGI_LIGHT_POINT && strcmp(l[0].name, "lamp") == 0);
        CHECK(l[0].position[0] == 1.0f && l[0].position[1] == 2.0f && l[0].position[2] == 3.0f);
        CHECK(l[0].color[0] == 10.0f && l[0].color[1] == 5.0f && l[0].color[2] == 2.5f);
        CHECK(l[0].range == 7.0f);
        CHECK(l[1].type == VDBGI_LIGHT_SPOT && strcmp(l[1].name, "torch") == 0);
        CHECK(l[1].position[1] == 4.0f && l[1].range == 0.0f && l[1].color[0] == 20.0f);
        CHECK_NEAR(l[1].direction[1], -1.0f, 1e-6f); /* -z turned a quarter about x: down */
        CHECK_NEAR(l[1].inner_cone, 0.3f, 1e-7f);
        CHECK_NEAR(l[1].outer_cone, 0.6f, 1e-7f);
        CHECK(l[2].type == VDBGI_LIGHT_DIRECTIONAL && l[2].color[1] == 3.0f);
        CHECK_NEAR(l[2].direction[1], -1.0f, 1e-6f);
        /* The scene's sun replaces the default one: an up-facing plane reads 3 / pi per unit. */
        vdbgi_bake_params bp;
        const vdbgi_bake_desc bd = {0};
        CHECK_RESULT(ctx, vdbgi_bake_params_resolve(ctx, &bd, s, &bp), VDBGI_OK);
        CHECK(!bp.sun_on && bp.lamp_count == 3 && bp.scene_lamps == 3);
        const vdbgi_bake_desc given = {.sun_dir = {0, 1, 0}};
        CHECK_RESULT(ctx, vdbgi_bake_params_resolve(ctx, &given, s, &bp), VDBGI_OK);
        CHECK(bp.sun_on && bp.lamp_count == 3 && bp.scene_lamps == 2 && bp.lamps[0].is_sun);
        const vdbgi_bake_desc off = {.lights = VDBGI_LIGHTS_OFF};
        CHECK_RESULT(ctx, vdbgi_bake_params_resolve(ctx, &off, s, &bp), VDBGI_OK);
        CHECK(bp.sun_on && bp.lamp_count == 1 && bp.scene_lamps == 0);
    } else {
        CHECK(false);
    }
    vdbgi_scene_destroy(s);
    vdbgi_context_destroy(ctx);
}

/* One line naming what is wrong; nothing added, nothing baked. */
static void bad_lights_skies_and_settings_are_refused(void)
{
    vdbgi_context *ctx = test_context();
    vdbgi_scene *s = plane_scene(ctx, 4.0f, 0.5f);
    if (!s) {
        vdbgi_context_destroy(ctx);
        return;
    }
    const vdbgi_light good = {.type = VDBGI_LIGHT_POINT, .position = {0, 1, 0}, .color = {1, 1, 1}};
    const struct {
        vdbgi_light light;
        const char *says;
    } bad[] = {
        {{.type = VDBGI_LIGHT_POINT, .color = {NAN, 1, 1}}, "not a number"},
        {{.type = VDBGI_LIGHT_POINT, .color = {1, -5, 1}}, "negative"},
        {{.type = VDBGI_LIGHT_POINT, .color = {1, 1, 1e9f}}, "above 1e6"},
        {{.type = VDBGI_LIGHT_POINT, .position = {INFINITY, 0, 0}, .color = {1, 1, 1}},
         "not finite"},
        {{.type = VDBGI_LIGHT_DIRECTIONAL, .color = {1, 1, 1}}, "no direction"},
        {{.type = VDBGI_LIGHT_SPOT,
          .direction = {0, -1, 0},
          .color = {1, 1, 1},
          .inner_cone = 0.5f,
          .outer_cone = 0.2f,
          .name = "torch"},
         "(torch) has an outer cone angle below its inner one"},
        {{.type = VDBGI_LIGHT_POINT, .color = {1, 1, 1}, .range = -1}, "range"},
        {{.type = 7, .color = {1, 1, 1}}, "unknown type"},
    };
    for (size_t i = 0; i < sizeof(bad) / sizeof(bad[0]); i++) {
        const vdbgi_light two[2] = {good, bad[i].light};
        CHECK_RESULT(ctx, vdbgi_scene_add_lights(s, two, 2), VDBGI_ERR_INVALID_ARG);
        if (!strstr(vdbgi_context_error(ctx), bad[i].says)) {
            fprintf(stderr, "light %zu: %s\n", i, vdbgi_context_error(ctx));
            CHECK(false);
        }
        vdbgi_scene_info si;
        vdbgi_scene_get_info(s, &si);
        CHECK(si.light_count == 0); /* all or none */
    }
    vdbgi_light many[VDBGI_MAX_LIGHTS + 1];
    for (int i = 0; i <= VDBGI_MAX_LIGHTS; i++)
        many[i] = good;
    CHECK_RESULT(ctx, vdbgi_scene_add_lights(s, many, VDBGI_MAX_LIGHTS + 1), VDBGI_ERR_INVALID_ARG);
    /* Settings the bake refuses. */
    const float at[3] = {0, 1, 0};
    float rgb[3];
    const struct {
        vdbgi_bake_desc bd;
        const char *says;
    } settings[] = {
        {{.bounces = -1}, "bounces must be in 1..16"},
        {{.bounces = 1000}, "bounces must be in 1..16"},
        {{.model = VDBGI_MODEL_PHYSICAL, .ambient = 0.2f}, "no ambient fill"},
        {{.model = VDBGI_MODEL_PHYSICAL, .falloff = 4.0f}, "no distance falloff"},
        {{.model = 9}, "unknown light model"},
        {{.lights = 5}, "unknown lights setting"},
    };
    for (size_t i = 0; i < sizeof(settings) / sizeof(settings[0]); i++) {
        CHECK_RESULT(ctx, vdbgi_scene_bake_points(s, &settings[i].bd, at, 1, rgb, NULL),
                     VDBGI_ERR_INVALID_ARG);
        CHECK(strstr(vdbgi_context_error(ctx), settings[i].says) != NULL);
    }
    /* Skies: not 2:1, negative texels, a bad intensity, missing, not an image. */
    const float neg[3] = {-1, 0, 0}, one[3] = {1, 1, 1};
    CHECK(write_sky(ctx, tmp_path("square.exr"), 32, 32, one, one));
    CHECK(write_sky(ctx, tmp_path("negative.exr"), 64, 32, one, neg));
    FILE *f = fopen(tmp_path("text.exr"), "w");
    fputs("not an image\n", f);
    fclose(f);
    const struct {
        const char *file;
        float intensity;
        vdbgi_result code;
        const char *says;
    } skies[] = {{"square.exr", 1.0f, VDBGI_ERR_FORMAT, "twice as wide as high (got 32 x 32)"},
                 {"negative.exr", 1.0f, VDBGI_ERR_FORMAT, "1024 sky map values are negative"},
                 {"square.exr", -1.0f, VDBGI_ERR_INVALID_ARG, "intensity"},
                 {"square.exr", 1e7f, VDBGI_ERR_INVALID_ARG, "intensity"},
                 {"missing.exr", 1.0f, VDBGI_ERR_IO, "missing.exr"},
                 {"text.exr", 1.0f, VDBGI_ERR_FORMAT, "text.exr"}};
    for (size_t i = 0; i < sizeof(skies) / sizeof(skies[0]); i++) {
        vdbgi_sky *sky = (vdbgi_sky *)1;
        const vdbgi_result r =
            vdbgi_sky_load(ctx, tmp_path(skies[i].file), skies[i].intensity, 0.0f, &sky);
        CHECK(sky == NULL);
        if (r != skies[i].code || !strstr(vdbgi_context_error(ctx), skies[i].says)) {
            fprintf(stderr, "sky %zu: %d %s\n", i, (int)r, vdbgi_context_error(ctx));
            CHECK(false);
        }
    }
    vdbgi_scene_destroy(s);
    vdbgi_context_destroy(ctx);
}

int main(void)
{
    test_tmpdir_make("test-lights");
    RUN(a_point_light_over_a_plane_gives_the_inverse_square_cosine);
    RUN(a_lamp_is_read_at_the_true_hit_with_or_without_a_far_speck);
    RUN(a_triangle_1000_km_away_leaves_a_room_as_it_was);
    RUN(a_spots_cone_ends_at_its_outer_angle);
    RUN(a_uniform_sky_map_lights_a_plane_and_a_probe);
    RUN(a_sky_maps_directions_follow_the_latlong_layout);
    RUN(a_sky_maps_sun_becomes_a_lamp);
    RUN(the_furnace_sums_the_series_for_probes_and_texels);
    RUN(passes_until_converged_stop_where_the_series_says);
    RUN(bounces_until_converged_stop_where_the_series_says);
    RUN(bounces_give_the_same_bits_on_any_thread_count);
    RUN(a_gltfs_lights_arrive_with_their_nodes_and_ranges);
    RUN(bad_lights_skies_and_settings_are_refused);
    test_tmpdir_remove();
    return CHECK_EXIT();
}
