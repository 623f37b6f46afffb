/*
 * Internal helpers shared by the dense linear algebra files: argument checks
 * and exact power-of-two scaling (so that squares and dot products of finite
 * inputs can neither overflow nor underflow to garbage).
 */
#ifndef SFM_CORE_LINALG_UTIL_H
#define SFM_CORE_LINALG_UTIL_H

#include <math.h>
#include <stddef.h>

#include "sfm/sfm_linalg.h"

static inline int sfm_la_dim_ok(int n)
{
    return n >= 1 && n <= SFM_LINALG_MAX_DIM;
}

static inline int sfm_la_all_finite(const double *a, size_t n)
{
    for (size_t i = 0; i < n; i++)
        if (!isfinite(a[i]))
            return 0;
    return 1;
}

static inline double sfm_la_max_abs(const double *a, size_t n)
{
    double m = 0.0;
    for (size_t i = 0; i < n; i++) {
        double v = fabs(a[i]);
        if (v > m)
            m = v;
    }
    return m;
}

/* A power of two f such that maxabs * f lies in [0.5, 1); 1 for zero. The
 * scaling is exact, so results unscale without rounding. */
static inline double sfm_la_pow2_scale(double maxabs)
{
    if (!(maxabs > 0.0))
        return 1.0;
    int e;
    (void)frexp(maxabs, &e);
    return ldexp(1.0, -e);
}

#endif
