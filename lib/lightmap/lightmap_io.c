/*
 * lightmap_io.c: a lightmap bake as files: each page's maps (8-bit PNG in
 * the .glb, half-float EXR beside it) and the scene with its second UV set
 * as a .glb (through gltf_shim.cpp).
 */
#define _POSIX_C_SOURCE 200809L
#include "encode.h"
#include "gltf_shim.h"
#include "lightmap.h"
#include "util.h"
#include "vdbgi_bench.h"

#include <errno.h>
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/stat.h>

void vdbgi_lightmap_files_free(vdbgi_context *ctx, vdbgi_lightmap_files *f)
{
    vdbgi_free(ctx, f->glb);
    for (size_t p = 0; f->exr && p < f->exr_count; p++)
        vdbgi_free(ctx, f->exr[p]);
    vdbgi_free(ctx, f->exr);
    vdbgi_free(ctx, f->exr_size);
    memset(f, 0, sizeof(*f));
}

/* The 8-bit maps' scale: the largest E a valid texel holds (AO is 0..1 already). */
static float map_scale(const vdbgi_lightmap *m, bool ao)
{
    float scale = 0.0f;
    for (size_t i = 0; !ao && i < m->texel_count; i++)
        for (int k = 0; k < 3 && m->valid[i]; k++)
            scale = fmaxf(scale, m->rgb[3 * i + (size_t)k]);
    return scale > 0.0f ? scale : 1.0f;
}

/* Triangles sorted by (material, page): one glTF primitive and material each. */
typedef struct keyed {
    uint32_t key, tri;
} keyed;

static int by_key(const void *pa, const void *pb)
{
    const keyed *a = pa, *b = pb;
    return a->key != b->key ? (a->key < b->key ? -1 : 1) : (a->tri < b->tri ? -1 : a->tri > b->tri);
}

/* Page p of map m as an 8-bit PNG (sRGB of E / scale; AO linear) and, for light, an EXR. */
static vdbgi_result encode_page(vdbgi_context *ctx, const vdbgi_lightmap *m, size_t p, size_t size,
                                bool ao, float scale, float *pix, uint8_t **png, size_t *png_size,
                                uint8_t **exr, size_t *exr_size)
{
    const size_t per = size * size;
    const float *const e = &m->rgb[3 * p * per];
    for (size_t i = 0; i < per; i++)
        for (int k = 0; k < 4; k++)
            pix[4 * i + (size_t)k] = k == 3 ? 1.0f
                                     : ao   ? e[3 * i]
                                            : vdbgi_srgb_from_linear(e[3 * i + (size_t)k] / scale);
    VDBGI_TRY(vdbgi_image_encode(ctx, "lightmap", "png", (int)size, (int)size, 4, pix, ao, png,
                                 png_size));
    return ao ? VDBGI_OK
              : vdbgi_image_encode(ctx, "lightmap", "exr", (int)size, (int)size, 3, e, true, exr,
                                   exr_size);
}

/* The scene's base colour and emissive textures, linear in the scene, sRGB in the file. */
static vdbgi_result encode_textures(vdbgi_context *ctx, const vdbgi_scene *s, uint8_t **png,
                                    vdbgi_gltf_image *img)
{
    for (size_t t = 0; t < s->texture_count; t++) {
        const vdbgi_texture *const tex = &s->textures[t];
        const size_t count = (size_t)tex->width * (size_t)tex->height;
        if (count == 0)
            continue; /* a texture that did not load: its materials keep their factor */
        float *const rgba = vdbgi_alloc(ctx, 4 * count * sizeof(float));
        if (!rgba)
            return VDBGI_ERR_OUT_OF_MEMORY;
        for (size_t i = 0; i < 4 * count; i++)
            rgba[i] = i % 4 == 3 ? tex->rgba[i] : vdbgi_srgb_from_linear(tex->rgba[i]);
        const vdbgi_result r = vdbgi_image_encode(ctx, "texture", "png", tex->width, tex->height, 4,
                                                  rgba, false, &png[t], &img[t].size);
        img[t].png = png[t];
        vdbgi_free(ctx, rgba);
        VDBGI_TRY(r);
    }
    return VDBGI_OK;
}

/*
 * The .glb from the bake's maps and the scene: one pass (about 120 lines)
 * whose arrays share one set of indices (images, their slots in the .glb,
 * primitives, materials, vertices), which helpers would each have to be
 * handed again.
 */
