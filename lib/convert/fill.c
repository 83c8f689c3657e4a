/*
 * fill.c: invalid and absent probes take values from valid neighbours, ring
 * by ring (fill_rings.c), over a sparse grid of 8^3 leaves; for 1 colour or 6
 * cube sides. Here: the grid from the probes, its target, and the field out.
 */
#include "fill_grid.h"

#include <stdlib.h>
#include <string.h>

static unsigned point_number(const int32_t ijk[3])
{
    return (unsigned)((ijk[0] & 7) << 6 | (ijk[1] & 7) << 3 | (ijk[2] & 7));
}

static void grid_free(vdbgi_fill_grid *g)
{
    vdbgi_map_free(&g->map);
    vdbgi_free(g->ctx, g->leaves);
    vdbgi_free(g->ctx, g->values);
    memset(g, 0, sizeof(*g));
}

/* The leaf holding ijk, created (all masks clear) if new. */
static vdbgi_result grid_touch(vdbgi_fill_grid *g, const int32_t ijk[3], uint32_t *leaf)
{
    const int32_t o[3] = {ijk[0] & ~7, ijk[1] & ~7, ijk[2] & ~7};
    size_t i;
    bool added;
    VDBGI_TRY(vdbgi_map_insert(&g->map, o, &i, &added));
    if (added) {
        if (i == g->leaf_capacity) {
            const size_t capacity = g->leaf_capacity ? 2 * g->leaf_capacity : 64;
            vdbgi_fill_leaf *const leaves = vdbgi_calloc(g->ctx, capacity, sizeof(*leaves));
            if (!leaves)
                return VDBGI_ERR_OUT_OF_MEMORY;
            if (g->leaves)
                memcpy(leaves, g->leaves, i * sizeof(*leaves));
            vdbgi_free(g->ctx, g->leaves);
            g->leaves = leaves;
            g->leaf_capacity = capacity;
        }
        memset(&g->leaves[i], 0, sizeof(g->leaves[i]));
        memcpy(g->leaves[i].origin, o, sizeof(o));
    }
    *leaf = (uint32_t)i;
    return VDBGI_OK;
}

static long grid_find(const vdbgi_fill_grid *g, const int32_t ijk[3])
{
    const int32_t o[3] = {ijk[0] & ~7, ijk[1] & ~7, ijk[2] & ~7};
    return vdbgi_map_find(&g->map, o);
}

/* Once the target is complete: neighbour tables and the value block. */
static vdbgi_result grid_finish_target(vdbgi_fill_grid *g)
{
    const size_t count = g->map.count;
    for (size_t l = 0; l < count; l++) {
        vdbgi_fill_leaf *const leaf = &g->leaves[l];
        for (int i = 0; i < 27; i++) {
            const int32_t o[3] = {leaf->origin[0] + (i % 3 - 1) * 8,
                                  leaf->origin[1] + (i / 3 % 3 - 1) * 8,
                                  leaf->origin[2] + (i / 9 - 1) * 8};
            leaf->nb[i] = (int32_t)vdbgi_map_find(&g->map, o);
        }
    }
    g->values = vdbgi_calloc(g->ctx, count ? count * VDBGI_LEAF_VOXELS : 1,
                             3 * (size_t)g->channels * sizeof(float));
    return g->values ? VDBGI_OK : VDBGI_ERR_OUT_OF_MEMORY;
}

/* ---- from probes to the field ---------------------------------------------- */

static int compare_triples(const void *a, const void *b)
{
    return vdbgi_tree_order(a, b);
}

/* A leaf to sort: its origin first, so compare_triples orders it. */
typedef struct leaf_order {
    int32_t origin[3];
    uint32_t leaf;
} leaf_order;

/*
 * The filled points as a field, leaves in tree order (the order sums over it
 * add in). The field takes over the grid's block of values.
 */
