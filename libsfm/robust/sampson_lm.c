/*
 * Levenberg-Marquardt on the Sampson error of an essential matrix
 * parametrised by (R, t) on SO(3) x S^2 (local rotation increment on the
 * left, translation increment in the tangent plane of t, then normalised).
 * Residual r = C / sqrt(D), C = b2^T E b1, D = |E b1|^2 + |E^T b2|^2 - 2 C^2
 * (see epipolar.h); its derivative along a direction dE of E is
 * dC / sqrt(D) - C dD / (2 D^1.5), dC = b2^T dE b1,
 * dD = 2 (E b1).(dE b1) + 2 (E^T b2).(dE^T b2) - 4 C dC.
 */
#include "robust/sampson_lm.h"

#include <math.h>
#include <string.h>

#include "core/lm.h"
#include "robust/epipolar.h"
#include "sfm/sfm_linalg.h"
#include "sfm/sfm_rotation.h"

/* The upright rotation: R <- exp([theta axis]x) R. */
static void upright_plus(const double *R, const double *d, double *out, const void *user)
{
    const double *axis = user;
    const double w[3] = {d[0] * axis[0], d[0] * axis[1], d[0] * axis[2]};
    double dR[9];
    if (sfm_rot_from_axis_angle(w, dR) != SFM_OK) {
        for (int k = 0; k < 9; k++)
            out[k] = (double)NAN;
        return;
    }
    sfmi_matmul3(dR, R, out);
}

/* The driver's tangent basis of the sphere at t, kept for the evaluation's
 * other residuals. == suffices: t values equal up to the sign of a zero give
 * the same basis bits (0 - (+-0) = +0), a NaN never matches. */
static const double *tangent_basis(const sfmi_sampson_problem *dat, const double *t)
{
    struct sfmi_sampson_basis *memo = dat->memo;
    if (!memo->valid || memo->t[0] != t[0] || memo->t[1] != t[1] || memo->t[2] != t[2]) {
        sfmi_lm_sphere_basis(t, 3, memo->B);
        memcpy(memo->t, t, sizeof memo->t);
        memo->valid = 1;
    }
    return memo->B;
}

/* Residual block j: the Sampson error of pair idx[j]; left out where D
 * vanishes (the pair at the epipoles). */
static int sampson_residual(const void *user, const double *const *x, int j, double *r, double *J)
{
    const sfmi_sampson_problem *dat = user;
    const double *R = x[0], *t = x[1];
    const double *x1 = dat->b1 + 3 * dat->idx[j], *x2 = dat->b2 + 3 * dat->idx[j];
    /* u = R b1, a = E b1 = t x u, v = b2 x t (so E^T b2 = R^T v and
     * |E^T b2| = |v|), C = u.v, D = |a|^2 + |v|^2 - 2 C^2. Under
     * u <- u + w x u: dC = w.(u x v), d|a|^2 = 2 w.(u x (a x t)).
     * Under t <- t + dt: dC = dt.(u x b2),
     * d|a|^2 + d|v|^2 = 2 dt.(u x a + v x b2). */
    double u[3], a[3], v[3];
    sfmi_matvec3(R, x1, u);
    sfmi_cross3(t, u, a);
    sfmi_cross3(x2, t, v);
    double C = sfmi_dot3(u, v);
    double D = sfmi_dot3(a, a) + sfmi_dot3(v, v) - 2.0 * C * C;
    if (!(D > 1e-300))
        return 0;
    double sD = sqrt(D);
    r[0] = C / sD;
    if (J == NULL)
        return 1;
    double gCw[3], axt[3], gDw[3], gCt[3], uxa[3], vxb[3], gDt[3];
    sfmi_cross3(u, v, gCw);
    sfmi_cross3(a, t, axt);
    sfmi_cross3(u, axt, gDw);
    sfmi_cross3(u, x2, gCt);
    sfmi_cross3(u, a, uxa);
    sfmi_cross3(v, x2, vxb);
    for (int k = 0; k < 3; k++) {
        gDw[k] = 2.0 * gDw[k] - 4.0 * C * gCw[k];
        gDt[k] = 2.0 * (uxa[k] + vxb[k]) - 4.0 * C * gCt[k];
    }
    const double ia = 1.0 / sD, ib = 0.5 * C / (D * sD);
    int nr;
    if (dat->axis) {
        J[0] = ia * sfmi_dot3(dat->axis, gCw) - ib * sfmi_dot3(dat->axis, gDw);
        nr = 1;
    } else {
        for (int k = 0; k < 3; k++)
            J[k] = ia * gCw[k] - ib * gDw[k];
        nr = 3;
    }
    if (dat->blocks[1].manifold == SFMI_LM_CONSTANT)
        return 1; /* t held: J has the rotation's columns only */
    /* t on the unit sphere, along the driver's tangent basis */
    const double *B = tangent_basis(dat, t);
    for (int c = 0; c < 2; c++) {
        const double e[3] = {B[c], B[2 + c], B[4 + c]};
        J[nr + c] = ia * sfmi_dot3(e, gCt) - ib * sfmi_dot3(e, gDt);
    }
    return 1;
}

