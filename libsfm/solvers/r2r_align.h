/*
 * Internal: small vector helpers shared by the robot-to-robot base-system
 * solvers (libsfm/solvers/r2r_*.c). Header-only, static inline; no state.
 */
#ifndef SFM_SOLVERS_R2R_ALIGN_H
#define SFM_SOLVERS_R2R_ALIGN_H

#include <math.h>

#include "sfm/sfm_r2r.h"
#include "solvers/small_math.h"

static inline double sfmi_r2r_max(double a, double b)
{
    return a > b ? a : b;
}

/* Orthonormal frame (columns e1, e2, e3) with e1 along v and e2 in the plane
 * of v and w, on the side of w. Returns 0 when v and w do not span a plane
 * (relative tolerance 1e-12). */
static inline int sfmi_r2r_frame(const double *v, const double *w, double F[9])
{
    double e1[3], e2[3], e3[3];
    double nv = sqrt(sfmi_dot3(v, v));
    if (!(nv > 0.0))
        return 0;
    for (int i = 0; i < 3; i++)
        e1[i] = v[i] / nv;
    double c = sfmi_dot3(e1, w);
    for (int i = 0; i < 3; i++)
        e2[i] = w[i] - c * e1[i];
    double n2 = sqrt(sfmi_dot3(e2, e2));
    if (!(n2 > 1e-12 * sqrt(sfmi_dot3(w, w))))
        return 0;
    for (int i = 0; i < 3; i++)
        e2[i] /= n2;
    sfmi_cross3(e1, e2, e3);
    for (int i = 0; i < 3; i++) {
        F[3 * i] = e1[i];
        F[3 * i + 1] = e2[i];
        F[3 * i + 2] = e3[i];
    }
    return 1;
}

/* The proper rotation C with C v1 along a1 and C v2 in the plane of a1, a2
 * on a2's side: C = F_a F_v^T (exact when the pairs have the same Gram
 * matrix). Returns 0 when either pair does not span a plane. */
static inline int sfmi_r2r_align2(const double *v1, const double *v2, const double *a1,
                                  const double *a2, double C[9])
{
    double Fv[9], Fa[9];
    if (!sfmi_r2r_frame(v1, v2, Fv) || !sfmi_r2r_frame(a1, a2, Fa))
        return 0;
    for (int r = 0; r < 3; r++)
        for (int c = 0; c < 3; c++)
            C[3 * r + c] = Fa[3 * r] * Fv[3 * c] + Fa[3 * r + 1] * Fv[3 * c + 1] + Fa[3 * r + 2] * Fv[3 * c + 2];
    return 1;
}

/* Bearing of robot 1 at step k rotated into {1}: u = R1 b1 */
static inline void sfmi_r2r_u(const sfm_r2r_step *s, double u[3])
{
    sfmi_matvec3(s->R1.m, s->b1.v, u);
}

/* Bearing of robot 2 at step k rotated into {2}: w = R2 b2 */
static inline void sfmi_r2r_w(const sfm_r2r_step *s, double w[3])
{
    sfmi_matvec3(s->R2.m, s->b2.v, w);
}

static inline double sfmi_r2r_det3(const double *M)
{
    return M[0] * (M[4] * M[8] - M[5] * M[7]) - M[1] * (M[3] * M[8] - M[5] * M[6]) +
           M[2] * (M[3] * M[7] - M[4] * M[6]);
}

/* x = J^-1 f by Cramer's rule (J row-major 3x3); 0 when J is singular or
 * the result is not finite. For Newton polishing of the small systems. */
static inline int sfmi_r2r_solve3(const double *J, const double *f, double *x)
{
    double det = sfmi_r2r_det3(J), y[3];
    if (!(fabs(det) > 1e-300))
        return 0;
    for (int i = 0; i < 3; i++) {
        double M[9];
        for (int k = 0; k < 9; k++)
            M[k] = J[k];
        for (int r = 0; r < 3; r++)
            M[3 * r + i] = f[r];
        y[i] = sfmi_r2r_det3(M) / det;
        if (!isfinite(y[i]))
            return 0;
    }
    for (int i = 0; i < 3; i++)
        x[i] = y[i];
    return 1;
}

/* One step of a Newton polish of a root x of three equations, given their
 * values f and Jacobian J at x. On the last step (last != 0) it only checks
 * the root: 1 when max |f| <= 1e-10 max |J| (1 + |x|_1), else 0 (a root the
 * equations do not confirm is no root). Otherwise x -= J^-1 f and -1 (go
 * on), or 0 when J is singular. */
/* A dip of |f| between a and b that keeps the sign s of f at both ends may
 * hide two close roots: golden-section search (at most 40 steps) for a
 * point where s f <= 0. Returns 1 with that point in *xm (the two roots then
 * lie on either side of it), 0 when the dip stays on one side. */
static inline int sfmi_r2r_dip_cross(double (*fn)(const void *, double), const void *ctx, double a,
                                     double b, double s, double *xm)
{
    const double gr = 0.38196601125010515;
    double x1 = a + gr * (b - a), x2 = b - gr * (b - a);
    double g1 = s * fn(ctx, x1), g2 = s * fn(ctx, x2);
    for (int it = 0; it < 40 && g1 > 0.0 && g2 > 0.0; it++) {
        if (g1 < g2) {
            b = x2;
            x2 = x1;
            g2 = g1;
            x1 = a + gr * (b - a);
            g1 = s * fn(ctx, x1);
        } else {
            a = x1;
            x1 = x2;
            g1 = g2;
            x2 = b - gr * (b - a);
            g2 = s * fn(ctx, x2);
        }
    }
    if (!(g1 <= 0.0) && !(g2 <= 0.0))
        return 0;
    *xm = g1 <= 0.0 ? x1 : x2;
    return 1;
}

static inline int sfmi_r2r_newton3(const double J[9], const double f[3], int last, double x[3])
{
    double dx[3], big = 0.0, res = 0.0;
    for (int i = 0; i < 9; i++)
        big = sfmi_r2r_max(big, fabs(J[i]));
    for (int i = 0; i < 3; i++)
        res = sfmi_r2r_max(res, fabs(f[i]));
    if (last)
        return res <= 1e-10 * big * (1.0 + fabs(x[0]) + fabs(x[1]) + fabs(x[2]));
    if (!sfmi_r2r_solve3(J, f, dx))
        return 0;
    for (int i = 0; i < 3; i++)
        x[i] -= dx[i];
    return -1;
}

#endif
