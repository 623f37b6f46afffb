/*
 * Gold-standard refinement for the trifocal tensor (Hartley & Zisserman,
 * 2nd ed., alg. 16.2 step (iii)): minimize the reprojection error over the
 * cameras P2, P3 and the points, P1 = [I | 0] held. Points are homogeneous
 * unit 4-vectors updated in their 3-dimensional tangent space, so points at
 * infinity of the projective frame need no special case (the driver's
 * SFMI_LM_SPHERE update and basis). The projective gauge left after fixing
 * P1 (4 DOF) and the camera scales are absorbed by a small additive
 * regularisation of the camera block beside the driver's damping; cameras
 * are rescaled to unit norm after each accepted step.
 *
 * The system handed to the LM driver eliminates the points (Schur
 * complement, H&Z A6.3): per point the 3x3 block V_j = Jp^T Jp (damped) is
 * inverted, the reduced 24x24 camera system S = U - sum W_j V_j^-1 W_j^T is
 * solved by Cholesky, and each point's step follows by back-substitution.
 * A camera Jacobian is a Kronecker product with the point (point_h), so
 * W_j V_j^-1 W_j^T is a 6x6 matrix times X_j X_j^T: the sums over the points
 * are kept per distinct entry (21 x 10) and unpacked into the lower triangle
 * once per solve.
 * The per-point Jacobians are recomputed in each solve rather than stored, so
 * the workspace stays at a few doubles per point.
 */
#include "core/linalg_util.h"
#include "robust/trifocal_refine.h"

#include <math.h>
#include <string.h>

#include "core/lm.h"
#include "sfm/sfm_common.h"
#include "sfm/sfm_linalg.h"
#include "sfm/sfm_trifocal.h"
#include "solvers/trifocal_internal.h"

enum { NC = 24 };

void sfmi_tf_refine_layout(sfmi_arena *a, int n, sfmi_tf_refine_ws *w)
{
    w->X = SFM_ARENA_ARRAY(a, double, 4 * (size_t)n);
    w->Xold = SFM_ARENA_ARRAY(a, double, 4 * (size_t)n);
    w->U = SFM_ARENA_ARRAY(a, double, NC * NC);
    w->S = SFM_ARENA_ARRAY(a, double, NC * NC);
    w->cap = n;
}

const double sfmi_tf_P1[12] = {1, 0, 0, 0, 0, 1, 0, 0, 0, 0, 1, 0};
#define P1 sfmi_tf_P1

static double total_cost(const double *const xs[3], const int *idx, int n, const double *P2,
                         const double *P3, const double *X)
{
    const double *P[3] = {P1, P2, P3};
    double c = 0;
    for (int q = 0; q < n; q++) {
        int p = idx[q];
        for (int v = 0; v < 3; v++) {
            double r[2];
            if (!sfmi_tf_residual(P[v], &X[4 * q], &xs[v][2 * p], r, NULL, NULL))
                return HUGE_VAL;
            c += r[0] * r[0] + r[1] * r[1];
        }
    }
    return c;
}

typedef sfmi_tf_point_blocks point_blocks;

int sfmi_tf_point_jacobians(const double *const xs[3], int p, const double *P2, const double *P3,
                           const double X[4], point_blocks *b)
{
    const double *P[3] = {P1, P2, P3};
    sfmi_tf_sphere_basis4(X, b->B);
    const double *B = b->B;
    for (int v = 0; v < 3; v++) {
        double JX[8];
        if (!sfmi_tf_residual(P[v], X, &xs[v][2 * p], &b->r[2 * v], JX,
                              v > 0 ? &b->cam[3 * (v - 1)] : NULL))
            return 0;
        for (int h = 0; h < 2; h++)
            for (int c = 0; c < 3; c++)
                b->Jp[(2 * v + h) * 3 + c] = JX[h * 4] * B[c] + JX[h * 4 + 1] * B[3 + c] +
                                             JX[h * 4 + 2] * B[6 + c] + JX[h * 4 + 3] * B[9 + c];
    }
    return 1;
}

