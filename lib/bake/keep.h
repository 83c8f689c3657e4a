/* keep.h: which of the probes near surfaces a game reads (the space what moves uses). */
#ifndef VDBGI_KEEP_H
#define VDBGI_KEEP_H

#include "probes.h"
#include "scene.h"

/*
 * Keeps only the probes desc asks for (vdbgi_place_desc's walkable_height
 * and keep boxes), in place; none asked for, all stay. Each probe is judged
 * by its own position alone, so tiles keep what the whole lattice keeps.
 */
vdbgi_result vdbgi_probes_keep(vdbgi_context *ctx, const vdbgi_scene *scene,
                               const vdbgi_place_desc *desc, vdbgi_probes *p);

#endif /* VDBGI_KEEP_H */
