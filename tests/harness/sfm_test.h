/*
 * A tiny test harness that runs the same way on a Linux host, under qemu-user
 * and on a Cortex-M under semihosting. Tests register themselves with
 * SFM_TEST(name); tools/gen_test_registry.sh collects them into a table.
 * Each test gets a generator seeded from a hash of its name, so a test's
 * inputs never depend on which other tests ran.
 */
#ifndef SFM_TEST_H
#define SFM_TEST_H

#include <math.h>
#include <stdio.h>

#include "sfm/sfm_rng.h"

typedef struct sfm_test_ctx {
    const char *name;
    int failures;
    sfm_rng rng; /* seeded from the test name */
} sfm_test_ctx;

typedef void (*sfm_test_fn)(sfm_test_ctx *t);

#define SFM_TEST(name) void sfm_test_##name(sfm_test_ctx *t)

void sfm_test_fail(sfm_test_ctx *t, const char *file, int line, const char *fmt, ...)
#if defined(__GNUC__)
    __attribute__((format(printf, 4, 5)))
#endif
    ;

#define SFM_CHECK(cond)                                                        \
    do {                                                                       \
        if (!(cond))                                                           \
            sfm_test_fail(t, __FILE__, __LINE__, "check failed: %s", #cond);   \
    } while (0)

#define SFM_CHECK_MSG(cond, ...)                                               \
    do {                                                                       \
        if (!(cond))                                                           \
            sfm_test_fail(t, __FILE__, __LINE__, __VA_ARGS__);                 \
    } while (0)

/* |a - b| <= tol, and both finite. */
#define SFM_CHECK_NEAR(a, b, tol)                                              \
    do {                                                                       \
        double sfm_a_ = (a), sfm_b_ = (b), sfm_t_ = (tol);                     \
        if (!(isfinite(sfm_a_) && isfinite(sfm_b_) &&                          \
              fabs(sfm_a_ - sfm_b_) <= sfm_t_))                                \
            sfm_test_fail(t, __FILE__, __LINE__, "%s = %.17g, %s = %.17g, tol %g", \
                          #a, sfm_a_, #b, sfm_b_, sfm_t_);                     \
    } while (0)

#define SFM_CHECK_EQ_INT(a, b)                                                 \
    do {                                                                       \
        long sfm_a_ = (long)(a), sfm_b_ = (long)(b);                           \
        if (sfm_a_ != sfm_b_)                                                  \
            sfm_test_fail(t, __FILE__, __LINE__, "%s = %ld, expected %s = %ld", \
                          #a, sfm_a_, #b, sfm_b_);                             \
    } while (0)

/* Informational output (figures a test measures); goes to the run log. */
#define SFM_TEST_LOG(...)                                                      \
    do {                                                                       \
        printf("  [%s] ", t->name);                                            \
        printf(__VA_ARGS__);                                                   \
        printf("\n");                                                          \
    } while (0)

/* Loop counts for randomized tests: full on a host, a tenth on targets that
 * run under emulation (qemu-system-arm and qemu-aarch64; built with
 * -DSFM_TEST_REDUCED), where the point is to prove the code runs there, not
 * to repeat the statistics. */
#ifdef SFM_TEST_REDUCED
#define SFM_TEST_ITERS(n) (((n) / 10) > 0 ? ((n) / 10) : 1)
#else
#define SFM_TEST_ITERS(n) (n)
#endif

/* Random helpers for building synthetic problems. */
double sfm_test_uniform(sfm_test_ctx *t, double lo, double hi);
double sfm_test_normal(sfm_test_ctx *t, double sigma);
/* Uniformly distributed random rotation (from a random unit quaternion). */
void sfm_test_random_rotation(sfm_test_ctx *t, double R[9]);
/* Random unit vector. */
void sfm_test_random_unit(sfm_test_ctx *t, double v[3]);
/* Bytes a canary-filled buffer still holds untouched: used to prove that a
 * failing call wrote nothing. */
void sfm_test_fill_canary(void *buf, size_t n);
int sfm_test_canary_intact(const void *buf, size_t n);

#endif
