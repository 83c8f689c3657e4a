/*
 * files.c: outputs written the safe way (a temporary beside the output, renamed when
 * whole, removed on failure or a signal), held outputs, and input and output checks.
 */
#define _POSIX_C_SOURCE 200809L
#include "context.h"

#include <dirent.h>
#include <errno.h>
#include <fcntl.h>
#include <signal.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/stat.h>
#include <sys/vfs.h>
#include <unistd.h>

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