vdbgi_result vdbgi_lightmap_encode(vdbgi_context *ctx, const vdbgi_scene *s, const vdbgi_unwrap *un,
                                   const vdbgi_texels *tx, const vdbgi_lightmap *m, bool ao,
                                   const vdbgi_lightmap_layers *ly, vdbgi_lightmap_files *out)
{
    memset(out, 0, sizeof(*out));
    const size_t pages = tx->page_count, size = (size_t)tx->size, per = size * size;
    const size_t layers = ly && !ao ? ly->count : 0, maps = pages * (1 + layers);
    VDBGI_FAIL_IF(ctx, pages > 64, VDBGI_ERR_INVALID_ARG,
                  "%zu atlases: at most 64 (raise --size or --texel)", pages);
    VDBGI_FAIL_IF(ctx, layers > VDBGI_LIGHTMAP_MAX_LAYERS, VDBGI_ERR_INVALID_ARG,
                  "%zu layers: at most %d", layers, VDBGI_LIGHTMAP_MAX_LAYERS);
    /* Images: each map's pages (the map, then its layers), then the scene's textures. */
    const size_t n = s->triangle_count, images = maps + s->texture_count;
    float *pix = vdbgi_alloc(ctx, 4 * per * sizeof(float));
    vdbgi_gltf_image *img = vdbgi_calloc(ctx, images, sizeof(*img));
    uint8_t **png = vdbgi_calloc(ctx, images, sizeof(*png));
    keyed *order = vdbgi_alloc(ctx, n * sizeof(*order));
    float *v = vdbgi_alloc(ctx, 3 * n * 13 * sizeof(float)); /* pos, normal, uv0, uv1, colour */
    vdbgi_gltf_primitive *prims = vdbgi_alloc(ctx, n * sizeof(*prims));
    vdbgi_gltf_material *mats = vdbgi_alloc(ctx, n * sizeof(*mats));
    int *slot = vdbgi_alloc(ctx, images * sizeof(*slot));
    int *layer_slots = vdbgi_calloc(ctx, n * (layers ? layers : 1), sizeof(int));
    float scales[1 + VDBGI_LIGHTMAP_MAX_LAYERS] = {0};
    const char *names[VDBGI_LIGHTMAP_MAX_LAYERS];
    out->exr = vdbgi_calloc(ctx, maps, sizeof(*out->exr));
    out->exr_size = vdbgi_calloc(ctx, maps, sizeof(*out->exr_size));
    vdbgi_result r = pix && img && png && order && v && prims && mats && slot && layer_slots &&
                             out->exr && out->exr_size
                         ? VDBGI_OK
                         : VDBGI_ERR_OUT_OF_MEMORY;
    for (size_t l = 0; r == VDBGI_OK && l <= layers; l++) {
        const vdbgi_lightmap *const map = l ? &ly->maps[l - 1] : m;
        scales[l] = map_scale(map, ao);
        if (l)
            names[l - 1] = ly->names[l - 1];
        for (size_t p = 0; r == VDBGI_OK && p < pages; p++) {
            const size_t i = l * pages + p;
            r = encode_page(ctx, map, p, size, ao, scales[l], pix, &png[i], &img[i].size,
                            &out->exr[i], &out->exr_size[i]);
            img[i].png = png[i];
        }
    }
    out->exr_count = ao ? 0 : maps;
    out->scale = scales[0];
    if (r != VDBGI_OK || (r = encode_textures(ctx, s, &png[maps], &img[maps])) != VDBGI_OK)
        goto done;
    for (size_t t = 0; t < n; t++)
        order[t] =
            (keyed){s->tris[t].material * (uint32_t)pages + un->page[un->chart[t]], (uint32_t)t};
    qsort(order, n, sizeof(*order), by_key);
    /* The images that exist, packed: slot[i] is image i's index in the .glb, or -1. */
    size_t used = 0;
    for (size_t i = 0; i < images; i++) {
        slot[i] = img[i].size ? (int)used : -1;
        if (img[i].size)
            img[used++] = img[i];
    }
    float *const pos = v, *const nrm = v + 9 * n, *const uv0 = v + 18 * n, *const uv1 = v + 24 * n,
                 *const col = v + 30 * n;
    bool coloured = false; /* vertex colours other than white: the bake used them */
    for (size_t i = 0; i < 3 * s->vertex_count && !coloured; i++)
        coloured = s->colors[i] != 1.0f;
    size_t prim_count = 0;
    for (size_t i = 0; i < n; i++) {
        const uint32_t t = order[i].tri;
        if (i == 0 || order[i].key != order[i - 1].key) {
            const uint32_t mat = s->tris[t].material, page = un->page[un->chart[t]];
            const vdbgi_material *const sm = &s->materials[mat];
            int *const ls = &layer_slots[prim_count * layers];
            for (size_t l = 0; l < layers; l++)
                ls[l] = slot[(l + 1) * pages + page];
            mats[prim_count] = (vdbgi_gltf_material){
                {sm->base[0], sm->base[1], sm->base[2]},
                sm->texture >= 0 ? slot[maps + (size_t)sm->texture] : -1,
                {sm->emissive[0], sm->emissive[1], sm->emissive[2]},
                sm->emissive_texture >= 0 ? slot[maps + (size_t)sm->emissive_texture] : -1,
                slot[page],
                layers ? ls : NULL,
                sm->double_sided};
            prims[prim_count] = (vdbgi_gltf_primitive){(uint32_t)(3 * i), 0, (uint32_t)prim_count};
            prim_count++;
        }
        prims[prim_count - 1].count += 3;
        for (int c = 0; c < 3; c++) {
            const size_t vi = s->indices[3 * (size_t)t + (size_t)c], o = 3 * i + (size_t)c;
            memcpy(&pos[3 * o], &s->positions[3 * vi], 3 * sizeof(float));
            memcpy(&nrm[3 * o], s->tris[t].normal, 3 * sizeof(float));
            /* The scene's v runs up the image (row 0 at v = 1), glTF's down. */
            uv0[2 * o] = s->uvs[2 * vi];
            uv0[2 * o + 1] = 1.0f - s->uvs[2 * vi + 1];
            memcpy(&col[3 * o], &s->colors[3 * vi], 3 * sizeof(float));
            uv1[2 * o] = un->uv[6 * (size_t)t + 2 * (size_t)c] / (float)size;
            uv1[2 * o + 1] = un->uv[6 * (size_t)t + 2 * (size_t)c + 1] / (float)size;
        }
    }
    const vdbgi_gltf_desc d = {.vertex_count = 3 * n,
                               .positions = pos,
                               .normals = nrm,
                               .uv0 = uv0, /* TEXCOORD_1 needs a TEXCOORD_0 before it */
                               .uv1 = uv1,
                               .colors = coloured ? col : NULL,
                               .primitives = prims,
                               .primitive_count = prim_count,
                               .materials = mats,
                               .material_count = prim_count,
                               .images = img,
                               .image_count = used,
                               .ao = ao,
                               .map_scale = scales[0],
                               .layer_count = layers,
                               .layer_names = names,
                               .layer_scales = &scales[1],
                               .generator = "vdbgi gi-lightmap"};
    r = vdbgi_gltf_encode(ctx, &d, &out->glb, &out->glb_size);
done:
    for (size_t i = 0; png && i < images; i++)
        vdbgi_free(ctx, png[i]);
    vdbgi_free(ctx, png);
    vdbgi_free(ctx, img);
    vdbgi_free(ctx, pix);
    vdbgi_free(ctx, order);
    vdbgi_free(ctx, v);
    vdbgi_free(ctx, prims);
    vdbgi_free(ctx, mats);
    vdbgi_free(ctx, slot);
    vdbgi_free(ctx, layer_slots);
    if (r != VDBGI_OK)
        vdbgi_lightmap_files_free(ctx, out);
    return r;
}