static vdbgi_result export_field(vdbgi_fill_grid *g, vdbgi_field *f)
{
    vdbgi_context *const ctx = g->ctx;
    memset(f, 0, sizeof(*f));
    f->ctx = ctx;
    f->channels = g->channels;
    size_t count = 0;
    for (size_t l = 0; l < g->map.count; l++)
        count += fill_popcount512(g->leaves[l].filled) > 0;
    leaf_order *const order = vdbgi_calloc(ctx, count ? count : 1, sizeof(leaf_order));
    vdbgi_result r = order ? vdbgi_map_init(ctx, &f->index, count) : VDBGI_ERR_OUT_OF_MEMORY;
    if (r == VDBGI_OK && !(f->leaves = vdbgi_calloc(ctx, count ? count : 1, sizeof(vdbgi_leaf))))
        r = VDBGI_ERR_OUT_OF_MEMORY;
    if (r != VDBGI_OK) {
        vdbgi_free(ctx, order);
        vdbgi_field_free(f);
        return r;
    }
    f->values = g->values;
    g->values = NULL;
    size_t n = 0;
    for (size_t l = 0; l < g->map.count; l++)
        if (fill_popcount512(g->leaves[l].filled) > 0) {
            memcpy(order[n].origin, g->leaves[l].origin, sizeof(order[n].origin));
            order[n++].leaf = (uint32_t)l;
        }
    qsort(order, count, sizeof(leaf_order), compare_triples);
    const size_t leaf_floats = VDBGI_LEAF_VOXELS * 3 * (size_t)g->channels;
    for (size_t i = 0; i < count && r == VDBGI_OK; i++) {
        const vdbgi_fill_leaf *const src = &g->leaves[order[i].leaf];
        vdbgi_leaf *const dst = &f->leaves[i];
        memcpy(dst->origin, src->origin, sizeof(dst->origin));
        memcpy(dst->mask, src->filled, sizeof(dst->mask));
        dst->values = f->values + order[i].leaf * leaf_floats;
        size_t index;
        r = vdbgi_map_insert(&f->index, dst->origin, &index, NULL);
    }
    f->leaf_count = count;
    vdbgi_free(ctx, order);
    if (r != VDBGI_OK)
        vdbgi_field_free(f);
    return r;
}

/* Every fine point of the cells, each dilated by rim points, as target. */
static vdbgi_result mark_target(vdbgi_fill_grid *g, const vdbgi_map *cells, int cell_size, int rim)
{
    uint32_t leaf = 0;
    int32_t leaf_origin[3] = {1, 1, 1}; /* no leaf has an odd origin */
    for (size_t c = 0; c < cells->count; c++) {
        const int32_t *const key = cells->keys[c];
        for (int32_t x = key[0] * cell_size - rim; x < (key[0] + 1) * cell_size + rim; x++)
            for (int32_t y = key[1] * cell_size - rim; y < (key[1] + 1) * cell_size + rim; y++)
                for (int32_t z = key[2] * cell_size - rim; z < (key[2] + 1) * cell_size + rim;
                     z++) {
                    const int32_t p[3] = {x, y, z};
                    if ((x & ~7) != leaf_origin[0] || (y & ~7) != leaf_origin[1] ||
                        (z & ~7) != leaf_origin[2]) {
                        VDBGI_TRY(grid_touch(g, p, &leaf));
                        memcpy(leaf_origin, g->leaves[leaf].origin, sizeof(leaf_origin));
                    }
                    fill_set_bit(g->leaves[leaf].target, point_number(p));
                }
    }
    return VDBGI_OK;
}

/*
 * With margin 0, the cells whose filter reads a source: those whose 4^3
 * points, or the points beyond their faces that the filter reaches (rim
 * above, filter_below below: the seed layout's apron, or the compact
 * layout's + border alone), include one. A position in any other cell would interpolate filled values
 * alone: nothing a receiver near a surface reads (docs/converter.md). With
 * margin k > 0, the cells holding a source dilated by k cells
 * (26-neighbourhood), for Bevy's coarser voxels, which read further.
 */
static vdbgi_result occupied_cells(vdbgi_context *ctx, const vdbgi_fill_input *in,
                                   const vdbgi_fill_params *fp, vdbgi_map *cells, size_t *sources,
                                   uint8_t **off_top_out)
{
    vdbgi_result r = vdbgi_map_init(ctx, cells, 1024);
    *sources = 0;
    const int s = fp->cell_size, m = fp->margin_cells;
    /* A cell's filter reads rim points above it and filter_below points below it. */
    const int above = m > 0 ? 0 : fp->rim, below = m > 0 ? 0 : fp->filter_below;
    const bool lift = fp->lift && m == 0;
    uint8_t *off_top = NULL; /* lift: the cell's filter reads a source off its top face */
    size_t off_top_size = 0;
    for (size_t n = 0; n < in->count && r == VDBGI_OK; n++) {
        if (in->backface[n] > fp->invalid_threshold)
            continue;
        (*sources)++;
        const int32_t *const p = &in->ijk[3 * n];
        int32_t lo[3], hi[3];
        for (int k = 0; k < 3; k++) {
            lo[k] = vdbgi_floor_div(p[k] - above, s) - m;
            hi[k] = vdbgi_floor_div(p[k] + below, s) + m;
        }
        for (int32_t x = lo[0]; x <= hi[0] && r == VDBGI_OK; x++)
            for (int32_t y = lo[1]; y <= hi[1] && r == VDBGI_OK; y++)
                for (int32_t z = lo[2]; z <= hi[2] && r == VDBGI_OK; z++) {
                    const int32_t cell[3] = {x, y, z};
                    size_t index;
                    r = vdbgi_map_insert(cells, cell, &index, NULL);
                    if (r != VDBGI_OK || !lift)
                        continue;
                    if (index >= off_top_size) {
                        const size_t size = 2 * index + 1024;
                        uint8_t *const grown = vdbgi_calloc(ctx, size, 1);
                        if (!grown) {
                            r = VDBGI_ERR_OUT_OF_MEMORY;
                            continue;
                        }
                        if (off_top)
                            memcpy(grown, off_top, off_top_size);
                        vdbgi_free(ctx, off_top);
                        off_top = grown, off_top_size = size;
                    }
                    off_top[index] |= p[1] != (y + 1) * s;
                }
    }
    *off_top_out = off_top; /* covers every cell: each index grew it */
    return r;
}