#if SFMI_LM_HAVE_BATCH
#define LANES SFMI_LM_BATCH

/* sampson_residual of the blocks i0 .. i0 + count - 1 (the driver's batch):
 * the same operations in the same order, one lane per block in arrays, each
 * loop free of branches so that it runs two blocks per instruction (SSE2,
 * NEON). Lanes past count repeat the last block and are dropped; the square
 * root is taken lane by lane, only where D > 1e-300. */
static void sampson_batch(const void *user, const double *const *x, int i0, int count, int *ok,
                          double *r, double *J)
{
    const sfmi_sampson_problem *dat = user;
    const double *R = x[0], *t = x[1];
    double p1[3][LANES], p2[3][LANES], u[3][LANES], a[3][LANES], v[3][LANES];
    double C[LANES], D[LANES], sD[LANES], rr[LANES];
    for (int l = 0; l < LANES; l++) {
        const int i = dat->idx[i0 + (l < count ? l : count - 1)];
        for (int k = 0; k < 3; k++) {
            p1[k][l] = dat->b1[3 * i + k];
            p2[k][l] = dat->b2[3 * i + k];
        }
    }
    const double R0 = R[0], R1 = R[1], R2 = R[2], R3 = R[3], R4 = R[4], R5 = R[5];
    const double R6 = R[6], R7 = R[7], R8 = R[8], t0 = t[0], t1 = t[1], t2 = t[2];
    /* u = R b1, a = t x u, v = b2 x t, C = u.v, D = |a|^2 + |v|^2 - 2 C^2 */
    for (int l = 0; l < LANES; l++) {
        const double x0 = p1[0][l], x1 = p1[1][l], x2 = p1[2][l];
        const double y0 = p2[0][l], y1 = p2[1][l], y2 = p2[2][l];
        const double u0 = R0 * x0 + R1 * x1 + R2 * x2;
        const double u1 = R3 * x0 + R4 * x1 + R5 * x2;
        const double u2 = R6 * x0 + R7 * x1 + R8 * x2;
        const double a0 = t1 * u2 - t2 * u1, a1 = t2 * u0 - t0 * u2, a2 = t0 * u1 - t1 * u0;
        const double v0 = y1 * t2 - y2 * t1, v1 = y2 * t0 - y0 * t2, v2 = y0 * t1 - y1 * t0;
        const double c = u0 * v0 + u1 * v1 + u2 * v2;
        D[l] = (a0 * a0 + a1 * a1 + a2 * a2) + (v0 * v0 + v1 * v1 + v2 * v2) - 2.0 * c * c;
        C[l] = c;
        u[0][l] = u0;
        u[1][l] = u1;
        u[2][l] = u2;
        a[0][l] = a0;
        a[1][l] = a1;
        a[2][l] = a2;
        v[0][l] = v0;
        v[1][l] = v1;
        v[2][l] = v2;
    }
    for (int l = 0; l < LANES; l++)
        sD[l] = D[l] > 1e-300 ? sqrt(D[l]) : 1.0;
    for (int l = 0; l < LANES; l++)
        rr[l] = C[l] / sD[l];
    for (int l = 0; l < count; l++) {
        ok[l] = D[l] > 1e-300;
        r[l] = rr[l];
    }
    if (J == NULL)
        return;
    double gCw[3][LANES], gDw[3][LANES], gCt[3][LANES], gDt[3][LANES], ia[LANES], ib[LANES];
    for (int l = 0; l < LANES; l++) {
        const double u0 = u[0][l], u1 = u[1][l], u2 = u[2][l];
        const double a0 = a[0][l], a1 = a[1][l], a2 = a[2][l];
        const double v0 = v[0][l], v1 = v[1][l], v2 = v[2][l];
        const double y0 = p2[0][l], y1 = p2[1][l], y2 = p2[2][l];
        const double c4 = 4.0 * C[l];
        /* gCw = u x v, gDw = 2 u x (a x t) - 4 C gCw, gCt = u x b2,
         * gDt = 2 (u x a + v x b2) - 4 C gCt */
        const double w0 = u1 * v2 - u2 * v1, w1 = u2 * v0 - u0 * v2, w2 = u0 * v1 - u1 * v0;
        const double e0 = a1 * t2 - a2 * t1, e1 = a2 * t0 - a0 * t2, e2 = a0 * t1 - a1 * t0;
        const double d0 = u1 * e2 - u2 * e1, d1 = u2 * e0 - u0 * e2, d2 = u0 * e1 - u1 * e0;
        const double g0 = u1 * y2 - u2 * y1, g1 = u2 * y0 - u0 * y2, g2 = u0 * y1 - u1 * y0;
        const double h0 = u1 * a2 - u2 * a1, h1 = u2 * a0 - u0 * a2, h2 = u0 * a1 - u1 * a0;
        const double k0 = v1 * y2 - v2 * y1, k1 = v2 * y0 - v0 * y2, k2 = v0 * y1 - v1 * y0;
        gCw[0][l] = w0;
        gCw[1][l] = w1;
        gCw[2][l] = w2;
        gDw[0][l] = 2.0 * d0 - c4 * w0;
        gDw[1][l] = 2.0 * d1 - c4 * w1;
        gDw[2][l] = 2.0 * d2 - c4 * w2;
        gCt[0][l] = g0;
        gCt[1][l] = g1;
        gCt[2][l] = g2;
        gDt[0][l] = 2.0 * (h0 + k0) - c4 * g0;
        gDt[1][l] = 2.0 * (h1 + k1) - c4 * g1;
        gDt[2][l] = 2.0 * (h2 + k2) - c4 * g2;
        ia[l] = 1.0 / sD[l];
        ib[l] = 0.5 * C[l] / (D[l] * sD[l]);
    }
    const int free_t = dat->blocks[1].manifold != SFMI_LM_CONSTANT;
    const int nr = dat->axis ? 1 : 3;
    /* the Jacobian by columns, as the driver reads it */
    double (*jr)[LANES] = (double (*)[LANES])J;
    if (dat->axis) {
        const double x0 = dat->axis[0], x1 = dat->axis[1], x2 = dat->axis[2];
        for (int l = 0; l < LANES; l++)
            jr[0][l] = ia[l] * (x0 * gCw[0][l] + x1 * gCw[1][l] + x2 * gCw[2][l]) -
                       ib[l] * (x0 * gDw[0][l] + x1 * gDw[1][l] + x2 * gDw[2][l]);
    } else {
        for (int l = 0; l < LANES; l++) {
            jr[0][l] = ia[l] * gCw[0][l] - ib[l] * gDw[0][l];
            jr[1][l] = ia[l] * gCw[1][l] - ib[l] * gDw[1][l];
            jr[2][l] = ia[l] * gCw[2][l] - ib[l] * gDw[2][l];
        }
    }
    if (free_t) {
        const double *B = tangent_basis(dat, t);
        for (int cc = 0; cc < 2; cc++) {
            const double e0 = B[cc], e1 = B[2 + cc], e2 = B[4 + cc];
            for (int l = 0; l < LANES; l++)
                jr[nr + cc][l] = ia[l] * (e0 * gCt[0][l] + e1 * gCt[1][l] + e2 * gCt[2][l]) -
                                 ib[l] * (e0 * gDt[0][l] + e1 * gDt[1][l] + e2 * gDt[2][l]);
        }
    }
}
#endif