/* ---- the public API ------------------------------------------------------------- */

struct vdbgi_lightmap_result {
    vdbgi_context *ctx;
    const vdbgi_scene *scene;
    vdbgi_unwrap un;
    vdbgi_texels tx;
    vdbgi_lightmap map; /* with layers: their sum */
    vdbgi_lightmap layers[VDBGI_LIGHTMAP_MAX_LAYERS];
    char layer_names[VDBGI_LIGHTMAP_MAX_LAYERS][32];
    size_t layer_count;
    bool ao;
};

void vdbgi_lightmap_result_destroy(vdbgi_lightmap_result *r)
{
    if (!r)
        return;
    for (size_t l = 0; l < r->layer_count; l++)
        vdbgi_lightmap_free(&r->layers[l]);
    vdbgi_lightmap_free(&r->map);
    vdbgi_texels_free(&r->tx);
    vdbgi_unwrap_free(&r->un);
    vdbgi_free(r->ctx, r);
}

/* The next layer: the light model with every light off, named name; NULL past the limit. */
static vdbgi_bake_params *next_layer(const vdbgi_bake_params *bp, vdbgi_bake_params *out,
                                     char (*names)[32], size_t *n, const char *name)
{
    if (*n == VDBGI_LIGHTMAP_MAX_LAYERS)
        return NULL;
    vdbgi_bake_params *const l = &out[*n];
    *l = *bp;
    l->ambient = 0.0f;
    l->sun_on = false;
    memset(l->sun_color, 0, sizeof(l->sun_color));
    l->lamp_count = 0;
    memset(l->sky, 0, sizeof(l->sky));
    l->sky_map = NULL;
    l->emission = VDBGI_EMISSION_NONE;
    snprintf(names[*n], sizeof(names[*n]), "%s", name);
    (*n)++;
    return l;
}

