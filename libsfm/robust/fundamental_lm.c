/*
 * Levenberg-Marquardt on the Sampson error of a fundamental matrix in the
 * orthonormal representation of Bartoli & Sturm ("Nonlinear estimation of
 * the fundamental matrix with minimal parameters", PAMI 2004): in Hartley-
 * normalised coordinates (x_n = T1 x, y_n = T2 y; Hartley 1997)
 *   F_n = U diag(cos th, sin th, 0) V^T,  U, V in SO(3),
 * updated as U <- U exp([a]x), V <- V exp([b]x), th <- th + dth: 7 degrees of
 * freedom, rank 2 and the scale fixed by construction, and
 * F = T2^T F_n T1 in pixels.
 *
 * The residual is the Sampson error in pixels (Hartley & Zisserman 11.4.3),
 * r = C / sqrt(D), C = y^T F x, D = |(F x)_12|^2 + |(F^T y)_12|^2. With
 * T = [s 0 a; 0 s b; 0 0 1], (F x)_12 = s2 (F_n x_n)_12 and
 * (F^T y)_12 = s1 (F_n^T y_n)_12, so both are evaluated in normalised
 * coordinates. Along a direction M of F_n: dC = y_n^T M x_n,
 * dD = 2 s2^2 (F_n x_n)_12 . (M x_n)_12 + 2 s1^2 (F_n^T y_n)_12 . (M^T y_n)_12,
 * dr = dC / sqrt(D) - C dD / (2 D^1.5).
 */
#include "robust/fundamental_lm.h"

#include <math.h>
#include <string.h>

#include "robust/epipolar.h"
#include "robust/lm_small.h"
#include "sfm/sfm_rotation.h"
#include "solvers/linear9.h"
#include "solvers/normalize.h"
#include "core/dmath.h"

#define NP 7

typedef struct fnorm {
    double t1[3], t2[3]; /* Hartley normalisations (s, -s cx, -s cy) */
} fnorm;

/* F_n = U diag(c, s, 0) V^T. */
static void compose(const double *U, const double *V, double th, double *Fn)
{
    double c = sfmi_cos(th), s = sfmi_sin(th);
    for (int r = 0; r < 3; r++)
        for (int k = 0; k < 3; k++)
            Fn[3 * r + k] = c * U[3 * r] * V[3 * k] + s * U[3 * r + 1] * V[3 * k + 1];
}

/* Pixel Sampson residual of point i under F_n; 0 with *ok = 0 when D
 * vanishes. Writes l = (F_n x_n), m = (F_n^T y_n), x_n and y_n. */
static double resid(const fnorm *N, const double *Fn, const double *p, const double *q, double *xn,
                    double *yn, double *l, double *m, double *C, double *D, int *ok)
{
    xn[0] = N->t1[0] * p[0] + N->t1[1];
    xn[1] = N->t1[0] * p[1] + N->t1[2];
    xn[2] = 1.0;
    yn[0] = N->t2[0] * q[0] + N->t2[1];
    yn[1] = N->t2[0] * q[1] + N->t2[2];
    yn[2] = 1.0;
    sfm_matvec3(Fn, xn, l);
    m[0] = Fn[0] * yn[0] + Fn[3] * yn[1] + Fn[6];
    m[1] = Fn[1] * yn[0] + Fn[4] * yn[1] + Fn[7];
    m[2] = Fn[2] * yn[0] + Fn[5] * yn[1] + Fn[8];
    const double s1 = N->t1[0] * N->t1[0], s2 = N->t2[0] * N->t2[0];
    *C = sfm_dot3(yn, l);
    *D = s2 * (l[0] * l[0] + l[1] * l[1]) + s1 * (m[0] * m[0] + m[1] * m[1]);
    *ok = *D > 1e-300;
    return *ok ? *C / sqrt(*D) : 0.0;
}