/* The camera Jacobian of view v (2 or 3) has the Kronecker form
 * iw [X^T 0 -u X^T; 0 X^T -v X^T] = iw N (x) X^T, N = [1 0 -u; 0 1 -v]
 * (sfmi_trifocal_residual), so every product with it factors into a 3-row
 * part and X: with G_v = iw N^T Jp_v (3x3), W_v = Jc_v^T Jp_v = G_v (x) X,
 * Jc_v^T Jc_v = iw^2 N^T N (x) X X^T and Jc_v^T r_v = iw N^T r_v (x) X. The
 * camera entry P_v[i][c] is row 4 i + c of its block. H holds G_2 over G_3
 * (6x3). */
static void point_h(const point_blocks *b, double H[18])
{
    for (int w = 0; w < 2; w++) {
        const double iw = b->cam[3 * w], u = b->cam[3 * w + 1], v = b->cam[3 * w + 2];
        const double *j0 = &b->Jp[(2 + 2 * w) * 3], *j1 = &b->Jp[(3 + 2 * w) * 3];
        double *h = &H[9 * w];
        for (int k = 0; k < 3; k++) {
            h[k] = iw * j0[k];
            h[3 + k] = iw * j1[k];
            h[6 + k] = -iw * (u * j0[k] + v * j1[k]);
        }
    }
}

/* V = Jp^T Jp (3x3, symmetric), gp = Jp^T r. */
static void point_products(const point_blocks *b, double V[9], double gp[3])
{
    for (int a = 0; a < 3; a++) {
        gp[a] = 0;
        for (int k = 0; k < 6; k++)
            gp[a] += b->Jp[k * 3 + a] * b->r[k];
        for (int c = 0; c <= a; c++) {
            double s = 0;
            for (int k = 0; k < 6; k++)
                s += b->Jp[k * 3 + a] * b->Jp[k * 3 + c];
            V[a * 3 + c] = V[c * 3 + a] = s;
        }
    }
}

/* Sums of Kronecker products K (x) X X^T over the points, K symmetric
 * (nk x nk, nk <= 6), in packed form: acc[pk][px] += K_pk (X X^T)_px over
 * the nk (nk + 1) / 2 lower entries pk of K and the 10 lower entries px of
 * X X^T, so each point costs one product per distinct entry of the sum. */
enum { KRON_MAX = 21, XX_N = 10 };

static void kron_accumulate(double acc[KRON_MAX][XX_N], const double *K, int nk, const double X[4])
{
    double xx[XX_N];
    for (int c = 0, p = 0; c < 4; c++)
        for (int d = 0; d <= c; d++)
            xx[p++] = X[c] * X[d];
    for (int ka = 0, pk = 0; ka < nk; ka++)
        for (int kb = 0; kb <= ka; kb++, pk++) {
            const double k = K[ka * nk + kb];
            double *a = acc[pk];
            for (int p = 0; p < XX_N; p++)
                a[p] += k * xx[p];
        }
}

/* S[a][b] += s (sum) over the lower triangle (b <= a) of the rows
 * a = 4 ka + ca, ka < nk, of the packed sum; S has row stride NC. */
static void kron_add_lower(double *S, double acc[KRON_MAX][XX_N], int nk, double s)
{
    for (int ka = 0; ka < nk; ka++)
        for (int kb = 0; kb <= ka; kb++) {
            const double *a = acc[ka * (ka + 1) / 2 + kb];
            for (int ca = 0; ca < 4; ca++) {
                double *Srow = S + (size_t)(4 * ka + ca) * NC + 4 * kb;
                for (int cb = 0; cb < 4 && (kb < ka || cb <= ca); cb++) {
                    const int hi = ca > cb ? ca : cb, lo = ca > cb ? cb : ca;
                    Srow[cb] += s * a[hi * (hi + 1) / 2 + lo];
                }
            }
        }
}

