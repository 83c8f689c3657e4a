/* threads.c: the wall clock, the core count and running work over threads. */
#define _POSIX_C_SOURCE 200809L
#include "context.h"

#include <pthread.h>
#include <stdbool.h>
#include <time.h>
#include <unistd.h>

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
