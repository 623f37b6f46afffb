/*
 * Inverse iteration for the smallest right singular vector of a triangular
 * factor (Golub & Van Loan, 4th ed., 8.2.2 and 8.2.4; the pivot floor
 * follows LAPACK's dstein). Each step solves R^T z = x, then R w = z, so the
 * component of x along the k-th right singular vector grows by 1/s_k^2: the
 * error falls by (s_n / s_{n-1})^2 a step. When that rate is slow, the
 * iteration goes on with two vectors (subspace iteration) and takes the
 * Ritz vector of R on their span each step: the error then falls by
 * (s_n / s_{n-2})^2. The iterates are compared after sign alignment; a step
 * is accepted when the change, extrapolated by the observed contraction
 * rate, is below the tolerance.
 */
#include <float.h>
#include <math.h>

#include "core/linalg_util.h"
#include "core/tri_null.h"

enum { TRI_NULL_ONE_STEPS = 20, TRI_NULL_TWO_STEPS = 40 };
/* The range of |R|_max taken (see inverse_step); beyond, 0 (the SVD). */
#define TRI_NULL_RANGE_LO 1e-100
#define TRI_NULL_RANGE_HI 1e100

/* x /= |x|; 0 when x is zero or not finite. */
static int normalize(double *x, int n)
{
    double m = sfmi_la_max_abs(x, (size_t)n);
    if (!(m > 0.0) || !isfinite(m))
        return 0;
    double inv = 1.0 / m, s = 0.0;
    for (int i = 0; i < n; i++) {
        x[i] *= inv;
        s += x[i] * x[i];
    }
    s = 1.0 / sqrt(s);
    for (int i = 0; i < n; i++)
        x[i] *= s;
    return 1;
}

/* s - sum_{k < m} a[k inc] x[k], the terms subtracted in the order of k.
 * Four terms a pass where the build is for speed: the same operations in
 * the same order as the plain loop of a build for size, so the same bits,
 * with a quarter of the loop's own instructions. */
static inline double sub_dot(double s, const double *a, size_t inc, const double *x, int m)
{
    int k = 0;
#if !defined(__OPTIMIZE_SIZE__)
    for (; k + 4 <= m; k += 4) {
        s -= a[k * inc] * x[k];
        s -= a[(k + 1) * inc] * x[k + 1];
        s -= a[(k + 2) * inc] * x[k + 2];
        s -= a[(k + 3) * inc] * x[k + 3];
    }
#endif
    for (; k < m; k++)
        s -= a[k * inc] * x[k];
    return s;
}

/* x <- R^-T x (forward substitution with the transpose); dinv: the
 * reciprocal pivots. */
static void solve_rt(const double *R, int n, const double *dinv, double *x)
{
    for (int i = 0; i < n; i++)
        x[i] = sub_dot(x[i], R + i, (size_t)n, x, i) * dinv[i];
}

/* x <- R^-1 x (back substitution). */
static void solve_r(const double *R, int n, const double *dinv, double *x)
{
    for (int i = n - 1; i >= 0; i--)
        x[i] = sub_dot(x[i], R + (size_t)i * n + i + 1, 1, x + i + 1, n - 1 - i) * dinv[i];
}

/* Tracks convergence of successive unit iterates: x <- y (sign-aligned
 * with x), returns 1 once the extrapolated remaining change is below the
 * tolerance. *prev holds the last change (0 before the first). */
static int settle(double *x, const double *y, int n, double tol, double *prev)
{
    double dot = 0.0;
    for (int i = 0; i < n; i++)
        dot += x[i] * y[i];
    double sg = dot < 0.0 ? -1.0 : 1.0, d2 = 0.0;
    for (int i = 0; i < n; i++) {
        double e = sg * y[i] - x[i];
        d2 += e * e;
        x[i] = sg * y[i];
    }
    double delta = sqrt(d2);
    /* remaining error ~ delta * rho / (1 - rho) for a contraction rate rho;
     * a rate >= 1 means the change is rounding noise */
    double est = delta;
    if (*prev > 0.0) {
        double rho = delta / *prev;
        if (rho < 1.0 && rho > 0.5)
            est = delta * rho / (1.0 - rho);
    }
    *prev = delta;
    return est <= tol;
}

/* y <- R^-1 R^-T y, normalized; 0 when not finite. With |R|_max within
 * TRI_NULL_RANGE_LO.._HI and the pivots floored at eps |R|_max, the two
 * solves of a unit vector stay far from overflow and underflow for any
 * factor short of a pathological growth of the substitution, so y is not
 * rescaled between them (an overflow would still be caught: the iterate
 * is not finite, 0, the caller's SVD). */
static int inverse_step(const double *R, int n, const double *dinv, double *y)
{
    sfmi_la_tri_gram_solve(R, n, dinv, y);
    return normalize(y, n);
}

