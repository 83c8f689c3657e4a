/*
 * test_damage.c: every cut, and FLIPS seeded byte flips, of a small
 * .vdb (all three value types vdbgi reads: vec3s, float, int32) and of a
 * small .gi.gz in each brick layout, read in process. Each either reads, or is refused with a
 * message that starts with the file's name and returns no object; none may
 * crash, and (outside ASan) none may need more than an address-space limit.
 * The .gi is also damaged before gzip, so that its own header is tested and
 * not only gzip's checksum.
 */
#define _DEFAULT_SOURCE
#include "test_util.h"

#include <fcntl.h>
#include <libdeflate.h>
#include <stdio.h>
#include <sys/resource.h>
#include <unistd.h>

#if defined(__SANITIZE_ADDRESS__)
#define UNDER_ASAN 1
#elif defined(__has_feature)
#if __has_feature(address_sanitizer)
#define UNDER_ASAN 1
#endif
#endif

/* Byte flips a file: at every byte of a smaller one. */
#define FLIPS 4000

/* A xorshift stream: only spread is needed, not quality. */
static uint64_t test_next(uint64_t *x)
{
    *x ^= *x << 13, *x ^= *x >> 7, *x ^= *x << 17;
    return *x;
}

static unsigned char next_mask(uint64_t *x)
{
    return (unsigned char)(1 + test_next(x) % 255);
}

typedef vdbgi_result (*read_fn)(vdbgi_context *ctx, const char *path, void **out);

static vdbgi_result read_vdb(vdbgi_context *ctx, const char *path, void **out)
{
    vdbgi_probes *p = NULL;
    const vdbgi_result r = vdbgi_probes_read(ctx, path, &p);
    *out = p;
    return r;
}

static vdbgi_result read_gi(vdbgi_context *ctx, const char *path, void **out)
{
    vdbgi_volume *v = NULL;
    const vdbgi_result r = vdbgi_volume_read(ctx, path, &v);
    *out = v;
    return r;
}

static unsigned char *slurp(const char *path, size_t *size);

/* The same file through vdbgi_volume_read_memory, named by its path. */
static vdbgi_result read_gi_memory(vdbgi_context *ctx, const char *path, void **out)
{
    size_t size = 0;
    unsigned char *const bytes = slurp(path, &size);
    vdbgi_volume *v = NULL;
    const vdbgi_result r = vdbgi_volume_read_memory(ctx, bytes, size, path, &v);
    free(bytes);
    *out = v;
    return r;
}

static void destroy(read_fn read, void *obj)
{
    if (read == read_vdb)
        vdbgi_probes_destroy(obj);
    else
        vdbgi_volume_destroy(obj);
}

static unsigned char *slurp(const char *path, size_t *size)
{
    FILE *const f = fopen(path, "rb");
    unsigned char *buf = NULL;
    *size = 0;
    if (f && fseek(f, 0, SEEK_END) == 0) {
        const long n = ftell(f);
        rewind(f);
        buf = malloc(n > 0 ? (size_t)n : 1);
        *size = buf ? fread(buf, 1, (size_t)n, f) : 0;
    }
    if (f)
        fclose(f);
    return buf;
}

static void spill(const char *path, const unsigned char *bytes, size_t size)
{
    FILE *const f = fopen(path, "wb");
    CHECK(f && fwrite(bytes, 1, size, f) == size);
    if (f)
        fclose(f);
}

typedef struct tally {
    int read, refused, bad;
} tally;

/* Read path; a failure must name it first and hand back nothing. */
static void try_read(vdbgi_context *ctx, read_fn read, const char *path, tally *t)
{
    void *obj = (void *)1;
    const vdbgi_result r = read(ctx, path, &obj);
    if (r == VDBGI_OK) {
        t->read++;
        destroy(read, obj);
        return;
    }
    t->refused++;
    const char *const msg = vdbgi_context_error(ctx);
    if (obj != NULL || strncmp(msg, path, strlen(path)) != 0 || strchr(msg, '\n')) {
        if (t->bad++ < 5)
            fprintf(stderr, "  bad refusal (%s): %s\n", vdbgi_result_string(r), msg);
    }
}

/*
 * Every cut of the file at path (which holds bytes), by truncating it in
 * place, then FLIPS flips at seeded places (every byte of a smaller file),
 * each written over the byte and undone after the read.
 */
