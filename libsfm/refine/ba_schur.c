/*
 * Bundle adjustment: the Levenberg-Marquardt system (core/lm.h) over the
 * layout of ba_layout.c.
 *
 * Normal equations of the (robustly reweighted) Gauss-Newton model, with the
 * driver's damping D = mu diag(clamp(diag JtJ, 1e-6, 1e32)):
 *
 *     [ U + Dc    W      ] [dc]   [gc]
 *     [ W^T       V + Dp ] [dp] = [gp]     (gc, gp = -J^T r)
 *
 * V is block diagonal (3x3 per point). With V_j + Dp_j = L_j L_j^T and
 * F_k = W_k L_j^{-T} for each observation k of point j, the reduced camera
 * system is S = U + Dc - sum_j F_j F_j^T (dense, small), solved by Cholesky;
 * then dp_j = L_j^{-T} (L_j^{-1} gp_j - F_j^T dc) (Triggs et al., "Bundle
 * Adjustment: A Modern Synthesis", 2000, section 6.1).
 *
 * Robust losses use the first-order reweighting sqrt(rho') on residual and
 * Jacobian (the gradient is exact; for rho'' <= 0, as for Huber and Cauchy,
 * this is also what Ceres' corrector does).
 *
 * Projection through the core's camera models (sfm_camera: pinhole,
 * Brown-Conrady, Kannala-Brandt), with the derivatives in the intrinsics:
 * px = (fx xd + cx, fy yd + cy), (xd, yd) the distorted normalised point;
 * Brown (x, y = X/Z, r2 = x^2 + y^2): d(xd, yd)/dk1 = r2 (x, y),
 * /dk2 = r2^2 (x, y), /dk3 = r2^3 (x, y), /dp1 = (2 x y, r2 + 2 y^2),
 * /dp2 = (r2 + 2 x^2, 2 x y); Kannala-Brandt (theta the angle to the axis,
 * rho = |(X0, X1)|): d(xd, yd)/dk_i = theta^(2i+1) / rho (X0, X1).
 */
#include <math.h>
#include <string.h>

#include "core/camera_internal.h"
#include "core/dmath.h"
#include "core/linalg_util.h"
#include "core/lm.h"
#include "refine/ba_internal.h"
#include "sfm/sfm_linalg.h"
#include "sfm/sfm_rotation.h"
#include "solvers/small_math.h"

#define NLOC SFMI_BA_NLOC

/* theta / rho for Kannala-Brandt, rho = |(X0, X1)| > 0 or on the axis
 * (z > 0): theta / rho = (1/z)(1 - q^2/3 + q^4/5 - ...), q = rho / z. */
static double fisheye_theta_over_rho(const double *X, double *theta)
{
    const double rho = sfmi_hypot(X[0], X[1]), z = X[2];
    const double th = sfmi_atan2(rho, z);
    *theta = th;
    if (z > 0.0 && rho < 1e-4 * z) {
        const double q2 = (rho / z) * (rho / z);
        return (1.0 - q2 / 3.0 + q2 * q2 / 5.0) / z;
    }
    return th / rho;
}

/* d(xd, yd)/d(dist) of the model at the camera-frame point Xc: dd[e] and
 * dd[SFMI_BA_NDIST + e] for coefficient e. */
static void distortion_jacobian(const sfm_camera *cam, const double *Xc, double *dd)
{
    if (cam->model == SFM_CAMERA_FISHEYE) {
        double th;
        const double tr = fisheye_theta_over_rho(Xc, &th);
        const double t2 = th * th;
        double p = tr * t2; /* theta^3 / rho */
        dd[4] = dd[SFMI_BA_NDIST + 4] = 0.0; /* no fifth coefficient */
        for (int e = 0; e < 4; e++) {
            dd[e] = p * Xc[0];
            dd[SFMI_BA_NDIST + e] = p * Xc[1];
            p *= t2;
        }
        return;
    }
    const double x = Xc[0] / Xc[2], y = Xc[1] / Xc[2], r2 = x * x + y * y;
    dd[0] = x * r2;
    dd[1] = x * r2 * r2;
    dd[2] = 2.0 * x * y;
    dd[3] = r2 + 2.0 * x * x;
    dd[4] = x * r2 * r2 * r2;
    dd[SFMI_BA_NDIST + 0] = y * r2;
    dd[SFMI_BA_NDIST + 1] = y * r2 * r2;
    dd[SFMI_BA_NDIST + 2] = r2 + 2.0 * y * y;
    dd[SFMI_BA_NDIST + 3] = 2.0 * x * y;
    dd[SFMI_BA_NDIST + 4] = y * r2 * r2 * r2;
}