static double cost_n(const fnorm *N, const double *p1, const double *p2, int n, double s2,
                     const double *Fn)
{
    double c = 0.0;
    for (int i = 0; i < n; i++) {
        double xn[3], yn[3], l[3], m[3], C, D;
        int ok;
        double r = resid(N, Fn, p1 + 2 * i, p2 + 2 * i, xn, yn, l, m, &C, &D, &ok);
        if (ok)
            c += sfm_lm_cauchy_loss(r * r, s2);
    }
    return c;
}

double sfm_robust_fundamental_cost(const double *p1, const double *p2, int n, double scale,
                                   const double F[9])
{
    const double s2 = scale > 0.0 ? scale * scale : 0.0;
    double c = 0.0;
    for (int i = 0; i < n; i++) {
        double r2 = sfm_sampson_pixel2(F, p1 + 2 * i, p2 + 2 * i);
        if (r2 < SFM_ROBUST_HUGE)
            c += sfm_lm_cauchy_loss(r2, s2);
    }
    return c;
}

/* Inverse of a normalisation stored as (s, a, b): (1/s, -a/s, -b/s). */
static void inv_norm(const double *t, double *ti)
{
    ti[0] = 1.0 / t[0];
    ti[1] = -t[1] / t[0];
    ti[2] = -t[2] / t[0];
}

/* B = T2a^T A T1a for normalisations stored as (s, a, b). */
static void congruence(const double *t2, const double *A, const double *t1, double *B)
{
    double T1[9], T2[9], T2t[9], tmp[9];
    sfm__hartley_matrix(t1, T1);
    sfm__hartley_matrix(t2, T2);
    for (int r = 0; r < 3; r++)
        for (int k = 0; k < 3; k++)
            T2t[3 * r + k] = T2[3 * k + r];
    sfm_matmul3(T2t, A, tmp);
    sfm_matmul3(tmp, T1, B);
}

static double det3(const double *a)
{
    return a[0] * (a[4] * a[8] - a[5] * a[7]) - a[1] * (a[3] * a[8] - a[5] * a[6]) +
           a[2] * (a[3] * a[7] - a[4] * a[6]);
}

