/* context.c: the context (allocator, log, last error) and small shared helpers. */
#define _POSIX_C_SOURCE 200809L
#include "context.h"

#include <dirent.h>
#include <errno.h>
#include <fcntl.h>
#include <pthread.h>
#include <signal.h>
#include <stddef.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/stat.h>
#include <sys/vfs.h>
#include <time.h>
#include <unistd.h>

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

double vdbgi_now(void)
{
    struct timespec ts;
    clock_gettime(CLOCK_MONOTONIC, &ts);
    return (double)ts.tv_sec + 1e-9 * (double)ts.tv_nsec;
}

int vdbgi_core_count(void)
{
    const long n = sysconf(_SC_NPROCESSORS_ONLN);
    return n > 0 ? (int)n : 1;
}

int vdbgi_run_threads(int n, void *(*fn)(void *), void *args, size_t stride)
{
    enum { MAX_THREADS = 64 };
    pthread_t threads[MAX_THREADS];
    bool started[MAX_THREADS] = {false};
    n = n < 1 ? 1 : n > MAX_THREADS ? MAX_THREADS : n;
    char *const base = args;
    for (int t = 1; t < n; t++)
        started[t] = pthread_create(&threads[t], NULL, fn, base + (size_t)t * stride) == 0;
    for (int t = 1; t < n; t++)
        if (!started[t])
            fn(base + (size_t)t * stride); /* no thread: do its share here */
    fn(base);
    int ran = 1;
    for (int t = 1; t < n; t++)
        if (started[t]) {
            pthread_join(threads[t], NULL);
            ran++;
        }
    return ran;
}

/*
 * Temporaries being written, so that a signal handler can remove them
 * (vdbgi_remove_temporaries): however many, in a list of slots that only
 * grows. A slot is claimed and released with an atomic swap of its path; a
 * new slot is pushed on the head atomically, whole before it is seen, so
 * the handler can walk the list at any moment. Slots are the process's, not
 * a context's (the handler has none), and stay for its life: as many as it
 * ever held temporaries at once.
 */
typedef struct live_slot {
    char *path; /* NULL: free */
    struct live_slot *next;
} live_slot;
static live_slot *live_head;

static void live_add(char *tmp)
{
    for (live_slot *s = __atomic_load_n(&live_head, __ATOMIC_SEQ_CST); s; s = s->next) {
        char *expected = NULL;
        if (__atomic_compare_exchange_n(&s->path, &expected, tmp, false, __ATOMIC_SEQ_CST,
                                        __ATOMIC_SEQ_CST))
            return;
    }
    live_slot *const s = calloc(1, sizeof(*s));
    if (!s)
        return; /* out of memory: only a temporary a signal would leave behind */
    s->path = tmp;
    s->next = __atomic_load_n(&live_head, __ATOMIC_SEQ_CST);
    while (!__atomic_compare_exchange_n(&live_head, &s->next, s, false, __ATOMIC_SEQ_CST,
                                        __ATOMIC_SEQ_CST))
        ;
}

static void live_remove(const char *tmp)
{
    for (live_slot *s = __atomic_load_n(&live_head, __ATOMIC_SEQ_CST); s; s = s->next) {
        char *expected = (char *)(uintptr_t)tmp;
        __atomic_compare_exchange_n(&s->path, &expected, NULL, false, __ATOMIC_SEQ_CST,
                                    __ATOMIC_SEQ_CST);
    }
}

void vdbgi_remove_temporaries(void)
{
    for (live_slot *s = __atomic_load_n(&live_head, __ATOMIC_SEQ_CST); s; s = s->next) {
        const char *const p = __atomic_load_n(&s->path, __ATOMIC_SEQ_CST);
        if (p)
            unlink(p); /* async-signal-safe */
    }
}

/*
 * Temporaries are named "OUT.tmp-PID-XXXXXX". One left by a run that was
 * killed outright (SIGKILL, a power cut) is removed by the next run that
 * writes OUT, once its process is gone.
 */
