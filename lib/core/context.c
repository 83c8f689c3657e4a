/* context.c: the context: allocator, log, last error, memory limit; version and result texts. */
#define _POSIX_C_SOURCE 200809L
#include "context.h"

#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#define VDBGI_STR2(x) #x
#define VDBGI_STR(x) VDBGI_STR2(x)

const char *vdbgi_version_string(void)
{
    return VDBGI_STR(VDBGI_VERSION_MAJOR) "." VDBGI_STR(VDBGI_VERSION_MINOR) "." VDBGI_STR(
        VDBGI_VERSION_PATCH);
}

const char *vdbgi_result_string(vdbgi_result result)
{
    switch (result) {
    case VDBGI_OK: return "ok";
    case VDBGI_ERR_INVALID_ARG: return "invalid argument";
    case VDBGI_ERR_OUT_OF_MEMORY: return "out of memory";
    case VDBGI_ERR_IO: return "input/output error";
    case VDBGI_ERR_FORMAT: return "unusable file contents";
    case VDBGI_ERR_BACKEND: return "library backend error";
    case VDBGI_ERR_CANCELLED: return "cancelled";
    }
    return "unknown result";
}

static void *default_alloc(void *user, size_t size)
{
    (void)user;
    return malloc(size);
}

static void default_free(void *user, void *ptr)
{
    (void)user;
    free(ptr);
}

vdbgi_result vdbgi_context_create(const vdbgi_context_desc *desc, vdbgi_context **out)
{
    if (!out)
        return VDBGI_ERR_INVALID_ARG;
    *out = NULL;
    const vdbgi_context_desc none = {0};
    if (!desc)
        desc = &none;
    if ((desc->alloc == NULL) != (desc->free == NULL))
        return VDBGI_ERR_INVALID_ARG;
    void *(*const alloc)(void *, size_t) = desc->alloc ? desc->alloc : default_alloc;
    vdbgi_context *const ctx = alloc(desc->user, sizeof(*ctx));
    if (!ctx)
        return VDBGI_ERR_OUT_OF_MEMORY;
    memset(ctx, 0, sizeof(*ctx));
    ctx->alloc = alloc;
    ctx->free = desc->free ? desc->free : default_free;
    ctx->log = desc->log;
    ctx->user = desc->user;
    ctx->memory_limit = desc->memory_limit;
    ctx->volume_budget = desc->volume_budget ? desc->volume_budget : VDBGI_VOLUME_BUDGET;
    *out = ctx;
    return VDBGI_OK;
}

void vdbgi_context_destroy(vdbgi_context *ctx)
{
    if (ctx) {
        vdbgi_context_discard_outputs(ctx);
        ctx->free(ctx->user, ctx);
    }
}

const char *vdbgi_context_error(const vdbgi_context *ctx)
{
    return ctx ? ctx->error : "no context";
}

vdbgi_result vdbgi_fail(vdbgi_context *ctx, vdbgi_result code, const char *fmt, ...)
{
    char raw[sizeof(ctx->error)];
    va_list ap;
    va_start(ap, fmt);
    vsnprintf(raw, sizeof(raw), fmt, ap);
    va_end(ap);
    /*
     * One line of text, whatever the message quotes: backends' exception texts
     * can carry newlines, or bytes read from a damaged file.
     */
    size_t n = 0;
    for (const char *c = raw; *c && n + 1 < sizeof(ctx->error); c++) {
        const unsigned char u = (unsigned char)*c;
        const char out = u < 0x20 || u == 0x7F ? ' ' : (u >= 0x80 ? '?' : *c);
        if (out == ' ' && (n == 0 || ctx->error[n - 1] == ' '))
            continue;
        ctx->error[n++] = out;
    }
    while (n > 0 && ctx->error[n - 1] == ' ')
        n--;
    ctx->error[n] = '\0';
    return code;
}

vdbgi_result vdbgi_fail_about(vdbgi_context *ctx, vdbgi_result code, const char *name)
{
    return vdbgi_fail(ctx, code, "%s: %s", name, ctx->error); /* formatted before it is copied */
}

void vdbgi_log(vdbgi_context *ctx, vdbgi_log_level level, const char *fmt, ...)
{
    if (!ctx->log)
        return;
    char line[512];
    va_list ap;
    va_start(ap, fmt);
    vsnprintf(line, sizeof(line), fmt, ap);
    va_end(ap);
    ctx->log(ctx->user, level, line);
}

size_t vdbgi_context_memory_peak(const vdbgi_context *ctx)
{
    return ctx ? __atomic_load_n(&ctx->memory_peak, __ATOMIC_RELAXED) : 0;
}

