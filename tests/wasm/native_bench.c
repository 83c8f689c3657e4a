/* native_bench.c: times gi_read + gi_prepare natively on an inflated .gi; writes the atlas (and
   sh textures, columns) to OUTPREFIX.* for comparison. Usage: native_bench file.gi [outprefix] */
#define _POSIX_C_SOURCE 200809L
#include <stdint.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <time.h>
int gi_read(const uint8_t *data, size_t size);
int gi_prepare(void);
const char *gi_error(void);
const uint8_t *gi_atlas(void);
size_t gi_atlas_size(void);
const uint8_t *gi_columns(void);
size_t gi_columns_size(void);
const uint8_t *gi_sh(int i);
void gi_free(void);
/* Linked with -Wl,--wrap=vdbgi_core_count: one thread, as the WASM build runs. */
int __wrap_vdbgi_core_count(void);
int __wrap_vdbgi_core_count(void)
{
    return 1;
}

static double now(void)
{
    struct timespec ts;
    clock_gettime(CLOCK_MONOTONIC, &ts);
    return ts.tv_sec * 1e3 + ts.tv_nsec * 1e-6;
}
static int cmp(const void *a, const void *b)
{
    double x = *(const double *)a, y = *(const double *)b;
    return x < y ? -1 : x > y;
}
static void dump(const char *prefix, const char *what, const uint8_t *p, size_t n)
{
    char path[512];
    snprintf(path, sizeof path, "%s.%s", prefix, what);
    FILE *f = fopen(path, "wb");
    if (!f || fwrite(p, 1, n, f) != n)
        fprintf(stderr, "%s: cannot write\n", path);
    if (f)
        fclose(f);
}
int main(int argc, char **argv)
{
    FILE *f = argc > 1 ? fopen(argv[1], "rb") : NULL;
    if (!f) {
        fprintf(stderr, "usage: native_bench FILE.gi [OUTPREFIX]\n");
        return 2;
    }
    fseek(f, 0, SEEK_END);
    long n = ftell(f);
    fseek(f, 0, SEEK_SET);
    uint8_t *b = n > 0 ? malloc(n) : NULL;
    if (!b || fread(b, 1, n, f) != (size_t)n)
        return 1;
    fclose(f);
    /* A cold run, three warm-ups, ten timed. */
    double t[14], tr[14];
    for (int i = 0; i < 14; i++) {
        double t0 = now();
        int r = gi_read(b, n);
        double t1 = now();
        if (r || gi_prepare()) {
            fprintf(stderr, "error %d: %s\n", r, gi_error());
            return 1;
        }
        double t2 = now();
        t[i] = t2 - t0;
        tr[i] = t1 - t0;
    }
    printf("cold %.2f ms (read %.2f)\n", t[0], tr[0]);
    double w[10];
    memcpy(w, t + 4, sizeof w);
    qsort(w, 10, sizeof w[0], cmp);
    double wr[10];
    memcpy(wr, tr + 4, sizeof wr);
    qsort(wr, 10, sizeof wr[0], cmp);
    printf("best %.2f ms median %.2f ms (read+rebuild only: best %.2f median %.2f)\n", w[0],
           (w[4] + w[5]) / 2, wr[0], (wr[4] + wr[5]) / 2);
    if (argc > 2) {
        dump(argv[2], "atlas", gi_atlas(), gi_atlas_size());
        dump(argv[2], "columns", gi_columns(), gi_columns_size());
        for (int i = 0; i < 6; i++)
            if (gi_sh(i)) {
                char w2[8];
                snprintf(w2, sizeof w2, "sh%d", i);
                dump(argv[2], w2, gi_sh(i), gi_atlas_size());
            }
    }
    gi_free();
    return 0;
}
