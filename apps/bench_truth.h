/* bench_truth.h: gi-bench truth, every method against the hemisphere estimator. */
#ifndef VDBGI_BENCH_TRUTH_H
#define VDBGI_BENCH_TRUTH_H

#include <stdbool.h>

/* Run it on the scene at path; one spacing when spacing_given, else 0.5 and 0.25 m. */
int bench_truth(const char *scene, double spacing, bool spacing_given, int rays, int threads,
                const char *out);

#endif /* VDBGI_BENCH_TRUTH_H */
