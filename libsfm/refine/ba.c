/*
 * Bundle adjustment: Levenberg-Marquardt on the Schur complement.
 *
 * Normal equations of the (robustly reweighted) Gauss-Newton model, damped as
 * in Marquardt (1963) with a trust-region radius update after Nielsen (1999),
 * as Ceres' LEVENBERG_MARQUARDT strategy does, so that the two can be run side
 * by side with the same settings:
 *
 *     [ U + Dc    W      ] [dc]   [gc]
 *     [ W^T       V + Dp ] [dp] = [gp],   D = diag(clamp(diag JtJ, 1e-6, 1e32)) / radius
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
 * Local camera-side parameter columns: 0-2 rotation (left update in the camera
 * frame), 3-5 translation, 6 focal, 7-8 principal point, 9-10 k1, k2.
 */
#include "sfm/sfm_ba.h"

#include <math.h>
#include <string.h>

#include "core/arena.h"
#include "refine/ba_project.h"
#include "sfm/sfm_linalg.h"
#include "sfm/sfm_rotation.h"
#include "core/dmath.h"

#define MIN_DIAG 1e-6
#define MAX_DIAG 1e32
#define MAX_RADIUS 1e16
#define MIN_RADIUS 1e-32
#define MIN_RELATIVE_DECREASE 1e-3

typedef struct ba_ws {
    int *cam_q;   /* m: camera-side parameters of an observation of camera c */
    int *cam_col; /* m x qmax: local column of each */
    int *cam_gi;  /* m x qmax: index in the reduced system */
    int *cam_base; /* m: cam_gi[0] when the indices are consecutive, else -1 */
    int *pt_start;   /* n + 1 */
    int *pt_obs;     /* nobs, observations grouped by point */
    int *pt_free;    /* n */
    double *R, *t, *K, *X;     /* current estimate */
    double *R2, *t2, *K2, *X2; /* trial estimate */
    double *res; /* 2 nobs: scaled residuals */
    double *Jc;  /* nobs x 2 x qmax */
    double *Jp;  /* nobs x 6 */
    double *F;   /* nobs x qmax x 3 */
    double *U, *S, *gc, *dc, *Dc; /* nc x nc, nc x nc, nc, nc, nc */
    double *V, *gp, *L, *zp, *dp, *Dp; /* 9n, 3n, 9n, 3n, 3n, 3n */
    double *aspect; /* m: fy / fx */
} ba_ws;

static int n_intr_params(int mode, int mask)
{
    if (mode == SFM_BA_INTRINSICS_FIXED)
        return 0;
    return ((mask & SFM_BA_REFINE_FOCAL) ? 1 : 0) + ((mask & SFM_BA_REFINE_PRINCIPAL) ? 2 : 0) +
           ((mask & SFM_BA_REFINE_RADIAL) ? 2 : 0);
}

static int dims_valid(const sfm_ba_dims *d)
{
    if (d == NULL || d->n_cameras < 1 || d->n_points < 0 || d->n_observations < 1)
        return 0;
    if (d->intrinsics < SFM_BA_INTRINSICS_FIXED || d->intrinsics > SFM_BA_INTRINSICS_PER_CAMERA)
        return 0;
    if (d->refine_intrinsics < 0 || d->refine_intrinsics > 7)
        return 0;
    /* the reduced system must fit the dense solver and int indexing */
    long long ni = n_intr_params(d->intrinsics, d->refine_intrinsics);
    long long nc = 6LL * d->n_cameras + (d->intrinsics == SFM_BA_INTRINSICS_PER_CAMERA ? ni * d->n_cameras : ni);
    if (nc > SFM_LINALG_MAX_DIM || d->n_points > (1 << 26) || d->n_observations > (1 << 26))
        return 0;
    return 1;
}