static tally damage_in_place(vdbgi_context *ctx, read_fn read, const unsigned char *bytes,
                             size_t size, const char *path)
{
    tally t = {0};
    int fd = open(path, O_WRONLY);
    for (size_t n = size; n-- > 0;) {
        CHECK(ftruncate(fd, (off_t)n) == 0);
        try_read(ctx, read, path, &t);
    }
    close(fd);
    spill(path, bytes, size);
    fd = open(path, O_WRONLY);
    uint64_t seed = 0x5eed;
    const size_t flips = size < FLIPS ? size : FLIPS;
    for (size_t k = 0; k < flips; k++) {
        const size_t i = flips == size ? k : (size_t)(test_next(&seed) % size);
        const unsigned char b = bytes[i] ^ next_mask(&seed);
        CHECK(pwrite(fd, &b, 1, (off_t)i) == 1);
        try_read(ctx, read, path, &t);
        CHECK(pwrite(fd, &bytes[i], 1, (off_t)i) == 1);
    }
    close(fd);
    return t;
}

/*
 * The same damage to the uncompressed bytes, gzipped after: every cut and
 * flip within the first 512 bytes (the header and the start of the
 * indirection), then cuts every 64 bytes and FLIPS / 2 flips at random.
 */
static tally damage_before_gzip(vdbgi_context *ctx, read_fn read, const unsigned char *bytes,
                                size_t size, const char *path)
{
    tally t = {0};
    unsigned char *const work = malloc(size);
    struct libdeflate_compressor *const z = libdeflate_alloc_compressor(1);
    const size_t zcap = libdeflate_gzip_compress_bound(z, size);
    unsigned char *const zbuf = malloc(zcap);
    uint64_t seed = 0x5eed;
    for (size_t k = 0; k < 2 * size; k++) {
        const size_t i = k % size; /* a cut below size, a flip from there */
        if (!(i < 512 || (k < size ? i % 64 == 0 : i % (2 * size / FLIPS + 1) == 0)))
            continue;
        memcpy(work, bytes, size);
        if (k >= size)
            work[i >= 512 ? test_next(&seed) % size : i] ^= next_mask(&seed);
        spill(path, zbuf, libdeflate_gzip_compress(z, work, k < size ? i : size, zbuf, zcap));
        try_read(ctx, read, path, &t);
    }
    libdeflate_free_compressor(z);
    free(zbuf);
    free(work);
    return t;
}

static vdbgi_probes *small_bake(vdbgi_context *ctx, vdbgi_scene **s)
{
    /* A floor under a box, probes within 0.3 m: a few hundred, a few leaves a grid, all at
       positive indices (one top-level node, whose masks alone take 8 kB). */
    test_mesh m = {0};
    test_mesh_plane(&m, 2.0f, 1.0f);
    const float lo[3] = {-0.3f, 1, -0.3f}, hi[3] = {0.3f, 1.6f, 0.3f};
    test_mesh_box(&m, lo, hi, 0);
    for (size_t i = 0; i < m.vertex_count; i++)
        m.pos[3 * i] += 2.0f, m.pos[3 * i + 2] += 2.0f;
    const vdbgi_mesh_desc d = test_mesh_desc(&m, 0.6f, 0);
    CHECK_RESULT(ctx, vdbgi_scene_create(ctx, &d, 1, s), VDBGI_OK);
    vdbgi_probes *p = NULL;
    const vdbgi_place_desc pd = {.spacing = 0.25, .margin = 0.3};
    CHECK_RESULT(ctx, vdbgi_probes_place(ctx, *s, &pd, &p), VDBGI_OK);
    /* Adaptive rays: stderr (float) and rays (int32) beside irradiance (vec3s). Cube sides
       are vec3s grids too, left out for time (make fuzz damages a cube bake). */
    const vdbgi_bake_desc bd = {.adaptive = 1, .max_rays = 64, .seed = 3};
    CHECK_RESULT(ctx, vdbgi_probes_bake(p, *s, &bd, NULL), VDBGI_OK);
    return p;
}