static void remove_stale(const char *path)
{
    const char *const slash = strrchr(path, '/');
    const char *const base = slash ? slash + 1 : path;
    const size_t dir_len = slash ? (size_t)(slash - path) : 0;
    char dir[4096], prefix[512], full[4096 + 512];
    if (dir_len >= sizeof(dir) || strlen(base) + 6 >= sizeof(prefix))
        return;
    if (!slash)
        snprintf(dir, sizeof(dir), ".");
    else if (dir_len == 0)
        snprintf(dir, sizeof(dir), "/");
    else
        snprintf(dir, sizeof(dir), "%.*s", (int)dir_len, path);
    snprintf(prefix, sizeof(prefix), "%s.tmp-", base);
    DIR *const d = opendir(dir);
    if (!d)
        return;
    const size_t plen = strlen(prefix);
    for (struct dirent *e; (e = readdir(d)) != NULL;) {
        if (strncmp(e->d_name, prefix, plen) != 0)
            continue;
        char *end = NULL;
        const long pid = strtol(e->d_name + plen, &end, 10);
        if (pid <= 0 || *end != '-' || pid == (long)getpid())
            continue;
        if (kill((pid_t)pid, 0) != 0 && errno == ESRCH) {
            snprintf(full, sizeof(full), "%s/%s", dir, e->d_name);
            unlink(full);
        }
    }
    closedir(d);
}

static vdbgi_result temp_create(vdbgi_context *ctx, const char *path, char **tmp_out)
{
    *tmp_out = NULL;
    VDBGI_FAIL_IF(ctx, !path || !*path, VDBGI_ERR_INVALID_ARG, "no output path given");
    remove_stale(path);
    char suffix[48];
    snprintf(suffix, sizeof(suffix), ".tmp-%ld-XXXXXX", (long)getpid());
    const size_t n = strlen(path), sn = strlen(suffix) + 1;
    char *const tmp = vdbgi_alloc(ctx, n + sn);
    if (!tmp)
        return VDBGI_ERR_OUT_OF_MEMORY;
    memcpy(tmp, path, n);
    memcpy(tmp + n, suffix, sn);
    /*
     * Listed before mkstemp writes its name into tmp and creates the file, so
     * that a signal arriving as the file appears still finds it (until then
     * the handler unlinks a name that does not exist).
     */
    live_add(tmp);
    const int fd = mkstemp(tmp);
    if (fd < 0) {
        const int err = errno;
        live_remove(tmp);
        vdbgi_free(ctx, tmp);
        return vdbgi_fail(ctx, VDBGI_ERR_IO, "%s: cannot write: %s", path, strerror(err));
    }
    /* mkstemp makes 0600; the finished file should get the usual umask mode. */
    const mode_t mask = umask(0);
    umask(mask);
    fchmod(fd, 0666 & ~mask);
    close(fd);
    *tmp_out = tmp;
    return VDBGI_OK;
}

static void temp_discard(vdbgi_context *ctx, char *tmp)
{
    if (tmp) {
        unlink(tmp);
        live_remove(tmp);
        vdbgi_free(ctx, tmp);
    }
}

static vdbgi_result hold_output(vdbgi_context *ctx, char *tmp, const char *path);

static vdbgi_result temp_commit(vdbgi_context *ctx, char *tmp, const char *path)
{
    /*
     * Whatever wrote the file, its data reach the disk before it replaces anything:
     * fsync reports the write errors a filesystem defers (a full disk, quota).
     */
    const int fd = open(tmp, O_RDONLY | O_CLOEXEC);
    const int synced = fd >= 0 ? fsync(fd) : -1;
    const int sync_err = errno;
    if (fd >= 0)
        close(fd);
    if (synced != 0) {
        temp_discard(ctx, tmp);
        return vdbgi_fail(ctx, VDBGI_ERR_IO, "%s: cannot write: %s", path, strerror(sync_err));
    }
    if (ctx->hold)
        return hold_output(ctx, tmp, path);
    if (rename(tmp, path) != 0) {
        const int err = errno;
        temp_discard(ctx, tmp);
        return vdbgi_fail(ctx, VDBGI_ERR_IO, "%s: cannot rename into place: %s", path,
                          strerror(err));
    }
    live_remove(tmp);
    vdbgi_free(ctx, tmp);
    return VDBGI_OK;
}

