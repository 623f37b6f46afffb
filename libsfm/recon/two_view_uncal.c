/*
 * Uncalibrated two-view reconstruction: fundamental RANSAC with DEGENSAC,
 * Bougnoux's focal length, focal sweep, metric bundle adjustment, physical
 * checks (see sfm_uncalibrated.h).
 */
#include <math.h>
#include <string.h>

#include "core/arena.h"
#include "core/linalg_util.h"
#include "recon/metric_upgrade.h"
#include "sfm/sfm_ransac.h"
#include "sfm/sfm_triangulate.h"
#include "sfm/sfm_uncalibrated.h"

typedef struct twu_ws {
    double *xc[3]; /* the third unused */
    uint8_t *mask;
    void *ransac_ws;
    size_t ransac_size;
    sfmi_mu mu;
} twu_ws;

static void layout(sfmi_arena *a, int n, twu_ws *w)
{
    for (int v = 0; v < 2; v++)
        w->xc[v] = SFM_ARENA_ARRAY(a, double, 2 * (size_t)n);
    w->xc[2] = NULL;
    w->mask = SFM_ARENA_ARRAY(a, uint8_t, n);
    w->ransac_size = sfm_ransac_fundamental_workspace_size(n);
    w->ransac_ws = sfmi_arena_alloc(a, w->ransac_size);
    sfmi_mu_layout(a, 2, n, 0, &w->mu); /* two views stay pinhole */
}

size_t sfm_recon_two_view_uncalibrated_workspace_size(int n)
{
    if (n < 8 || n > SFM_RANSAC_MAX_POINTS)
        return 0;
    sfmi_arena a;
    twu_ws w;
    sfmi_arena_measure(&a);
    layout(&a, n, &w);
    return sfmi_arena_required(&a);
}

static void cross3(const double a[3], const double b[3], double c[3])
{
    c[0] = a[1] * b[2] - a[2] * b[1];
    c[1] = a[2] * b[0] - a[0] * b[2];
    c[2] = a[0] * b[1] - a[1] * b[0];
}

/* Unit vector e with M^T e = 0 for a rank-2 3x3 M: the largest cross
 * product of two of its columns. */
static int left_null(const double M[9], double e[3])
{
    double c[3][3], best = 0;
    for (int k = 0; k < 3; k++)
        for (int r = 0; r < 3; r++)
            c[k][r] = M[3 * r + k];
    for (int a = 0; a < 3; a++)
        for (int b = a + 1; b < 3; b++) {
            double x[3];
            cross3(c[a], c[b], x);
            double s = x[0] * x[0] + x[1] * x[1] + x[2] * x[2];
            if (s > best) {
                best = s;
                memcpy(e, x, sizeof x);
            }
        }
    if (!(best > 0))
        return 0;
    best = sqrt(best);
    for (int k = 0; k < 3; k++)
        e[k] /= best;
    return 1;
}

/* Bougnoux: the focal length of the second camera of F (x2^T F x1 = 0),
 * principal points at the origin:
 * f^2 = -(p'^T [e']x I~ F p p^T F^T p') / (p'^T [e']x I~ F I~ F^T p'),
 * I~ = diag(1, 1, 0), p = p' = (0, 0, 1). 0 when f^2 <= 0. */
static double bougnoux(const double F[9])
{
    double e[3];
    if (!left_null(F, e))
        return 0;
    /* a = p'^T [e']x = (e' x p')^T ... written out: [e']x^T p' = -e' x p' */
    const double p[3] = {0, 0, 1};
    double ex_p[3];
    cross3(e, p, ex_p); /* [e]x p */
    double row[3] = {-ex_p[0], -ex_p[1], -ex_p[2]}; /* p^T [e]x = -([e]x p)^T */
    /* row I~ F */
    double rIF[3];
    for (int k = 0; k < 3; k++)
        rIF[k] = row[0] * F[k] + row[1] * F[3 + k];
    /* numerator: (rIF . p) (p^T F^T p') = rIF[2] * F[8] */
    double num = rIF[2] * F[8];
    /* denominator: rIF I~ F^T p' = sum_{k<2} rIF[k] * F[2*3 + k]... (F^T p')_k = F[6 + k] */
    double den = rIF[0] * F[6] + rIF[1] * F[7];
    if (!(fabs(den) > 0))
        return 0;
    double f2 = -num / den;
    return f2 > 0 && isfinite(f2) ? sqrt(f2) : 0;
}

typedef struct twu_ctx {
    twu_ws *w;
    int n, width, height;
} twu_ctx;