/* Distorted normalised point of Xc and D = d(xd)/d(Xc) (2x3, when D is not
 * NULL) by the camera's model. A pinhole camera, or a Brown one whose
 * coefficients are all zero (the common case of an undistorted feed), is
 * the plain perspective division, written here to keep the per-observation
 * path free of a call; it gives the same bits as the Brown evaluation with
 * zero coefficients. Returns 0 when the point cannot be projected. */
static inline int distorted_point(const sfm_camera *cam, const double *Xc, double xd[2], double *D)
{
    const double *k = cam->dist;
    const int plain = cam->model == SFM_CAMERA_PINHOLE ||
                      (cam->model == SFM_CAMERA_BROWN && k[0] == 0.0 && k[1] == 0.0 && k[2] == 0.0 &&
                       k[3] == 0.0 && k[4] == 0.0);
    if (plain) {
        if (!(Xc[2] > 0.0))
            return 0;
        const double iz = 1.0 / Xc[2];
        const double x = Xc[0] / Xc[2], y = Xc[1] / Xc[2];
        xd[0] = x;
        xd[1] = y;
        if (D) {
            D[0] = iz;
            D[1] = 0.0;
            D[2] = -x * iz;
            D[3] = 0.0;
            D[4] = iz;
            D[5] = -y * iz;
        }
        return 1;
    }
    int st = cam->model == SFM_CAMERA_FISHEYE ? sfmi_cam_fisheye_project(k, Xc, xd, D)
                                              : sfmi_cam_brown_project(k, Xc, xd, D);
    return st >= 0;
}

/* The projection and its Jacobians; the intrinsics columns only when
 * with_intrinsics (a solve that holds them never reads them). */
static inline int project(const sfm_camera *cam, double aspect, const double *R, const double *t,
                          const double *X, double uv[2], double *J, double *Jp, int with_intrinsics)
{
    const double a0 = R[0] * X[0] + R[1] * X[1] + R[2] * X[2];
    const double a1 = R[3] * X[0] + R[4] * X[1] + R[5] * X[2];
    const double a2 = R[6] * X[0] + R[7] * X[1] + R[8] * X[2];
    const double Xc[3] = {a0 + t[0], a1 + t[1], a2 + t[2]};
    double xd[2], D[6];
    const int want = J != NULL || Jp != NULL;
    if (!distorted_point(cam, Xc, xd, want ? D : NULL))
        return 0;
    const double fx = cam->fx, fy = cam->fy;
    uv[0] = fx * xd[0] + cam->cx;
    uv[1] = fy * xd[1] + cam->cy;
    if (!want)
        return 1;
    /* P = d(px)/d(Xc) */
    const double P00 = fx * D[0], P01 = fx * D[1], P02 = fx * D[2];
    const double P10 = fy * D[3], P11 = fy * D[4], P12 = fy * D[5];
    if (J != NULL) {
        double *j0 = J, *j1 = J + NLOC;
        /* d x_cam / d w = -[R X]_x */
        j0[0] = -P01 * a2 + P02 * a1;
        j0[1] = P00 * a2 - P02 * a0;
        j0[2] = -P00 * a1 + P01 * a0;
        j1[0] = -P11 * a2 + P12 * a1;
        j1[1] = P10 * a2 - P12 * a0;
        j1[2] = -P10 * a1 + P11 * a0;
        j0[3] = P00; j0[4] = P01; j0[5] = P02;
        j1[3] = P10; j1[4] = P11; j1[5] = P12;
        if (with_intrinsics) {
            j0[6] = xd[0];           j1[6] = aspect * xd[1];
            j0[7] = 1.0;             j1[7] = 0.0;
            j0[8] = 0.0;             j1[8] = 1.0;
            if (cam->model != SFM_CAMERA_PINHOLE) {
                double dd[2 * SFMI_BA_NDIST];
                distortion_jacobian(cam, Xc, dd);
                for (int e = 0; e < SFMI_BA_NDIST; e++) {
                    j0[9 + e] = fx * dd[e];
                    j1[9 + e] = fy * dd[SFMI_BA_NDIST + e];
                }
            } else {
                for (int e = 0; e < SFMI_BA_NDIST; e++)
                    j0[9 + e] = j1[9 + e] = 0.0;
            }
        }
    }
    if (Jp != NULL) {
        Jp[0] = P00 * R[0] + P01 * R[3] + P02 * R[6];
        Jp[1] = P00 * R[1] + P01 * R[4] + P02 * R[7];
        Jp[2] = P00 * R[2] + P01 * R[5] + P02 * R[8];
        Jp[3] = P10 * R[0] + P11 * R[3] + P12 * R[6];
        Jp[4] = P10 * R[1] + P11 * R[4] + P12 * R[7];
        Jp[5] = P10 * R[2] + P11 * R[5] + P12 * R[8];
    }
    return 1;
}