vdbgi_result vdbgi_input_check(vdbgi_context *ctx, const char *path)
{
    VDBGI_FAIL_IF(ctx, !path || !*path, VDBGI_ERR_INVALID_ARG, "no input path given");
    /* O_NONBLOCK: opening a FIFO with no writer must not hang. */
    const int fd = open(path, O_RDONLY | O_NONBLOCK | O_CLOEXEC);
    VDBGI_FAIL_IF(ctx, fd < 0, VDBGI_ERR_IO, "%s: cannot open: %s", path, strerror(errno));
    struct stat st;
    struct statfs fs;
    const int stat_r = fstat(fd, &st) == 0 && fstatfs(fd, &fs) == 0 ? 0 : -1;
    close(fd);
    VDBGI_FAIL_IF(ctx, stat_r != 0, VDBGI_ERR_IO, "%s: cannot open: %s", path, strerror(errno));
    VDBGI_FAIL_IF(ctx, S_ISDIR(st.st_mode), VDBGI_ERR_IO, "%s: is a directory, not a file", path);
    VDBGI_FAIL_IF(ctx, !S_ISREG(st.st_mode), VDBGI_ERR_IO,
                  "%s: not a regular file (a pipe or device is never read)", path);
    /* procfs and sysfs files claim to be regular, and some never end. */
    VDBGI_FAIL_IF(ctx, fs.f_type == 0x9fa0 || fs.f_type == 0x62656572, VDBGI_ERR_IO,
                  "%s: a /proc or /sys file, never read", path);
    return VDBGI_OK;
}

/* A directory where an output goes would take none of it: say so before any is written. */
static vdbgi_result not_a_directory(vdbgi_context *ctx, const char *path)
{
    struct stat st;
    VDBGI_FAIL_IF(ctx, stat(path, &st) == 0 && S_ISDIR(st.st_mode), VDBGI_ERR_IO,
                  "%s: is a directory, not a file to write", path);
    return VDBGI_OK;
}

vdbgi_result vdbgi_output_check(vdbgi_context *ctx, const char *path)
{
    VDBGI_TRY(not_a_directory(ctx, path));
    char *tmp = NULL;
    VDBGI_TRY(temp_create(ctx, path, &tmp));
    temp_discard(ctx, tmp);
    return VDBGI_OK;
}

typedef struct bytes_job {
    const void *bytes;
    size_t size;
    const char *path; /* for messages: the name the user gave */
} bytes_job;

static vdbgi_result write_bytes(vdbgi_context *ctx, const char *tmp, const void *user)
{
    const bytes_job *const job = user;
    FILE *const f = fopen(tmp, "wb");
    const bool ok = f && fwrite(job->bytes, 1, job->size, f) == job->size && fflush(f) == 0;
    const int err = errno;
    const bool closed = f && fclose(f) == 0;
    VDBGI_FAIL_IF(ctx, !ok || !closed, VDBGI_ERR_IO, "%s: cannot write: %s", job->path,
                  strerror(ok ? errno : err));
    return VDBGI_OK;
}

vdbgi_result vdbgi_write_bytes_atomic(vdbgi_context *ctx, const char *path, const void *bytes,
                                      size_t size)
{
    const bytes_job job = {bytes, size, path};
    return vdbgi_write_atomic(ctx, path, write_bytes, &job);
}

vdbgi_result vdbgi_write_atomic(vdbgi_context *ctx, const char *path, vdbgi_writer write,
                                const void *user)
{
    char *tmp = NULL;
    VDBGI_TRY(temp_create(ctx, path, &tmp));
    const vdbgi_result r = write(ctx, tmp, user);
    if (r != VDBGI_OK) {
        temp_discard(ctx, tmp);
        return r;
    }
    return temp_commit(ctx, tmp, path);
}