/* One run from fundamental RANSAC to the checked metric answer. */
static int once2(void *ctx, const sfm_uncal_options *o, sfm_pose est[3], double *f, sfm_uncal_report *rep)
{
    twu_ctx *c = ctx;
    twu_ws *w = c->w;
    const int n = c->n, width = c->width, height = c->height;
    rep->stage = SFM_UNCAL_STAGE_RANSAC;
    sfmi_mu *mu = &w->mu;
    int cnt = sfm_ransac_fundamental(w->xc[0], w->xc[1], n, NULL, NULL, &o->ransac, &mu->F[0], w->mask,
                                     &rep->ransac, w->ransac_ws, w->ransac_size);
    int st = cnt;
    if (cnt < 0)
        return st;
    rep->ransac_inliers = cnt;
    mu->thr = o->ransac.threshold;
    mu->evaluations = 0;

    /* inliers and their error under the canonical cameras of F:
     * P1 = [I | 0], P2 = [[e']x F | e'] */
    double e[3], P1[12] = {1, 0, 0, 0, 0, 1, 0, 0, 0, 0, 1, 0}, P2[12];
    st = SFM_E_SINGULAR;
    if (!left_null(mu->F[0].m, e))
        return st;
    for (int r = 0; r < 3; r++) {
        for (int k = 0; k < 3; k++) {
            const double *F = mu->F[0].m;
            double ex[9] = {0, -e[2], e[1], e[2], 0, -e[0], -e[1], e[0], 0};
            P2[4 * r + k] = ex[3 * r] * F[k] + ex[3 * r + 1] * F[3 + k] + ex[3 * r + 2] * F[6 + k];
        }
        P2[4 * r + 3] = e[r];
    }
    int m = 0;
    double se = 0;
    for (int i = 0; i < n; i++) {
        if (!w->mask[i])
            continue;
        double Xh[3];
        int fl;
        if (sfm_triangulate_optimal2(P1, P2, 1, &w->xc[0][2 * i], &w->xc[1][2 * i], Xh, &fl) < 0)
            continue;
        const double *Ps[2] = {P1, P2};
        for (int v = 0; v < 2; v++) {
            double y[3];
            for (int r = 0; r < 3; r++)
                y[r] = Ps[v][4 * r] * Xh[0] + Ps[v][4 * r + 1] * Xh[1] + Ps[v][4 * r + 2] * Xh[2] + Ps[v][4 * r + 3];
            if (fabs(y[2]) > 0) {
                double du = y[0] / y[2] - w->xc[v][2 * i], dv = y[1] / y[2] - w->xc[v][2 * i + 1];
                se += du * du + dv * dv;
            }
        }
        for (int v = 0; v < 2; v++) {
            mu->x[v][2 * m] = w->xc[v][2 * i];
            mu->x[v][2 * m + 1] = w->xc[v][2 * i + 1];
        }
        mu->idx[m] = i;
        m++;
    }
    mu->m = m;
    rep->projective_rms = m > 0 ? sqrt(se / (2.0 * m)) : 0;
    if (m < 9)
        return st;

    /* Bougnoux for each camera (F and F^T), shared: their mean */
    rep->stage = SFM_UNCAL_STAGE_SELFCAL;
    {
        double Ft[9];
        for (int r = 0; r < 3; r++)
            for (int k = 0; k < 3; k++)
                Ft[3 * r + k] = mu->F[0].m[3 * k + r];
        double f2 = bougnoux(mu->F[0].m), f1 = bougnoux(Ft);
        if (f1 > 0 && f2 > 0)
            rep->focal_linear = 0.5 * (f1 + f2);
        else
            rep->focal_linear = f1 > 0 ? f1 : f2;
        rep->linear_status = rep->focal_linear > 0 ? SFM_OK : SFM_E_SINGULAR;
    }

    const double *xall[3] = {w->xc[0], w->xc[1], NULL};
    st = sfmi_mu_solve(mu, xall, n, rep->focal_linear, (double)(width > height ? width : height), o, est, f,
                       rep);
    rep->evaluations = mu->evaluations;
    return st;
}

int sfm_recon_two_view_uncalibrated(const double *px1, const double *px2, int n, int width, int height,
                                    const sfm_uncal_options *opt, double *K, sfm_pose poses[2],
                                    double *X, uint8_t *inlier_mask, sfm_uncal_report *report, void *ws,
                                    size_t ws_size)
{
    if (px1 == NULL || px2 == NULL || K == NULL || poses == NULL || ws == NULL || n < 8 ||
        n > SFM_RANSAC_MAX_POINTS || width < 2 || height < 2)
        return SFM_E_ARGUMENT;
    sfm_uncal_options o;
    if (sfmi_uncal_options(opt, &o) < 0)
        return SFM_E_ARGUMENT;
    sfmi_arena a;
    twu_ws w;
    sfmi_arena_init(&a, ws, ws_size);
    layout(&a, n, &w);
    sfm_uncal_report rep;
    const double *px[3] = {px1, px2, NULL};
    if (!sfmi_arena_ok(&a))
        return SFM_E_WORKSPACE;
    int st0 = sfmi_uncal_centre(2, px, n, width, height, w.xc, &rep);
    if (st0 < 0)
        return st0;
    const double cx = 0.5 * (width - 1), cy = 0.5 * (height - 1);
    sfmi_mu *mu = &w.mu;
    double f[3];
    sfm_pose est[3];
    twu_ctx ctx = {&w, n, width, height};
    int st = sfmi_uncal_attempts(once2, &ctx, &o, n, est, f, &rep);
    if (st < 0)
        goto fail;
    sfmi_mu_outputs(mu, n, f, cx, cy, K, X, inlier_mask);
    memcpy(poses, est, 2 * sizeof(sfm_pose));
    if (report != NULL)
        *report = rep;
    return mu->m;
fail:
    if (report != NULL)
        *report = rep;
    return st;
}
