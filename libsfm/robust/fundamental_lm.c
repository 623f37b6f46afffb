/*
 * Levenberg-Marquardt on the Sampson error of a fundamental matrix in the
 * orthonormal representation of Bartoli & Sturm ("Nonlinear estimation of
 * the fundamental matrix with minimal parameters", PAMI 2004): in Hartley-
 * normalised coordinates (x_n = T1 x, y_n = T2 y; Hartley 1997)
 *   F_n = U diag(c, s, 0) V^T,  U, V in SO(3), (c, s) on the unit circle,
 * updated as U <- U exp([a]x), V <- V exp([b]x) and (c, s) along its
 * tangent (the paper's angle th = atan2(s, c), without its trigonometry): 7
 * degrees of freedom, rank 2 and the scale fixed by construction, and
 * F = T2^T F_n T1 in pixels.
 *
 * The residual is the Sampson error in pixels (Hartley & Zisserman 11.4.3),
 * r = C / sqrt(D), C = y^T F x, D = |(F x)_12|^2 + |(F^T y)_12|^2. With
 * T = [s 0 a; 0 s b; 0 0 1], (F x)_12 = s2 (F_n x_n)_12 and
 * (F^T y)_12 = s1 (F_n^T y_n)_12, so both are evaluated in normalised
 * coordinates. Along a direction M of F_n: dC = y_n^T M x_n,
 * dD = 2 s2^2 (F_n x_n)_12 . (M x_n)_12 + 2 s1^2 (F_n^T y_n)_12 . (M^T y_n)_12,
 * dr = dC / sqrt(D) - C dD / (2 D^1.5). With z = V^T x_n, p = U^T y_n,
 * S = diag(c, s, 0), the seven directions act on a point through 3-vectors:
 *   a_k: M x_n = -U [S z]x e_k, M^T y_n = V S [p]x e_k, dC = e_k.((S z) x p);
 *   b_k: M x_n = U S [z]x e_k, M^T y_n = -V [S p]x e_k, dC = -e_k.(z x S p);
 *   (c, s) along (dc, ds): M x_n = U dS z, M^T y_n = V dS p, dC = p.dS z.
 */
#include "robust/fundamental_lm.h"

#include <math.h>
#include <string.h>

#include "core/lm.h"
#include "robust/epipolar.h"
#include "robust/estimator.h"
#include "sfm/sfm_rotation.h"
#include "solvers/linear9.h"
#include "solvers/normalize.h"

#define NP 7

typedef sfmi_fundamental_problem fnorm;

/* F_n = U diag(c, s, 0) V^T. */
static void compose(const double *U, const double *V, const double *cs, double *Fn)
{
    for (int r = 0; r < 3; r++)
        for (int k = 0; k < 3; k++)
            Fn[3 * r + k] = cs[0] * U[3 * r] * V[3 * k] + cs[1] * U[3 * r + 1] * V[3 * k + 1];
}

/* dr along the F_n direction with M x_n = Mx, M^T y_n = Mty and y_n^T M x_n = dC. */
static double dres(const double *l, const double *m, double q1, double q2, double C, double D,
                   double sD, const double *Mx, const double *Mty, double dC)
{
    const double dD = 2.0 * q2 * (l[0] * Mx[0] + l[1] * Mx[1]) + 2.0 * q1 * (m[0] * Mty[0] + m[1] * Mty[1]);
    return dC / sD - 0.5 * C * dD / (D * sD);
}

/* Residual block i: the pixel Sampson error of pair i; left out where D
 * vanishes. Blocks: U, V (rotations), (c, s). */
static int fundamental_residual(const void *user, const double *const *x, int i, double *r,
                                double *J)
{
    const fnorm *N = user;
    const double *U = x[0], *V = x[1], *cs = x[2];
    const double *pp = N->p1 + 2 * i, *qq = N->p2 + 2 * i;
    const double xn[3] = {N->t1[0] * pp[0] + N->t1[1], N->t1[0] * pp[1] + N->t1[2], 1.0};
    const double yn[3] = {N->t2[0] * qq[0] + N->t2[1], N->t2[0] * qq[1] + N->t2[2], 1.0};
    double z[3], p[3], Sz[3], Sp[3], l[3], m[3];
    sfmi_matvec3_t(V, xn, z);
    sfmi_matvec3_t(U, yn, p);
    Sz[0] = cs[0] * z[0];
    Sz[1] = cs[1] * z[1];
    Sz[2] = 0.0;
    Sp[0] = cs[0] * p[0];
    Sp[1] = cs[1] * p[1];
    Sp[2] = 0.0;
    sfmi_matvec3(U, Sz, l); /* F_n x_n */
    sfmi_matvec3(V, Sp, m); /* F_n^T y_n */
    const double q1 = N->t1[0] * N->t1[0], q2 = N->t2[0] * N->t2[0];
    const double C = p[0] * Sz[0] + p[1] * Sz[1];
    const double D = q2 * (l[0] * l[0] + l[1] * l[1]) + q1 * (m[0] * m[0] + m[1] * m[1]);
    if (!(D > 1e-300))
        return 0;
    const double sD = sqrt(D);
    r[0] = C / sD;
    if (J == NULL)
        return 1;
    double Szxp[3], zxSp[3];
    sfmi_cross3(Sz, p, Szxp);
    sfmi_cross3(z, Sp, zxSp);
    for (int k = 0; k < 3; k++) {
        double e[3] = {0.0, 0.0, 0.0}, ez[3], ep[3], Mx[3], Mty[3], w[3];
        e[k] = 1.0;
        /* a_k: -U (S z x e_k) = U (e_k x S z); V S (p x e_k) */
        sfmi_cross3(e, Sz, ez);
        sfmi_matvec3(U, ez, Mx);
        sfmi_cross3(p, e, ep);
        w[0] = cs[0] * ep[0];
        w[1] = cs[1] * ep[1];
        w[2] = 0.0;
        sfmi_matvec3(V, w, Mty);
        J[k] = dres(l, m, q1, q2, C, D, sD, Mx, Mty, Szxp[k]);
        /* b_k: U S (z x e_k); -V (S p x e_k) = V (e_k x S p) */
        sfmi_cross3(z, e, ez);
        w[0] = cs[0] * ez[0];
        w[1] = cs[1] * ez[1];
        w[2] = 0.0;
        sfmi_matvec3(U, w, Mx);
        sfmi_cross3(e, Sp, ep);
        sfmi_matvec3(V, ep, Mty);
        J[3 + k] = dres(l, m, q1, q2, C, D, sD, Mx, Mty, -zxSp[k]);
    }
    double B[2], dz[3], dp[3], Mx[3], Mty[3];
    sfmi_lm_sphere_basis(cs, 2, B);
    dz[0] = B[0] * z[0];
    dz[1] = B[1] * z[1];
    dz[2] = 0.0;
    dp[0] = B[0] * p[0];
    dp[1] = B[1] * p[1];
    dp[2] = 0.0;
    sfmi_matvec3(U, dz, Mx);
    sfmi_matvec3(V, dp, Mty);
    J[6] = dres(l, m, q1, q2, C, D, sD, Mx, Mty, p[0] * dz[0] + p[1] * dz[1]);
    return 1;
}

