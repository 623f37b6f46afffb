/*
 * Uncalibrated three-view reconstruction: trifocal RANSAC, linear
 * self-calibration, focal sweep, metric bundle adjustment, physical checks
 * (see sfm_uncalibrated.h).
 */
#include <math.h>
#include <string.h>

#include "core/arena.h"
#include "core/linalg_util.h"
#include "recon/metric_upgrade.h"
#include "sfm/sfm_ransac_trifocal.h"
#include "sfm/sfm_selfcal.h"
#include "sfm/sfm_trifocal.h"
#include "sfm/sfm_uncalibrated.h"

typedef struct tu_ws {
    double *xc[3];  /* n x 2 centred pixels */
    uint8_t *mask;  /* n */
    double *Xh;     /* n x 4 projective points of the RANSAC inliers */
    void *ransac_ws;
    size_t ransac_size;
    sfmi_mu mu;
} tu_ws;

static void layout(sfmi_arena *a, int n, int radial, tu_ws *w)
{
    for (int v = 0; v < 3; v++)
        w->xc[v] = SFM_ARENA_ARRAY(a, double, 2 * (size_t)n);
    w->mask = SFM_ARENA_ARRAY(a, uint8_t, n);
    w->Xh = SFM_ARENA_ARRAY(a, double, 4 * (size_t)n);
    w->ransac_size = sfm_ransac_trifocal_workspace_size(n);
    w->ransac_ws = sfmi_arena_alloc(a, w->ransac_size);
    sfmi_mu_layout(a, 3, n, radial, &w->mu);
}

int sfm_uncal_default_options(sfm_uncal_options *opt)
{
    if (opt == NULL)
        return SFM_E_ARGUMENT;
    sfm_ransac_default_options(&opt->ransac);
    opt->sweep_steps = 17;
    opt->sweep_iterations = 4;
    opt->focal_min = 0.2;
    opt->focal_max = 5.0;
    opt->max_rms = 0;
    opt->min_front = 0.95;
    opt->min_profile = 100;
    opt->min_parallax_deg = 0.5;
    opt->max_focal_sigma = 0.05 / 3;
    opt->per_view_focal = 0;
    opt->radial = 2;
    opt->principal_sigma = 0.01;
    opt->aspect_sigma = 0.0025;
    return SFM_OK;
}

int sfmi_uncal_check_options(const sfm_uncal_options *o);
int sfmi_uncal_check_options(const sfm_uncal_options *o)
{
    if (o->sweep_steps < 2 || o->sweep_steps > SFM_UNCAL_MAX_SWEEP || o->sweep_iterations < 1 ||
        o->sweep_iterations > 50 || !(o->focal_min > 0) ||
        !(o->focal_max > o->focal_min) || !isfinite(o->focal_max) || !(o->max_rms >= 0) ||
        !isfinite(o->max_rms) || !(o->min_front >= 0 && o->min_front <= 1) || !(o->min_profile >= 0) ||
        !isfinite(o->min_profile) ||
        !(o->max_focal_sigma > 0) || (o->per_view_focal != 0 && o->per_view_focal != 1) ||
        (o->radial < 0 || o->radial > 2) || !(o->principal_sigma >= 0 && o->principal_sigma < 1) ||
        !(o->aspect_sigma >= 0 && o->aspect_sigma < 1) || !(o->min_parallax_deg >= 0) || !isfinite(o->min_parallax_deg) || !(o->ransac.threshold > 0))
        return SFM_E_ARGUMENT;
    return SFM_OK;
}

size_t sfm_recon_three_view_uncalibrated_workspace_size_radial(int n, int radial)
{
    if (n < SFM_TRIFOCAL_MIN_POINTS || n > SFM_RANSAC_MAX_POINTS || radial < 0 || radial > 2)
        return 0;
    sfmi_arena a;
    tu_ws w;
    sfmi_arena_measure(&a);
    layout(&a, n, radial, &w);
    return sfmi_arena_required(&a);
}

size_t sfm_recon_three_view_uncalibrated_workspace_size(int n)
{
    return sfm_recon_three_view_uncalibrated_workspace_size_radial(n, 2);
}