int sfmi_ba_project(const sfm_camera *cam, double aspect, const double *R, const double *t,
                    const double *X, double uv[2], double *J, double *Jp)
{
    return project(cam, aspect, R, t, X, uv, J, Jp, 1);
}

/* rho(s) and the IRLS weight rho'(s): the squared loss inline. */
static inline void loss(const sfmi_ba_ctx *c, double s, double *rho, double *rho1)
{
    if (c->o->loss == SFM_BA_LOSS_SQUARED) {
        *rho = s;
        *rho1 = 1.0;
        return;
    }
    sfmi_lm_loss_eval((sfmi_lm_loss)c->o->loss, c->a2, s, rho, rho1);
}

/* Observation k's residual (r = projection - observed) at the estimate
 * (R, t, K, X), with J and Jp as project(); its weight and loss terms.
 * Returns 0 when its camera cannot project the point. */
static inline int observation(const sfmi_ba_ctx *c, int k, const double *R, const double *t,
                              const sfm_camera *K, const double *X, double *J, double *Jp,
                              double r[2], double *wgt, double *rho, double *rho1)
{
    const sfm_ba_problem *p = c->p;
    const int ci = p->obs_camera[k], pj = p->obs_point[k];
    double uv[2];
    if (!project(K + ci, c->w.aspect[ci], R + 9 * ci, t + 3 * ci, X + 3 * pj, uv, J, Jp, c->nic > 0))
        return 0;
    r[0] = uv[0] - p->obs_xy[2 * k];
    r[1] = uv[1] - p->obs_xy[2 * k + 1];
    *wgt = p->obs_weight ? p->obs_weight[k] : 1.0;
    loss(c, *wgt * (r[0] * r[0] + r[1] * r[1]), rho, rho1);
    return 1;
}

/* Cost at (R, t, K, X); +Inf when a camera cannot project a point it sees
 * or the sum is not finite. */
static double eval_cost(const sfmi_ba_ctx *c, const double *R, const double *t, const sfm_camera *K,
                        const double *X)
{
    double cost = 0.0;
    for (int k = 0; k < c->nobs; k++) {
        double r[2], wgt, rho, rho1;
        if (!observation(c, k, R, t, K, X, NULL, NULL, r, &wgt, &rho, &rho1))
            return HUGE_VAL;
        cost += rho;
    }
    cost *= 0.5;
    return isfinite(cost) ? cost : HUGE_VAL;
}

/* Residuals, Jacobians, U, gc (= -J^T r), V, gp at the current estimate;
 * the cost (+Inf when not finite) and max |gradient|. U holds only its
 * lower triangle. */
