/*
 * Internal: the frames, aligning rotations and small numerical routines the
 * robot-to-robot base-system solvers share (libsfm/solvers/r2r_*.c).
 * Header-only, static inline (but the bisection and dip search of the root
 * scan, r2r_scan.c); no state.
 *
 * Two kinds of frame: sfmi_r2r_frame fixes all three axes from two vectors
 * (e1 along v, e2 towards w), so sfmi_r2r_align2 is the one rotation
 * matching two vector pairs; sfmi_r2r_unit_frame completes one vector to
 * some right-handed frame, so sfmi_r2r_align is one rotation of the circle
 * matching a single pair, and the circle itself is swept by
 * sfmi_r2r_axis_rotate / sfmi_r2r_circle_solve.
 *
 * The circle of rotations (the solvers with a step of three or more
 * equations, r2r_db1b2_d.c ... r2r_db1_d_d_d.c): most of them learn, from
 * their first steps, one vector correspondence C u = v (|u| = |v|). The
 * rotations satisfying it are one circle, C = R_n(theta) C0 with
 * n = v / |v| and C0 any rotation taking u to v. One more scalar equation
 * y^T C x = c is then linear in (cos theta, sin theta) and has at most two
 * solutions, found without trigonometry.
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
    sfmi_matmul3_nt(Fa, Fv, C);
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

/* The middle of [a, b] after iters halvings that keep a sign change of fn
 * inside (fa = fn(a)); with stop_nonfinite it stops at the first value of
 * fn that is not finite. Out of line (r2r_scan.c), as the next. */
double sfmi_r2r_bisect(double (*fn)(const void *, double), const void *ctx, double a, double b,
                       double fa, int iters, int stop_nonfinite);

/* A dip of |f| between a and b that keeps the sign s of f at both ends may
 * hide two close roots: golden-section search (at most 40 steps) for a
 * point where s f <= 0. Returns 1 with that point in *xm (the two roots then
 * lie on either side of it), 0 when the dip stays on one side. */
int sfmi_r2r_dip_cross(double (*fn)(const void *, double), const void *ctx, double a, double b,
                       double s, double *xm);

/* One step of the sampled root scan of r2r_b1_b2_d_d.c and
 * r2r_b1_d_d_d_d.c: the new sample (tn, fv) of fn enters the window of the
 * last three samples (t[j], f[j]), oldest first, f not finite where there
 * is no sample (yet), and the oldest leaves it. Then a sign change between
 * the last two is bisected; a dip of |f| at the middle one that
 * keeps the sign is searched, and when it crosses, both roots are bisected
 * (iters and stop_nonfinite as sfmi_r2r_bisect). The roots go to roots[m],
 * roots[m + 1] (the two cases exclude each other: room for two); returns
 * the new m. Inline: it runs once a sample. */
static inline int sfmi_r2r_scan_step(double (*fn)(const void *, double), const void *ctx,
                                     double t[3], double f[3], double tn, double fv, int iters,
                                     int stop_nonfinite, double *roots, int m)
{
    t[0] = t[1];
    f[0] = f[1];
    t[1] = t[2];
    f[1] = f[2];
    t[2] = tn;
    f[2] = fv;
    if (!(isfinite(f[1]) && isfinite(f[2])))
        return m;
    if ((f[1] < 0.0) != (f[2] < 0.0))
        roots[m++] = sfmi_r2r_bisect(fn, ctx, t[1], t[2], f[1], iters, stop_nonfinite);
    if (isfinite(f[0]) && (f[0] < 0.0) == (f[1] < 0.0) && (f[1] < 0.0) == (f[2] < 0.0) &&
        fabs(f[1]) < fabs(f[0]) && fabs(f[1]) < fabs(f[2])) {
        double xm;
        if (sfmi_r2r_dip_cross(fn, ctx, t[0], t[2], f[1] < 0.0 ? -1.0 : 1.0, &xm)) {
            roots[m++] = sfmi_r2r_bisect(fn, ctx, t[0], xm, f[0], iters, stop_nonfinite);
            /* f(xm) has the other sign */
            roots[m++] = sfmi_r2r_bisect(fn, ctx, xm, t[2], -f[2], iters, stop_nonfinite);
        }
    }
    return m;
}