/* The valid probes' values into the grid's leaves; the invalid ones marked, for the darkest fill. */
static void place_sources(vdbgi_fill_grid *g, const vdbgi_fill_input *in,
                          const vdbgi_fill_params *fp)
{
    const size_t ch3 = 3 * (size_t)in->channels;
    for (size_t n = 0; n < in->count; n++) {
        const int32_t *const p = &in->ijk[3 * n];
        const long l = grid_find(g, p);
        const unsigned pn = point_number(p);
        if (in->backface[n] <= fp->invalid_threshold) {
            /* Every source lies in a target cell, so its leaf exists. */
            fill_set_bit(g->leaves[l].filled, pn);
            memcpy(fill_grid_value(g, (size_t)l, pn), &in->values[ch3 * n], ch3 * sizeof(float));
        } else if (fp->darkest && l >= 0) {
            fill_set_bit(g->leaves[l].invalid, pn);
        }
    }
}

vdbgi_result vdbgi_fill_check_sparse(vdbgi_context *ctx, size_t sources, size_t cells,
                                     int cell_size, size_t allowed)
{
    VDBGI_FAIL_IF(ctx, cells > VDBGI_FILL_SPARSE_CELLS && cells > allowed, VDBGI_ERR_FORMAT,
                  "%zu valid probes spread over %zu cells of %d^3 points (more than %zu, and "
                  "more than %d): too sparse a lattice to convert",
                  sources, cells, cell_size, allowed, VDBGI_FILL_SPARSE_CELLS);
    return VDBGI_OK;
}

vdbgi_result vdbgi_field_fill(vdbgi_context *ctx, const vdbgi_fill_input *in,
                              const vdbgi_fill_params *fp, vdbgi_field *field, int32_t **cells_out,
                              size_t *cell_count, int32_t **top_only_out, size_t *top_only_count,
                              size_t *unreached)
{
    memset(field, 0, sizeof(*field));
    *cells_out = NULL;
    *cell_count = 0;
    if (top_only_out) {
        *top_only_out = NULL;
        *top_only_count = 0;
    }
    *unreached = 0;
    uint8_t *off_top = NULL;
    int32_t *top_only = NULL;
    VDBGI_FAIL_IF(ctx, in->channels < 1 || in->channels > VDBGI_FIELD_MAX_CHANNELS,
                  VDBGI_ERR_INVALID_ARG, "a field holds 1 to %d colours a point (got %d)",
                  VDBGI_FIELD_MAX_CHANNELS, in->channels);
    vdbgi_map cells = {0};
    size_t sources = 0;
    vdbgi_fill_grid g = {
        .ctx = ctx, .channels = in->channels, .judged = in->signed_terms ? 1 : in->channels};
    int32_t *out = NULL;
    vdbgi_result r = occupied_cells(ctx, in, fp, &cells, &sources, &off_top);
    if (r != VDBGI_OK)
        goto done;
    if (sources == 0) {
        r = vdbgi_fail(ctx, VDBGI_ERR_FORMAT,
                       "no valid probe to fill from (%zu probes, all invalid or none)", in->count);
        goto done;
    }
    /*
     * A scene's lattice holds about 30 valid probes a cell (the bundled world,
     * the 200 m world and the interior: 1 cell for 27-45): a file of probes
     * one per leaf asked for 8 cells a probe (the most one can reach) and
     * gigabytes of fill. Refused past an eighth of that most, before the fill
     * allocates; a margin of m cells lets a probe reach (2m + 2)^3.
     */
    const size_t reach = (size_t)fp->margin_cells + 1, allowed = reach * reach * reach * sources;
    if ((r = vdbgi_fill_check_sparse(ctx, sources, cells.count, fp->cell_size, allowed)) !=
        VDBGI_OK)
        goto done;
    if ((r = vdbgi_map_init(ctx, &g.map, 4 * cells.count / 8 + 64)) != VDBGI_OK ||
        (r = mark_target(&g, &cells, fp->cell_size, fp->rim)) != VDBGI_OK ||
        (r = grid_finish_target(&g)) != VDBGI_OK)
        goto done;
    place_sources(&g, in, fp);
    if ((r = vdbgi_fill_spread(&g, fp, unreached)) != VDBGI_OK)
        goto done;
    out = vdbgi_calloc(ctx, cells.count ? cells.count : 1, 3 * sizeof(int32_t));
    if (!out) {
        r = VDBGI_ERR_OUT_OF_MEMORY;
        goto done;
    }
    memcpy(out, cells.keys, cells.count * 3 * sizeof(int32_t));
    qsort(out, cells.count, 3 * sizeof(int32_t), compare_triples);
    /* The cells whose filter reads sources only on their top face (the caller looks
       them up, so their order is the map's). */
    size_t tops = 0;
    for (size_t c = 0; off_top && c < cells.count; c++)
        tops += !off_top[c];
    if (off_top && top_only_out) {
        top_only = vdbgi_calloc(ctx, tops ? tops : 1, 3 * sizeof(int32_t));
        if (!top_only) {
            r = VDBGI_ERR_OUT_OF_MEMORY;
            goto done;
        }
        for (size_t c = 0, t = 0; c < cells.count; c++)
            if (!off_top[c])
                memcpy(&top_only[3 * t++], cells.keys[c], 3 * sizeof(int32_t));
    }
    if ((r = export_field(&g, field)) != VDBGI_OK)
        goto done;
    *cells_out = out;
    *cell_count = cells.count;
    out = NULL;
    if (top_only_out) {
        *top_only_out = top_only;
        *top_only_count = top_only ? tops : 0;
        top_only = NULL;
    }
done:
    vdbgi_free(ctx, out);
    vdbgi_free(ctx, off_top);
    vdbgi_free(ctx, top_only);
    vdbgi_map_free(&cells);
    grid_free(&g);
    return r;
}

