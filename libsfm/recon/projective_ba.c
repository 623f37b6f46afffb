/*
 * Projective bundle adjustment (see projective_ba.h): cameras are unit
 * 12-vectors (11 degrees of freedom, the projective scale removed), points
 * unit homogeneous 4-vectors (3 degrees of freedom), both updated on their
 * spheres; Hartley & Zisserman 18.1 and A6.3. The normal equations are
 * reduced to the cameras by the Schur complement (each point's 3x3 block
 * eliminated) and solved by Cholesky; the driver is the library's one
 * Levenberg-Marquardt loop (core/lm.h). The 15-dimensional projective gauge
 * is left free: the damping keeps the system definite, and the cost does
 * not depend on it.
 */
#include <math.h>
#include <string.h>

#include "core/arena.h"
#include "core/linalg_util.h"
#include "core/lm.h"
#include "recon/projective.h"
#include "recon/projective_ba.h"
#include "recon/selfcal_internal.h"
#include "sfm/sfm_common.h"
#include "sfm/sfm_linalg.h"

enum { CT = 11, PT = 3 };

typedef struct pba {
    int m, n, nobs;
    const int *oc, *op;   /* observation camera / point, grouped by point */
    const double *oxy;    /* normalized observations */
    const double *iscale; /* per camera: pixels per normalized unit */
    const int *first;     /* n + 1: observations of point j are first[j]..first[j+1]-1 */
    double *P, *X;        /* current values */
    double *Pt, *Xt;      /* trial values */
    double *Jc, *Jp, *r;  /* per observation 2x11, 2x3, 2 */
    double *Bc, *Bp;      /* sphere bases per camera (12x11), point (4x3) */
    double *Hcc, *gc;     /* per camera 11x11, 11 */
    double *Hpp, *gp;     /* per point 3x3, 3 */
    double *Cinv;         /* per point damped inverse 3x3 */
    double *S, *rhs, *dc, *dp;
} pba;

static void layout(sfmi_arena *a, int m, int n, int nobs, pba *s)
{
    s->Pt = SFM_ARENA_ARRAY(a, double, 12 * (size_t)m);
    s->Xt = SFM_ARENA_ARRAY(a, double, 4 * (size_t)n);
    s->Jc = SFM_ARENA_ARRAY(a, double, 2 * CT * (size_t)nobs);
    s->Jp = SFM_ARENA_ARRAY(a, double, 2 * PT * (size_t)nobs);
    s->r = SFM_ARENA_ARRAY(a, double, 2 * (size_t)nobs);
    s->Bc = SFM_ARENA_ARRAY(a, double, 12 * CT * (size_t)m);
    s->Bp = SFM_ARENA_ARRAY(a, double, 4 * PT * (size_t)n);
    s->Hcc = SFM_ARENA_ARRAY(a, double, CT * CT * (size_t)m);
    s->gc = SFM_ARENA_ARRAY(a, double, CT * (size_t)m);
    s->Hpp = SFM_ARENA_ARRAY(a, double, PT * PT * (size_t)n);
    s->gp = SFM_ARENA_ARRAY(a, double, PT * (size_t)n);
    s->Cinv = SFM_ARENA_ARRAY(a, double, PT * PT * (size_t)n);
    s->S = SFM_ARENA_ARRAY(a, double, (size_t)CT * m * CT * m);
    s->rhs = SFM_ARENA_ARRAY(a, double, CT * (size_t)m);
    s->dc = SFM_ARENA_ARRAY(a, double, CT * (size_t)m);
    s->dp = SFM_ARENA_ARRAY(a, double, PT * (size_t)n);
}

size_t sfmi_projective_ba_workspace_size(int m, int n, int nobs)
{
    if (m < 2 || n < 1 || nobs < 1)
        return 0;
    sfmi_arena a;
    pba s;
    sfmi_arena_measure(&a);
    layout(&a, m, n, nobs, &s);
    return sfmi_arena_required(&a);
}