void sfmi_sampson_lm_problem(const double *b1, const double *b2, const int *idx, int n,
                             const double *axis, double scale, double R[9], double t[3],
                             sfmi_sampson_problem *sp)
{
    sp->b1 = b1;
    sp->b2 = b2;
    sp->axis = axis;
    sp->idx = idx;
    sp->memo = &sp->memo_store;
    sp->memo->valid = 0;
    const sfmi_lm_block rb = {R, 9, SFMI_LM_SO3, 0, NULL, NULL};
    const sfmi_lm_block ub = {R, 9, SFMI_LM_CUSTOM, 1, upright_plus, axis};
    const sfmi_lm_block tb = {t, 3, SFMI_LM_SPHERE, 0, NULL, NULL};
    sp->blocks[0] = axis ? ub : rb;
    sp->blocks[1] = tb;
    const sfmi_lm_problem prob = {sp->blocks, 2, n, 1, sampson_residual, sp,
                                  scale > 0.0 ? SFMI_LM_LOSS_CAUCHY : SFMI_LM_LOSS_SQUARED, scale,
#if SFMI_LM_HAVE_BATCH
                                  sampson_batch
#else
                                  NULL
#endif
    };
    sp->prob = prob;
}

int sfmi_robust_sampson_lm(const double *b1, const double *b2, const int *idx, int n,
                          const double *axis, double scale, int iters, double R[9], double t[3])
{
    sfmi_sampson_problem sp;
    sfmi_sampson_lm_problem(b1, b2, idx, n, axis, scale, R, t, &sp);
    double ws[SFMI_LM_DENSE_WS_DOUBLES(12, 5, 1)];
    /* iters linearisations of the previous loop, each with its rejected
     * retries: the driver counts every step tried, so twice as many (on a
     * dominant plane four steps could leave LO in the planar twin) */
    return sfmi_lm_refine(&sp.prob, 2 * iters, 1e-6, ws, sizeof ws);
}

