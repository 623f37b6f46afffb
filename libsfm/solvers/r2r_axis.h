/*
 * Internal: the geometry the robot-to-robot solvers with a step of three or
 * more equations share (r2r_db1b2_d.c ... r2r_db1_d_d_d.c).
 *
 * Most of them learn, from their first steps, one vector correspondence
 * C u = v (|u| = |v|). The rotations satisfying it are one circle,
 * C = R_n(theta) C0 with n = v / |v| and C0 any rotation taking u to v. One
 * more scalar equation y^T C x = c is then linear in (cos theta, sin theta)
 * and has at most two solutions, found without trigonometry.
 */
#ifndef SFM_SOLVERS_R2R_AXIS_H
#define SFM_SOLVERS_R2R_AXIS_H

#include <math.h>

#include "sfm/sfm_r2r.h"
#include "solvers/small_math.h"

/* Unit n and a right-handed orthonormal frame (n, e1, e2). 0 for a zero or
 * non-finite a. */
static inline int sfmi_r2r_unit_frame(const double a[3], double n[3], double e1[3], double e2[3])
{
    double l = sqrt(sfmi_dot3(a, a));
    if (!(l > 0.0) || !isfinite(l))
        return 0;
    for (int i = 0; i < 3; i++)
        n[i] = a[i] / l;
    /* cross with the axis of n's smallest component: never near-parallel */
    int k = fabs(n[0]) <= fabs(n[1]) ? (fabs(n[0]) <= fabs(n[2]) ? 0 : 2)
                                      : (fabs(n[1]) <= fabs(n[2]) ? 1 : 2);
    double ek[3] = {0.0, 0.0, 0.0};
    ek[k] = 1.0;
    sfmi_cross3(n, ek, e1);
    double m = sqrt(sfmi_dot3(e1, e1));
    for (int i = 0; i < 3; i++)
        e1[i] /= m;
    sfmi_cross3(n, e1, e2);
    return 1;
}

/* A proper rotation C0 with C0 u/|u| = v/|v| (one of the circle). 0 when u
 * or v is zero. */
static inline int sfmi_r2r_align(const double u[3], const double v[3], double C0[9])
{
    double a[3], a1[3], a2[3], b[3], b1[3], b2[3];
    if (!sfmi_r2r_unit_frame(u, a, a1, a2) || !sfmi_r2r_unit_frame(v, b, b1, b2))
        return 0;
    for (int r = 0; r < 3; r++)
        for (int c = 0; c < 3; c++)
            C0[3 * r + c] = b[r] * a[c] + b1[r] * a1[c] + b2[r] * a2[c];
    return 1;
}

/* C = R_n(theta) C0 from (cos theta, sin theta), n unit:
 * R = cos I + sin [n]x + (1 - cos) n n^T. C must not alias C0. */
static inline void sfmi_r2r_axis_rotate(const double n[3], double co, double si,
                                        const double C0[9], double C[9])
{
    double R[9];
    for (int i = 0; i < 3; i++)
        for (int l = 0; l < 3; l++)
            R[3 * i + l] = (1.0 - co) * n[i] * n[l] + (i == l ? co : 0.0);
    R[1] -= si * n[2];
    R[2] += si * n[1];
    R[3] += si * n[2];
    R[5] -= si * n[0];
    R[6] -= si * n[1];
    R[7] += si * n[0];
    sfmi_matmul3(R, C0, C);
}

/* The rotations C = R_n(theta) C0 (n unit) with y^T C x = c: at most two,
 * written to C[0..1]. With z = C0 x, y^T R_n(theta) z =
 * A cos + B sin + E, A = z.y - (n.z)(n.y), B = (n x z).y, E = (n.z)(n.y).
 * Returns 0 when |A, B| vanishes against |z||y| (the equation does not see
 * theta) or when the circle misses (|c - E| > |A, B|, beyond a relative
 * 1e-9 that rounding of exact data can cause: clamped to the tangent). */
static inline int sfmi_r2r_circle_solve(const double C0[9], const double n[3],
                                        const double x[3], const double y[3], double c,
                                        double C[2][9])
{
    double z[3], nz[3];
    sfmi_matvec3(C0, x, z);
    sfmi_cross3(n, z, nz);
    double zn = sfmi_dot3(n, z), yn = sfmi_dot3(n, y);
    double A = sfmi_dot3(z, y) - zn * yn, B = sfmi_dot3(nz, y), E = zn * yn;
    double r = sqrt(A * A + B * B);
    double scale = sqrt(sfmi_dot3(z, z) * sfmi_dot3(y, y));
    if (!(r > 1e-12 * scale))
        return 0;
    double k = (c - E) / r;
    if (!(fabs(k) <= 1.0 + 1e-9))
        return 0;
    k = k > 1.0 ? 1.0 : (k < -1.0 ? -1.0 : k);
    double s = sqrt(1.0 - k * k), a = A / r, b = B / r;
    int m = s > 0.0 ? 2 : 1;
    for (int j = 0; j < m; j++) {
        double sg = j == 0 ? 1.0 : -1.0;
        sfmi_r2r_axis_rotate(n, k * a - sg * s * b, k * b + sg * s * a, C0, C[j]);
    }
    return m;
}

/* 1 when (C, p) points every bearing of the step the way it was measured
 * (positive dot product): the algebra solves q parallel to b, which admits
 * the reversed direction too. */
static inline int sfmi_r2r_bearings_agree(const sfm_r2r_step *s, const double C[9],
                                          const double p[3])
{
    double q[3], w[3];
    sfmi_matvec3(C, s->t2.v, q);
    for (int i = 0; i < 3; i++)
        q[i] += p[i] - s->t1.v[i];
    if (s->has & SFM_R2R_B1) {
        /* R1^T q . b1 = q . R1 b1 */
        sfmi_matvec3(s->R1.m, s->b1.v, w);
        if (!(sfmi_dot3(q, w) > 0.0))
            return 0;
    }
    if (s->has & SFM_R2R_B2) {
        /* R2^T (-C^T q) . b2 = -q . C R2 b2 */
        double g[3];
        sfmi_matvec3(s->R2.m, s->b2.v, g);
        sfmi_matvec3(C, g, w);
        if (!(sfmi_dot3(q, w) < 0.0))
            return 0;
    }
    return 1;
}

/* Appends (C, p) to out[*n] when it agrees with every bearing of the steps. */
static inline void sfmi_r2r_emit(const sfm_r2r_step *steps, int n_steps, const double C[9],
                                 const double p[3], sfm_r2r_transform *out, int *n)
{
    for (int k = 0; k < n_steps; k++)
        if (!sfmi_r2r_bearings_agree(&steps[k], C, p))
            return;
    for (int i = 0; i < 9; i++)
        if (!isfinite(C[i]))
            return;
    for (int i = 0; i < 3; i++)
        if (!isfinite(p[i]))
            return;
    for (int i = 0; i < 9; i++)
        out[*n].C.m[i] = C[i];
    for (int i = 0; i < 3; i++)
        out[*n].p.v[i] = p[i];
    (*n)++;
}

#endif