/* residual (pixels) of one observation; Jacobians along the sphere bases
 * when Jc != NULL. 0 when the point projects to infinity. */
static int residual(const pba *s, const double *P, const double *X, int k, double r[2], double *Jc, double *Jp)
{
    int i = s->oc[k], j = s->op[k];
    const double *Pi = &P[12 * i], *Xj = &X[4 * j];
    double y[3];
    for (int a = 0; a < 3; a++)
        y[a] = Pi[4 * a] * Xj[0] + Pi[4 * a + 1] * Xj[1] + Pi[4 * a + 2] * Xj[2] + Pi[4 * a + 3] * Xj[3];
    double sc = fabs(y[0]) + fabs(y[1]) + fabs(y[2]);
    if (!(fabs(y[2]) > 1e-12 * sc))
        return 0;
    double u = y[0] / y[2], v = y[1] / y[2], w = s->iscale[i];
    r[0] = w * (u - s->oxy[2 * k]);
    r[1] = w * (v - s->oxy[2 * k + 1]);
    if (Jc == NULL)
        return 1;
    /* d(u, v)/dP (2x12) and d(u, v)/dX (2x4) */
    double dP[2][12] = {{0}}, dX[2][4];
    for (int c = 0; c < 4; c++) {
        dP[0][c] = w * Xj[c] / y[2];
        dP[0][8 + c] = -w * u * Xj[c] / y[2];
        dP[1][4 + c] = w * Xj[c] / y[2];
        dP[1][8 + c] = -w * v * Xj[c] / y[2];
        dX[0][c] = w * (Pi[c] - u * Pi[8 + c]) / y[2];
        dX[1][c] = w * (Pi[4 + c] - v * Pi[8 + c]) / y[2];
    }
    const double *Bc = &s->Bc[12 * CT * i], *Bp = &s->Bp[4 * PT * j];
    for (int e = 0; e < 2; e++) {
        for (int t = 0; t < CT; t++) {
            double acc = 0;
            for (int q = 0; q < 12; q++)
                acc += dP[e][q] * Bc[q * CT + t];
            Jc[e * CT + t] = acc;
        }
        for (int t = 0; t < PT; t++) {
            double acc = 0;
            for (int q = 0; q < 4; q++)
                acc += dX[e][q] * Bp[q * PT + t];
            Jp[e * PT + t] = acc;
        }
    }
    return 1;
}

/* Tangent basis of a unit 12-vector (a camera): the core's sphere basis
 * stops at SFMI_LM_SPHERE_MAX entries, so the same Householder
 * construction is applied here: B = the columns other than k of I - 2 v v^T / v.v, v = x + sign(x_k) |x| e_k. */
static void camera_basis(const double x[12], double B[12 * CT])
{
    int k = 0;
    double nn = 0;
    for (int i = 0; i < 12; i++) {
        nn += x[i] * x[i];
        if (fabs(x[i]) > fabs(x[k]))
            k = i;
    }
    double v[12];
    memcpy(v, x, sizeof v);
    v[k] += (x[k] >= 0 ? 1.0 : -1.0) * sqrt(nn);
    double vv = 0;
    for (int i = 0; i < 12; i++)
        vv += v[i] * v[i];
    double sc = vv > 0 ? 2.0 / vv : 0.0;
    for (int r = 0; r < 12; r++)
        for (int j = 0, c = 0; j < 12; j++) {
            if (j == k)
                continue;
            B[r * CT + c] = (r == j ? 1.0 : 0.0) - sc * v[r] * v[j];
            c++;
        }
}

