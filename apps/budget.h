/*
 * budget.h: --budget, a volume's GPU memory in decimal megabytes, for gi-bake
 * (the spacing and the terms) and vdb-to-gi (the bricks' levels and the
 * terms), and the error the measured curves give what they choose
 * (docs/directional.md, "A budget").
 */
#ifndef VDBGI_BUDGET_H
#define VDBGI_BUDGET_H

#include "vdbgi.h"

#include <stdbool.h>
#include <stddef.h>

/* Parse --budget's MB (decimal) into bytes; false (and a usage message) when absurd. */
bool budget_parse(const char *text, double *bytes);

/* The bytes vdbgi's runtime uploads for a volume: columns (or the 3D indirection where
   there are none), atlas and L2 terms. */
size_t budget_vram(const vdbgi_volume_info *vi);

/*
 * The measured error of a volume converted like this one, on the bundled and
 * the 200 m worlds (docs/data/memory_world*.csv: compact layout, seed model,
 * characters and surfaces against the hemisphere truth, RMSE in % of the
 * mean), written into text as one clause; "no measured curve ..." where that
 * spacing or eps was not measured.
 */
void budget_expected(double spacing, bool terms, double eps, char *text, size_t size);

/*
 * The same for a lightmap of texel metres (docs/data/lightmap_world.csv, one
 * pass, seed model; lightmap_interior.csv, three passes, physical model:
 * surfaces against the hemisphere truth at as many bounces); 0: the scene's
 * own second UV set, no curve.
 */
void budget_lightmap_expected(double texel, char *text, size_t size);

#endif /* VDBGI_BUDGET_H */