/* One step of a Newton polish of a root x of three equations, given their
 * values f and Jacobian J at x. On the last step (last != 0) it only checks
 * the root: 1 when max |f| <= 1e-10 max |J| (1 + |x|_1), else 0 (a root the
 * equations do not confirm is no root). Otherwise x -= J^-1 f and -1 (go
 * on), or 0 when J is singular. */
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

/* Newton polish of a root x of three equations whose values f and Jacobian
 * J at x come from fj(coef, x, f, J): two steps of sfmi_r2r_newton3, then
 * its check. Returns 1 for a root the equations confirm, else 0. */
static inline int sfmi_r2r_polish3(void (*fj)(const double *coef, const double *x, double f[3],
                                              double J[9]),
                                   const double *coef, double x[3])
{
    for (int it = 0; it < 3; it++) {
        double f[3], J[9];
        fj(coef, x, f, J);
        int r = sfmi_r2r_newton3(J, f, it == 2, x);
        if (r >= 0)
            return r;
    }
    return 0;
}

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

/* The solvers with two bearings or one and distances (r2r_b1_b1_d_d.c,
 * r2r_b1_d_d_d_d.c) write C = F Rx(theta) G^T: G a frame of {2} whose first
 * axis is t2_1, F the frame at the point a = C t2_1 of a circle
 * {|a| = rho, n.a = h0} (radius r), Rx(theta) the turn about their first
 * axes left free. Then C t2_k = v0 a / rho + cos(theta) (v1 f2 + v2 f3) +
 * sin(theta) (v1 f3 - v2 f2), v = G^T t2_k, and each distance equation is
 * linear in (cos theta, sin theta). */

/* G (columns) and its axes (rows of ax): t / rho (rho = |t| > 0), then two
 * perpendicular axes completing it right-handed. */
static inline void sfmi_r2r_axis_frame(const double t[3], double rho, double ax[3][3],
                                       double G[9])
{
    double *g1 = ax[0], *g2 = ax[1], *g3 = ax[2], aux[3] = {0.0, 0.0, 0.0};
    for (int i = 0; i < 3; i++)
        g1[i] = t[i] / rho;
    int mi = fabs(g1[0]) < fabs(g1[1]) ? (fabs(g1[0]) < fabs(g1[2]) ? 0 : 2)
                                       : (fabs(g1[1]) < fabs(g1[2]) ? 1 : 2);
    aux[mi] = 1.0;
    sfmi_cross3(g1, aux, g2);
    double n2 = sqrt(sfmi_dot3(g2, g2));
    for (int i = 0; i < 3; i++)
        g2[i] /= n2;
    sfmi_cross3(g1, g2, g3);
    for (int i = 0; i < 3; i++) {
        G[3 * i] = g1[i];
        G[3 * i + 1] = g2[i];
        G[3 * i + 2] = g3[i];
    }
}

/* F (columns a / rho, f2 = n x a / r, f3 = (rho^2 n - h0 a) / (rho r)) at
 * the point a of the circle; n unit. */
static inline void sfmi_r2r_circle_frame(const double n[3], const double a[3], double h0,
                                         double r, double rho, double F[9], double f2[3],
                                         double f3[3])
{
    sfmi_cross3(n, a, f2);
    for (int i = 0; i < 3; i++) {
        f2[i] /= r;
        f3[i] = (rho * rho * n[i] - h0 * a[i]) / (rho * r);
        F[3 * i] = a[i] / rho;
        F[3 * i + 1] = f2[i];
        F[3 * i + 2] = f3[i];
    }
}

