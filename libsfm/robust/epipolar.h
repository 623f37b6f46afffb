/*
 * Internal: small inline helpers shared by the two-view estimators.
 *
 * Sampson error on unit bearings: for C = b2^T E b1, the gradients of C on
 * the tangent planes of the two unit spheres are E^T b2 - C b1 and
 * E b1 - C b2, so the first-order squared angular distance to the epipolar
 * constraint is C^2 / (|E b1|^2 + |E^T b2|^2 - 2 C^2). With narrow fields of
 * view it equals the classic Sampson error on the z = 1 plane divided by the
 * focal length squared.
 */
#ifndef SFM_ROBUST_EPIPOLAR_H
#define SFM_ROBUST_EPIPOLAR_H

#include <math.h>

#include "solvers/small_math.h"

#define SFM_ROBUST_HUGE 1e300

static inline double sfmi_sampson_bearing2(const double *E, const double *b1, const double *b2)
{
    double e0 = E[0] * b1[0] + E[1] * b1[1] + E[2] * b1[2];
    double e1 = E[3] * b1[0] + E[4] * b1[1] + E[5] * b1[2];
    double e2 = E[6] * b1[0] + E[7] * b1[1] + E[8] * b1[2];
    double f0 = E[0] * b2[0] + E[3] * b2[1] + E[6] * b2[2];
    double f1 = E[1] * b2[0] + E[4] * b2[1] + E[7] * b2[2];
    double f2 = E[2] * b2[0] + E[5] * b2[1] + E[8] * b2[2];
    double C = b2[0] * e0 + b2[1] * e1 + b2[2] * e2;
    double D = e0 * e0 + e1 * e1 + e2 * e2 + f0 * f0 + f1 * f1 + f2 * f2 - 2.0 * C * C;
    if (!(D > 1e-300))
        return SFM_ROBUST_HUGE;
    return C * C / D;
}

/* Sampson error of a fundamental matrix on pixels (classic form). */
static inline double sfmi_sampson_pixel2(const double *F, const double *p1, const double *p2)
{
    double x = p1[0], y = p1[1], u = p2[0], v = p2[1];
    double l0 = F[0] * x + F[1] * y + F[2];
    double l1 = F[3] * x + F[4] * y + F[5];
    double l2 = F[6] * x + F[7] * y + F[8];
    double m0 = F[0] * u + F[3] * v + F[6];
    double m1 = F[1] * u + F[4] * v + F[7];
    double C = u * l0 + v * l1 + l2;
    double D = l0 * l0 + l1 * l1 + m0 * m0 + m1 * m1;
    if (!(D > 1e-300))
        return SFM_ROBUST_HUGE;
    return C * C / D;
}

/* Adjugate v of the 3x3 a (a v = det I); returns det. */
static inline double sfmi_adj3(const double *a, double *v)
{
    v[0] = a[4] * a[8] - a[5] * a[7];
    v[1] = a[2] * a[7] - a[1] * a[8];
    v[2] = a[1] * a[5] - a[2] * a[4];
    v[3] = a[5] * a[6] - a[3] * a[8];
    v[4] = a[0] * a[8] - a[2] * a[6];
    v[5] = a[2] * a[3] - a[0] * a[5];
    v[6] = a[3] * a[7] - a[4] * a[6];
    v[7] = a[1] * a[6] - a[0] * a[7];
    v[8] = a[0] * a[4] - a[1] * a[3];
    return a[0] * v[0] + a[1] * v[3] + a[2] * v[6];
}

/* Squared distance of y from the homography's transfer of x (pixels). */
static inline double sfmi_transfer2(const double *H, const double *x, const double *y)
{
    double w = H[6] * x[0] + H[7] * x[1] + H[8];
    if (w == 0.0)
        return SFM_ROBUST_HUGE;
    double u = (H[0] * x[0] + H[1] * x[1] + H[2]) / w - y[0];
    double v = (H[3] * x[0] + H[4] * x[1] + H[5]) / w - y[1];
    return u * u + v * v;
}

/* E = [t]x R. */
static inline void sfmi_essential_from_pose(const double *R, const double *t, double *E)
{
    for (int c = 0; c < 3; c++) {
        double r0 = R[c], r1 = R[3 + c], r2 = R[6 + c];
        E[c] = t[1] * r2 - t[2] * r1;
        E[3 + c] = t[2] * r0 - t[0] * r2;
        E[6 + c] = t[0] * r1 - t[1] * r0;
    }
}

/* Two unit vectors completing the unit vector n to an orthonormal basis. */
static inline void sfmi_tangent_basis(const double *n, double *e1, double *e2)
{
    double a[3] = {0.0, 0.0, 0.0};
    double ax = fabs(n[0]), ay = fabs(n[1]), az = fabs(n[2]);
    if (ax <= ay && ax <= az)
        a[0] = 1.0;
    else if (ay <= az)
        a[1] = 1.0;
    else
        a[2] = 1.0;
    sfmi_cross3(n, a, e1);
    double l = sqrt(sfmi_dot3(e1, e1));
    e1[0] /= l;
    e1[1] /= l;
    e1[2] /= l;
    sfmi_cross3(n, e1, e2);
}

/* The oriented epipolar constraint (Chum, Werner & Matas, "Epipolar
 * geometry estimation via RANSAC benefits from the oriented epipolar
 * constraint", ICPR 2004): with E = [t]x R and every point in front of
 * both cameras, (t x b2) . (E b1) = d1 |t x (R b1)|^2 / |b2'| keeps one
 * sign, so the signs must agree (t, the left null vector of E, is only known
 * up to sign). The same holds for a fundamental matrix and homogeneous
 * pixels (u, v, 1) (cameras with a positive focal length). x1, x2: n
 * homogeneous 3-vectors each. Returns 1 when the model can place all n
 * pairs in front of both cameras (a necessary condition); the solvers drop
 * the models that fail it on their own sample before any verification. */
static inline int sfmi_oriented_epipolar(const double *E, const double *x1, const double *x2,
                                        int n)
{
    /* t: the largest cross product of two columns of E */
    const double c0[3] = {E[0], E[3], E[6]}, c1[3] = {E[1], E[4], E[7]},
                 c2[3] = {E[2], E[5], E[8]};
    double t[3], u[3], v[3];
    sfmi_cross3(c0, c1, t);
    sfmi_cross3(c0, c2, u);
    sfmi_cross3(c1, c2, v);
    const double *w = t;
    double nt = sfmi_dot3(t, t), nu = sfmi_dot3(u, u), nv = sfmi_dot3(v, v);
    if (nu > nt) {
        w = u;
        nt = nu;
    }
    if (nv > nt)
        w = v;
    /* done at the first pair whose sign differs from an earlier one's (most
     * models that fail, fail there) */
    int pos = 0, neg = 0;
    for (int i = 0; i < n; i++) {
        double Eb[3], txb[3];
        sfmi_matvec3(E, x1 + 3 * i, Eb);
        sfmi_cross3(w, x2 + 3 * i, txb);
        double sgn = sfmi_dot3(txb, Eb);
        pos |= sgn > 0.0;
        neg |= sgn < 0.0;
        if (pos && neg)
            return 0;
    }
    return 1;
}

#endif