static double linearize(void *self, double *grad_max)
{
    pba *s = self;
    for (int i = 0; i < s->m; i++)
        camera_basis(&s->P[12 * i], &s->Bc[12 * CT * i]);
    for (int j = 0; j < s->n; j++)
        sfmi_lm_sphere_basis(&s->X[4 * j], 4, &s->Bp[4 * PT * j]);
    memset(s->Hcc, 0, sizeof(double) * CT * CT * (size_t)s->m);
    memset(s->gc, 0, sizeof(double) * CT * (size_t)s->m);
    memset(s->Hpp, 0, sizeof(double) * PT * PT * (size_t)s->n);
    memset(s->gp, 0, sizeof(double) * PT * (size_t)s->n);
    double cost = 0;
    for (int k = 0; k < s->nobs; k++) {
        double *Jc = &s->Jc[2 * CT * k], *Jp = &s->Jp[2 * PT * k], *r = &s->r[2 * k];
        if (!residual(s, s->P, s->X, k, r, Jc, Jp))
            return HUGE_VAL;
        cost += 0.5 * (r[0] * r[0] + r[1] * r[1]);
        int i = s->oc[k], j = s->op[k];
        double *H = &s->Hcc[CT * CT * i], *g = &s->gc[CT * i], *Hp = &s->Hpp[PT * PT * j], *gq = &s->gp[PT * j];
        for (int a = 0; a < CT; a++) {
            g[a] += Jc[a] * r[0] + Jc[CT + a] * r[1];
            for (int b = 0; b < CT; b++)
                H[a * CT + b] += Jc[a] * Jc[b] + Jc[CT + a] * Jc[CT + b];
        }
        for (int a = 0; a < PT; a++) {
            gq[a] += Jp[a] * r[0] + Jp[PT + a] * r[1];
            for (int b = 0; b < PT; b++)
                Hp[a * PT + b] += Jp[a] * Jp[b] + Jp[PT + a] * Jp[PT + b];
        }
    }
    double gm = 0;
    for (int q = 0; q < CT * s->m; q++)
        gm = fmax(gm, fabs(s->gc[q]));
    for (int q = 0; q < PT * s->n; q++)
        gm = fmax(gm, fabs(s->gp[q]));
    *grad_max = gm;
    return cost;
}