static void layout(sfm_arena *a, const sfm_ba_dims *d, ba_ws *w, int *qmax_out, int *ncmax_out)
{
    int m = d->n_cameras, n = d->n_points, no = d->n_observations;
    int ni = n_intr_params(d->intrinsics, d->refine_intrinsics);
    int qmax = 6 + ni;
    int ncmax = 6 * m + (d->intrinsics == SFM_BA_INTRINSICS_PER_CAMERA ? ni * m : ni);
    size_t nc = (size_t)ncmax;
    w->cam_q = SFM_ARENA_ARRAY(a, int, m);
    w->cam_col = SFM_ARENA_ARRAY(a, int, (size_t)m * qmax);
    w->cam_gi = SFM_ARENA_ARRAY(a, int, (size_t)m * qmax);
    w->cam_base = SFM_ARENA_ARRAY(a, int, m);
    w->pt_start = SFM_ARENA_ARRAY(a, int, (size_t)n + 1);
    w->pt_obs = SFM_ARENA_ARRAY(a, int, no);
    w->pt_free = SFM_ARENA_ARRAY(a, int, (size_t)n + 1);
    w->R = SFM_ARENA_ARRAY(a, double, 9 * (size_t)m);
    w->t = SFM_ARENA_ARRAY(a, double, 3 * (size_t)m);
    w->K = SFM_ARENA_ARRAY(a, double, 6 * (size_t)m);
    w->X = SFM_ARENA_ARRAY(a, double, 3 * (size_t)n + 1);
    w->R2 = SFM_ARENA_ARRAY(a, double, 9 * (size_t)m);
    w->t2 = SFM_ARENA_ARRAY(a, double, 3 * (size_t)m);
    w->K2 = SFM_ARENA_ARRAY(a, double, 6 * (size_t)m);
    w->X2 = SFM_ARENA_ARRAY(a, double, 3 * (size_t)n + 1);
    w->res = SFM_ARENA_ARRAY(a, double, 2 * (size_t)no);
    w->Jc = SFM_ARENA_ARRAY(a, double, (size_t)no * 2 * qmax);
    w->Jp = SFM_ARENA_ARRAY(a, double, (size_t)no * 6);
    w->F = SFM_ARENA_ARRAY(a, double, (size_t)no * 3 * qmax);
    w->U = SFM_ARENA_ARRAY(a, double, nc * nc);
    w->S = SFM_ARENA_ARRAY(a, double, nc * nc);
    w->gc = SFM_ARENA_ARRAY(a, double, nc);
    w->dc = SFM_ARENA_ARRAY(a, double, nc);
    w->Dc = SFM_ARENA_ARRAY(a, double, nc);
    w->V = SFM_ARENA_ARRAY(a, double, 9 * (size_t)n + 1);
    w->gp = SFM_ARENA_ARRAY(a, double, 3 * (size_t)n + 1);
    w->L = SFM_ARENA_ARRAY(a, double, 9 * (size_t)n + 1);
    w->zp = SFM_ARENA_ARRAY(a, double, 3 * (size_t)n + 1);
    w->dp = SFM_ARENA_ARRAY(a, double, 3 * (size_t)n + 1);
    w->Dp = SFM_ARENA_ARRAY(a, double, 3 * (size_t)n + 1);
    w->aspect = SFM_ARENA_ARRAY(a, double, m);
    *qmax_out = qmax;
    *ncmax_out = ncmax;
}

size_t sfm_ba_workspace_size(const sfm_ba_dims *dims)
{
    if (!dims_valid(dims))
        return 0;
    sfm_arena a;
    ba_ws w;
    int q, nc;
    sfm_arena_measure(&a);
    layout(&a, dims, &w, &q, &nc);
    return sfm_arena_required(&a);
}

int sfm_ba_default_options(sfm_ba_options *o)
{
    if (o == NULL)
        return SFM_E_ARGUMENT;
    memset(o, 0, sizeof *o);
    o->mode = SFM_BA_MODE_FULL;
    o->intrinsics = SFM_BA_INTRINSICS_FIXED;
    o->refine_intrinsics = 0;
    o->loss = SFM_BA_LOSS_SQUARED;
    o->loss_scale = 1.0;
    o->gauge = SFM_BA_GAUGE_FIRST_CAMERA;
    o->scale_gauge = SFM_BA_SCALE_NONE;
    o->scale_camera = 1;
    o->scale_coordinate = 0;
    o->scale_distance = 1.0;
    o->max_iterations = 50;
    o->function_tolerance = 1e-6;
    o->gradient_tolerance = 1e-10;
    o->parameter_tolerance = 1e-8;
    o->initial_trust_radius = 1e4;
    o->want_covariance = 0;
    return SFM_OK;
}

/* ---- model ---------------------------------------------------------------- */

static void loss_eval(int type, double a2, double s, double *rho, double *rho1)
{
    switch (type) {
    case SFM_BA_LOSS_HUBER:
        if (s <= a2) {
            *rho = s;
            *rho1 = 1.0;
        } else {
            double r = sqrt(s), a = sqrt(a2);
            *rho = 2.0 * a * r - a2;
            *rho1 = a / r;
        }
        break;
    case SFM_BA_LOSS_CAUCHY:
        *rho = a2 * sfmi_log1p(s / a2);
        *rho1 = 1.0 / (1.0 + s / a2);
        break;
    case SFM_BA_LOSS_TRUNCATED:
        if (s <= a2) {
            *rho = s;
            *rho1 = 1.0;
        } else {
            *rho = a2;
            *rho1 = 0.0;
        }
        break;
    default:
        *rho = s;
        *rho1 = 1.0;
        break;
    }
}

typedef struct ba_ctx {
    const sfm_ba_problem *p;
    const sfm_ba_options *o;
    ba_ws w;
    int m, n, nobs, qmax, nc;
    double a2;
} ba_ctx;

/* Cost at (R, t, K, X); +Inf when a point lands on a camera plane or the sum
 * is not finite. */
