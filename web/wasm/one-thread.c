/*
 * one-thread.c: lib/core/threads.c for the WebAssembly reader, which runs in
 * one worker without threads: every share of the work on the calling thread,
 * in order (the results are the same bytes for any thread count).
 */
#include "context.h"

double vdbgi_now(void)
{
    return 0; /* only timings use it, and the reader keeps none */
}

int vdbgi_core_count(void)
{
    return 1;
}

int vdbgi_run_threads(int n, void *(*fn)(void *), void *args, size_t stride)
{
    n = n < 1 ? 1 : n > 64 ? 64 : n;
    for (int t = 0; t < n; t++)
        fn((char *)args + (size_t)t * stride);
    return 1;
}
