/* bench_lights.h: gi-bench lights, the cost and the error of the scene's own light. */
#ifndef VDBGI_BENCH_LIGHTS_H
#define VDBGI_BENCH_LIGHTS_H

/* Run it on the scene at path with probes at spacing; tables on stdout, out/lights.csv. */
int bench_lights(const char *scene, double spacing, int threads, int repeat, const char *out);

#endif /* VDBGI_BENCH_LIGHTS_H */
