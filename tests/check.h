/* check.h: always-on checks for vdbgi's test programs (not assert: NDEBUG never hides them). */
#ifndef VDBGI_CHECK_H
#define VDBGI_CHECK_H

#include <math.h>
#include <stdio.h>

static int check_failures;      /* in the whole program */
static int check_test_failures; /* in the running test */

#define CHECK(cond)                                                                                \
    do {                                                                                           \
        if (!(cond)) {                                                                             \
            fprintf(stderr, "%s:%d: CHECK(%s) failed\n", __FILE__, __LINE__, #cond);               \
            check_failures++, check_test_failures++;                                               \
        }                                                                                          \
    } while (0)

#define CHECK_NEAR(a, b, tol)                                                                      \
    do {                                                                                           \
        const double check_a_ = (double)(a), check_b_ = (double)(b), check_t_ = (double)(tol);     \
        if (!(fabs(check_a_ - check_b_) <= check_t_)) {                                            \
            fprintf(stderr, "%s:%d: CHECK_NEAR(%s, %s, %s) failed: %.9g vs %.9g (diff %.3g)\n",    \
                    __FILE__, __LINE__, #a, #b, #tol, check_a_, check_b_, check_a_ - check_b_);    \
            check_failures++, check_test_failures++;                                               \
        }                                                                                          \
    } while (0)

/* Check a vdbgi call's result, printing the context's message when it differs. */
#define CHECK_RESULT(ctx, call, expected)                                                          \
    do {                                                                                           \
        const vdbgi_result check_r_ = (call);                                                      \
        if (check_r_ != (expected)) {                                                              \
            fprintf(stderr, "%s:%d: %s returned %d (%s: %s), expected %d\n", __FILE__, __LINE__,   \
                    #call, (int)check_r_, vdbgi_result_string(check_r_), vdbgi_context_error(ctx), \
                    (int)(expected));                                                              \
            check_failures++, check_test_failures++;                                               \
        }                                                                                          \
    } while (0)

/* Run one test: a line "ok - name" or "not ok - name" per test, as tests/run.sh counts them. */
#define RUN(test)                                                                                  \
    do {                                                                                           \
        check_test_failures = 0;                                                                   \
        test();                                                                                    \
        printf("%s - %s\n", check_test_failures ? "not ok" : "ok", #test);                         \
        fflush(stdout);                                                                            \
    } while (0)

#define CHECK_EXIT() (check_failures ? 1 : 0)

#endif /* VDBGI_CHECK_H */