/* "1.5 GiB", "800 MiB": a figure of memory for a message, in the limit's 1024s. */
static void memory_figure(size_t bytes, char out[32])
{
    if (bytes >= (size_t)1 << 30)
        snprintf(out, 32, "%.1f GiB", (double)bytes / (1 << 30));
    else
        snprintf(out, 32, "%.0f MiB", (double)bytes / (1 << 20));
}

bool vdbgi_memory_charge(vdbgi_context *ctx, size_t bytes)
{
    const size_t held = __atomic_add_fetch(&ctx->memory_held, bytes, __ATOMIC_RELAXED);
    if (held < bytes || (ctx->memory_limit && held > ctx->memory_limit)) {
        __atomic_sub_fetch(&ctx->memory_held, bytes, __ATOMIC_RELAXED);
        char limit[32], asked[32], have[32];
        memory_figure(ctx->memory_limit, limit);
        memory_figure(bytes, asked);
        memory_figure(held - bytes, have);
        vdbgi_fail(ctx, VDBGI_ERR_OUT_OF_MEMORY,
                   "needs more than the memory limit of %s (%s held, %s more asked)", limit, have,
                   asked);
        return false;
    }
    size_t peak = __atomic_load_n(&ctx->memory_peak, __ATOMIC_RELAXED);
    while (held > peak && !__atomic_compare_exchange_n(&ctx->memory_peak, &peak, held, true,
                                                       __ATOMIC_RELAXED, __ATOMIC_RELAXED))
        ;
    return true;
}

void vdbgi_memory_release(vdbgi_context *ctx, size_t bytes)
{
    __atomic_sub_fetch(&ctx->memory_held, bytes, __ATOMIC_RELAXED);
}

/*
 * Every block carries its size in front of it, so that freeing it releases
 * what allocating it charged; the front keeps malloc's alignment.
 */
#define BLOCK_HEADER                                                                               \
    ((sizeof(size_t) + _Alignof(max_align_t) - 1) / _Alignof(max_align_t) * _Alignof(max_align_t))

static void *block_open(vdbgi_context *ctx, char *raw, size_t size)
{
    if (!raw) {
        char figure[32];
        memory_figure(size, figure);
        vdbgi_fail(ctx, VDBGI_ERR_OUT_OF_MEMORY, "out of memory allocating %s (%zu bytes)", figure,
                   size);
        vdbgi_memory_release(ctx, size);
        return NULL;
    }
    memcpy(raw, &size, sizeof(size));
    return raw + BLOCK_HEADER;
}

void *vdbgi_alloc(vdbgi_context *ctx, size_t size)
{
    size = size ? size : 1;
    if (size > SIZE_MAX - BLOCK_HEADER) {
        vdbgi_fail(ctx, VDBGI_ERR_OUT_OF_MEMORY, "allocation of %zu bytes overflows", size);
        return NULL;
    }
    if (!vdbgi_memory_charge(ctx, size))
        return NULL;
    return block_open(ctx, ctx->alloc(ctx->user, BLOCK_HEADER + size), size);
}

void *vdbgi_calloc(vdbgi_context *ctx, size_t count, size_t size)
{
    if (size && count > (SIZE_MAX - BLOCK_HEADER) / size) {
        vdbgi_fail(ctx, VDBGI_ERR_OUT_OF_MEMORY, "allocation of %zu x %zu bytes overflows", count,
                   size);
        return NULL;
    }
    const size_t bytes = count && size ? count * size : 1;
    if (!vdbgi_memory_charge(ctx, bytes))
        return NULL;
    /*
     * libc's calloc maps large blocks as zero pages and touches only what is
     * used; zeroing after malloc faulted in every page (an eighth of a
     * conversion's time went to it).
     */
    if (ctx->alloc == default_alloc)
        return block_open(ctx, calloc(1, BLOCK_HEADER + bytes), bytes);
    char *const p = block_open(ctx, ctx->alloc(ctx->user, BLOCK_HEADER + bytes), bytes);
    if (p)
        memset(p, 0, bytes);
    return p;
}

void vdbgi_free(vdbgi_context *ctx, void *ptr)
{
    if (!ptr)
        return;
    char *const raw = (char *)ptr - BLOCK_HEADER;
    size_t size;
    memcpy(&size, raw, sizeof(size));
    vdbgi_memory_release(ctx, size);
    ctx->free(ctx->user, raw);
}

char *vdbgi_strdup(vdbgi_context *ctx, const char *s)
{
    const size_t n = strlen(s) + 1;
    char *const p = vdbgi_alloc(ctx, n);
    if (p)
        memcpy(p, s, n);
    return p;
}