/* The LM system: cameras A2, A3 and points X at the current point; the
 * trial B2, B3, Xt (formed by solve). U (lower triangle), Udiag, gc: the
 * camera block of the normal equations at the current point. */
typedef struct tf_sys {
    const double *const *xs;
    const int *idx;
    int n;
    double A2[12], A3[12], B2[12], B3[12];
    double *X, *Xt;
    double *U, *S; /* NC x NC */
    double Udiag[NC], gc[NC], dc[NC];
} tf_sys;

/* The camera block's regularisation beside the damping: the Schur
 * complement's diagonal vanishes along the gauge directions. */
static double gauge_reg(double u)
{
    return 1e-12 * (u + 1.0);
}

static double tf_linearize(void *self, double *gmax)
{
    tf_sys *c = self;
    /* the cost is summed from the Jacobians' residuals, which are
     * total_cost's terms in its order (the same bits); a point no view
     * projects makes it infinite there and here */
    double cost = 0.0;
    memset(c->U, 0, sizeof(double) * NC * NC);
    memset(c->gc, 0, sizeof c->gc);
    double m = 0.0, acc[2][KRON_MAX][XX_N];
    memset(acc, 0, sizeof acc);
    for (int q = 0; q < c->n; q++) {
        point_blocks b;
        const double *X = &c->X[4 * q];
        if (!sfmi_tf_point_jacobians(c->xs, c->idx[q], c->A2, c->A3, X, &b))
            return HUGE_VAL;
        for (int v = 0; v < 3; v++)
            cost += b.r[2 * v] * b.r[2 * v] + b.r[2 * v + 1] * b.r[2 * v + 1];
        for (int w = 0; w < 2; w++) {
            const double iw = b.cam[3 * w], u = b.cam[3 * w + 1], v = b.cam[3 * w + 2];
            const double *r = &b.r[2 + 2 * w];
            /* iw^2 N^T N and iw N^T r */
            const double iw2 = iw * iw;
            const double M[9] = {iw2, 0, -iw2 * u, 0, iw2, -iw2 * v, -iw2 * u, -iw2 * v, iw2 * (u * u + v * v)};
            const double g[3] = {r[0], r[1], -u * r[0] - v * r[1]};
            kron_accumulate(acc[w], M, 3, X);
            for (int i = 0; i < 3; i++)
                for (int k = 0; k < 4; k++)
                    c->gc[12 * w + 4 * i + k] += iw * g[i] * X[k];
        }
        for (int a = 0; a < 3; a++) { /* gp = Jp^T r, for the gradient bound */
            double gp = 0;
            for (int k = 0; k < 6; k++)
                gp += b.Jp[k * 3 + a] * b.r[k];
            m = fmax(m, fabs(gp));
        }
    }
    if (!isfinite(cost))
        return HUGE_VAL;
    for (int w = 0; w < 2; w++)
        kron_add_lower(c->U + (size_t)(12 * w) * NC + 12 * w, acc[w], 3, 1.0);
    for (int a = 0; a < NC; a++) {
        c->Udiag[a] = c->U[a * NC + a];
        m = fmax(m, fabs(c->gc[a]));
    }
    *gmax = m;
    /* the driver's cost is half the sum of squares */
    return 0.5 * cost;
}

/* Point q's damped block and its inverse; 0 when not invertible. */
static int point_system(const tf_sys *c, int q, double mu, point_blocks *b, double gp[3],
                        double Vi[9], double Dp[3])
{
    double V[9];
    if (!sfmi_tf_point_jacobians(c->xs, c->idx[q], c->A2, c->A3, &c->X[4 * q], b))
        return 0;
    point_products(b, V, gp);
    for (int k = 0; k < 3; k++) {
        Dp[k] = mu * sfmi_lm_clamp_diag(V[k * 4]);
        V[k * 4] += Dp[k];
    }
    return sfmi_mat3_inverse(V, Vi, 1e-300);
}

