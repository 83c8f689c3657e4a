/* internal.h: every stage's internal header at once (being retired). */
#ifndef VDBGI_INTERNAL_H
#define VDBGI_INTERNAL_H

#include "context.h"
#include "field.h"
#include "probes.h"
#include "scene.h"
#include "tracer.h"

#endif /* VDBGI_INTERNAL_H */