static void damaged_vdb_files_read_or_are_refused(void)
{
    vdbgi_context *ctx = test_context();
    vdbgi_scene *s = NULL;
    vdbgi_probes *p = small_bake(ctx, &s);
    CHECK_RESULT(ctx, vdbgi_probes_write(p, tmp_path("good.vdb")), VDBGI_OK);
    size_t size = 0;
    unsigned char *const bytes = slurp(tmp_path("good.vdb"), &size);
    CHECK(bytes && size > 4000);
    if (bytes) {
        const tally t = damage_in_place(ctx, read_vdb, bytes, size, tmp_path("good.vdb"));
        printf("  .vdb of %zu bytes: %d reads, %d refusals\n", size, t.read, t.refused);
        CHECK(t.bad == 0);
        /* Every cut is refused; a flip in a value or in metadata may still read. */
        CHECK(t.refused >= (int)size && t.read > 0);
    }
    free(bytes);
    vdbgi_probes_destroy(p);
    vdbgi_scene_destroy(s);
    vdbgi_context_destroy(ctx);
}

/* A .gi.gz of the layout: its cuts and flips in place, then (gzipped after) its .gi's. */
static void damage_gi(vdbgi_layout layout)
{
    vdbgi_context *ctx = test_context();
    vdbgi_scene *s = NULL;
    vdbgi_probes *p = small_bake(ctx, &s);
    vdbgi_volume *v = NULL;
    const vdbgi_convert_desc cd = {.layout = layout};
    CHECK_RESULT(ctx, vdbgi_volume_build(ctx, p, &cd, &v), VDBGI_OK);
    CHECK_RESULT(ctx, vdbgi_volume_write(v, tmp_path("good.gi.gz")), VDBGI_OK);
    size_t zsize = 0, size = 0;
    unsigned char *const zbytes = slurp(tmp_path("good.gi.gz"), &zsize);
    CHECK(zbytes && zsize > 100);
    /* The .gi inside, for damage that gzip's checksum does not see. */
    unsigned char *raw = NULL;
    if (zbytes) {
        struct libdeflate_decompressor *const d = libdeflate_alloc_decompressor();
        raw = malloc(1 << 22);
        CHECK(libdeflate_gzip_decompress(d, zbytes, zsize, raw, 1 << 22, &size) ==
              LIBDEFLATE_SUCCESS);
        libdeflate_free_decompressor(d);
        /* Through the file reader and the memory reader: the same verdicts. */
        const read_fn readers[2] = {read_gi, read_gi_memory};
        tally seen[2][2];
        for (int m = 0; m < 2; m++) {
            tally t = damage_in_place(ctx, readers[m], zbytes, zsize, tmp_path("good.gi.gz"));
            printf("  %s .gi.gz of %zu bytes (%s): %d reads, %d refusals\n",
                   layout == VDBGI_LAYOUT_COMPACT ? "compact" : "seed", zsize,
                   m ? "memory" : "file", t.read, t.refused);
            CHECK(t.bad == 0 && t.refused >= (int)zsize);
            seen[m][0] = t;
            t = damage_before_gzip(ctx, readers[m], raw, size, tmp_path("damaged.gi.gz"));
            printf("  .gi of %zu bytes, gzipped after damage (%s): %d reads, %d refusals\n", size,
                   m ? "memory" : "file", t.read, t.refused);
            CHECK(t.bad == 0 && t.refused > 512 && t.read > 0);
            seen[m][1] = t;
        }
        for (int k = 0; k < 2; k++)
            CHECK(seen[0][k].read == seen[1][k].read && seen[0][k].refused == seen[1][k].refused);
    }
    free(raw);
    free(zbytes);
    vdbgi_volume_destroy(v);
    vdbgi_probes_destroy(p);
    vdbgi_scene_destroy(s);
    vdbgi_context_destroy(ctx);
}

static void damaged_gi_files_read_or_are_refused(void)
{
    damage_gi(VDBGI_LAYOUT_SEED);
    damage_gi(VDBGI_LAYOUT_COMPACT);
}

int main(void)
{
#ifndef UNDER_ASAN
    /* An allocation sized by a damaged number fails here, not on the machine. */
    const struct rlimit as = {(rlim_t)4 << 30, (rlim_t)4 << 30};
    setrlimit(RLIMIT_AS, &as);
#endif
    test_tmpdir_make("test-damage");
    RUN(damaged_vdb_files_read_or_are_refused);
    RUN(damaged_gi_files_read_or_are_refused);
    test_tmpdir_remove();
    return CHECK_EXIT();
}