vdbgi_result vdbgi_fill_dense(vdbgi_context *ctx, const int res[3], int channels, float *values,
                              unsigned char *valued, const vdbgi_fill_params *fp)
{
    VDBGI_FAIL_IF(ctx, channels < 1 || channels > VDBGI_FIELD_MAX_CHANNELS, VDBGI_ERR_INVALID_ARG,
                  "a field holds 1 to %d colours a point (got %d)", VDBGI_FIELD_MAX_CHANNELS,
                  channels);
    vdbgi_fill_grid g = {.ctx = ctx, .channels = channels, .judged = channels};
    const size_t ch3 = 3 * (size_t)channels;
    vdbgi_fill_params dense = *fp;
    dense.darkest = false;
    vdbgi_result r = vdbgi_map_init(ctx, &g.map, 64);
    for (int z = 0; z < res[2] && r == VDBGI_OK; z++)
        for (int y = 0; y < res[1] && r == VDBGI_OK; y++)
            for (int x = 0; x < res[0] && r == VDBGI_OK; x++) {
                const int32_t p[3] = {x, y, z};
                uint32_t l;
                if ((r = grid_touch(&g, p, &l)) == VDBGI_OK)
                    fill_set_bit(g.leaves[l].target, point_number(p));
            }
    if (r == VDBGI_OK)
        r = grid_finish_target(&g);
    for (int z = 0; z < res[2] && r == VDBGI_OK; z++)
        for (int y = 0; y < res[1]; y++)
            for (int x = 0; x < res[0]; x++) {
                const size_t i =
                    ((size_t)z * (size_t)res[1] + (size_t)y) * (size_t)res[0] + (size_t)x;
                if (!valued[i])
                    continue;
                const int32_t p[3] = {x, y, z};
                const long l = grid_find(&g, p);
                fill_set_bit(g.leaves[l].filled, point_number(p));
                memcpy(fill_grid_value(&g, (size_t)l, point_number(p)), &values[ch3 * i],
                       ch3 * sizeof(float));
            }
    size_t unreached = 0;
    if (r == VDBGI_OK)
        r = vdbgi_fill_spread(&g, &dense, &unreached);
    for (int z = 0; z < res[2] && r == VDBGI_OK; z++)
        for (int y = 0; y < res[1]; y++)
            for (int x = 0; x < res[0]; x++) {
                const size_t i =
                    ((size_t)z * (size_t)res[1] + (size_t)y) * (size_t)res[0] + (size_t)x;
                const int32_t p[3] = {x, y, z};
                const long l = grid_find(&g, p);
                if (valued[i] || !fill_bit(g.leaves[l].filled, point_number(p)))
                    continue;
                memcpy(&values[ch3 * i], fill_grid_value(&g, (size_t)l, point_number(p)),
                       ch3 * sizeof(float));
                valued[i] = 1;
            }
    grid_free(&g);
    return r;
}