static double eval_cost(const ba_ctx *c, const double *R, const double *t, const double *K,
                        const double *X)
{
    const sfm_ba_problem *p = c->p;
    double cost = 0.0;
    for (int k = 0; k < c->nobs; k++) {
        int ci = p->obs_camera[k], pj = p->obs_point[k];
        double uv[2];
        if (!sfm_ba_project(R + 9 * ci, t + 3 * ci, K + 6 * ci, X + 3 * pj, uv, NULL, NULL))
            return HUGE_VAL;
        double rx = uv[0] - p->obs_xy[2 * k], ry = uv[1] - p->obs_xy[2 * k + 1];
        double wgt = p->obs_weight ? p->obs_weight[k] : 1.0;
        double rho, rho1;
        loss_eval(c->o->loss, c->a2, wgt * (rx * rx + ry * ry), &rho, &rho1);
        cost += rho;
    }
    cost *= 0.5;
    return isfinite(cost) ? cost : HUGE_VAL;
}

/* Residuals, Jacobians, U, gc (= -J^T r), V, gp at the current estimate.
 * Returns the cost (+Inf when not finite). U holds only its lower triangle. */
static double linearize(ba_ctx *c)
{
    const sfm_ba_problem *p = c->p;
    ba_ws *w = &c->w;
    int nc = c->nc, qmax = c->qmax;
    double cost = 0.0;
    if (nc > 0) {
        memset(w->U, 0, sizeof(double) * (size_t)nc * (size_t)nc);
        memset(w->gc, 0, sizeof(double) * (size_t)nc);
    }
    memset(w->V, 0, sizeof(double) * 9 * (size_t)c->n);
    memset(w->gp, 0, sizeof(double) * 3 * (size_t)c->n);
    for (int k = 0; k < c->nobs; k++) {
        int ci = p->obs_camera[k], pj = p->obs_point[k];
        double uv[2], J[2 * NLOC], *Jp = w->Jp + 6 * (size_t)k;
        if (!sfm_ba_project(w->R + 9 * ci, w->t + 3 * ci, w->K + 6 * ci, w->X + 3 * pj, uv, J, Jp))
            return HUGE_VAL;
        double rx = uv[0] - p->obs_xy[2 * k], ry = uv[1] - p->obs_xy[2 * k + 1];
        double wgt = p->obs_weight ? p->obs_weight[k] : 1.0;
        double rho, rho1;
        loss_eval(c->o->loss, c->a2, wgt * (rx * rx + ry * ry), &rho, &rho1);
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
    return isfinite(cost) ? cost : HUGE_VAL;
}

static double clampd(double v)
{
    return v < MIN_DIAG ? MIN_DIAG : (v > MAX_DIAG ? MAX_DIAG : v);
}

/* 3x3 Cholesky of the lower triangle of A into L (lower, row-major). This is
 * the per-point hot path of the elimination, kept inline; returns 0 when A is
 * not positive definite. */
static int chol3(const double *A, double *L)
{
    double l00 = A[0];
    if (!(l00 > 0.0))
        return 0;
    l00 = sqrt(l00);
    double l10 = A[3] / l00, l20 = A[6] / l00;
    double d1 = A[4] - l10 * l10;
    if (!(d1 > 0.0))
        return 0;
    double l11 = sqrt(d1);
    double l21 = (A[7] - l20 * l10) / l11;
    double d2 = A[8] - l20 * l20 - l21 * l21;
    if (!(d2 > 0.0))
        return 0;
    L[0] = l00; L[1] = 0; L[2] = 0;
    L[3] = l10; L[4] = l11; L[5] = 0;
    L[6] = l20; L[7] = l21; L[8] = sqrt(d2);
    return 1;
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
static int form_reduced(ba_ctx *c, double mu)
{
    ba_ws *w = &c->w;
    const sfm_ba_problem *p = c->p;
    int nc = c->nc, qmax = c->qmax;
    if (nc > 0) {
        memcpy(w->S, w->U, sizeof(double) * (size_t)nc * (size_t)nc);
        memcpy(w->dc, w->gc, sizeof(double) * (size_t)nc);
        for (int i = 0; i < nc; i++) {
            w->Dc[i] = mu * clampd(w->U[(size_t)i * nc + i]);
            w->S[(size_t)i * nc + i] += w->Dc[i];
        }
    }
    for (int j = 0; j < c->n; j++) {
        if (!w->pt_free[j])
            continue;
        double Vd[9], *L = w->L + 9 * (size_t)j, *Dp = w->Dp + 3 * (size_t)j;
        memcpy(Vd, w->V + 9 * (size_t)j, sizeof Vd);
        for (int a = 0; a < 3; a++) {
            Dp[a] = mu * clampd(Vd[4 * a]);
            Vd[4 * a] += Dp[a];
        }
        if (!chol3(Vd, L))
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
static int solve_step(ba_ctx *c, double mu)
{
    ba_ws *w = &c->w;
    const sfm_ba_problem *p = c->p;
    int nc = c->nc, qmax = c->qmax;
    if (!form_reduced(c, mu))
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

/* trial = current (+) step */
static void apply_step(ba_ctx *c)
{
    ba_ws *w = &c->w;
    int m = c->m, qmax = c->qmax;
    memcpy(w->R2, w->R, sizeof(double) * 9 * (size_t)m);
    memcpy(w->t2, w->t, sizeof(double) * 3 * (size_t)m);
    memcpy(w->K2, w->K, sizeof(double) * 6 * (size_t)m);
    for (int ci = 0; ci < m; ci++) {
        int q = w->cam_q[ci];
        const int *col = w->cam_col + (size_t)ci * qmax;
        const int *gi = w->cam_gi + (size_t)ci * qmax;
        double rot[3] = {0, 0, 0};
        int has_rot = 0;
        double *K2 = w->K2 + 6 * ci;
        for (int a = 0; a < q; a++) {
            double d = w->dc[gi[a]];
            int l = col[a];
            if (l < 3) {
                rot[l] = d;
                has_rot = 1;
            } else if (l < 6) {
                w->t2[3 * ci + l - 3] += d;
            } else if (l == 6) {
                K2[0] += d;
                K2[1] = K2[0] * w->aspect[ci];
            } else {
                K2[l - 5] += d; /* 7,8 -> cx,cy (2,3); 9,10 -> k1,k2 (4,5) */
            }
        }
        if (has_rot) {
            double dR[9], Rn[9];
            const double *R = w->R + 9 * ci;
            (void)sfm_rot_from_axis_angle(rot, dR);
            for (int r = 0; r < 3; r++)
                for (int s = 0; s < 3; s++)
                    Rn[3 * r + s] = dR[3 * r] * R[s] + dR[3 * r + 1] * R[3 + s] + dR[3 * r + 2] * R[6 + s];
            memcpy(w->R2 + 9 * ci, Rn, sizeof Rn);
        }
    }
    for (int j = 0; j < c->n; j++) {
        for (int a = 0; a < 3; a++)
            w->X2[3 * j + a] = w->X[3 * j + a] + (w->pt_free[j] ? w->dp[3 * j + a] : 0.0);
    }
}

static void swap_ptr(double **a, double **b)
{
    double *t = *a;
    *a = *b;
    *b = t;
}

static int finite_array(const double *a, size_t n)
{
    for (size_t i = 0; i < n; i++)
        if (!isfinite(a[i]))
            return 0;
    return 1;
}

/* ---- argument checks ------------------------------------------------------ */

static int check_args(const sfm_ba_problem *p, const sfm_ba_options *o)
{
    if (p == NULL || o == NULL)
        return SFM_E_ARGUMENT;
    int m = p->n_cameras, n = p->n_points, no = p->n_observations;
    if (m < 1 || n < 0 || no < 1)
        return SFM_E_ARGUMENT;
    if (!p->rotations || !p->translations || !p->intrinsics || (n > 0 && !p->points) ||
        !p->obs_camera || !p->obs_point || !p->obs_xy)
        return SFM_E_ARGUMENT;
    if (o->mode < SFM_BA_MODE_FULL || o->mode > SFM_BA_MODE_POINTS_ONLY)
        return SFM_E_ARGUMENT;
    if (o->intrinsics < SFM_BA_INTRINSICS_FIXED || o->intrinsics > SFM_BA_INTRINSICS_PER_CAMERA)
        return SFM_E_ARGUMENT;
    if (o->refine_intrinsics < 0 || o->refine_intrinsics > 7)
        return SFM_E_ARGUMENT;
    if (o->loss < SFM_BA_LOSS_SQUARED || o->loss > SFM_BA_LOSS_TRUNCATED)
        return SFM_E_ARGUMENT;
    if (!isfinite(o->loss_scale) || !(o->loss_scale > 0.0))
        return SFM_E_ARGUMENT;
    if (o->gauge != SFM_BA_GAUGE_NONE && o->gauge != SFM_BA_GAUGE_FIRST_CAMERA)
        return SFM_E_ARGUMENT;
    if (o->scale_gauge < SFM_BA_SCALE_NONE || o->scale_gauge > SFM_BA_SCALE_DISTANCE)
        return SFM_E_ARGUMENT;
    if (o->scale_gauge != SFM_BA_SCALE_NONE) {
        if (o->gauge != SFM_BA_GAUGE_FIRST_CAMERA || o->scale_camera < 1 || o->scale_camera >= m)
            return SFM_E_ARGUMENT;
        if (o->scale_gauge == SFM_BA_SCALE_COORDINATE &&
            (o->scale_coordinate < 0 || o->scale_coordinate > 2))
            return SFM_E_ARGUMENT;
        if (o->scale_gauge == SFM_BA_SCALE_DISTANCE &&
            (!isfinite(o->scale_distance) || !(o->scale_distance > 0.0)))
            return SFM_E_ARGUMENT;
    }
    if (o->max_iterations < 0 || !(o->function_tolerance >= 0.0) ||
        !(o->gradient_tolerance >= 0.0) || !(o->parameter_tolerance >= 0.0) ||
        !isfinite(o->initial_trust_radius) || !(o->initial_trust_radius > 0.0))
        return SFM_E_ARGUMENT;
    for (int k = 0; k < no; k++) {
        if (p->obs_camera[k] < 0 || p->obs_camera[k] >= m || p->obs_point[k] < 0 ||
            p->obs_point[k] >= n)
            return SFM_E_ARGUMENT;
    }
    if (p->obs_weight) {
        for (int k = 0; k < no; k++) {
            if (isnan(p->obs_weight[k]) || isinf(p->obs_weight[k]))
                return SFM_E_NONFINITE;
            if (p->obs_weight[k] < 0.0)
                return SFM_E_ARGUMENT;
        }
    }
    if (!finite_array(p->rotations, 9 * (size_t)m) || !finite_array(p->translations, 3 * (size_t)m) ||
        !finite_array(p->intrinsics, 6 * (size_t)m) || (n > 0 && !finite_array(p->points, 3 * (size_t)n)) ||
        !finite_array(p->obs_xy, 2 * (size_t)no))
        return SFM_E_NONFINITE;
    for (int i = 0; i < m; i++) {
        if (p->intrinsics[6 * i] == 0.0 || p->intrinsics[6 * i + 1] == 0.0)
            return SFM_E_ARGUMENT;
        /* a rotation: R R^T = I to 1e-6 and det R > 0 */
        const double *R = p->rotations + 9 * i;
        for (int r = 0; r < 3; r++)
            for (int c2 = 0; c2 < 3; c2++) {
                double d = R[3 * r] * R[3 * c2] + R[3 * r + 1] * R[3 * c2 + 1] + R[3 * r + 2] * R[3 * c2 + 2];
                if (fabs(d - (r == c2 ? 1.0 : 0.0)) > 1e-6)
                    return SFM_E_ARGUMENT;
            }
        double det = R[0] * (R[4] * R[8] - R[5] * R[7]) - R[1] * (R[3] * R[8] - R[5] * R[6]) +
                     R[2] * (R[3] * R[7] - R[4] * R[6]);
        if (!(det > 0.0))
            return SFM_E_ARGUMENT;
    }
    return SFM_OK;
}

/* ---- solve ---------------------------------------------------------------- */

int sfm_ba_solve(sfm_ba_problem *p, const sfm_ba_options *o, void *ws, size_t ws_size,
                 sfm_ba_result *result, double *pose_covariance)
{
    int st = check_args(p, o);
    if (st != SFM_OK)
        return st;
    if (result == NULL || (o->want_covariance && pose_covariance == NULL))
        return SFM_E_ARGUMENT;
    sfm_ba_dims dims = {p->n_cameras, p->n_points, p->n_observations, o->intrinsics,
                        o->refine_intrinsics};
    if (!dims_valid(&dims))
        return SFM_E_ARGUMENT;
    size_t need = sfm_ba_workspace_size(&dims);
    if (ws == NULL || ws_size < need)
        return SFM_E_WORKSPACE;

    ba_ctx c;
    memset(&c, 0, sizeof c);
    c.p = p;
    c.o = o;
    c.m = p->n_cameras;
    c.n = p->n_points;
    c.nobs = p->n_observations;
    c.a2 = o->loss_scale * o->loss_scale;
    sfm_arena ar;
    int ncmax;
    sfm_arena_init(&ar, ws, ws_size);
    layout(&ar, &dims, &c.w, &c.qmax, &ncmax);
    if (!sfm_arena_ok(&ar))
        return SFM_E_WORKSPACE;
    ba_ws *w = &c.w;
    int m = c.m, n = c.n, qmax = c.qmax;

    /* points: free flags, observations grouped by point (counting sort) */
    for (int j = 0; j < n; j++)
        w->pt_free[j] = (o->mode != SFM_BA_MODE_POSE_ONLY) && !(p->point_fixed && p->point_fixed[j]);
    memset(w->pt_start, 0, sizeof(int) * ((size_t)n + 1));
    for (int k = 0; k < c.nobs; k++)
        w->pt_start[p->obs_point[k] + 1]++;
    for (int j = 0; j < n; j++) {
        if (w->pt_free[j] && w->pt_start[j + 1] == 0)
            return SFM_E_ARGUMENT; /* a free point nobody sees */
        w->pt_start[j + 1] += w->pt_start[j];
    }
    /* cam_q first counts observations per camera */
    memset(w->cam_q, 0, sizeof(int) * (size_t)m);
    for (int k = 0; k < c.nobs; k++)
        w->cam_q[p->obs_camera[k]]++;
    {
        int *cursor = (int *)w->Dp; /* 3n + 1 doubles: room for n ints */
        for (int j = 0; j < n; j++)
            cursor[j] = w->pt_start[j];
        for (int k = 0; k < c.nobs; k++)
            w->pt_obs[cursor[p->obs_point[k]]++] = k;
    }

    /* camera-side parameters */
    int ni_mask = o->intrinsics == SFM_BA_INTRINSICS_FIXED ? 0 : o->refine_intrinsics;
    int intr_cols[5], nic = 0;
    if (ni_mask & SFM_BA_REFINE_FOCAL)
        intr_cols[nic++] = 6;
    if (ni_mask & SFM_BA_REFINE_PRINCIPAL) {
        intr_cols[nic++] = 7;
        intr_cols[nic++] = 8;
    }
    if (ni_mask & SFM_BA_REFINE_RADIAL) {
        intr_cols[nic++] = 9;
        intr_cols[nic++] = 10;
    }
    if (o->mode == SFM_BA_MODE_POINTS_ONLY)
        nic = 0;

    /* The gauge options act in FULL mode only: held points fix the gauge of a
     * pose-only solve, and a points-only solve holds every camera. */
    const int full = o->mode == SFM_BA_MODE_FULL;
    const int gauge = full ? o->gauge : SFM_BA_GAUGE_NONE;
    const int scale_gauge = full ? o->scale_gauge : SFM_BA_SCALE_NONE;

    /* scale gauge: which translation coordinate is held */
    int scale_cam = -1, scale_coord = -1;
    if (scale_gauge == SFM_BA_SCALE_COORDINATE) {
        scale_cam = o->scale_camera;
        scale_coord = o->scale_coordinate;
    } else if (scale_gauge == SFM_BA_SCALE_DISTANCE) {
        /* other held cameras or points would fix the scale themselves */
        for (int i = 1; i < m; i++)
            if (p->camera_flags && (p->camera_flags[i] & SFM_BA_FIX_POSE))
                return SFM_E_ARGUMENT;
        for (int j = 0; j < n; j++)
            if (!w->pt_free[j])
                return SFM_E_ARGUMENT;
        /* hold the coordinate of t_c whose change best measures scale:
         * t_c(s) = s t_c - (1 - s) R_c C0 moves by t_c + R_c C0 per unit s */
        const double *R0 = p->rotations, *t0 = p->translations;
        const double *Rc = p->rotations + 9 * o->scale_camera, *tc = p->translations + 3 * o->scale_camera;
        double C0[3], best = 0.0;
        for (int r = 0; r < 3; r++)
            C0[r] = -(R0[r] * t0[0] + R0[3 + r] * t0[1] + R0[6 + r] * t0[2]);
        for (int r = 0; r < 3; r++) {
            double v = tc[r] + Rc[3 * r] * C0[0] + Rc[3 * r + 1] * C0[1] + Rc[3 * r + 2] * C0[2];
            if (fabs(v) > best) {
                best = fabs(v);
                scale_coord = r;
            }
        }
        if (!(best > 0.0))
            return SFM_E_ARGUMENT; /* camera centres coincide: no scale to fix */
        scale_cam = o->scale_camera;
    }

    int nc = 0;
    for (int ci = 0; ci < m; ci++) {
        int q = 0;
        int pose_free = o->mode != SFM_BA_MODE_POINTS_ONLY &&
                        !(p->camera_flags && (p->camera_flags[ci] & SFM_BA_FIX_POSE)) &&
                        !(ci == 0 && gauge == SFM_BA_GAUGE_FIRST_CAMERA);
        if (pose_free) {
            for (int l = 0; l < 6; l++) {
                if (ci == scale_cam && l == 3 + scale_coord)
                    continue;
                w->cam_col[(size_t)ci * qmax + q] = l;
                w->cam_gi[(size_t)ci * qmax + q] = nc++;
                q++;
            }
        }
        if (o->intrinsics == SFM_BA_INTRINSICS_PER_CAMERA &&
            !(p->camera_flags && (p->camera_flags[ci] & SFM_BA_FIX_INTRINSICS))) {
            for (int e = 0; e < nic; e++) {
                w->cam_col[(size_t)ci * qmax + q] = intr_cols[e];
                w->cam_gi[(size_t)ci * qmax + q] = nc++;
                q++;
            }
        }
        /* a camera with free parameters must be observed */
        if (q > 0 && w->cam_q[ci] == 0)
            return SFM_E_ARGUMENT;
        w->cam_q[ci] = q;
    }
    if (o->intrinsics == SFM_BA_INTRINSICS_SHARED && nic > 0) {
        for (int ci = 0; ci < m; ci++) {
            for (int e = 0; e < nic; e++) {
                w->cam_col[(size_t)ci * qmax + w->cam_q[ci] + e] = intr_cols[e];
                w->cam_gi[(size_t)ci * qmax + w->cam_q[ci] + e] = nc + e;
            }
            w->cam_q[ci] += nic;
        }
        nc += nic;
    }
    for (int ci = 0; ci < m; ci++) {
        const int *gi = w->cam_gi + (size_t)ci * qmax;
        int contig = w->cam_q[ci] > 0;
        for (int e = 1; e < w->cam_q[ci]; e++)
            contig = contig && gi[e] == gi[0] + e;
        w->cam_base[ci] = contig ? gi[0] : -1;
    }
    c.nc = nc;
    if (nc > ncmax)
        return SFM_E_ARGUMENT; /* cannot happen: ncmax bounds every layout */

    /* working copies */
    memcpy(w->R, p->rotations, sizeof(double) * 9 * (size_t)m);
    memcpy(w->t, p->translations, sizeof(double) * 3 * (size_t)m);
    memcpy(w->K, p->intrinsics, sizeof(double) * 6 * (size_t)m);
    if (n > 0)
        memcpy(w->X, p->points, sizeof(double) * 3 * (size_t)n);
    for (int ci = 0; ci < m; ci++)
        w->aspect[ci] = w->K[6 * ci + 1] / w->K[6 * ci];
    if (o->intrinsics == SFM_BA_INTRINSICS_SHARED && nic > 0) {
        /* the shared block starts from camera 0's refined entries */
        for (int ci = 1; ci < m; ci++) {
            double *K = w->K + 6 * ci;
            if (ni_mask & SFM_BA_REFINE_FOCAL) {
                K[0] = w->K[0];
                K[1] = K[0] * w->aspect[ci];
            }
            if (ni_mask & SFM_BA_REFINE_PRINCIPAL) {
                K[2] = w->K[2];
                K[3] = w->K[3];
            }
            if (ni_mask & SFM_BA_REFINE_RADIAL) {
                K[4] = w->K[4];
                K[5] = w->K[5];
            }
        }
    }
    int npp = 0;
    for (int j = 0; j < n; j++)
        npp += w->pt_free[j] ? 3 : 0;

    sfm_ba_result res;
    memset(&res, 0, sizeof res);
    res.n_camera_params = nc;
    res.n_point_params = npp;
    res.covariance_status = 1;

    double cost = linearize(&c);
    if (!isfinite(cost))
        return SFM_E_NONFINITE;
    res.initial_cost = cost;

    double radius = o->initial_trust_radius, decrease = 2.0;
    int reason = 0;
    if (nc == 0 && npp == 0)
        reason = SFM_BA_STOP_NO_PARAMETERS;
    int iter = 0;
    while (!reason) {
        /* gradient test */
        double gmax = 0.0;
        for (int i = 0; i < nc; i++)
            gmax = fmax(gmax, fabs(w->gc[i]));
        for (int i = 0; i < 3 * n; i++)
            gmax = fmax(gmax, fabs(w->gp[i]));
        if (gmax <= o->gradient_tolerance) {
            reason = SFM_BA_STOP_GRADIENT;
            break;
        }
        if (iter >= o->max_iterations) {
            reason = SFM_BA_STOP_MAX_ITERATIONS;
            break;
        }
        iter++;
        double mu = 1.0 / radius;
        if (!solve_step(&c, mu)) {
            radius /= decrease;
            decrease *= 2.0;
            if (radius < MIN_RADIUS)
                reason = SFM_BA_STOP_TRUST_REGION;
            continue;
        }
        /* step size test */
        double h2 = 0.0, x2 = 0.0, pred = 0.0;
        for (int i = 0; i < nc; i++) {
            double h = w->dc[i];
            h2 += h * h;
            pred += h * (w->gc[i] + w->Dc[i] * h);
        }
        for (int j = 0; j < n; j++) {
            if (!w->pt_free[j])
                continue;
            for (int a = 0; a < 3; a++) {
                double h = w->dp[3 * j + a];
                h2 += h * h;
                pred += h * (w->gp[3 * j + a] + w->Dp[3 * j + a] * h);
            }
        }
        pred *= 0.5;
        for (int i = 0; i < 3 * m; i++)
            x2 += w->t[i] * w->t[i];
        for (int i = 0; i < 3 * n; i++)
            x2 += w->X[i] * w->X[i];
        if (nic > 0)
            for (int i = 0; i < 6 * m; i++)
                x2 += w->K[i] * w->K[i];
        if (sqrt(h2) <= o->parameter_tolerance * (sqrt(x2) + o->parameter_tolerance)) {
            reason = SFM_BA_STOP_PARAMETER;
            break;
        }
        apply_step(&c);
        double cost2 = eval_cost(&c, w->R2, w->t2, w->K2, w->X2);
        double rho = (isfinite(cost2) && pred > 0.0) ? (cost - cost2) / pred : -1.0;
        if (rho > MIN_RELATIVE_DECREASE) {
            double change = cost - cost2;
            swap_ptr(&w->R, &w->R2);
            swap_ptr(&w->t, &w->t2);
            swap_ptr(&w->K, &w->K2);
            swap_ptr(&w->X, &w->X2);
            double prev = cost;
            cost = linearize(&c);
            if (!isfinite(cost)) { /* cannot happen: cost2 was finite */
                swap_ptr(&w->R, &w->R2);
                swap_ptr(&w->t, &w->t2);
                swap_ptr(&w->K, &w->K2);
                swap_ptr(&w->X, &w->X2);
                cost = linearize(&c);
                reason = SFM_BA_STOP_TRUST_REGION;
                break;
            }
            res.successful_steps++;
            double f = 2.0 * rho - 1.0;
            radius = radius / fmax(1.0 / 3.0, 1.0 - f * f * f);
            if (radius > MAX_RADIUS)
                radius = MAX_RADIUS;
            decrease = 2.0;
            if (fabs(change) <= o->function_tolerance * prev)
                reason = SFM_BA_STOP_FUNCTION;
        } else {
            radius /= decrease;
            decrease *= 2.0;
            if (radius < MIN_RADIUS)
                reason = SFM_BA_STOP_TRUST_REGION;
            else if (isfinite(cost2) && fabs(cost - cost2) <= o->function_tolerance * cost)
                reason = SFM_BA_STOP_FUNCTION;
        }
    }
    res.iterations = iter;
    res.stop_reason = reason;
    res.final_cost = cost;

    /* covariance: inverse of the undamped reduced system at the solution.
     * S^-1 is the camera-side block of (J^T W J)^-1. U is reused as the
     * inverse (it is not needed any more). */
    if (o->want_covariance) {
        res.covariance_status = SFM_OK;
        if (nc > 0) {
            if (!form_reduced(&c, 0.0) || sfm_cholesky_factor(w->S, nc) != SFM_OK) {
                res.covariance_status = SFM_E_SINGULAR;
            } else {
                memset(w->U, 0, sizeof(double) * (size_t)nc * (size_t)nc);
                for (int i = 0; i < nc; i++)
                    w->U[(size_t)i * nc + i] = 1.0;
                if (sfm_cholesky_solve(w->S, nc, w->U, nc) != SFM_OK)
                    res.covariance_status = SFM_E_SINGULAR;
            }
        }
    }

    /* scale gauge by distance: scale the scene about camera 0's centre */
    if (scale_gauge == SFM_BA_SCALE_DISTANCE) {
        const double *R0 = w->R, *t0 = w->t;
        const double *Rc = w->R + 9 * scale_cam, *tc = w->t + 3 * scale_cam;
        double C0[3], Cc[3], dist2 = 0.0;
        for (int r = 0; r < 3; r++) {
            C0[r] = -(R0[r] * t0[0] + R0[3 + r] * t0[1] + R0[6 + r] * t0[2]);
            Cc[r] = -(Rc[r] * tc[0] + Rc[3 + r] * tc[1] + Rc[6 + r] * tc[2]);
            dist2 += (Cc[r] - C0[r]) * (Cc[r] - C0[r]);
        }
        if (!(dist2 > 0.0))
            return SFM_E_SINGULAR;
        double s = o->scale_distance / sqrt(dist2);
        for (int j = 0; j < n; j++)
            for (int r = 0; r < 3; r++)
                w->X[3 * j + r] = C0[r] + s * (w->X[3 * j + r] - C0[r]);
        for (int ci = 0; ci < m; ci++) {
            const double *R = w->R + 9 * ci;
            double *tt = w->t + 3 * ci;
            for (int r = 0; r < 3; r++)
                tt[r] = s * tt[r] - (1.0 - s) * (R[3 * r] * C0[0] + R[3 * r + 1] * C0[1] + R[3 * r + 2] * C0[2]);
        }
    }

    /* write outputs */
    if (o->want_covariance && res.covariance_status == SFM_OK) {
        memset(pose_covariance, 0, sizeof(double) * 36 * (size_t)m);
        for (int ci = 0; ci < m; ci++) {
            const int *col = w->cam_col + (size_t)ci * qmax;
            const int *gi = w->cam_gi + (size_t)ci * qmax;
            double *C = pose_covariance + 36 * (size_t)ci;
            for (int a = 0; a < w->cam_q[ci]; a++) {
                if (col[a] >= 6)
                    continue;
                for (int b = 0; b < w->cam_q[ci]; b++) {
                    if (col[b] >= 6)
                        continue;
                    C[6 * col[a] + col[b]] = w->U[(size_t)gi[a] * nc + gi[b]];
                }
            }
        }
    }
    memcpy(p->rotations, w->R, sizeof(double) * 9 * (size_t)m);
    memcpy(p->translations, w->t, sizeof(double) * 3 * (size_t)m);
    memcpy(p->intrinsics, w->K, sizeof(double) * 6 * (size_t)m);
    if (n > 0)
        memcpy(p->points, w->X, sizeof(double) * 3 * (size_t)n);
    *result = res;
    return SFM_OK;
}
