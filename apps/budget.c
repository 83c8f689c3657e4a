/* budget.c: --budget's parsing, a volume's VRAM, and the measured curves it quotes. */
#include "budget.h"
#include "cli.h"

#include <math.h>
#include <stdio.h>

bool budget_parse(const char *text, double *bytes)
{
    double mb;
    /* Past a terabyte no GPU holds it; under a kilobyte no volume fits. */
    if (!cli_parse_double(text, &mb) || !(mb >= 0.001 && mb <= 1e6)) {
        cli_usage_error("--budget must be megabytes of GPU memory in 0.001..1e6 (got '%s')", text);
        return false;
    }
    *bytes = mb * 1e6;
    return true;
}

size_t budget_vram(const vdbgi_volume_info *vi)
{
    /* No columns past the runtime's limit: the 3D indirection then, never nothing. */
    const size_t indirection = vi->columns_size ? vi->columns_size : vi->indirection_size;
    return indirection + vi->atlas_size + vi->sh_size;
}

/*
 * gi-bench memory's rows (docs/data/memory_world.csv and memory_world200.csv,
 * compact layout, terms at the default 6 bits): character and surface RMSE,
 * % of the mean, on the bundled world and on the 200 m world.
 * cli/budget checks these against the CSV files, so they move together.
 */
static const struct curve {
    double spacing;
    bool terms;
    float eps;
    float bundled[2], world200[2];
} curves[] = {
    {0.25, 0, 0.05f, {86.9f, 597.9f}, {83.1f, 1031.2f}},
    {0.25, 0, 0.1f, {86.9f, 597.7f}, {83.1f, 1031.1f}},
    {0.25, 0, 0.2f, {86.9f, 597.4f}, {83.1f, 1027.5f}},
    {0.25, 0, 0.4f, {86.9f, 595.8f}, {83.1f, 1014.0f}},
    {0.25, 1, 0.05f, {4.2f, 26.7f}, {2.8f, 57.6f}},
    {0.25, 1, 0.1f, {4.1f, 26.6f}, {2.8f, 57.6f}},
    {0.25, 1, 0.2f, {4.1f, 26.3f}, {2.8f, 57.9f}},
    {0.25, 1, 0.4f, {4.2f, 29.8f}, {3.2f, 63.1f}},
    {0.5, 0, 0.05f, {87.0f, 549.1f}, {83.1f, 969.9f}},
    {0.5, 0, 0.1f, {87.0f, 549.1f}, {83.1f, 969.9f}},
    {0.5, 0, 0.2f, {87.0f, 548.9f}, {83.1f, 969.9f}},
    {0.5, 0, 0.4f, {87.0f, 548.6f}, {83.1f, 965.7f}},
    {0.5, 1, 0.05f, {6.6f, 46.2f}, {3.8f, 75.4f}},
    {0.5, 1, 0.1f, {6.6f, 46.2f}, {3.8f, 75.4f}},
    {0.5, 1, 0.2f, {6.6f, 46.4f}, {3.8f, 75.5f}},
    {0.5, 1, 0.4f, {6.8f, 46.4f}, {5.5f, 76.2f}},
    {1, 0, 0.05f, {87.2f, 497.4f}, {83.2f, 876.5f}},
    {1, 0, 0.1f, {87.2f, 497.4f}, {83.2f, 876.5f}},
    {1, 0, 0.2f, {87.2f, 497.4f}, {83.2f, 876.5f}},
    {1, 0, 0.4f, {87.2f, 497.4f}, {83.2f, 876.6f}},
    {1, 1, 0.05f, {11.4f, 83.1f}, {6.2f, 126.4f}},
    {1, 1, 0.1f, {11.4f, 83.1f}, {6.2f, 126.4f}},
    {1, 1, 0.2f, {11.4f, 83.1f}, {6.2f, 126.4f}},
    {1, 1, 0.4f, {11.4f, 83.1f}, {6.3f, 136.3f}},
};

void budget_expected(double spacing, bool terms, double eps, char *text, size_t size)
{
    for (size_t i = 0; i < sizeof(curves) / sizeof(curves[0]); i++) {
        const struct curve *c = &curves[i];
        if (c->terms == terms && fabs(c->spacing - spacing) < 1e-3 * spacing &&
            fabs(c->eps - eps) < 1e-4) {
            snprintf(text, size,
                     "expected, from the curves measured at %g m (seed model, against the "
                     "hemisphere truth): characters %.1f %% RMSE on the bundled world, %.1f %% "
                     "on the 200 m world; surfaces %.1f %%, %.1f %%",
                     spacing, (double)c->bundled[0], (double)c->world200[0], (double)c->bundled[1],
                     (double)c->world200[1]);
            return;
        }
    }
    snprintf(text, size,
             "no measured curve at %g m, eps %g (0.25, 0.5 and 1 m were; eps 0.05..0.4)", spacing,
             eps);
}

/* gi-bench lightmap's rows (docs/data/lightmap_world.csv, lightmap_interior.csv): RMSE, %. */
static const struct lightmap_curve {
    double texel;
    float bundled, interior;
} lightmap_curves[] = {
    {1, 40.6f, 17.2f}, {0.5, 18.8f, 11.7f}, {0.25, 11.0f, 10.7f}, {0.125, 7.7f, 11.0f}};

void budget_lightmap_expected(double texel, char *text, size_t size)
{
    for (size_t i = 0; i < sizeof(lightmap_curves) / sizeof(lightmap_curves[0]); i++) {
        const struct lightmap_curve *c = &lightmap_curves[i];
        if (texel > 0.0 && fabs(c->texel - texel) < 1e-3 * texel) {
            snprintf(text, size,
                     "expected, from the curves measured at %g m texels (against the "
                     "hemisphere truth): surfaces %.1f %% RMSE on the bundled world (one pass, "
                     "seed model), %.1f %% on the interior (three passes, physical)",
                     texel, (double)c->bundled, (double)c->interior);
            return;
        }
    }
    const size_t n = sizeof(lightmap_curves) / sizeof(lightmap_curves[0]);
    for (size_t i = 0; i + 1 < n && texel > 0.0; i++) {
        const struct lightmap_curve *a = &lightmap_curves[i], *b = &lightmap_curves[i + 1];
        if (texel < a->texel && texel > b->texel) {
            snprintf(text, size,
                     "expected between the curves' %g m (surfaces %.1f %% RMSE on the bundled "
                     "world, %.1f %% on the interior) and %g m (%.1f %%, %.1f %%)",
                     a->texel, (double)a->bundled, (double)a->interior, b->texel,
                     (double)b->bundled, (double)b->interior);
            return;
        }
    }
    if (texel > 0.0)
        snprintf(text, size, "no measured curve at %g m texels (1, 0.5, 0.25 and 0.125 m were)",
                 texel);
    else
        snprintf(text, size, "no measured curve for a scene's own second UV set");
}