vdbgi_result vdbgi_context_write_file(vdbgi_context *ctx, const char *path, const void *data,
                                      size_t size)
{
    VDBGI_FAIL_IF(ctx, !data && size, VDBGI_ERR_INVALID_ARG, "no data given");
    return vdbgi_write_bytes_atomic(ctx, path, data, size);
}

/* ---- held outputs: all of a run's files, or none ------------------------------- */

static vdbgi_result hold_output(vdbgi_context *ctx, char *tmp, const char *path)
{
    for (size_t i = 0; i < ctx->held_count; i++)
        if (strcmp(ctx->held_path[i], path) == 0) {
            temp_discard(ctx, tmp);
            return vdbgi_fail(ctx, VDBGI_ERR_INVALID_ARG, "%s: written twice in one run", path);
        }
    if (ctx->held_count == ctx->held_capacity) {
        const size_t cap = ctx->held_capacity ? 2 * ctx->held_capacity : 16;
        char **const t = vdbgi_calloc(ctx, cap, sizeof(char *));
        char **const p = vdbgi_calloc(ctx, cap, sizeof(char *));
        if (!t || !p) {
            vdbgi_free(ctx, t);
            vdbgi_free(ctx, p);
            temp_discard(ctx, tmp);
            return VDBGI_ERR_OUT_OF_MEMORY;
        }
        if (ctx->held_count) {
            memcpy(t, ctx->held_tmp, ctx->held_count * sizeof(char *));
            memcpy(p, ctx->held_path, ctx->held_count * sizeof(char *));
        }
        vdbgi_free(ctx, ctx->held_tmp);
        vdbgi_free(ctx, ctx->held_path);
        ctx->held_tmp = t;
        ctx->held_path = p;
        ctx->held_capacity = cap;
    }
    char *const copy = vdbgi_strdup(ctx, path);
    if (!copy) {
        temp_discard(ctx, tmp);
        return VDBGI_ERR_OUT_OF_MEMORY;
    }
    ctx->held_tmp[ctx->held_count] = tmp; /* still registered for the signal handler */
    ctx->held_path[ctx->held_count++] = copy;
    return VDBGI_OK;
}

void vdbgi_context_hold_outputs(vdbgi_context *ctx, int hold)
{
    ctx->hold = hold != 0;
}

static void release_held(vdbgi_context *ctx)
{
    vdbgi_free(ctx, ctx->held_tmp);
    vdbgi_free(ctx, ctx->held_path);
    ctx->held_tmp = ctx->held_path = NULL;
    ctx->held_count = ctx->held_capacity = 0;
}

vdbgi_result vdbgi_context_commit_outputs(vdbgi_context *ctx)
{
    /* Every place checked before the first rename: all of them, or none. */
    vdbgi_result r = VDBGI_OK;
    for (size_t i = 0; i < ctx->held_count && r == VDBGI_OK; i++)
        r = not_a_directory(ctx, ctx->held_path[i]);
    for (size_t i = 0; i < ctx->held_count; i++) {
        char *const tmp = ctx->held_tmp[i];
        if (r == VDBGI_OK && rename(tmp, ctx->held_path[i]) != 0)
            r = vdbgi_fail(ctx, VDBGI_ERR_IO, "%s: cannot rename into place: %s", ctx->held_path[i],
                           strerror(errno));
        if (r != VDBGI_OK)
            unlink(tmp); /* what follows a failed rename is dropped, not half-committed */
        live_remove(tmp);
        vdbgi_free(ctx, tmp);
        vdbgi_free(ctx, ctx->held_path[i]);
    }
    release_held(ctx);
    return r;
}

void vdbgi_context_discard_outputs(vdbgi_context *ctx)
{
    for (size_t i = 0; i < ctx->held_count; i++) {
        temp_discard(ctx, ctx->held_tmp[i]);
        vdbgi_free(ctx, ctx->held_path[i]);
    }
    release_held(ctx);
}