/*
 * The lights that are on in bp, each as bp with that light alone: the sun
 * and each scene light, the ambient fill, the sky, and each emissive
 * material some triangle uses.
 */
static vdbgi_result light_layers(vdbgi_context *ctx, const vdbgi_scene *s,
                                 const vdbgi_bake_params *bp, vdbgi_bake_params *out,
                                 char (*names)[32], size_t *count)
{
    size_t n = 0;
    vdbgi_bake_params *l;
    bool full = false;
    for (int li = 0, scene_light = 0; li < bp->lamp_count && !full; li++) {
        if (bp->lamps[li].is_sky)
            continue; /* the sky's layer holds its sun */
        char name[32];
        const bool sun = bp->lamps[li].is_sun;
        snprintf(name, sizeof(name), "light%d", sun ? 0 : scene_light++);
        if (!(full = !(l = next_layer(bp, out, names, &n, sun ? "sun" : name)))) {
            l->lamps[0] = bp->lamps[li];
            l->lamp_count = 1;
            l->sun_on = sun;
            if (sun)
                memcpy(l->sun_color, bp->sun_color, sizeof(l->sun_color));
        }
    }
    if (!full && bp->ambient > 0.0f && !(full = !(l = next_layer(bp, out, names, &n, "ambient"))))
        l->ambient = bp->ambient;
    if (!full && (bp->sky[0] > 0.0f || bp->sky[1] > 0.0f || bp->sky[2] > 0.0f || bp->sky_map) &&
        !(full = !(l = next_layer(bp, out, names, &n, "sky")))) {
        memcpy(l->sky, bp->sky, sizeof(l->sky));
        l->sky_map = bp->sky_map;
        for (int li = 0; li < bp->lamp_count; li++)
            if (bp->lamps[li].is_sky)
                l->lamps[l->lamp_count++] = bp->lamps[li];
    }
    /* The emitters some triangle uses, found in one pass over the triangles. */
    bool *const used = vdbgi_calloc(ctx, s->material_count ? s->material_count : 1, sizeof(bool));
    if (!used)
        return VDBGI_ERR_OUT_OF_MEMORY;
    for (size_t t = 0; t < s->triangle_count; t++)
        if (s->tris[t].flags & VDBGI_TRI_EMISSIVE)
            used[s->tris[t].material] = true;
    for (size_t m = 0; !full && bp->emission != VDBGI_EMISSION_NONE && m < s->material_count; m++) {
        char name[32];
        snprintf(name, sizeof(name), "emissive%zu", m);
        if (used[m] && !(full = !(l = next_layer(bp, out, names, &n, name))))
            l->emission = (uint32_t)m + 1;
    }
    vdbgi_free(ctx, used);
    VDBGI_FAIL_IF(ctx, full, VDBGI_ERR_INVALID_ARG, "more than %d lights for layers",
                  VDBGI_LIGHTMAP_MAX_LAYERS);
    *count = n;
    return VDBGI_OK;
}

/* Add map b into a (the same texels): layers sum to the whole map. */
static void lightmap_add(vdbgi_lightmap *a, const vdbgi_lightmap *b)
{
    for (size_t i = 0; i < 3 * a->texel_count; i++)
        a->rgb[i] += b->rgb[i];
    for (int p = 0; p < 16; p++)
        a->pass_seconds[p] += b->pass_seconds[p];
    a->rays += b->rays, a->gathers += b->gathers, a->gathered += b->gathered;
}

/* Bake the map, or with layers each light's map and their sum as the map. */
static vdbgi_result bake_maps(vdbgi_context *ctx, vdbgi_lightmap_result *r,
                              const vdbgi_bake_params *bp, const vdbgi_lightmap_params *lp,
                              bool layers)
{
    if (!layers)
        return vdbgi_lightmap_bake(ctx, r->scene, bp, &r->un, &r->tx, lp, &r->map);
    vdbgi_bake_params lights[VDBGI_LIGHTMAP_MAX_LAYERS];
    size_t n = 0;
    VDBGI_TRY(light_layers(ctx, r->scene, bp, lights, r->layer_names, &n));
    if (n == 0) {
        vdbgi_log(ctx, VDBGI_LOG_WARNING, "no light is on: --layers has no map to write");
        return vdbgi_lightmap_bake(ctx, r->scene, bp, &r->un, &r->tx, lp, &r->map);
    }
    for (size_t l = 0; l < n; l++) {
        vdbgi_log(ctx, VDBGI_LOG_INFO, "layer %zu of %zu: %s", l + 1, n, r->layer_names[l]);
        VDBGI_TRY(
            vdbgi_lightmap_bake(ctx, r->scene, &lights[l], &r->un, &r->tx, lp, &r->layers[l]));
        r->layer_count = l + 1;
    }
    /* The sum, in a map of its own: validity does not depend on the light. */
    vdbgi_lightmap *const m = &r->map;
    *m = (vdbgi_lightmap){.ctx = ctx,
                          .texel_count = r->layers[0].texel_count,
                          .invalid_count = r->layers[0].invalid_count};
    m->rgb = vdbgi_calloc(ctx, m->texel_count, 3 * sizeof(float));
    m->valid = vdbgi_alloc(ctx, m->texel_count);
    if (!m->rgb || !m->valid)
        return VDBGI_ERR_OUT_OF_MEMORY;
    memcpy(m->valid, r->layers[0].valid, m->texel_count);
    for (size_t l = 0; l < n; l++) {
        lightmap_add(m, &r->layers[l]);
        /* Until converged each layer takes its own count: the most, and its share, stand. */
        m->passes = r->layers[l].passes > m->passes ? r->layers[l].passes : m->passes;
        m->last_share = fmax(m->last_share, r->layers[l].last_share);
        m->bounces = r->layers[l].bounces > m->bounces ? r->layers[l].bounces : m->bounces;
        m->tail_share = fmax(m->tail_share, r->layers[l].tail_share);
    }
    return VDBGI_OK;
}