double sfmi_ba_linearize(void *self, double *grad_max)
{
    sfmi_ba_ctx *c = self;
    const sfm_ba_problem *p = c->p;
    sfmi_ba_ws *w = &c->w;
    int nc = c->nc, qmax = c->qmax;
    double cost = 0.0;
    if (nc > 0) {
        memset(w->U, 0, sizeof(double) * (size_t)nc * (size_t)nc);
        memset(w->gc, 0, sizeof(double) * (size_t)nc);
    }
    memset(w->V, 0, sizeof(double) * 9 * (size_t)c->n);
    memset(w->gp, 0, sizeof(double) * 3 * (size_t)c->n);
    for (int k = 0; k < c->nobs; k++) {
        const int ci = p->obs_camera[k], pj = p->obs_point[k];
        double r[2], wgt, rho, rho1, J[2 * NLOC], *Jp = w->Jp + 6 * (size_t)k;
        if (!observation(c, k, w->R, w->t, w->K, w->X, J, Jp, r, &wgt, &rho, &rho1))
            return HUGE_VAL;
        double rx = r[0], ry = r[1];
        cost += rho;
        double sc = sqrt(wgt * rho1);
        rx *= sc;
        ry *= sc;
        w->res[2 * k] = rx;
        w->res[2 * k + 1] = ry;
        int q = w->cam_q[ci];
        const int *col = w->cam_col + (size_t)ci * qmax;
        const int *gi = w->cam_gi + (size_t)ci * qmax;
        double *jc = w->Jc + (size_t)k * 2 * qmax;
        for (int a = 0; a < q; a++) {
            jc[a] = sc * J[col[a]];
            jc[qmax + a] = sc * J[NLOC + col[a]];
        }
        int g0 = w->cam_base[ci];
        for (int a = 0; a < q; a++) {
            double j0 = jc[a], j1 = jc[qmax + a];
            int ga = gi[a];
            w->gc[ga] -= j0 * rx + j1 * ry;
            if (g0 >= 0) {
                double *Urow = w->U + (size_t)ga * nc + g0;
                for (int b = 0; b <= a; b++)
                    Urow[b] += j0 * jc[b] + j1 * jc[qmax + b];
                continue;
            }
            for (int b = 0; b < q; b++) {
                int gb = gi[b];
                if (gb <= ga)
                    w->U[(size_t)ga * nc + gb] += j0 * jc[b] + j1 * jc[qmax + b];
            }
        }
        if (w->pt_free[pj]) {
            for (int e = 0; e < 6; e++)
                Jp[e] *= sc;
            double *V = w->V + 9 * (size_t)pj, *g = w->gp + 3 * (size_t)pj;
            for (int a = 0; a < 3; a++) {
                g[a] -= Jp[a] * rx + Jp[3 + a] * ry;
                for (int b = 0; b <= a; b++)
                    V[3 * a + b] += Jp[a] * Jp[b] + Jp[3 + a] * Jp[3 + b];
            }
        }
    }
    cost *= 0.5;
    double gmax = 0.0;
    for (int i = 0; i < nc; i++)
        gmax = fmax(gmax, fabs(w->gc[i]));
    for (int i = 0; i < 3 * c->n; i++)
        gmax = fmax(gmax, fabs(w->gp[i]));
    *grad_max = gmax;
    return isfinite(cost) ? cost : HUGE_VAL;
}

/* y = L^{-1} b */
static void fwd3(const double *L, const double *b, double *y)
{
    y[0] = b[0] / L[0];
    y[1] = (b[1] - L[3] * y[0]) / L[4];
    y[2] = (b[2] - L[6] * y[0] - L[7] * y[1]) / L[8];
}

/* y = L^{-T} b */
static void bwd3(const double *L, const double *b, double *y)
{
    y[2] = b[2] / L[8];
    y[1] = (b[1] - L[7] * y[2]) / L[4];
    y[0] = (b[0] - L[3] * y[1] - L[6] * y[2]) / L[0];
}

/* S[a][b] -= sum_r A[r][a] B[r][b] for a 6x6 block (rows of A and B are
 * qmax apart): the common pose-only case, with constant trip counts. */
