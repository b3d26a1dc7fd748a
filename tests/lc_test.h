/* Minimal table-friendly test harness: CHECK macros and a closing
 * "N passed, N failed" line. Each test program is one ctest test. */
#ifndef LC_TEST_H
#define LC_TEST_H

#include <math.h>
#include <stdio.h>
#include <stdlib.h>

static int lc_test_passed, lc_test_failed;

#define CHECK(cond, ...)                                                                                               \
    do {                                                                                                               \
        if (cond) {                                                                                                    \
            lc_test_passed++;                                                                                          \
        } else {                                                                                                       \
            lc_test_failed++;                                                                                          \
            fprintf(stderr, "%s:%d: CHECK(%s) failed: ", __FILE__, __LINE__, #cond);                                   \
            fprintf(stderr, __VA_ARGS__);                                                                              \
            fputc('\n', stderr);                                                                                       \
        }                                                                                                              \
    } while (0)

#define CHECK_NEAR(a, b, tol, what)                                                                                    \
    do {                                                                                                               \
        double lc_a_ = (a), lc_b_ = (b);                                                                               \
        CHECK(fabs(lc_a_ - lc_b_) <= (tol), "%s: %.9g vs %.9g (tol %g)", what, lc_a_, lc_b_, (double)(tol));           \
    } while (0)

/* Prints the closing line and returns the process exit code. */
static inline int lc_test_finish(void)
{
    printf("%d passed, %d failed\n", lc_test_passed, lc_test_failed);
    return lc_test_failed ? 1 : 0;
}

/* Exit code 77 makes ctest report a test as skipped (SKIP_RETURN_CODE). */
#define LC_TEST_SKIP 77

#endif