/* Rays a texel unless the desc says. */
#define LIGHTMAP_RAYS 64

/*
 * An adaptive bake's rays a texel are not known before its pilot: about the
 * most measured at the default noise (182-259 a texel on three worlds:
 * docs/performance.md, "Rays by default"), 256, scaled as noise^-2, held
 * between the pilot's 32 and the cap. Counting the cap itself (1,024)
 * refused the default bake of any map past 2.6 M texels.
 */
static int adaptive_rays_expected(const vdbgi_bake_desc *b)
{
    const double noise = b->noise > 0.0f ? b->noise : VDBGI_NOISE;
    const double cap = b->max_rays ? b->max_rays : 1024;
    const double rays = 256.0 * (VDBGI_NOISE / noise) * (VDBGI_NOISE / noise);
    return rays < VDBGI_ADAPTIVE_BATCH ? VDBGI_ADAPTIVE_BATCH : (int)(rays < cap ? rays : cap);
}

/*
 * The passes d asks for: by default the physical model bakes until converged
 * (0); the seed model keeps seed 004's two passes, its fill standing in for
 * the rest (more would count the fill again).
 */
static int asked_passes(const vdbgi_lightmap_desc *d)
{
    return d->passes ? d->passes : d->bake.model == VDBGI_MODEL_PHYSICAL ? 0 : 2;
}

/*
 * The unwrap d asks for: the scene's own second UV set where it is usable,
 * else a new one (saying why, when say); refused past the atlas limits,
 * before the texels' memory (about 60 bytes each: 1 GB) is spent, and past
 * the ray limit, counting the most passes a bake until converged sweeps (3).
 */
static vdbgi_result unwrap_scene(vdbgi_context *ctx, const vdbgi_scene *scene,
                                 const vdbgi_lightmap_desc *d, bool say, vdbgi_unwrap *un,
                                 bool *kept)
{
    const vdbgi_unwrap_params up = {
        .texel = d->texel, .size = d->size, .max_angle = d->chart_angle};
    const char *why = NULL;
    vdbgi_result res = vdbgi_unwrap_from_uv1(ctx, scene, &up, un, kept, &why);
    if (res == VDBGI_OK && *kept && say)
        vdbgi_log(ctx, VDBGI_LOG_INFO, "keeping the scene's second UV set");
    else if (res == VDBGI_OK && scene->uv1_count && say)
        vdbgi_log(ctx, VDBGI_LOG_WARNING,
                  "the scene's second UV set is not usable (%s): unwrapping anew", why);
    if (res == VDBGI_OK && !*kept)
        res = vdbgi_unwrap_build(ctx, scene, &up, un);
    const double texels = (double)un->size * un->size * (double)un->page_count;
    if (res == VDBGI_OK && (un->page_count > 64 || texels > (double)VDBGI_LIGHTMAP_MAX_TEXELS))
        res = vdbgi_fail(ctx, VDBGI_ERR_OUT_OF_MEMORY,
                         "the charts take %zu atlases of %d texels (%.1f M texels; at most 64 "
                         "atlases and %.1f M texels): raise --texel or lower --size",
                         un->page_count, un->size, texels * 1e-6, VDBGI_LIGHTMAP_MAX_TEXELS * 1e-6);
    const int rays = d->bake.adaptive ? adaptive_rays_expected(&d->bake)
                     : d->bake.rays   ? d->bake.rays
                                      : LIGHTMAP_RAYS;
    const int passes = d->ao_dist > 0.0f ? 1 : asked_passes(d) ? asked_passes(d) : 3;
    const double work = texels * passes * rays;
    if (res == VDBGI_OK && work > VDBGI_LIGHTMAP_MAX_RAYS)
        res = vdbgi_fail(ctx, VDBGI_ERR_OUT_OF_MEMORY,
                         "%.1f M texels x %s%d rays x %d passes is %.1f G rays (at most %.1f G, "
                         "minutes at tens of M rays/s): raise --texel%s or lower %s or --passes",
                         texels * 1e-6, d->bake.adaptive ? "about " : "", rays, passes, work * 1e-9,
                         VDBGI_LIGHTMAP_MAX_RAYS * 1e-9, d->bake.adaptive ? " or --noise" : "",
                         d->bake.adaptive ? "--max-rays" : "--rays");
    return res;
}