static void sub_outer6(double *restrict S, int nc, const double *restrict A, const double *restrict B,
                       int qmax)
{
    const double *B0 = B, *B1 = B + qmax, *B2 = B + 2 * qmax;
    for (int a = 0; a < 6; a++) {
        double f0 = A[a], f1 = A[qmax + a], f2 = A[2 * qmax + a];
        double *Srow = S + (size_t)a * nc;
        for (int b = 0; b < 6; b++)
            Srow[b] -= f0 * B0[b] + f1 * B1[b] + f2 * B2[b];
    }
}

/* Forms S (lower) = U + Dc - sum F F^T and its right-hand side in dc, with the
 * damping mu (0: undamped). Returns 0 when a point block is not positive
 * definite. */
int sfmi_ba_form_reduced(sfmi_ba_ctx *c, double mu)
{
    sfmi_ba_ws *w = &c->w;
    const sfm_ba_problem *p = c->p;
    int nc = c->nc, qmax = c->qmax;
    if (nc > 0) {
        memcpy(w->S, w->U, sizeof(double) * (size_t)nc * (size_t)nc);
        memcpy(w->dc, w->gc, sizeof(double) * (size_t)nc);
        for (int i = 0; i < nc; i++) {
            w->Dc[i] = mu * sfmi_lm_clamp_diag(w->U[(size_t)i * nc + i]);
            w->S[(size_t)i * nc + i] += w->Dc[i];
        }
    }
    for (int j = 0; j < c->n; j++) {
        if (!w->pt_free[j])
            continue;
        double Vd[9], *L = w->L + 9 * (size_t)j, *Dp = w->Dp + 3 * (size_t)j;
        memcpy(Vd, w->V + 9 * (size_t)j, sizeof Vd);
        for (int a = 0; a < 3; a++) {
            Dp[a] = mu * sfmi_lm_clamp_diag(Vd[4 * a]);
            Vd[4 * a] += Dp[a];
        }
        if (!sfmi_chol3(Vd, L))
            return 0;
        double *z = w->zp + 3 * (size_t)j;
        fwd3(L, w->gp + 3 * (size_t)j, z);
        if (nc == 0)
            continue;
        int s0 = w->pt_start[j], s1 = w->pt_start[j + 1];
        for (int i = s0; i < s1; i++) {
            int k = w->pt_obs[i], ci = p->obs_camera[k];
            int q = w->cam_q[ci];
            const double *jc = w->Jc + (size_t)k * 2 * qmax;
            const double *Jp = w->Jp + 6 * (size_t)k;
            double E0[3], E1[3];
            fwd3(L, Jp, E0);
            fwd3(L, Jp + 3, E1);
            /* F is stored transposed, 3 rows of qmax, so the pair products
             * below run over contiguous rows */
            double *F = w->F + (size_t)k * 3 * qmax;
            const int *gi = w->cam_gi + (size_t)ci * qmax;
            for (int a = 0; a < q; a++) {
                double j0 = jc[a], j1 = jc[qmax + a];
                double f0 = j0 * E0[0] + j1 * E1[0];
                double f1 = j0 * E0[1] + j1 * E1[1];
                double f2 = j0 * E0[2] + j1 * E1[2];
                F[a] = f0;
                F[qmax + a] = f1;
                F[2 * qmax + a] = f2;
                w->dc[gi[a]] -= f0 * z[0] + f1 * z[1] + f2 * z[2];
            }
            /* pairs (i, i2), i2 <= i: subtract F_i F_i2^T folded into the lower triangle */
            int g0 = w->cam_base[ci];
            for (int i2 = s0; i2 <= i; i2++) {
                int k2 = w->pt_obs[i2], c2 = p->obs_camera[k2];
                int q2 = w->cam_q[c2];
                const double *F2 = w->F + (size_t)k2 * 3 * qmax;
                int h0 = w->cam_base[c2];
                if (g0 >= 0 && h0 >= 0) {
                    /* contiguous parameter blocks: no index lists */
                    if (i2 == i) {
                        for (int a = 0; a < q; a++) {
                            double f0 = F[a], f1 = F[qmax + a], f2 = F[2 * qmax + a];
                            double *Srow = w->S + (size_t)(g0 + a) * nc + g0;
                            for (int b = 0; b <= a; b++)
                                Srow[b] -= f0 * F2[b] + f1 * F2[qmax + b] + f2 * F2[2 * qmax + b];
                        }
                        continue;
                    }
                    const double *A = F, *B = F2;
                    int ra = g0, rb = h0, qa = q, qb = q2;
                    if (h0 >= g0 + q) { /* block above the diagonal: write its transpose */
                        A = F2; B = F; ra = h0; rb = g0; qa = q2; qb = q;
                    } else if (!(g0 >= h0 + q2)) {
                        goto general;
                    }
                    if (qa == 6 && qb == 6) {
                        sub_outer6(w->S + (size_t)ra * nc + rb, nc, A, B, qmax);
                    } else {
                        for (int a = 0; a < qa; a++) {
                            double f0 = A[a], f1 = A[qmax + a], f2 = A[2 * qmax + a];
                            double *Srow = w->S + (size_t)(ra + a) * nc + rb;
                            for (int b = 0; b < qb; b++)
                                Srow[b] -= f0 * B[b] + f1 * B[qmax + b] + f2 * B[2 * qmax + b];
                        }
                    }
                    continue;
                }
            general:;
                const int *gi2 = w->cam_gi + (size_t)c2 * qmax;
                for (int a = 0; a < q; a++) {
                    double f0 = F[a], f1 = F[qmax + a], f2 = F[2 * qmax + a];
                    int ga = gi[a];
                    double *Srow = w->S + (size_t)ga * nc;
                    for (int b = 0; b < q2; b++) {
                        double v = f0 * F2[b] + f1 * F2[qmax + b] + f2 * F2[2 * qmax + b];
                        int gb = gi2[b];
                        if (i2 == i) {
                            if (gb <= ga)
                                Srow[gb] -= v;
                        } else if (gb < ga) {
                            Srow[gb] -= v;
                        } else if (gb > ga) {
                            w->S[(size_t)gb * nc + ga] -= v;
                        } else {
                            Srow[gb] -= 2.0 * v;
                        }
                    }
                }
            }
        }
    }
    return 1;
}