static int solve(void *self, double mu, double *step2, double *x2, double *pred)
{
    pba *s = self;
    const int nc = CT * s->m;
    memset(s->S, 0, sizeof(double) * (size_t)nc * nc);
    for (int i = 0; i < s->m; i++) {
        const double *H = &s->Hcc[CT * CT * i];
        for (int a = 0; a < CT; a++) {
            for (int b = 0; b < CT; b++)
                s->S[(size_t)(CT * i + a) * nc + CT * i + b] = H[a * CT + b];
            s->S[(size_t)(CT * i + a) * nc + CT * i + a] += mu * sfmi_lm_clamp_diag(H[a * CT + a]);
            s->rhs[CT * i + a] = -s->gc[CT * i + a];
        }
    }
    for (int j = 0; j < s->n; j++) {
        int k0 = s->first[j], k1 = s->first[j + 1];
        if (k0 == k1)
            continue;
        double C[9];
        memcpy(C, &s->Hpp[9 * j], sizeof C);
        for (int a = 0; a < 3; a++)
            C[4 * a] += mu * sfmi_lm_clamp_diag(C[4 * a]);
        double *Ci = &s->Cinv[9 * j];
        /* det C is the one sfmi_mat3_inverse divides by; an overflowed
         * det would leave Ci = 0 */
        if (!sfmi_mat3_inverse(C, Ci, 0) || !isfinite(sfmi_selfcal_det3(C)))
            return 0;
        /* W_k = Jc_k^T Jp_k (11x3); S -= W_a Ci W_b^T; rhs += W_a Ci gp */
        double Ciq[3];
        for (int a = 0; a < 3; a++)
            Ciq[a] = Ci[3 * a] * s->gp[3 * j] + Ci[3 * a + 1] * s->gp[3 * j + 1] + Ci[3 * a + 2] * s->gp[3 * j + 2];
        for (int ka = k0; ka < k1; ka++) {
            const double *Ja = &s->Jc[2 * CT * ka], *Pa = &s->Jp[2 * PT * ka];
            double Wa[CT * 3], WC[CT * 3];
            for (int t = 0; t < CT; t++)
                for (int q = 0; q < 3; q++)
                    Wa[t * 3 + q] = Ja[t] * Pa[q] + Ja[CT + t] * Pa[PT + q];
            for (int t = 0; t < CT; t++)
                for (int q = 0; q < 3; q++)
                    WC[t * 3 + q] = Wa[t * 3] * Ci[q] + Wa[t * 3 + 1] * Ci[3 + q] + Wa[t * 3 + 2] * Ci[6 + q];
            int ia = s->oc[ka];
            for (int t = 0; t < CT; t++)
                s->rhs[CT * ia + t] += Wa[t * 3] * Ciq[0] + Wa[t * 3 + 1] * Ciq[1] + Wa[t * 3 + 2] * Ciq[2];
            for (int kb = k0; kb < k1; kb++) {
                const double *Jb = &s->Jc[2 * CT * kb], *Pb = &s->Jp[2 * PT * kb];
                int ib = s->oc[kb];
                double Wb[CT * 3];
                for (int t = 0; t < CT; t++)
                    for (int q = 0; q < 3; q++)
                        Wb[t * 3 + q] = Jb[t] * Pb[q] + Jb[CT + t] * Pb[PT + q];
                for (int t = 0; t < CT; t++)
                    for (int u = 0; u < CT; u++)
                        s->S[(size_t)(CT * ia + t) * nc + CT * ib + u] -=
                            WC[t * 3] * Wb[u * 3] + WC[t * 3 + 1] * Wb[u * 3 + 1] + WC[t * 3 + 2] * Wb[u * 3 + 2];
            }
        }
    }
    if (sfm_cholesky_factor(s->S, nc) != SFM_OK)
        return 0;
    memcpy(s->dc, s->rhs, sizeof(double) * nc);
    if (sfm_cholesky_solve(s->S, nc, s->dc, 1) != SFM_OK)
        return 0;
    /* back-substitution and the model decrease -(g.h + h^T J^T J h / 2) */
    double gh = 0, hh = 0, jj = 0;
    for (int q = 0; q < nc; q++) {
        gh += s->gc[q] * s->dc[q];
        hh += s->dc[q] * s->dc[q];
    }
    for (int j = 0; j < s->n; j++) {
        int k0 = s->first[j], k1 = s->first[j + 1];
        double *dp = &s->dp[3 * j];
        if (k0 == k1) {
            dp[0] = dp[1] = dp[2] = 0;
            continue;
        }
        double b[3] = {-s->gp[3 * j], -s->gp[3 * j + 1], -s->gp[3 * j + 2]};
        for (int k = k0; k < k1; k++) {
            const double *Jc = &s->Jc[2 * CT * k], *Jp = &s->Jp[2 * PT * k];
            const double *dci = &s->dc[CT * s->oc[k]];
            for (int e = 0; e < 2; e++) {
                double jd = 0;
                for (int t = 0; t < CT; t++)
                    jd += Jc[e * CT + t] * dci[t];
                for (int q = 0; q < 3; q++)
                    b[q] -= Jp[e * PT + q] * jd;
            }
        }
        const double *Ci = &s->Cinv[9 * j];
        for (int q = 0; q < 3; q++) {
            dp[q] = Ci[3 * q] * b[0] + Ci[3 * q + 1] * b[1] + Ci[3 * q + 2] * b[2];
            gh += s->gp[3 * j + q] * dp[q];
            hh += dp[q] * dp[q];
        }
    }
    for (int k = 0; k < s->nobs; k++) {
        const double *Jc = &s->Jc[2 * CT * k], *Jp = &s->Jp[2 * PT * k];
        const double *dci = &s->dc[CT * s->oc[k]], *dpj = &s->dp[3 * s->op[k]];
        for (int e = 0; e < 2; e++) {
            double jd = 0;
            for (int t = 0; t < CT; t++)
                jd += Jc[e * CT + t] * dci[t];
            for (int q = 0; q < 3; q++)
                jd += Jp[e * PT + q] * dpj[q];
            jj += jd * jd;
        }
    }
    *step2 = hh;
    *x2 = (double)(s->m + s->n); /* unit vectors */
    *pred = -(gh + 0.5 * jj);
    return isfinite(*pred);
}

