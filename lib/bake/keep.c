/*
 * keep.c: the probes a game reads when its statics take a lightmap and the
 * volume serves what moves: those in the space above walkable surfaces up
 * to a height, and those in boxes the user names.
 */
#include "keep.h"
#include "map.h"
#include "tracer.h"

#include <math.h>
#include <string.h>

/* A surface a character stands on: facing up within 45 degrees (glTF's +y). */
#define WALKABLE_COS 0.70710678
/* Probes judged a batch at a time (the batch's rays and hits on the heap). */
#define BATCH 1024

/* Whether triangle t faces up within 45 degrees, on a side that is seen (both when double-sided). */
static bool walkable(const vdbgi_scene *s, uint32_t t)
{
    double n[3];
    vdbgi_scene_triangle_cross(s, t, n);
    const double len = sqrt(n[0] * n[0] + n[1] * n[1] + n[2] * n[2]);
    const bool two = s->tris[t].flags & VDBGI_TRI_DOUBLE_SIDED;
    return n[1] >= WALKABLE_COS * len || (two && -n[1] >= WALKABLE_COS * len);
}

static bool in_boxes(const vdbgi_place_desc *d, const float pos[3])
{
    for (size_t b = 0; b < d->keep_box_count; b++) {
        const double *const box = d->keep_boxes[b];
        if (pos[0] >= box[0] && pos[1] >= box[1] && pos[2] >= box[2] && pos[0] <= box[3] &&
            pos[1] <= box[4] && pos[2] <= box[5])
            return true;
    }
    return false;
}

/* The lattice point ijk's world position. */
static void position(const vdbgi_probes *p, const int32_t ijk[3], float pos[3])
{
    for (int k = 0; k < 3; k++)
        pos[k] = (float)(p->origin[k] + p->spacing * ijk[k]);
}

/*
 * Whether each lattice point of m (keys in order) stands over a walkable surface:
 * its ray down meets one within height, or its ray up one within a spacing (the
 * floor just over a point under it). Rays a batch at a time.
 */
static vdbgi_result over_floors(vdbgi_context *ctx, const vdbgi_scene *scene, const vdbgi_probes *p,
                                double height, const vdbgi_map *m, bool *floor)
{
    vdbgi_tracer *tracer = NULL;
    VDBGI_TRY(vdbgi_tracer_create(ctx, scene->positions, scene->vertex_count, scene->indices,
                                  scene->triangle_count, &tracer));
    float *const org = vdbgi_alloc(ctx, 3 * BATCH * sizeof(float));
    vdbgi_hit *const down = vdbgi_alloc(ctx, 2 * BATCH * sizeof(vdbgi_hit));
    void *const scratch = vdbgi_alloc(ctx, vdbgi_tracer_scratch_size(BATCH));
    vdbgi_result r = org && down && scratch ? VDBGI_OK : VDBGI_ERR_OUT_OF_MEMORY;
    vdbgi_hit *const up = down ? down + BATCH : NULL;
    static const float below[3] = {0.0f, -1.0f, 0.0f}, above[3] = {0.0f, 1.0f, 0.0f};
    for (size_t first = 0; r == VDBGI_OK && first < m->count; first += BATCH) {
        const size_t n = m->count - first < BATCH ? m->count - first : BATCH;
        for (size_t i = 0; i < n; i++)
            position(p, m->keys[first + i], &org[3 * i]);
        const vdbgi_ray_batch d = {
            .org = org, .dir = below, .org_stride = 3, .tfar = (float)height, .count = n};
        const vdbgi_ray_batch u = {
            .org = org, .dir = above, .org_stride = 3, .tfar = (float)p->spacing, .count = n};
        vdbgi_tracer_intersect(tracer, VDBGI_TRACE_SINGLE, &d, down, scratch);
        vdbgi_tracer_intersect(tracer, VDBGI_TRACE_SINGLE, &u, up, scratch);
        for (size_t i = 0; i < n; i++)
            floor[first + i] = (isfinite(down[i].t) && walkable(scene, down[i].prim)) ||
                               (isfinite(up[i].t) && walkable(scene, up[i].prim));
    }
    if (r == VDBGI_OK)
        r = vdbgi_tracer_check(tracer);
    vdbgi_free(ctx, org);
    vdbgi_free(ctx, down);
    vdbgi_free(ctx, scratch);
    vdbgi_tracer_destroy(tracer);
    return r;
}

vdbgi_result vdbgi_probes_keep(vdbgi_context *ctx, const vdbgi_scene *scene,
                               const vdbgi_place_desc *desc, vdbgi_probes *p)
{
    const double height = desc->walkable_height;
    if (height == 0.0 && desc->keep_box_count == 0)
        return VDBGI_OK;
    /*
     * Over floors: a probe is kept when it or one of its 26 lattice neighbours stands
     * over one, so every cell a lookup in that space interpolates has all eight
     * corners. The neighbours are judged by position, placed or not: a tile keeps
     * what the whole lattice keeps.
     */
    vdbgi_map m = {0};
    bool *floor = NULL;
    vdbgi_result r = VDBGI_OK;
    if (height > 0.0) {
        r = vdbgi_map_init(ctx, &m, 4 * p->count);
        for (size_t i = 0; r == VDBGI_OK && i < p->count; i++)
            for (int n = 0; r == VDBGI_OK && n < 27; n++) {
                const int32_t *const c = &p->ijk[3 * i];
                const int32_t k[3] = {c[0] + n % 3 - 1, c[1] + n / 3 % 3 - 1, c[2] + n / 9 - 1};
                size_t index;
                bool added;
                r = vdbgi_map_insert(&m, k, &index, &added);
            }
        if (r == VDBGI_OK)
            r = (floor = vdbgi_alloc(ctx, m.count * sizeof(bool))) ? VDBGI_OK
                                                                   : VDBGI_ERR_OUT_OF_MEMORY;
        if (r == VDBGI_OK)
            r = over_floors(ctx, scene, p, height, &m, floor);
    }
    size_t kept = 0;
    for (size_t i = 0; r == VDBGI_OK && i < p->count; i++) {
        const int32_t *const c = &p->ijk[3 * i];
        bool keep = false;
        for (int n = 0; floor && !keep && n < 27; n++) {
            const int32_t k[3] = {c[0] + n % 3 - 1, c[1] + n / 3 % 3 - 1, c[2] + n / 9 - 1};
            keep = floor[vdbgi_map_find(&m, k)];
        }
        float pos[3];
        position(p, c, pos);
        if (keep || in_boxes(desc, pos))
            memmove(&p->ijk[3 * kept++], c, 3 * sizeof(int32_t));
    }
    vdbgi_map_free(&m);
    vdbgi_free(ctx, floor);
    if (r == VDBGI_OK) {
        vdbgi_log(ctx, VDBGI_LOG_DEBUG, "kept %zu of %zu probes near surfaces", kept, p->count);
        p->count = kept;
    }
    return r;
}