static int tf_solve(void *self, double mu, double *step2, double *x2, double *pred)
{
    tf_sys *c = self;
    double *S = c->S, rhs[NC], Dc[NC];
    memcpy(S, c->U, sizeof(double) * NC * NC);
    for (int a = 0; a < NC; a++) {
        Dc[a] = mu * sfmi_lm_clamp_diag(c->Udiag[a]) + gauge_reg(c->Udiag[a]);
        S[a * NC + a] += Dc[a];
        rhs[a] = c->gc[a];
    }
    /* reduced camera system S dc = -(gc - sum W V^-1 gp), with
     * W V^-1 W^T = (H V^-1 H^T) (x) X X^T (point_h) */
    double acc[KRON_MAX][XX_N];
    memset(acc, 0, sizeof acc);
    for (int q = 0; q < c->n; q++) {
        point_blocks b;
        double gp[3], Vi[9], Dp[3], H[18], HV[18], K[36], y[6];
        if (!point_system(c, q, mu, &b, gp, Vi, Dp))
            continue;
        point_h(&b, H);
        for (int a = 0; a < 6; a++)
            for (int k = 0; k < 3; k++)
                HV[a * 3 + k] = H[a * 3] * Vi[k] + H[a * 3 + 1] * Vi[3 + k] + H[a * 3 + 2] * Vi[6 + k];
        for (int a = 0; a < 6; a++) {
            for (int k = 0; k <= a; k++)
                K[a * 6 + k] = HV[a * 3] * H[k * 3] + HV[a * 3 + 1] * H[k * 3 + 1] + HV[a * 3 + 2] * H[k * 3 + 2];
            y[a] = HV[a * 3] * gp[0] + HV[a * 3 + 1] * gp[1] + HV[a * 3 + 2] * gp[2];
        }
        const double *X = &c->X[4 * q];
        kron_accumulate(acc, K, 6, X);
        for (int a = 0; a < 6; a++)
            for (int k = 0; k < 4; k++)
                rhs[4 * a + k] -= y[a] * X[k];
    }
    kron_add_lower(S, acc, 6, -1.0);
    for (int a = 0; a < NC; a++)
        c->dc[a] = -rhs[a];
    if (sfm_cholesky_factor(S, NC) != SFM_OK || sfm_cholesky_solve(S, NC, c->dc, 1) != SFM_OK)
        return 0;
    double h2 = 0.0, xx = 0.0, pr = 0.0;
    for (int a = 0; a < NC; a++) {
        const double h = c->dc[a];
        h2 += h * h;
        pr += h * (Dc[a] * h - c->gc[a]);
    }
    for (int k = 0; k < 12; k++) {
        c->B2[k] = c->A2[k] + c->dc[k];
        c->B3[k] = c->A3[k] + c->dc[12 + k];
        xx += c->A2[k] * c->A2[k] + c->A3[k] * c->A3[k];
    }
    /* back-substitution: each point's step, applied on its sphere;
     * W^T dc = H^T z with z = (dP_2 X, dP_3 X) */
    for (int q = 0; q < c->n; q++) {
        const double *X = &c->X[4 * q];
        double *Xt = &c->Xt[4 * q];
        point_blocks b;
        double gp[3], Vi[9], Dp[3], H[18], z[6], r3[3], d[3];
        memcpy(Xt, X, 4 * sizeof(double));
        for (int k = 0; k < 4; k++)
            xx += X[k] * X[k];
        if (!point_system(c, q, mu, &b, gp, Vi, Dp))
            continue;
        point_h(&b, H);
        for (int a = 0; a < 6; a++) {
            const double *dp = &c->dc[4 * a];
            z[a] = dp[0] * X[0] + dp[1] * X[1] + dp[2] * X[2] + dp[3] * X[3];
        }
        for (int k = 0; k < 3; k++) {
            r3[k] = -gp[k];
            for (int a = 0; a < 6; a++)
                r3[k] -= H[a * 3 + k] * z[a];
        }
        for (int k = 0; k < 3; k++) {
            d[k] = Vi[k * 3] * r3[0] + Vi[k * 3 + 1] * r3[1] + Vi[k * 3 + 2] * r3[2];
            h2 += d[k] * d[k];
            pr += d[k] * (Dp[k] * d[k] - gp[k]);
        }
        const double *B = b.B;
        double nn = 0;
        for (int r = 0; r < 4; r++) {
            Xt[r] = X[r] + B[r * 3] * d[0] + B[r * 3 + 1] * d[1] + B[r * 3 + 2] * d[2];
            nn += Xt[r] * Xt[r];
        }
        nn = sqrt(nn);
        for (int r = 0; r < 4; r++)
            Xt[r] /= nn;
    }
    *step2 = h2;
    *x2 = xx;
    *pred = 0.5 * pr;
    return isfinite(h2) && isfinite(pr);
}