static double trial(void *self)
{
    pba *s = self;
    for (int i = 0; i < s->m; i++) {
        double d[12];
        const double *B = &s->Bc[12 * CT * i], *dc = &s->dc[CT * i];
        double *out = &s->Pt[12 * i], nrm = 0;
        for (int q = 0; q < 12; q++) {
            d[q] = 0;
            for (int t = 0; t < CT; t++)
                d[q] += B[q * CT + t] * dc[t];
            out[q] = s->P[12 * i + q] + d[q];
            nrm += out[q] * out[q];
        }
        nrm = sqrt(nrm);
        for (int q = 0; q < 12; q++)
            out[q] /= nrm;
    }
    for (int j = 0; j < s->n; j++) {
        const double *B = &s->Bp[4 * PT * j], *dp = &s->dp[3 * j];
        double *out = &s->Xt[4 * j], nrm = 0;
        for (int q = 0; q < 4; q++) {
            out[q] = s->X[4 * j + q] + B[q * PT] * dp[0] + B[q * PT + 1] * dp[1] + B[q * PT + 2] * dp[2];
            nrm += out[q] * out[q];
        }
        nrm = sqrt(nrm);
        for (int q = 0; q < 4; q++)
            out[q] = nrm > 0 ? out[q] / nrm : out[q];
    }
    double cost = 0;
    for (int k = 0; k < s->nobs; k++) {
        double r[2];
        if (!residual(s, s->Pt, s->Xt, k, r, NULL, NULL))
            return HUGE_VAL;
        cost += 0.5 * (r[0] * r[0] + r[1] * r[1]);
    }
    return cost;
}

static void accept(void *self)
{
    pba *s = self;
    memcpy(s->P, s->Pt, sizeof(double) * 12 * (size_t)s->m);
    memcpy(s->X, s->Xt, sizeof(double) * 4 * (size_t)s->n);
}

int sfmi_projective_ba(int m, int n, int nobs, const int *obs_cam, const int *obs_pt, const int *first,
                       const double *obs_xy, const double *iscale, double *P, double *X, int max_iterations,
                       sfmi_lm_summary *summary, void *ws, size_t ws_size)
{
    sfmi_arena a;
    pba s;
    sfmi_arena_init(&a, ws, ws_size);
    layout(&a, m, n, nobs, &s);
    if (!sfmi_arena_ok(&a))
        return SFM_E_WORKSPACE;
    s.m = m;
    s.n = n;
    s.nobs = nobs;
    s.oc = obs_cam;
    s.op = obs_pt;
    s.oxy = obs_xy;
    s.iscale = iscale;
    s.first = first;
    s.P = P;
    s.X = X;
    for (int i = 0; i < m; i++)
        sfmi_normalize_vec(&P[12 * i], 12);
    for (int j = 0; j < n; j++)
        sfmi_normalize_vec(&X[4 * j], 4);
    sfmi_lm_system sys = {&s, linearize, solve, trial, accept, CT * m + PT * n};
    sfmi_lm_options o;
    sfmi_lm_default_options(&o);
    o.max_iterations = max_iterations;
    /* the relative cost change of the default (1e-6) stops a projective
     * adjustment while the weakly constrained tracks still move */
    o.function_tolerance = 1e-10;
    return sfmi_lm_run(&sys, &o, summary);
}