/* The cos and sin coefficients of |C t2_k + l u0 - t1_k|^2 = d_k^2 at the
 * frame (f2, f3): with q = l u0 - t1_k, 2 q.(v1 f2 + v2 f3) into cs[0] and
 * 2 q.(v1 f3 - v2 f2) into cs[1]; q out (the constant term is the
 * caller's). */
static inline void sfmi_r2r_distance_cs(double l, const double u0[3], const double t1[3],
                                        const double v[3], const double f2[3],
                                        const double f3[3], double q[3], double cs[2])
{
    double x[3], y[3];
    for (int i = 0; i < 3; i++) {
        q[i] = l * u0[i] - t1[i];
        x[i] = v[1] * f2[i] + v[2] * f3[i];
        y[i] = v[1] * f3[i] - v[2] * f2[i];
    }
    cs[0] = 2.0 * sfmi_dot3(q, x);
    cs[1] = 2.0 * sfmi_dot3(q, y);
}

/* C = F Rx(theta) G^T, Rx(theta) = [1 0 0; 0 ct -st; 0 st ct]: the
 * rotation taking G's axes to F's after the turn (r2r_b1_b2_d_d.c too). */
static inline void sfmi_r2r_turn_compose(const double F[9], double ct, double st,
                                         const double G[9], double C[9])
{
    double Rx[9] = {1, 0, 0, 0, ct, -st, 0, st, ct}, FR[9];
    sfmi_matmul3(F, Rx, FR);
    sfmi_matmul3_nt(FR, G, C);
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

/* The rotations of the circle C a = b (sfmi_r2r_align, axis b / |b|) on
 * which y^T C x = c (sfmi_r2r_circle_solve), each appended with p by
 * sfmi_r2r_emit (n_steps). Returns 0, emitting nothing, when a or b is
 * zero; else 1. */
static inline int sfmi_r2r_circle_emit(const sfm_r2r_step *steps, int n_steps, const double a[3],
                                       const double b[3], const double x[3], const double y[3],
                                       double c, const double p[3], sfm_r2r_transform *out,
                                       int *n)
{
    double C0[9], axis[3], e1[3], e2[3], C[2][9];
    if (!sfmi_r2r_align(a, b, C0) || !sfmi_r2r_unit_frame(b, axis, e1, e2))
        return 0;
    int m = sfmi_r2r_circle_solve(C0, axis, x, y, c, C);
    for (int j = 0; j < m; j++)
        sfmi_r2r_emit(steps, n_steps, C[j], p, out, n);
    return 1;
}

/* The real roots B + sqrt(disc), B - sqrt(disc) of a quadratic into mu
 * (one when disc is 0). Exact data tangent to the sphere can round disc to
 * slightly below 0: above -1e-12 scale it counts as 0. Returns the count,
 * 0 when disc is negative or not a number. */
static inline int sfmi_r2r_quadratic_roots(double B, double disc, double scale, double mu[2])
{
    if (disc < 0.0 && disc > -1e-12 * scale)
        disc = 0.0;
    if (!(disc >= 0.0))
        return 0;
    double sq = sqrt(disc);
    mu[0] = B + sq;
    mu[1] = B - sq;
    return sq > 0.0 ? 2 : 1;
}

/* 1 when T is already in out[0..n): every entry of C and of p / scale within
 * tol of a kept solution (two close roots polished onto one answer). */
static inline int sfmi_r2r_is_duplicate(const sfm_r2r_transform *out, int n,
                                        const sfm_r2r_transform *T, double scale, double tol)
{
    for (int j = 0; j < n; j++) {
        double d = 0.0;
        for (int i = 0; i < 9; i++)
            d = sfmi_r2r_max(d, fabs(out[j].C.m[i] - T->C.m[i]));
        for (int i = 0; i < 3; i++)
            d = sfmi_r2r_max(d, fabs(out[j].p.v[i] - T->p.v[i]) / scale);
        if (d < tol)
            return 1;
    }
    return 0;
}

#endif