int sfm_robust_fundamental_lm(const double *p1, const double *p2, int n, double scale, int iters,
                              double F[9])
{
    fnorm N;
    if (n < NP || sfm__hartley_2d(p1, n, N.t1) < 0 || sfm__hartley_2d(p2, n, N.t2) < 0)
        return -1;
    const double s2 = scale > 0.0 ? scale * scale : 0.0;
    const double q1 = N.t1[0] * N.t1[0], q2 = N.t2[0] * N.t2[0];
    /* F_n = T2^-T F T1^-1, then its SVD with U, V rotations (the third
     * singular vectors carry no weight, so their signs are free) */
    double ti1[3], ti2[3], Fn[9], U[9], S[3], V[9];
    inv_norm(N.t1, ti1);
    inv_norm(N.t2, ti2);
    congruence(ti2, F, ti1, Fn);
    if (sfm__svd3(Fn, U, S, V) != 0 || !(S[0] > 0.0))
        return -1;
    if (det3(U) < 0.0)
        for (int r = 0; r < 3; r++)
            U[3 * r + 2] = -U[3 * r + 2];
    if (det3(V) < 0.0)
        for (int r = 0; r < 3; r++)
            V[3 * r + 2] = -V[3 * r + 2];
    double th = sfmi_atan2(S[1], S[0]);
    compose(U, V, th, Fn);
    double cur = cost_n(&N, p1, p2, n, s2, Fn);
    double lambda = 1e-4;
    int improved = 0;
    for (int it = 0; it < iters; it++) {
        /* directions of F_n: U [e_k]x Sg V^T, -U Sg [e_k]x V^T, U dSg V^T */
        double dF[NP][9];
        double c = sfmi_cos(th), s = sfmi_sin(th);
        for (int k = 0; k < 3; k++) {
            double e[3] = {0.0, 0.0, 0.0}, K[9], A[9], B[9], Vt[9];
            e[k] = 1.0;
            sfm_skew(e, K);
            for (int r = 0; r < 3; r++)
                for (int j = 0; j < 3; j++)
                    Vt[3 * r + j] = V[3 * j + r];
            /* U K Sg V^T: scale K's columns by (c, s, 0) */
            for (int r = 0; r < 3; r++) {
                A[3 * r] = K[3 * r] * c;
                A[3 * r + 1] = K[3 * r + 1] * s;
                A[3 * r + 2] = 0.0;
            }
            sfm_matmul3(U, A, B);
            sfm_matmul3(B, Vt, dF[k]);
            /* -U Sg K V^T: scale K's rows by (c, s, 0) */
            for (int j = 0; j < 3; j++) {
                A[j] = -K[j] * c;
                A[3 + j] = -K[3 + j] * s;
                A[6 + j] = 0.0;
            }
            sfm_matmul3(U, A, B);
            sfm_matmul3(B, Vt, dF[3 + k]);
        }
        for (int r = 0; r < 3; r++)
            for (int k = 0; k < 3; k++)
                dF[6][3 * r + k] = -s * U[3 * r] * V[3 * k] + c * U[3 * r + 1] * V[3 * k + 1];

        double JtJ[NP * NP], g[NP];
        memset(JtJ, 0, sizeof JtJ);
        memset(g, 0, sizeof g);
        for (int i = 0; i < n; i++) {
            double xn[3], yn[3], l[3], m[3], C, D;
            int ok;
            double r = resid(&N, Fn, p1 + 2 * i, p2 + 2 * i, xn, yn, l, m, &C, &D, &ok);
            if (!ok)
                continue;
            double sD = sqrt(D), J[NP], w;
            w = sfm_lm_cauchy_weight(r * r, s2);
            for (int p = 0; p < NP; p++) {
                const double *M = dF[p];
                double Mx[3], Mty0, Mty1;
                sfm_matvec3(M, xn, Mx);
                Mty0 = M[0] * yn[0] + M[3] * yn[1] + M[6];
                Mty1 = M[1] * yn[0] + M[4] * yn[1] + M[7];
                double dC = sfm_dot3(yn, Mx);
                double dD = 2.0 * q2 * (l[0] * Mx[0] + l[1] * Mx[1]) +
                            2.0 * q1 * (m[0] * Mty0 + m[1] * Mty1);
                J[p] = dC / sD - 0.5 * C * dD / (D * sD);
            }
            for (int p = 0; p < NP; p++) {
                g[p] += w * J[p] * r;
                for (int q = 0; q <= p; q++)
                    JtJ[p * NP + q] += w * J[p] * J[q];
            }
        }
        int accepted = 0;
        for (int tries = 0; tries < 6 && !accepted; tries++) {
            double x[NP], Ra[9], Rb[9], Un[9], Vn[9], Fnn[9];
            if (sfm_lm_small_step(JtJ, g, NP, lambda, x) < 0) {
                lambda *= 10.0;
                continue;
            }
            if (sfm_rot_from_axis_angle(x, Ra) != SFM_OK ||
                sfm_rot_from_axis_angle(x + 3, Rb) != SFM_OK)
                return -1;
            sfm_matmul3(U, Ra, Un);
            sfm_matmul3(V, Rb, Vn);
            double thn = th + x[6];
            compose(Un, Vn, thn, Fnn);
            double cn = cost_n(&N, p1, p2, n, s2, Fnn);
            if (cn < cur) {
                double rel = (cur - cn) / (cur > 0.0 ? cur : 1.0);
                memcpy(U, Un, sizeof Un);
                memcpy(V, Vn, sizeof Vn);
                memcpy(Fn, Fnn, sizeof Fnn);
                th = thn;
                cur = cn;
                accepted = 1;
                improved = 1;
                lambda = sfm_lm_small_relax(lambda);
                if (rel < 1e-6)
                    it = iters;
            } else {
                lambda *= 10.0;
            }
        }
        if (!accepted)
            break;
    }
    if (!improved)
        return 1;
    double Fp[9];
    congruence(N.t2, Fn, N.t1, Fp);
    if (sfm__normalize9(Fp) != 0)
        return -1;
    memcpy(F, Fp, sizeof Fp);
    return 0;
}