/* One run from RANSAC to the checked metric answer. */
static int attempt_once(tu_ws *w, int n, const sfm_uncal_options *o, int width, int height, sfm_pose est[3],
                        double *f, sfm_uncal_report *rep)
{
    double T[27], P[36];
    rep->stage = SFM_UNCAL_STAGE_RANSAC;
    int cnt = sfm_ransac_trifocal(w->xc[0], w->xc[1], w->xc[2], n, &o->ransac, T, P, w->mask, &rep->ransac,
                                  w->ransac_ws, w->ransac_size);
    int st = cnt;
    if (cnt < 0)
        return st;
    rep->ransac_inliers = cnt;

    /* the inliers, their projective points and error */
    sfmi_mu *mu = &w->mu;
    mu->thr = o->ransac.threshold;
    mu->evaluations = 0;
    int m = 0;
    double se = 0;
    for (int i = 0; i < n; i++) {
        if (!w->mask[i])
            continue;
        double e2, Xh[4];
        if (sfm_trifocal_point_error(&P[0], &P[12], &P[24], &w->xc[0][2 * i], &w->xc[1][2 * i],
                                     &w->xc[2][2 * i], &e2, Xh) != SFM_OK)
            continue;
        se += e2;
        memcpy(&w->Xh[4 * m], Xh, sizeof Xh);
        for (int v = 0; v < 3; v++) {
            mu->x[v][2 * m] = w->xc[v][2 * i];
            mu->x[v][2 * m + 1] = w->xc[v][2 * i + 1];
        }
        mu->idx[m] = i;
        m++;
    }
    mu->m = m;
    rep->projective_rms = m > 0 ? sqrt(se / (3.0 * m)) : 0;
    st = SFM_E_SINGULAR;
    if (m < SFM_TRIFOCAL_MIN_POINTS + 1)
        return st;
    st = sfm_trifocal_fundamentals(T, &mu->F[0], &mu->F[1], NULL);
    if (st < 0)
        return st;

    /* linear self-calibration (centred coordinates: prior principal point 0,
     * passed as an image of size 1 centred there) */
    rep->stage = SFM_UNCAL_STAGE_SELFCAL;
    {
        double Kl[27], Hl[16];
        const double wh[6] = {1, 1, 1, 1, 1, 1};
        sfm_selfcal_result sr;
        memset(&sr, 0, sizeof sr);
        /* the image size sets the focal guess: keep it, move the centre */
        double Pg[36];
        const double s = 0.5 * (width + height);
        for (int v = 0; v < 3; v++)
            for (int k = 0; k < 12; k++)
                Pg[12 * v + k] = k < 8 ? P[12 * v + k] / s : P[12 * v + k];
        rep->linear_status = sfm_selfcal_linear(3, Pg, wh, m, w->Xh, Kl, Hl, &sr);
        rep->linear_flags = sr.flags;
        if (rep->linear_status == SFM_OK) {
            double fl = (Kl[0] + Kl[9] + Kl[18]) / 3.0 * s;
            rep->focal_linear = fl > 0 && isfinite(fl) ? fl : 0;
        }
    }

    const double *xall[3] = {w->xc[0], w->xc[1], w->xc[2]};
    st = sfmi_mu_solve(mu, xall, n, rep->focal_linear, (double)(width > height ? width : height), o, est,
                       f, rep);
    rep->evaluations = mu->evaluations;
    return st;
}

typedef struct tu_ctx {
    tu_ws *w;
    int n, width, height;
} tu_ctx;

static int once3(void *ctx, const sfm_uncal_options *o, sfm_pose est[3], double *f, sfm_uncal_report *rep)
{
    tu_ctx *c = ctx;
    return attempt_once(c->w, c->n, o, c->width, c->height, est, f, rep);
}

int sfm_recon_three_view_uncalibrated(const double *px1, const double *px2, const double *px3, int n,
                                      int width, int height, const sfm_uncal_options *opt,
                                      double *K, sfm_pose poses[3], double *X, uint8_t *inlier_mask,
                                      sfm_uncal_report *report, void *ws, size_t ws_size)
{
    if (px1 == NULL || px2 == NULL || px3 == NULL || K == NULL || poses == NULL || ws == NULL ||
        n < SFM_TRIFOCAL_MIN_POINTS || n > SFM_RANSAC_MAX_POINTS || width < 2 || height < 2)
        return SFM_E_ARGUMENT;
    sfm_uncal_options o;
    if (sfmi_uncal_options(opt, &o) < 0)
        return SFM_E_ARGUMENT;
    sfmi_arena a;
    tu_ws w;
    sfmi_arena_init(&a, ws, ws_size);
    layout(&a, n, o.radial, &w);
    sfm_uncal_report rep;
    const double *px[3] = {px1, px2, px3};
    if (!sfmi_arena_ok(&a))
        return SFM_E_WORKSPACE;
    int st0 = sfmi_uncal_centre(3, px, n, width, height, w.xc, &rep);
    if (st0 < 0)
        return st0;
    const double cx = 0.5 * (width - 1), cy = 0.5 * (height - 1);
    double f[3];
    sfm_pose est[3];
    sfmi_mu *mu = &w.mu;
    tu_ctx ctx = {&w, n, width, height};
    int st = sfmi_uncal_attempts(once3, &ctx, &o, n, est, f, &rep);
    if (st < 0)
        goto fail;

    sfmi_mu_outputs(mu, n, f, cx, cy, K, X, inlier_mask);
    memcpy(poses, est, sizeof est);
    if (report != NULL)
        *report = rep;
    return mu->m;
fail:
    if (report != NULL)
        *report = rep;
    return st;
}
