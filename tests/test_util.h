/* test_util.h: scenes built in memory for the tests, and a counting allocator. */
#ifndef VDBGI_TEST_UTIL_H
#define VDBGI_TEST_UTIL_H

#include "check.h"
#include "vdbgi.h"

#include <stdlib.h>
#include <string.h>

/* A square of side size at height y, centred on the origin, front face up (+y). */
typedef struct test_mesh {
    float pos[3 * 64];
    uint32_t idx[3 * 64];
    size_t vertex_count, triangle_count;
} test_mesh;

static inline void test_mesh_quad(test_mesh *m, const float a[3], const float b[3],
                                  const float c[3], const float d[3])
{
    const uint32_t base = (uint32_t)m->vertex_count;
    const float *const v[4] = {a, b, c, d};
    for (int i = 0; i < 4; i++)
        memcpy(&m->pos[3 * (m->vertex_count++)], v[i], 3 * sizeof(float));
    const uint32_t t[6] = {base, base + 1, base + 2, base, base + 2, base + 3};
    memcpy(&m->idx[3 * m->triangle_count], t, sizeof(t));
    m->triangle_count += 2;
}

static inline void test_mesh_plane(test_mesh *m, float size, float y)
{
    const float h = size / 2;
    const float a[3] = {-h, y, h}, b[3] = {h, y, h}, c[3] = {h, y, -h}, d[3] = {-h, y, -h};
    test_mesh_quad(m, a, b, c, d);
}

/* Axis-aligned box [lo, hi]; faces point out, or in when inward is set (a closed room). */
static inline void test_mesh_box(test_mesh *m, const float lo[3], const float hi[3], int inward)
{
    static const int faces[6][4][3] = {
        {{0, 0, 1}, {1, 0, 1}, {1, 1, 1}, {0, 1, 1}}, {{1, 0, 0}, {0, 0, 0}, {0, 1, 0}, {1, 1, 0}},
        {{1, 0, 1}, {1, 0, 0}, {1, 1, 0}, {1, 1, 1}}, {{0, 0, 0}, {0, 0, 1}, {0, 1, 1}, {0, 1, 0}},
        {{0, 1, 1}, {1, 1, 1}, {1, 1, 0}, {0, 1, 0}}, {{0, 0, 0}, {1, 0, 0}, {1, 0, 1}, {0, 0, 1}}};
    for (int f = 0; f < 6; f++) {
        float p[4][3];
        for (int i = 0; i < 4; i++)
            for (int k = 0; k < 3; k++)
                p[i][k] = faces[f][i][k] ? hi[k] : lo[k];
        if (inward)
            test_mesh_quad(m, p[3], p[2], p[1], p[0]);
        else
            test_mesh_quad(m, p[0], p[1], p[2], p[3]);
    }
}

static inline vdbgi_mesh_desc test_mesh_desc(const test_mesh *m, float albedo, int double_sided)
{
    vdbgi_mesh_desc d = {.positions = m->pos,
                         .vertex_count = m->vertex_count,
                         .indices = m->idx,
                         .triangle_count = m->triangle_count,
                         .albedo = {albedo, albedo, albedo},
                         .double_sided = double_sided};
    return d;
}

/* Allocator that counts live blocks and fails its Nth call (fail_at < 0: never). */
typedef struct test_alloc {
    long calls, fail_at, live;
} test_alloc;

static inline void *test_alloc_fn(void *user, size_t size)
{
    test_alloc *const a = user;
    if (a->fail_at >= 0 && a->calls++ == a->fail_at)
        return NULL;
    void *const p = malloc(size);
    a->live += p != NULL;
    return p;
}

static inline void test_free_fn(void *user, void *ptr)
{
    test_alloc *const a = user;
    if (ptr) {
        a->live--;
        free(ptr);
    }
}

/* Warnings the library logs, kept for tests that expect one. */
static char test_last_warning[512];
static int test_warning_count;

static inline void test_log(void *user, vdbgi_log_level level, const char *message)
{
    (void)user;
    if (level == VDBGI_LOG_WARNING) {
        test_warning_count++;
        snprintf(test_last_warning, sizeof(test_last_warning), "%s", message);
    }
}

static inline vdbgi_context *test_context(void)
{
    const vdbgi_context_desc d = {.log = test_log};
    vdbgi_context *ctx = NULL;
    if (vdbgi_context_create(&d, &ctx) != VDBGI_OK) {
        fprintf(stderr, "cannot create a context\n");
        exit(1);
    }
    return ctx;
}

/* A scratch directory per test program: made by test_tmpdir_make, removed at the end. */
static char test_tmpdir[256];

static inline void test_tmpdir_make(const char *name)
{
    snprintf(test_tmpdir, sizeof(test_tmpdir), "/tmp/vdbgi-%s-XXXXXX", name);
    if (!mkdtemp(test_tmpdir)) {
        perror("mkdtemp");
        exit(1);
    }
}

static inline void test_tmpdir_remove(void)
{
    char cmd[300];
    snprintf(cmd, sizeof(cmd), "rm -rf '%s'", test_tmpdir);
    if (system(cmd) != 0)
        fprintf(stderr, "could not remove %s\n", test_tmpdir);
}

/* name inside the scratch directory; four results may be held at once. */
static inline const char *tmp_path(const char *name)
{
    static char buf[4][512];
    static int slot;
    char *const p = buf[slot++ & 3];
    snprintf(p, 512, "%s/%s", test_tmpdir, name);
    return p;
}

#endif /* VDBGI_TEST_UTIL_H */
