/*
 * Internal: small inline helpers of the minimal solvers, shared with the
 * estimators above them: branch-free finiteness of short vectors, 3-vector
 * and 3x3 products, and the one real root of a monic cubic that P3P and the upright
 * 3-point solver need.
 */
#ifndef SFM_SOLVERS_SMALL_MATH_H
#define SFM_SOLVERS_SMALL_MATH_H

#include <math.h>
#include "core/dmath.h"
#include "core/inline.h"

/* 1 when all values are finite: x * 0 is NaN exactly for NaN and +-Inf. */
SFMI_INLINE int sfmi_all_finite3(const double *v)
{
    return (v[0] * 0.0 + v[1] * 0.0) + v[2] * 0.0 == 0.0;
}

SFMI_INLINE int sfmi_all_finite9(const double *v)
{
    return ((v[0] * 0.0 + v[1] * 0.0) + (v[2] * 0.0 + v[3] * 0.0)) +
               ((v[4] * 0.0 + v[5] * 0.0) + (v[6] * 0.0 + v[7] * 0.0)) + v[8] * 0.0 ==
           0.0;
}

SFMI_INLINE void sfmi_cross3(const double *a, const double *b, double *c)
{
    c[0] = a[1] * b[2] - a[2] * b[1];
    c[1] = a[2] * b[0] - a[0] * b[2];
    c[2] = a[0] * b[1] - a[1] * b[0];
}

SFMI_INLINE double sfmi_dot3(const double *a, const double *b)
{
    return a[0] * b[0] + a[1] * b[1] + a[2] * b[2];
}

/* y = M x for a row-major 3x3 M (y may alias x). */
SFMI_INLINE void sfmi_matvec3(const double *M, const double *x, double *y)
{
    double a = M[0] * x[0] + M[1] * x[1] + M[2] * x[2];
    double b = M[3] * x[0] + M[4] * x[1] + M[5] * x[2];
    double c = M[6] * x[0] + M[7] * x[1] + M[8] * x[2];
    y[0] = a;
    y[1] = b;
    y[2] = c;
}

/* y = M^T x (y may alias x). */
SFMI_INLINE void sfmi_matvec3_t(const double *M, const double *x, double *y)
{
    double a = M[0] * x[0] + M[3] * x[1] + M[6] * x[2];
    double b = M[1] * x[0] + M[4] * x[1] + M[7] * x[2];
    double c = M[2] * x[0] + M[5] * x[1] + M[8] * x[2];
    y[0] = a;
    y[1] = b;
    y[2] = c;
}

/* 3x3 products C = A B, C = A^T B and C = A B^T (C may alias A or B). */
SFMI_INLINE void sfmi_matmul3(const double *A, const double *B, double *C)
{
    double T[9];
    for (int r = 0; r < 3; r++)
        for (int c = 0; c < 3; c++)
            T[3 * r + c] = A[3 * r] * B[c] + A[3 * r + 1] * B[3 + c] + A[3 * r + 2] * B[6 + c];
    for (int i = 0; i < 9; i++)
        C[i] = T[i];
}

SFMI_INLINE void sfmi_matmul3_tn(const double *A, const double *B, double *C)
{
    double T[9];
    for (int r = 0; r < 3; r++)
        for (int c = 0; c < 3; c++)
            T[3 * r + c] = A[r] * B[c] + A[3 + r] * B[3 + c] + A[6 + r] * B[6 + c];
    for (int i = 0; i < 9; i++)
        C[i] = T[i];
}

SFMI_INLINE void sfmi_matmul3_nt(const double *A, const double *B, double *C)
{
    double T[9];
    for (int r = 0; r < 3; r++)
        for (int c = 0; c < 3; c++)
            T[3 * r + c] = A[3 * r] * B[3 * c] + A[3 * r + 1] * B[3 * c + 1] + A[3 * r + 2] * B[3 * c + 2];
    for (int i = 0; i < 9; i++)
        C[i] = T[i];
}

/* A vector n orthogonal to the rows r0, r1, r2 of a rank-2 3x3: r0 x r1, or,
 * when |r0 x r1|^2 <= rel |r0|^2 |r1|^2 (r0, r1 nearly parallel), the longest
 * of the three cross products. Returns |n|^2 (not > 0: rank below 2). */
SFMI_INLINE double sfmi_rank2_null3(const double *r0, const double *r1, const double *r2,
                                     double rel, double n[3])
{
    sfmi_cross3(r0, r1, n);
    double m = sfmi_dot3(n, n);
    if (!(m > rel * sfmi_dot3(r0, r0) * sfmi_dot3(r1, r1))) {
        double n02[3], n12[3];
        sfmi_cross3(r0, r2, n02);
        sfmi_cross3(r1, r2, n12);
        double m02 = sfmi_dot3(n02, n02), m12 = sfmi_dot3(n12, n12);
        if (m02 > m) {
            n[0] = n02[0];
            n[1] = n02[1];
            n[2] = n02[2];
            m = m02;
        }
        if (m12 > m) {
            n[0] = n12[0];
            n[1] = n12[1];
            n[2] = n12[2];
            m = m12;
        }
    }
    return m;
}

/* A real root of the monic cubic x^3 + b x^2 + c x + d, the largest when
 * there are three: Cardano with a single cube root when one root is real
 * (u v = -p/3, u taken on the side without cancellation), else the largest
 * of the trigonometric form; then two Newton steps. */
SFMI_INLINE double sfmi_cubic_largest_root(double b, double c, double d)
{
    double b3 = b * (1.0 / 3.0);
    double p = c - b * b3;
    double q = (2.0 * b3 * b3 - c) * b3 + d;
    double disc = 0.25 * q * q + p * p * p * (1.0 / 27.0);
    double x;
    if (disc >= 0.0) {
        double s = sqrt(disc);
        double u = sfmi_cbrt(-0.5 * q - copysign(s, q));
        x = (u != 0.0 ? u - p / (3.0 * u) : 0.0) - b3;
    } else {
        /* p < 0 here */
        double r = sqrt(-p * (1.0 / 3.0));
        double arg = -0.5 * q / (r * r * r);
        if (arg > 1.0)
            arg = 1.0;
        if (arg < -1.0)
            arg = -1.0;
        x = 2.0 * r * sfmi_cos(sfmi_acos(arg) * (1.0 / 3.0)) - b3;
    }
    for (int it = 0; it < 2; it++) {
        double f = ((x + b) * x + c) * x + d;
        double df = (3.0 * x + 2.0 * b) * x + c;
        if (df != 0.0)
            x -= f / df;
    }
    return x;
}

#endif