/* Solves the damped system; dc and dp receive the step. Returns 0 when not
 * positive definite. */
static int solve_damped(sfmi_ba_ctx *c, double mu)
{
    sfmi_ba_ws *w = &c->w;
    const sfm_ba_problem *p = c->p;
    int nc = c->nc, qmax = c->qmax;
    if (!sfmi_ba_form_reduced(c, mu))
        return 0;
    if (nc > 0) {
        if (sfm_cholesky_factor(w->S, nc) != SFM_OK)
            return 0;
        if (sfm_cholesky_solve(w->S, nc, w->dc, 1) != SFM_OK)
            return 0;
    }
    for (int j = 0; j < c->n; j++) {
        if (!w->pt_free[j])
            continue;
        double y[3];
        memcpy(y, w->zp + 3 * (size_t)j, sizeof y);
        if (nc > 0) {
            for (int i = w->pt_start[j]; i < w->pt_start[j + 1]; i++) {
                int k = w->pt_obs[i], ci = p->obs_camera[k];
                int q = w->cam_q[ci];
                const double *F = w->F + (size_t)k * 3 * qmax;
                const int *gi = w->cam_gi + (size_t)ci * qmax;
                for (int a = 0; a < q; a++) {
                    double d = w->dc[gi[a]];
                    y[0] -= F[a] * d;
                    y[1] -= F[qmax + a] * d;
                    y[2] -= F[2 * qmax + a] * d;
                }
            }
        }
        bwd3(w->L + 9 * (size_t)j, y, w->dp + 3 * (size_t)j);
    }
    return 1;
}

