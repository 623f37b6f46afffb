/*
 * Homography by RANSAC over 4-point samples, scored on the Sampson error in
 * pixels (Hartley & Zisserman 4.2.6: the first-order distance of a pair to
 * the homography, with noise in both images); LO and final polish by a
 * normalised DLT refit followed by a few Levenberg-Marquardt steps on the
 * same error (homography_lm.c). A transfer error in one image, or the larger
 * of the two, weighs a point by how much H stretches the image around it:
 * under strong perspective (a ground plane towards the horizon) the far
 * points of the plane fall out of the inlier band, and the fit leans on the
 * near ones.
 * Model: H[9] (unit Frobenius norm, nonsingular).
 */
#include <math.h>
#include <string.h>

#include "robust/epipolar.h"
#include "robust/estimator.h"
#include "robust/homography_lm.h"
#include "robust/pixel_pairs.h"
#include "robust/support_check.h"
#include "sfm/sfm_solvers.h"
#include "solvers/normalize.h"

#define HMODEL SFM_RANSAC_HOMOGRAPHY_MODEL
/* LM steps per refinement round. */
#define H_LM_STEPS 4

/* The model the engine carries (it copies models as bytes, HMODEL doubles). */
typedef struct h_model {
    double H[9]; /* unit Frobenius norm, not singular */
} h_model;
_Static_assert(sizeof(h_model) == HMODEL * sizeof(double), "h_model is the engine's model size");

typedef struct h_ctx {
    const double *p1, *p2;
    double *g1, *g2;
    double tau;
} h_ctx;

/* m = H at unit Frobenius norm; 0 when H is singular. */
static int finish_model(const double *H, h_model *m)
{
    double adj[9];
    memmove(m->H, H, sizeof m->H);
    if (sfmi_normalize9(m->H))
        return 0;
    double det = sfmi_adj3(m->H, adj);
    if (!(fabs(det) > 1e-15))
        return 0;
    return 1;
}

static int solve4(void *ctx, const int *s, double *models)
{
    const h_ctx *c = ctx;
    double a[8], b[8];
    sfmi_robust_gather(c->p1, 2, s, 4, a);
    sfmi_robust_gather(c->p2, 2, s, 4, b);
    sfm_mat3 H;
    int ns = sfm_homography_4pt(a, b, &H);
    if (ns < 0)
        return ns == SFM_E_NONFINITE ? 0 : ns;
    if (ns == 0)
        return 0;
    return finish_model(H.m, (h_model *)models);
}

static double residual(void *ctx, const double *model, int i)
{
    const h_ctx *c = ctx;
    const h_model *m = (const h_model *)model;
    return sfmi_robust_homography_sampson2(m->H, c->p1 + 2 * i, c->p2 + 2 * i);
}

/* A linear refit (normalised DLT), then LM on the Sampson error from
 * whichever of it and the current model has the lower robust cost. It runs
 * on the points within 2 thresholds (the estimator forces wide_mult 2): a
 * random point falls inside a disc of 2 tau around its transfer with
 * probability ~ 4 pi tau^2 / image area, so the band adds true inliers and
 * almost no outliers; a Cauchy loss keeps those few from pulling. Its scale
 * is 2 tau: the Sampson errors of true inliers reach tau (3 sigma), and a
 * scale of tau would down-weight them too (on synthetic planes that cost
 * about 2 % of accuracy against the truth). */
static int refine(void *ctx, const int *inl, int n, double *model)
{
    h_ctx *c = ctx;
    h_model *m = (h_model *)model;
    if (n < 4)
        return -1;
    double H[9];
    memcpy(H, m->H, sizeof H);
    sfmi_pixel_pairs_refit(c->p1, c->p2, inl, n, c->tau, sfm_homography_dlt,
                           sfmi_robust_homography_cost, c->g1, c->g2, H);
    (void)sfmi_robust_homography_lm(c->g1, c->g2, n, 2.0 * c->tau, H_LM_STEPS, H);
    h_model tmp;
    if (!finish_model(H, &tmp))
        return -1;
    *m = tmp;
    return 0;
}

size_t sfm_ransac_homography_workspace_size(int n)
{
    return sfmi_pixel_pairs_workspace_size(n, 4, SFM_HOMOGRAPHY_4PT_MAX_SOLUTIONS, HMODEL);
}

int sfm_ransac_homography(const double *px1, const double *px2, int n, const sfm_camera *cam1,
                          const sfm_camera *cam2, const sfm_ransac_options *opt, sfm_mat3 *H_out,
                          uint8_t *inlier_mask, sfm_ransac_stats *stats, void *ws, size_t ws_size)
{
    double *H = H_out ? H_out->m : NULL;
    if (H == NULL)
        return SFM_E_ARGUMENT;
    pixel_pairs pp;
    sfm_ransac_options eopt;
    int st = sfmi_pixel_pairs_setup(px1, px2, n, cam1, cam2, opt, 4,
                                   SFM_HOMOGRAPHY_4PT_MAX_SOLUTIONS, HMODEL, ws, ws_size, &pp,
                                   &eopt);
    if (st < 0)
        return st;
    eopt.wide_mult = 2.0;
    h_ctx c = {pp.p1, pp.p2, pp.g1, pp.g2, eopt.threshold};
    sfm_ransac_estimator est = {4, SFM_HOMOGRAPHY_4PT_MAX_SOLUTIONS, HMODEL, solve4,
                                residual, refine, NULL, NULL, &c, NULL, NULL, NULL};
    h_model model;
    sfm_ransac_stats rs;
    int ni = sfm_ransac_run(&est, n, &eopt, (double *)&model, NULL, &rs, pp.eng, pp.eng_size);
    if (ni < 0)
        return ni;
    const double tau2 = eopt.threshold * eopt.threshold;
    int m = 0;
    for (int i = 0; i < n; i++)
        if (sfmi_robust_homography_sampson2(model.H, c.p1 + 2 * i, c.p2 + 2 * i) < tau2)
            pp.idx[m++] = i;
    /* a random pair is an inlier when it lands within about sqrt(2) tau of
     * the transfer (the Sampson error splits the distance over both images) */
    double diag, area = sfmi_bbox_area(pp.p2, 2, n, &diag);
    st = sfmi_pixel_pairs_support(&pp, n, 4, m,
                                 sfmi_chance_disc(area, 1.4142135623730951 * eopt.threshold), 1,
                                 eopt.threshold);
    if (st < 0)
        return st;
    /* outputs from here on: nothing can fail any more */
    memcpy(H, model.H, sizeof model.H);
    if (inlier_mask != NULL)
        for (int i = 0; i < n; i++)
            inlier_mask[i] =
                (uint8_t)(sfmi_robust_homography_sampson2(model.H, c.p1 + 2 * i, c.p2 + 2 * i) < tau2);
    if (stats != NULL) {
        *stats = rs;
        stats->cov_dim = 0;
    }
    return ni;
}
