/* kt_test.h: a minimal test harness; each program ends with "N passed, N failed". */
#ifndef KT_TEST_H
#define KT_TEST_H

#include <math.h>
#include <stdio.h>

static int kt_test_pass, kt_test_fail;

#define CHECK(cond, ...)                                                                       \
    do {                                                                                       \
        if (cond) {                                                                            \
            kt_test_pass++;                                                                    \
        } else {                                                                               \
            kt_test_fail++;                                                                    \
            fprintf(stderr, "%s:%d: FAILED %s: ", __FILE__, __LINE__, #cond);                 \
            fprintf(stderr, __VA_ARGS__);                                                      \
            fputc('\n', stderr);                                                               \
        }                                                                                      \
    } while (0)

/* |a - b| <= tol * max(1, |b|) */
#define CHECK_NEAR(a, b, tol, what)                                                            \
    do {                                                                                       \
        double a_ = (a), b_ = (b);                                                             \
        CHECK(fabs(a_ - b_) <= (tol) * fmax(1.0, fabs(b_)), "%s: %.15g vs %.15g", what, a_, b_); \
    } while (0)

static inline int kt_test_done(const char *name)
{
    printf("%s: %d passed, %d failed\n", name, kt_test_pass, kt_test_fail);
    return kt_test_fail ? 1 : 0;
}

#endif
