/* test_bricks.h: the fields and lattice helpers the bricked-volume tests share. */
#ifndef VDBGI_TEST_BRICKS_H
#define VDBGI_TEST_BRICKS_H

#include "probes.h"

#include <math.h>

static inline float smooth(double x, double y, double z, int c)
{
    return (float)(0.2 + 0.08 * sin(0.35 * x + c) * cos(0.23 * z) + 0.01 * y);
}

static inline float flat(double x, double y, double z, int c)
{
    (void)x, (void)y, (void)z;
    return 0.3f + 0.1f * (float)c;
}

/* World position of lattice coordinates ijk (fractions allowed). */
static inline void world_of(const vdbgi_probes *p, const double ijk[3], float pos[3])
{
    for (int k = 0; k < 3; k++)
        pos[k] = (float)(p->origin[k] + p->spacing * ijk[k]);
}

#endif /* VDBGI_TEST_BRICKS_H */
