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
#include "core/inline.h"

SFMI_INLINE int sfmi_la_dim_ok(int n)
{
    return n >= 1 && n <= SFM_LINALG_MAX_DIM;
}

SFMI_INLINE int sfmi_la_all_finite(const double *a, size_t n)
{
    for (size_t i = 0; i < n; i++)
        if (!isfinite(a[i]))
            return 0;
    return 1;
}

/* R (row-major 3x3) is a proper rotation: R^T R within tol of I in every
 * entry and det R > 0 (NaN fails). */
SFMI_INLINE int sfmi_la_is_rotation(const double *R, double tol)
{
    for (int r = 0; r < 3; r++)
        for (int c = 0; c < 3; c++) {
            double s = R[r] * R[c] + R[3 + r] * R[3 + c] + R[6 + r] * R[6 + c];
            if (!(fabs(s - (r == c ? 1.0 : 0.0)) <= tol))
                return 0;
        }
    double det = R[0] * (R[4] * R[8] - R[5] * R[7]) - R[1] * (R[3] * R[8] - R[5] * R[6]) +
                 R[2] * (R[3] * R[7] - R[4] * R[6]);
    return det > 0.0;
}

SFMI_INLINE double sfmi_la_max_abs(const double *a, size_t n)
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
SFMI_INLINE double sfmi_la_pow2_scale(double maxabs)
{
    if (!(maxabs > 0.0))
        return 1.0;
    int e;
    (void)frexp(maxabs, &e);
    return ldexp(1.0, -e);
}

/* One step of cyclic Jacobi (the 2x2 symmetric Schur rotation): for
 * zeta = (a_qq - a_pp) / (2 a_pq), the tangent t of the smaller angle that
 * zeroes a_pq, with c = 1 / sqrt(1 + t^2), s = t c. Returns t. */
SFMI_INLINE double sfmi_la_jacobi_angle(double zeta, double *c, double *s)
{
    double t;
    if (fabs(zeta) > 1e150)
        t = 0.5 / zeta;
    else
        t = copysign(1.0, zeta) / (fabs(zeta) + sqrt(1.0 + zeta * zeta));
    *c = 1.0 / sqrt(1.0 + t * t);
    *s = t * *c;
    return t;
}

/* The plane rotation (x, y) <- (c x - s y, s x + c y) of n pairs, x[k inc]
 * and y[k inc]. */
SFMI_INLINE void sfmi_la_rotate(double *x, double *y, int n, size_t inc, double c, double s)
{
    /* c a + (-s) b: the same bits as c a - s b, but GCC 12's vectorizer
     * turns the pair (c a - s b, s a + c b) into a fused
     * multiply-add-subtract on x86-64-v3 even with -ffp-contract=off
     * (mk/check-fma.mk) */
    const double ns = -s;
    for (int k = 0; k < n; k++) {
        double a = x[(size_t)k * inc], b = y[(size_t)k * inc];
        x[(size_t)k * inc] = c * a + ns * b;
        y[(size_t)k * inc] = s * a + c * b;
    }
}


/* Inverse of a 3x3 by cofactors; 0 (nothing written) when |det| is not
 * above min_abs_det. */
SFMI_INLINE int sfmi_mat3_inverse(const double *A, double *Ai, double min_abs_det)
{
    double c0 = A[4] * A[8] - A[5] * A[7], c1 = A[5] * A[6] - A[3] * A[8], c2 = A[3] * A[7] - A[4] * A[6];
    double det = A[0] * c0 + A[1] * c1 + A[2] * c2;
    if (!(fabs(det) > min_abs_det))
        return 0;
    double id = 1.0 / det;
    Ai[0] = c0 * id;
    Ai[1] = (A[2] * A[7] - A[1] * A[8]) * id;
    Ai[2] = (A[1] * A[5] - A[2] * A[4]) * id;
    Ai[3] = c1 * id;
    Ai[4] = (A[0] * A[8] - A[2] * A[6]) * id;
    Ai[5] = (A[2] * A[3] - A[0] * A[5]) * id;
    Ai[6] = c2 * id;
    Ai[7] = (A[1] * A[6] - A[0] * A[7]) * id;
    Ai[8] = (A[0] * A[4] - A[1] * A[3]) * id;
    return 1;
}

/* 3x3 Cholesky A = L L^T of the lower triangle of A into L (lower,
 * row-major); 0 (L not written) when a pivot is not strictly positive: A
 * not positive definite. Inline for the per-point elimination of the
 * bundle adjustment (refine/ba_schur.c). */
SFMI_INLINE int sfmi_chol3(const double *A, double *L)
{
    double l00 = A[0];
    if (!(l00 > 0.0))
        return 0;
    l00 = sqrt(l00);
    double l10 = A[3] / l00, l20 = A[6] / l00;
    double d1 = A[4] - l10 * l10;
    if (!(d1 > 0.0))
        return 0;
    double l11 = sqrt(d1);
    double l21 = (A[7] - l20 * l10) / l11;
    double d2 = A[8] - l20 * l20 - l21 * l21;
    if (!(d2 > 0.0))
        return 0;
    L[0] = l00; L[1] = 0; L[2] = 0;
    L[3] = l10; L[4] = l11; L[5] = 0;
    L[6] = l20; L[7] = l21; L[8] = sqrt(d2);
    return 1;
}

#endif