/* |R x|^2 for upper triangular R. */
static double rx_dot(const double *R, int n, const double *x, const double *y)
{
    double s = 0.0;
    for (int i = 0; i < n; i++) {
        const double *row = R + (size_t)i * n;
        double a = 0.0, b = 0.0;
        for (int k = i; k < n; k++) {
            a += row[k] * x[k];
            b += row[k] * y[k];
        }
        s += a * b;
    }
    return s;
}

/* The reciprocals of R's pivots, floored at eps |R|_max, in dinv; 0 when
 * |R|_max is zero, not finite or outside TRI_NULL_RANGE_LO.._HI. */
static int pivots(const double *R, int n, double *dinv)
{
    double rmax = 0.0;
    for (int i = 0; i < n; i++)
        for (int k = i; k < n; k++) {
            double a = fabs(R[(size_t)i * n + k]);
            if (!(a <= rmax))
                rmax = a; /* NaN propagates */
        }
    if (!(rmax > TRI_NULL_RANGE_LO && rmax < TRI_NULL_RANGE_HI))
        return 0;
    const double floor = DBL_EPSILON * rmax;
    for (int i = 0; i < n; i++) {
        const double d = R[(size_t)i * n + i];
        dinv[i] = 1.0 / (fabs(d) >= floor ? d : copysign(floor, d));
    }
    return 1;
}

void sfmi_la_tri_gram_solve(const double *R, int n, const double *dinv, double *x)
{
    solve_rt(R, n, dinv, x);
    solve_r(R, n, dinv, x);
}

int sfmi_la_tri_smallest_right(const double *R, int n, double tol, double *v, double *scratch)
{
    double *x = scratch, *y = scratch + n, *q = scratch + 2 * n, *w = scratch + 3 * n;
    double *dinv = scratch + 4 * n;
    if (!pivots(R, n, dinv))
        return 0;
    /* Start from R^-1 e_n: the last column of R^-1, large where R is
     * nearly singular. */
    for (int i = 0; i < n; i++)
        x[i] = 0.0;
    x[n - 1] = 1.0;
    solve_r(R, n, dinv, x);
    if (!normalize(x, n))
        return 0;
    double prev = 0.0;
    for (int step = 0; step < TRI_NULL_ONE_STEPS; step++) {
        for (int i = 0; i < n; i++)
            y[i] = x[i];
        if (!inverse_step(R, n, dinv, y))
            return 0;
        for (int i = 0; i < n; i++)
            q[i] = y[i] - x[i]; /* the last change: mostly the next vector */
        if (settle(x, y, n, tol, &prev)) {
            for (int i = 0; i < n; i++)
                v[i] = x[i];
            return 1;
        }
    }
    if (n < 2)
        return 0;
    /* Two vectors: x and the last change, orthonormalized (twice, as
     * classical Gram-Schmidt needs for orthogonality to rounding). */
    for (int pass = 0; pass < 2; pass++) {
        double d = 0.0;
        for (int i = 0; i < n; i++)
            d += x[i] * q[i];
        for (int i = 0; i < n; i++)
            q[i] -= d * x[i];
    }
    if (!normalize(q, n))
        return 0;
    prev = 0.0;
    for (int step = 0; step < TRI_NULL_TWO_STEPS; step++) {
        for (int i = 0; i < n; i++) {
            y[i] = x[i];
            w[i] = q[i];
        }
        if (!inverse_step(R, n, dinv, y) || !inverse_step(R, n, dinv, w))
            return 0;
        for (int pass = 0; pass < 2; pass++) {
            double d = 0.0;
            for (int i = 0; i < n; i++)
                d += y[i] * w[i];
            for (int i = 0; i < n; i++)
                w[i] -= d * y[i];
        }
        if (!normalize(w, n))
            return 0;
        /* Ritz vectors of R on span(y, w): the Jacobi rotation that makes
         * R y and R w orthogonal */
        double alpha = rx_dot(R, n, y, y), beta = rx_dot(R, n, w, w), gamma = rx_dot(R, n, y, w);
        if (gamma != 0.0) {
            double c, s;
            double tt = sfmi_la_jacobi_angle((beta - alpha) / (2.0 * gamma), &c, &s);
            sfmi_la_rotate(y, w, n, 1, c, s);
            alpha -= tt * gamma;
            beta += tt * gamma;
        }
        if (beta < alpha) { /* y: the smaller Ritz value */
            for (int i = 0; i < n; i++) {
                double tmp = y[i];
                y[i] = w[i];
                w[i] = tmp;
            }
        }
        if (!normalize(y, n) || !normalize(w, n))
            return 0;
        for (int i = 0; i < n; i++)
            q[i] = w[i];
        if (settle(x, y, n, tol, &prev)) {
            for (int i = 0; i < n; i++)
                v[i] = x[i];
            return 1;
        }
    }
    return 0;
}