double sfmi_robust_fundamental_cost(const double *p1, const double *p2, int n, double scale,
                                   const double F[9])
{
    return sfmi_robust_pair_cost(p1, p2, n, scale, F, sfmi_sampson_pixel2);
}

/* B = T2a^T A T1a for normalisations stored as (s, a, b). */
static void congruence(const double *t2, const double *A, const double *t1, double *B)
{
    double T1[9], T2[9], T2t[9], tmp[9];
    sfmi_hartley_matrix(t1, T1);
    sfmi_hartley_matrix(t2, T2);
    for (int r = 0; r < 3; r++)
        for (int k = 0; k < 3; k++)
            T2t[3 * r + k] = T2[3 * k + r];
    sfmi_matmul3(T2t, A, tmp);
    sfmi_matmul3(tmp, T1, B);
}

static double det3(const double *a)
{
    return a[0] * (a[4] * a[8] - a[5] * a[7]) - a[1] * (a[3] * a[8] - a[5] * a[6]) +
           a[2] * (a[3] * a[7] - a[4] * a[6]);
}

int sfmi_fundamental_lm_problem(const double *p1, const double *p2, int n, double scale,
                                const double F[9], sfmi_fundamental_problem *N)
{
    if (n < NP || sfmi_hartley_2d(p1, n, N->t1) < 0 || sfmi_hartley_2d(p2, n, N->t2) < 0)
        return -1;
    N->p1 = p1;
    N->p2 = p2;
    /* F_n = T2^-T F T1^-1, then its SVD with U, V rotations (the third
     * singular vectors carry no weight, so their signs are free) */
    double ti1[3], ti2[3], Fn[9], S[3];
    double *U = N->U, *V = N->V;
    sfmi_hartley_inverse(N->t1, ti1);
    sfmi_hartley_inverse(N->t2, ti2);
    congruence(ti2, F, ti1, Fn);
    if (sfmi_svd3(Fn, U, S, V) != 0 || !(S[0] > 0.0))
        return -1;
    if (det3(U) < 0.0)
        for (int r = 0; r < 3; r++)
            U[3 * r + 2] = -U[3 * r + 2];
    if (det3(V) < 0.0)
        for (int r = 0; r < 3; r++)
            V[3 * r + 2] = -V[3 * r + 2];
    const double sn = sqrt(S[0] * S[0] + S[1] * S[1]);
    N->cs[0] = S[0] / sn;
    N->cs[1] = S[1] / sn;
    const sfmi_lm_block blocks[3] = {{U, 9, SFMI_LM_SO3_RIGHT, 0, NULL, NULL},
                                     {V, 9, SFMI_LM_SO3_RIGHT, 0, NULL, NULL},
                                     {N->cs, 2, SFMI_LM_SPHERE, 0, NULL, NULL}};
    memcpy(N->blocks, blocks, sizeof blocks);
    const sfmi_lm_problem prob = {N->blocks, 3, n, 1, fundamental_residual, N,
                                  scale > 0.0 ? SFMI_LM_LOSS_CAUCHY : SFMI_LM_LOSS_SQUARED, scale, NULL};
    N->prob = prob;
    return 0;
}

int sfmi_robust_fundamental_lm(const double *p1, const double *p2, int n, double scale, int iters,
                              double F[9])
{
    fnorm N;
    if (sfmi_fundamental_lm_problem(p1, p2, n, scale, F, &N) < 0)
        return -1;
    double ws[SFMI_LM_DENSE_WS_DOUBLES(20, NP, 1)];
    int st = sfmi_lm_refine(&N.prob, iters, 1e-6, ws, sizeof ws);
    if (st != 0)
        return st;
    double Fn[9], Fp[9];
    compose(N.U, N.V, N.cs, Fn);
    congruence(N.t2, Fn, N.t1, Fp);
    if (sfmi_normalize9(Fp) != 0)
        return -1;
    memcpy(F, Fp, sizeof Fp);
    return 0;
}