static double tf_trial(void *self)
{
    tf_sys *c = self;
    double cost = total_cost(c->xs, c->idx, c->n, c->B2, c->B3, c->Xt);
    return isfinite(cost) ? 0.5 * cost : HUGE_VAL;
}

static void tf_accept(void *self)
{
    tf_sys *c = self;
    (void)sfmi_trifocal_normalize(c->B2, 12);
    (void)sfmi_trifocal_normalize(c->B3, 12);
    memcpy(c->A2, c->B2, sizeof c->A2);
    memcpy(c->A3, c->B3, sizeof c->A3);
    double *t = c->X;
    c->X = c->Xt;
    c->Xt = t;
}

double sfmi_tf_refine(const double *x1, const double *x2, const double *x3, const int *idx, int n,
                     const double *X0, double P2[12], double P3[12], int max_iters,
                     sfmi_tf_refine_ws *w, int *status)
{
    const double *xs[3] = {x1, x2, x3};
    *status = SFM_OK;
    if (n > w->cap || n < SFM_TRIFOCAL_MIN_POINTS || max_iters < 0) {
        *status = SFM_E_ARGUMENT;
        return HUGE_VAL;
    }
    tf_sys c;
    c.xs = xs;
    c.idx = idx;
    c.n = n;
    c.X = w->X;
    c.Xt = w->Xold;
    c.U = w->U;
    c.S = w->S;
    memcpy(c.A2, P2, sizeof c.A2);
    memcpy(c.A3, P3, sizeof c.A3);
    (void)sfmi_trifocal_normalize(c.A2, 12);
    (void)sfmi_trifocal_normalize(c.A3, 12);
    /* Initial points: optimal triangulation under the current cameras,
     * unless the caller has it. */
    for (int q = 0; q < n; q++) {
        int p = idx[q];
        double e;
        if (X0 != NULL) {
            memcpy(&c.X[4 * q], &X0[4 * (size_t)p], 4 * sizeof(double));
            continue;
        }
        int st = sfm_trifocal_point_error(P1, c.A2, c.A3, &x1[2 * p], &x2[2 * p], &x3[2 * p], &e, &c.X[4 * q]);
        if (st < 0) {
            *status = st;
            return HUGE_VAL;
        }
    }
    sfmi_lm_options opt;
    sfmi_lm_default_options(&opt);
    opt.max_iterations = max_iters;
    opt.function_tolerance = 1e-10;
    /* From a minimal-sample start the Gauss-Newton step is already good and
     * the gauge directions are held by gauge_reg: start nearly undamped
     * (1e-8), or the few LO steps are spent shrinking the damping (at most
     * 3x per accepted step) before the points converge. */
    opt.initial_radius = 1e8;
    opt.gradient_tolerance = 0.0;
    opt.step_tolerance = 0.0;
    const sfmi_lm_system sys = {&c, tf_linearize, tf_solve, tf_trial, tf_accept, 2 * 12 + 3 * n};
    sfmi_lm_summary sum;
    if (sfmi_lm_run(&sys, &opt, &sum) != SFM_OK) {
        *status = SFM_E_SINGULAR;
        return HUGE_VAL;
    }
    memcpy(P2, c.A2, sizeof c.A2);
    memcpy(P3, c.A3, sizeof c.A3);
    return 2.0 * sum.final_cost;
}