static vdbgi_result bake_scene(vdbgi_context *ctx, const vdbgi_scene *scene,
                               const vdbgi_lightmap_desc *desc, bool bare,
                               vdbgi_lightmap_result **out, vdbgi_lightmap_stats *stats)
{
    VDBGI_FAIL_IF(ctx, !out || !scene, VDBGI_ERR_INVALID_ARG, "no scene or no output pointer");
    *out = NULL;
    const vdbgi_lightmap_desc none = {0};
    const vdbgi_lightmap_desc *const d = desc ? desc : &none;
    const double t0 = vdbgi_now();
    vdbgi_bake_desc bd = d->bake;
    bd.rays = bd.rays == 0 && !bd.adaptive ? LIGHTMAP_RAYS : bd.rays;
    vdbgi_bake_params bp;
    VDBGI_TRY(vdbgi_bake_params_resolve(ctx, &bd, scene, &bp));
    VDBGI_FAIL_IF(ctx, bp.bounces > 1, VDBGI_ERR_INVALID_ARG,
                  "a lightmap bounces by its passes, not by bounces (got %d)", bp.bounces);
    VDBGI_FAIL_IF(ctx, bd.converge != 0.0f, VDBGI_ERR_INVALID_ARG,
                  "a lightmap converges by its passes: give the share as its converge");
    VDBGI_FAIL_IF(ctx, d->passes < 0 || d->passes > VDBGI_LIGHTMAP_MAX_PASSES,
                  VDBGI_ERR_INVALID_ARG, "passes must be 1..%d, or 0 until converged (got %d)",
                  VDBGI_LIGHTMAP_MAX_PASSES, d->passes);
    const float converge = d->converge == 0.0f ? VDBGI_CONVERGE : d->converge;
    VDBGI_FAIL_IF(ctx, !(converge > 0.0f && converge < 1.0f), VDBGI_ERR_INVALID_ARG,
                  "the converged share must be in (0, 1) (got %g)", (double)d->converge);
    const int asked = asked_passes(d);
    VDBGI_FAIL_IF(ctx, d->layers && d->ao_dist > 0.0f, VDBGI_ERR_INVALID_ARG,
                  "layers are for lightmaps, not AO");
    vdbgi_lightmap_result *const r = vdbgi_calloc(ctx, 1, sizeof(*r));
    if (!r)
        return VDBGI_ERR_OUT_OF_MEMORY;
    r->ctx = ctx;
    r->scene = scene;
    r->ao = d->ao_dist > 0.0f;
    bool kept = false;
    vdbgi_result res = unwrap_scene(ctx, scene, d, true, &r->un, &kept);
    if (res == VDBGI_OK)
        res = vdbgi_texels_build(ctx, scene, &r->un, &r->tx);
    /* Dilate past the gutters on both sides of a chart edge, and over invalid texels. */
    const bool ao = d->ao_dist > 0.0f;
    const vdbgi_lightmap_params lp = {.passes = asked,
                                      .converge = converge,
                                      .direct = d->direct != 0,
                                      .rings = 2 * (int)r->un.gutter + 2,
                                      .ao_dist = d->ao_dist,
                                      .bare = bare,
                                      .noise = stats && !ao && !bare && !d->layers};
    if (res == VDBGI_OK)
        res = bake_maps(ctx, r, &bp, &lp, d->layers != 0);
    /* A black map is a scene without light (a closed room with no lamp under the physical model)
       or, bounced light only, one with nothing lit in view of its surfaces (a lone plane under
       the sun): say so rather than write darkness silently. */
    bool lit = false;
    for (size_t i = 0; res == VDBGI_OK && !ao && i < 3 * r->map.texel_count && !lit; i++)
        lit = r->map.rgb[i] > 0.0f;
    if (res == VDBGI_OK && !ao && r->map.texel_count && !lit)
        vdbgi_log(ctx, VDBGI_LOG_WARNING, "the lightmap is black: no %slight reached any texel%s%s",
                  d->direct ? "" : "bounced ",
                  d->direct ? "" : " (its direct light is left to the runtime)",
                  bp.model == VDBGI_MODEL_PHYSICAL
                      ? "; the seed model's ambient fill would light it"
                      : "");
    if (res != VDBGI_OK) {
        vdbgi_lightmap_result_destroy(r);
        return res;
    }
    if (stats) {
        memset(stats, 0, sizeof(*stats));
        stats->charts = r->un.chart_count;
        stats->kept_uv1 = kept;
        stats->layers = r->layer_count;
        stats->atlases = r->un.page_count;
        stats->atlas_size = r->un.size;
        stats->texels = r->map.texel_count;
        stats->samples = r->tx.sample_count;
        stats->invalid = r->map.invalid_count;
        stats->utilisation = r->un.chart_texels / (double)r->map.texel_count;
        stats->passes = r->map.passes;
        stats->last_share = r->map.last_share;
        stats->bounces = r->map.bounces;
        stats->tail_share = r->map.tail_share;
        memcpy(stats->pass_seconds, r->map.pass_seconds, sizeof(stats->pass_seconds));
        stats->rays = r->map.rays;
        stats->gather_rays =
            r->map.gathers ? (double)r->map.gathered / (double)r->map.gathers : 0.0;
        stats->seconds = vdbgi_now() - t0;
        /* Measured by the bake after its passes; layers' bakes each took one light of bp. */
        stats->noise = r->map.noise;
        if (!r->ao && !bare && d->layers)
            res = vdbgi_lightmap_noise(ctx, scene, &bp, &stats->noise);
        if (res != VDBGI_OK) {
            vdbgi_lightmap_result_destroy(r);
            return res;
        }
    }
    *out = r;
    return VDBGI_OK;
}