/* Residuals and Jacobian rows of blocks j0 .. j0 + count - 1 (count <=
 * SFMI_LM_BATCH), entry c of block k at J[c * SFMI_LM_BATCH + k]: the batch
 * where there is one, else block by block (the same bits either way). */
static void rows(const sfmi_sampson_problem *sp, const double *const *x, int j0, int count, int *ok,
                 double *r, double *J)
{
#if SFMI_LM_HAVE_BATCH
    sampson_batch(sp, x, j0, count, ok, r, J);
#else
    for (int k = 0; k < count; k++) {
        double Jk[5];
        ok[k] = sampson_residual(sp, x, j0 + k, &r[k], Jk);
        for (int c = 0; c < 5; c++)
            J[c * SFMI_LM_BATCH + k] = Jk[c];
    }
#endif
}

int sfmi_sampson_prune(const double *b1, const double *b2, int *idx, int n, const double *axis,
                       const double R[9], const double t[3], double sigma2, double cut)
{
    const int p = axis ? 3 : 5;
    if (n <= p + 1 || !(sigma2 > 0.0))
        return n;
    double Rc[9], tc[3];
    memcpy(Rc, R, sizeof Rc);
    memcpy(tc, t, sizeof tc);
    sfmi_sampson_problem sp;
    sfmi_sampson_lm_problem(b1, b2, idx, n, axis, 0.0, Rc, tc, &sp);
    const double *const x[2] = {Rc, tc};
    double M[25] = {0}, J[5 * SFMI_LM_BATCH], r[SFMI_LM_BATCH];
    int ok[SFMI_LM_BATCH], kept = 0;
    /* pass 0: M = J^T J over the pairs; pass 1: Cook's distance
     * r^2 h / (p sigma^2 (1 - h)^2) of each pair, h its leverage
     * J^T M^-1 J = |L^-1 J|^2 (M = L L^T) */
    const double bound = cut * (double)p * sigma2;
    for (int pass = 0; pass < 2; pass++) {
        if (pass == 1 && sfm_cholesky_factor(M, p) != SFM_OK)
            return n;
        for (int j0 = 0; j0 < n; j0 += SFMI_LM_BATCH) {
            const int cnt = n - j0 < SFMI_LM_BATCH ? n - j0 : SFMI_LM_BATCH;
            int own[SFMI_LM_BATCH];
            memcpy(own, idx + j0, sizeof(int) * (size_t)cnt); /* kept <= j0: written below */
            rows(&sp, x, j0, cnt, ok, r, J);
            for (int k = 0; k < cnt; k++) {
                const double *Jk = J + k;
                if (pass == 0) {
                    for (int a = 0; ok[k] && a < p; a++)
                        for (int b = 0; b <= a; b++)
                            M[a * p + b] += Jk[a * SFMI_LM_BATCH] * Jk[b * SFMI_LM_BATCH];
                    continue;
                }
                double h = 0.0, y[5];
                for (int a = 0; ok[k] && a < p; a++) {
                    double s = Jk[a * SFMI_LM_BATCH];
                    for (int b = 0; b < a; b++)
                        s -= M[a * p + b] * y[b];
                    y[a] = s / M[a * p + a];
                    h += y[a] * y[a];
                }
                const double q = 1.0 - h;
                if (ok[k] && q > 0.0 && !(r[k] * r[k] * h < bound * q * q))
                    continue;
                idx[kept++] = own[k];
            }
        }
    }
    return kept;
}
