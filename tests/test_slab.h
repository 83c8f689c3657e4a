/* test_slab.h: probes on a box of lattice points holding a given field, for converter tests. */
#ifndef VDBGI_TEST_SLAB_H
#define VDBGI_TEST_SLAB_H

#include "check.h"
#include "probes.h"
#include "volume.h"

typedef float (*field_fn)(double x, double y, double z, int channel);

/* nx x ny x nz probes, all valid, spacing 0.5 from (0.25, 0.25, 0.25), values f at the lattice. */
static inline vdbgi_probes *test_slab(vdbgi_context *ctx, int nx, int ny, int nz, field_fn f)
{
    vdbgi_probes *p = NULL;
    CHECK_RESULT(ctx, vdbgi_probes_alloc(ctx, (size_t)nx * ny * nz, true, &p), VDBGI_OK);
    if (!p)
        return NULL;
    p->spacing = 0.5;
    p->margin = 2.0;
    p->origin[0] = 0.25, p->origin[1] = 0.25, p->origin[2] = 0.25;
    size_t n = 0;
    for (int x = 0; x < nx; x++)
        for (int y = 0; y < ny; y++)
            for (int z = 0; z < nz; z++, n++) {
                p->ijk[3 * n] = x, p->ijk[3 * n + 1] = y, p->ijk[3 * n + 2] = z;
                for (int c = 0; c < 3; c++)
                    p->rgb[3 * n + c] = f(x, y, z, c);
                p->backface[n] = 0.0f;
            }
    return p;
}

#endif /* VDBGI_TEST_SLAB_H */