vdbgi_result vdbgi_lightmap_bake_scene(vdbgi_context *ctx, const vdbgi_scene *scene,
                                       const vdbgi_lightmap_desc *desc, vdbgi_lightmap_result **out,
                                       vdbgi_lightmap_stats *stats)
{
    return bake_scene(ctx, scene, desc, false, out, stats);
}

vdbgi_result vdbgi_lightmap_plan(vdbgi_context *ctx, const vdbgi_scene *scene,
                                 const vdbgi_lightmap_desc *desc, vdbgi_lightmap_stats *stats)
{
    VDBGI_FAIL_IF(ctx, !scene || !stats, VDBGI_ERR_INVALID_ARG, "no scene or no stats");
    memset(stats, 0, sizeof(*stats));
    const vdbgi_lightmap_desc none = {0};
    vdbgi_unwrap un = {0};
    bool kept = false;
    const vdbgi_result res = unwrap_scene(ctx, scene, desc ? desc : &none, false, &un, &kept);
    if (res == VDBGI_OK) {
        stats->kept_uv1 = kept;
        stats->charts = un.chart_count;
        stats->atlases = un.page_count;
        stats->atlas_size = un.size;
        stats->texels = (size_t)un.size * (size_t)un.size * un.page_count;
        stats->utilisation = stats->texels ? un.chart_texels / (double)stats->texels : 0.0;
    }
    vdbgi_unwrap_free(&un);
    return res;
}

vdbgi_result vdbgi_lightmap_trace_bare(vdbgi_context *ctx, const vdbgi_scene *scene,
                                       const vdbgi_lightmap_desc *desc, vdbgi_lightmap_stats *stats)
{
    vdbgi_lightmap_result *r = NULL;
    const vdbgi_result res = bake_scene(ctx, scene, desc, true, &r, stats);
    vdbgi_lightmap_result_destroy(r);
    return res;
}

void vdbgi_lightmap_result_sample(const vdbgi_lightmap_result *r, uint32_t prim, float u, float v,
                                  float rgb[3])
{
    vdbgi_lightmap_at(&r->map, &r->un, &r->tx, prim, u, v, rgb);
}

const float *vdbgi_lightmap_result_texels(const vdbgi_lightmap_result *r,
                                          const unsigned char **valid, size_t *count)
{
    *valid = r->map.valid;
    *count = r->map.texel_count;
    return r->map.rgb;
}

const int32_t *vdbgi_lightmap_result_boxes(const vdbgi_lightmap_result *r, const uint32_t **pages,
                                           size_t *count)
{
    *pages = r->un.page;
    *count = r->un.chart_count;
    return r->un.rect;
}

const vdbgi_lightmap *vdbgi_lightmap_result_map(const vdbgi_lightmap_result *r, size_t i,
                                                const char **name)
{
    if (name)
        *name = i ? (i <= r->layer_count ? r->layer_names[i - 1] : NULL) : "map";
    return i == 0 ? &r->map : i <= r->layer_count ? &r->layers[i - 1] : NULL;
}