int sfmi_ba_solve_step(void *self, double mu, double *step2, double *x2, double *pred)
{
    sfmi_ba_ctx *c = self;
    sfmi_ba_ws *w = &c->w;
    const int nc = c->nc, n = c->n, m = c->m;
    if (!solve_damped(c, mu))
        return 0;
    double h2 = 0.0, xx = 0.0, pr = 0.0;
    for (int i = 0; i < nc; i++) {
        double h = w->dc[i];
        h2 += h * h;
        pr += h * (w->gc[i] + w->Dc[i] * h);
    }
    for (int j = 0; j < n; j++) {
        if (!w->pt_free[j])
            continue;
        for (int a = 0; a < 3; a++) {
            double h = w->dp[3 * j + a];
            h2 += h * h;
            pr += h * (w->gp[3 * j + a] + w->Dp[3 * j + a] * h);
        }
    }
    for (int i = 0; i < 3 * m; i++)
        xx += w->t[i] * w->t[i];
    for (int i = 0; i < 3 * n; i++)
        xx += w->X[i] * w->X[i];
    if (c->nic > 0) {
        for (int i = 0; i < m; i++) {
            const sfm_camera *K = &w->K[i];
            xx += K->fx * K->fx + K->fy * K->fy + K->cx * K->cx + K->cy * K->cy;
            for (int e = 0; e < SFMI_BA_NDIST; e++)
                xx += K->dist[e] * K->dist[e];
        }
    }
    *step2 = h2;
    *x2 = xx;
    *pred = 0.5 * pr;
    return 1;
}

/* trial = current (+) step; its cost */
double sfmi_ba_trial(void *self)
{
    sfmi_ba_ctx *c = self;
    sfmi_ba_ws *w = &c->w;
    int m = c->m, qmax = c->qmax;
    memcpy(w->R2, w->R, sizeof(double) * 9 * (size_t)m);
    memcpy(w->t2, w->t, sizeof(double) * 3 * (size_t)m);
    memcpy(w->K2, w->K, sizeof(sfm_camera) * (size_t)m);
    for (int ci = 0; ci < m; ci++) {
        int q = w->cam_q[ci];
        const int *col = w->cam_col + (size_t)ci * qmax;
        const int *gi = w->cam_gi + (size_t)ci * qmax;
        double rot[3] = {0, 0, 0};
        int has_rot = 0;
        sfm_camera *K2 = &w->K2[ci];
        for (int a = 0; a < q; a++) {
            double d = w->dc[gi[a]];
            int l = col[a];
            if (l < 3) {
                rot[l] = d;
                has_rot = 1;
            } else if (l < 6) {
                w->t2[3 * ci + l - 3] += d;
            } else if (l == 6) {
                K2->fx += d;
                K2->fy = K2->fx * w->aspect[ci];
            } else if (l == 7) {
                K2->cx += d;
            } else if (l == 8) {
                K2->cy += d;
            } else {
                K2->dist[l - 9] += d;
            }
        }
        if (has_rot) {
            double dR[9], Rn[9];
            const double *R = w->R + 9 * ci;
            if (sfm_rot_from_axis_angle(rot, dR) != SFM_OK)
                return HUGE_VAL;
            sfmi_matmul3(dR, R, Rn);
            memcpy(w->R2 + 9 * ci, Rn, sizeof Rn);
        }
    }
    for (int j = 0; j < c->n; j++) {
        for (int a = 0; a < 3; a++)
            w->X2[3 * j + a] = w->X[3 * j + a] + (w->pt_free[j] ? w->dp[3 * j + a] : 0.0);
    }
    return eval_cost(c, w->R2, w->t2, w->K2, w->X2);
}

static void swap_ptr(double **a, double **b)
{
    double *t = *a;
    *a = *b;
    *b = t;
}

void sfmi_ba_accept(void *self)
{
    sfmi_ba_ctx *c = self;
    sfmi_ba_ws *w = &c->w;
    swap_ptr(&w->R, &w->R2);
    swap_ptr(&w->t, &w->t2);
    swap_ptr(&w->X, &w->X2);
    sfm_camera *k = w->K;
    w->K = w->K2;
    w->K2 = k;
}
