/* context.h: the context (allocator, log, last error), failure macros, threads, atomic writes. */
#ifndef VDBGI_CONTEXT_H
#define VDBGI_CONTEXT_H

#include "vdbgi_bench.h" /* the library defines its benchmark calls too */

#include <stdarg.h>
#include <stdbool.h>

#ifdef __cplusplus
extern "C" {
#endif

#if defined(__GNUC__)
#define VDBGI_PRINTF(f, a) __attribute__((format(printf, f, a)))
#else
#define VDBGI_PRINTF(f, a)
#endif

struct vdbgi_context {
    void *(*alloc)(void *user, size_t size);
    void (*free)(void *user, void *ptr);
    void (*log)(void *user, vdbgi_log_level level, const char *message);
    void *user;
    char error[512];
    /* Outputs written but held under their temporary names (vdbgi_context_hold_outputs). */
    bool hold;
    char **held_tmp, **held_path;
    size_t held_count, held_capacity;
    /* Bytes held now and at most, against memory_limit (0: none); updated
       atomically, as workers allocate too. */
    size_t memory_held, memory_peak, memory_limit;
    /* What a .gi read may unpack to (vdbgi_context_desc.volume_budget, resolved). */
    size_t volume_budget;
};

/*
 * Count bytes held outside vdbgi's allocator (a library's objects) against
 * the memory limit: false, with the failure recorded, if they would pass it.
 * Each successful charge is released with the same figure.
 */
bool vdbgi_memory_charge(vdbgi_context *ctx, size_t bytes);
void vdbgi_memory_release(vdbgi_context *ctx, size_t bytes);

/* Put name (the file a failure was about) in front of ctx's last message; returns code. */
vdbgi_result vdbgi_fail_about(vdbgi_context *ctx, vdbgi_result code, const char *name);

/* Record a failure message on ctx and return code (for one-line returns). */
vdbgi_result vdbgi_fail(vdbgi_context *ctx, vdbgi_result code, const char *fmt, ...)
    VDBGI_PRINTF(3, 4);
void vdbgi_log(vdbgi_context *ctx, vdbgi_log_level level, const char *fmt, ...) VDBGI_PRINTF(3, 4);

/* Return error code with a message if cond holds (zstd's RETURN_ERROR_IF). */
#define VDBGI_FAIL_IF(ctx, cond, code, ...)                                                        \
    do {                                                                                           \
        if (cond)                                                                                  \
            return vdbgi_fail((ctx), (code), __VA_ARGS__);                                         \
    } while (0)

/* Forward a failure of call; the message is already on the context. */
#define VDBGI_TRY(call)                                                                            \
    do {                                                                                           \
        const vdbgi_result vdbgi_try_r_ = (call);                                                  \
        if (vdbgi_try_r_ != VDBGI_OK)                                                              \
            return vdbgi_try_r_;                                                                   \
    } while (0)

/* Allocation through the context's hooks. NULL on failure, message recorded. */
void *vdbgi_alloc(vdbgi_context *ctx, size_t size);
/* count * size bytes, zeroed; refuses (NULL) when the product would wrap. */
void *vdbgi_calloc(vdbgi_context *ctx, size_t count, size_t size);
void vdbgi_free(vdbgi_context *ctx, void *ptr);
char *vdbgi_strdup(vdbgi_context *ctx, const char *s);

/* Wall clock, seconds, monotonic. */
double vdbgi_now(void);
/* Online cores, at least 1. */
int vdbgi_core_count(void);
/*
 * Run fn(args + t * stride) for t in 0..n-1 (n <= 64): t > 0 on threads of
 * their own, t == 0 on this one, which also runs any whose thread did not
 * start. Returns when all are done, with how many threads ran them (this
 * one included).
 */
int vdbgi_run_threads(int n, void *(*fn)(void *), void *args, size_t stride);

/*
 * Write an output the safe way: write(ctx, tmp, user) fills a temporary
 * file "path.tmp-XXXXXX" made beside path, which is renamed over path if it
 * succeeds and removed if it fails. A failed write never leaves a partial
 * file nor touches an existing one. VDBGI_ERR_IO if the directory refuses.
 */
typedef vdbgi_result (*vdbgi_writer)(vdbgi_context *ctx, const char *tmp, const void *user);
vdbgi_result vdbgi_write_atomic(vdbgi_context *ctx, const char *path, vdbgi_writer write,
                                const void *user);
/*
 * An input file, checked the one way every reader checks it before handing
 * the path to a library: it opens for reading and is a regular file (a
 * directory, FIFO or device would be misread, block or never end).
 * VDBGI_ERR_IO with a message naming path.
 */
vdbgi_result vdbgi_input_check(vdbgi_context *ctx, const char *path);

/*
 * The counts an OFF or PLY header declares against the file's size, and an
 * OBJ's faces against the triangle limit, before assimp reads them
 * (scene_counts.c); other files pass.
 */
vdbgi_result vdbgi_scene_counts_check(vdbgi_context *ctx, const char *path);

/* The same for a block of bytes already in memory. */
vdbgi_result vdbgi_write_bytes_atomic(vdbgi_context *ctx, const char *path, const void *bytes,
                                      size_t size);

static inline int32_t vdbgi_floor_div(int32_t a, int32_t b) /* b > 0 */
{
    return a >= 0 ? a / b : -((-a + b - 1) / b);
}

#ifdef __cplusplus
}
#endif

#endif /* VDBGI_CONTEXT_H */