vdbgi_result vdbgi_lightmap_write(const vdbgi_lightmap_result *r, const char *path,
                                  size_t *glb_size)
{
    if (glb_size)
        *glb_size = 0;
    vdbgi_context *const ctx = r->ctx;
    const size_t len = strlen(path);
    VDBGI_FAIL_IF(ctx, len < 5 || strcmp(path + len - 4, ".glb") != 0, VDBGI_ERR_INVALID_ARG,
                  "%s: the output is a .glb", path);
    vdbgi_lightmap_files f;
    const vdbgi_lightmap_layers ly = {r->layers, (const char(*)[32])r->layer_names, r->layer_count};
    VDBGI_TRY(vdbgi_lightmap_encode(ctx, r->scene, &r->un, &r->tx, &r->map, r->ao, &ly, &f));
    char *const name = vdbgi_alloc(ctx, len + 64);
    vdbgi_result res = name ? VDBGI_OK : VDBGI_ERR_OUT_OF_MEMORY;
    const size_t pages = r->tx.page_count;
    for (size_t i = 0; res == VDBGI_OK && i < f.exr_count; i++) {
        /* OUT.lightmapP.exr, and each layer's OUT.NAME.lightmapP.exr */
        const size_t l = i / pages, p = i % pages;
        snprintf(name, len + 64, "%.*s%s%s.lightmap%zu.exr", (int)(len - 4), path, l ? "." : "",
                 l ? r->layer_names[l - 1] : "", p);
        res = vdbgi_write_bytes_atomic(ctx, name, f.exr[i], f.exr_size[i]);
    }
    if (res == VDBGI_OK)
        res = vdbgi_write_bytes_atomic(ctx, path, f.glb, f.glb_size);
    if (res == VDBGI_OK && glb_size)
        *glb_size = f.glb_size;
    vdbgi_free(ctx, name);
    vdbgi_lightmap_files_free(ctx, &f);
    return res;
}

vdbgi_result vdbgi_lightmap_write_slices(const vdbgi_lightmap_result *r, const char *dir)
{
    vdbgi_context *const ctx = r->ctx;
    VDBGI_FAIL_IF(ctx, !dir || !*dir, VDBGI_ERR_INVALID_ARG, "no slice directory given");
    VDBGI_FAIL_IF(ctx, mkdir(dir, 0777) != 0 && errno != EEXIST, VDBGI_ERR_IO,
                  "%s: cannot make directory: %s", dir, strerror(errno));
    const size_t size = (size_t)r->tx.size, per = size * size;
    const float scale = map_scale(&r->map, r->ao);
    float *const pix = vdbgi_alloc(ctx, 3 * per * sizeof(float));
    char *const name = vdbgi_alloc(ctx, strlen(dir) + 32);
    vdbgi_result res = pix && name ? VDBGI_OK : VDBGI_ERR_OUT_OF_MEMORY;
    for (size_t p = 0; res == VDBGI_OK && p < r->tx.page_count; p++) {
        for (size_t i = 0; i < per; i++)
            for (int k = 0; k < 3; k++) {
                const float e = r->map.rgb[3 * (p * per + i) + (size_t)k];
                pix[3 * i + (size_t)k] = r->ao ? e : vdbgi_srgb_from_linear(e / scale);
            }
        snprintf(name, strlen(dir) + 32, "%s/map%zu.png", dir, p);
        res = vdbgi_image_write(ctx, name, (int)size, (int)size, 3, pix, r->ao);
        /* Charts: a colour from each chart's number (golden-ratio hues), invalid samples red. */
        for (size_t i = 0; res == VDBGI_OK && i < per; i++) {
            const int32_t t = r->tx.tri[p * per + i];
            float *const o = &pix[3 * i];
            if (t < 0) {
                o[0] = o[1] = o[2] = 0.0f;
                continue;
            }
            if (!r->map.valid[p * per + i]) {
                o[0] = 1.0f, o[1] = o[2] = 0.0f;
                continue;
            }
            const double h = fmod(r->un.chart[t] * 0.618033988749895, 1.0);
            for (int k = 0; k < 3; k++)
                o[k] = (float)(0.35 + 0.3 * cos(6.283185307179586 * (h + k / 3.0)));
        }
        snprintf(name, strlen(dir) + 32, "%s/charts%zu.png", dir, p);
        if (res == VDBGI_OK)
            res = vdbgi_image_write(ctx, name, (int)size, (int)size, 3, pix, true);
    }
    vdbgi_free(ctx, pix);
    vdbgi_free(ctx, name);
    return res;
}
