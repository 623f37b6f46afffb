/*
 * Internal: small vector helpers shared by the robot-to-robot base-system
 * solvers (libsfm/solvers/r2r_*.c). Header-only, static inline; no state.
 */
#ifndef SFM_SOLVERS_R2R_ALIGN_H
#define SFM_SOLVERS_R2R_ALIGN_H

#include <math.h>

#include "sfm/sfm_r2r.h"

static inline double sfmi_r2r_max(double a, double b)
{
    return a > b ? a : b;
}

static inline double sfmi_r2r_dot(const double *a, const double *b)
{
    return a[0] * b[0] + a[1] * b[1] + a[2] * b[2];
}

static inline void sfmi_r2r_cross(const double *a, const double *b, double *c)
{
    double x = a[1] * b[2] - a[2] * b[1], y = a[2] * b[0] - a[0] * b[2], z = a[0] * b[1] - a[1] * b[0];
    c[0] = x;
    c[1] = y;
    c[2] = z;
}

/* y = R x (R row-major) */
static inline void sfmi_r2r_mulv(const double *R, const double *x, double *y)
{
    double a = R[0] * x[0] + R[1] * x[1] + R[2] * x[2];
    double b = R[3] * x[0] + R[4] * x[1] + R[5] * x[2];
    double c = R[6] * x[0] + R[7] * x[1] + R[8] * x[2];
    y[0] = a;
    y[1] = b;
    y[2] = c;
}

/* Orthonormal frame (columns e1, e2, e3) with e1 along v and e2 in the plane
 * of v and w, on the side of w. Returns 0 when v and w do not span a plane
 * (relative tolerance 1e-12). */
static inline int sfmi_r2r_frame(const double *v, const double *w, double F[9])
{
    double e1[3], e2[3], e3[3];
    double nv = sqrt(sfmi_r2r_dot(v, v));
    if (!(nv > 0.0))
        return 0;
    for (int i = 0; i < 3; i++)
        e1[i] = v[i] / nv;
    double c = sfmi_r2r_dot(e1, w);
    for (int i = 0; i < 3; i++)
        e2[i] = w[i] - c * e1[i];
    double n2 = sqrt(sfmi_r2r_dot(e2, e2));
    if (!(n2 > 1e-12 * sqrt(sfmi_r2r_dot(w, w))))
        return 0;
    for (int i = 0; i < 3; i++)
        e2[i] /= n2;
    sfmi_r2r_cross(e1, e2, e3);
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
    sfmi_r2r_mulv(s->R1.m, s->b1.v, u);
}

/* Bearing of robot 2 at step k rotated into {2}: w = R2 b2 */
static inline void sfmi_r2r_w(const sfm_r2r_step *s, double w[3])
{
    sfmi_r2r_mulv(s->R2.m, s->b2.v, w);
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

#endif
