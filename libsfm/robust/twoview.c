/* Shared two-view estimator machinery (see twoview.h). */
#include "robust/twoview.h"

#include <math.h>
#include <string.h>

#include "core/linalg_util.h"
#include "robust/cheirality.h"
#include "robust/estimator.h"
#include "robust/epipolar.h"
#include "robust/sampson_lm.h"
#include "robust/support_check.h"
#include "robust/support_pose.h"
#include "robust/twoview_degeneracy.h"
#include "solvers/homography_decompose.h"
#include "solvers/normalize.h"

static void layout(sfmi_arena *a, int n, size_t eng_size, twoview_ws *w)
{
    w->b1 = SFM_ARENA_ARRAY(a, double, 3 * (size_t)n);
    w->b2 = SFM_ARENA_ARRAY(a, double, 3 * (size_t)n);
    w->p1 = SFM_ARENA_ARRAY(a, double, 2 * (size_t)n);
    w->p2 = SFM_ARENA_ARRAY(a, double, 2 * (size_t)n);
    w->idx = SFM_ARENA_ARRAY(a, int, n);
    w->sel = SFM_ARENA_ARRAY(a, int, n);
    w->eng = sfmi_arena_alloc(a, eng_size);
    w->eng_size = eng_size;
}

static size_t engine_size(int n, int sample, int max_models)
{
    return sfmi_robust_engine_size(n, sample, max_models, SFM_RANSAC_RELPOSE_MODEL);
}

size_t sfmi_twoview_workspace_size(int n, int sample, int max_models)
{
    if (n < sample || n > SFM_RANSAC_MAX_POINTS)
        return 0;
    size_t es = engine_size(n, sample, max_models);
    if (es == 0)
        return 0;
    sfmi_arena a;
    twoview_ws w;
    sfmi_arena_measure(&a);
    layout(&a, n, es, &w);
    return sfmi_arena_required(&a);
}

int sfmi_twoview_setup(const twoview_call *call, twoview_ws *w, sfm_ransac_options *eopt,
                      double *focal)
{
    const double *px1 = call->px1, *px2 = call->px2;
    const sfm_camera *cam1 = call->cam1, *cam2 = call->cam2;
    const int n = call->n, sample = call->sample, max_models = call->max_models;
    void *ws = call->ws;
    const size_t ws_size = call->ws_size;
    if (px1 == NULL || px2 == NULL || cam1 == NULL || cam2 == NULL || ws == NULL)
        return SFM_E_ARGUMENT;
    int st = sfmi_robust_pair_inputs(px1, px2, n, sample, cam1, cam2, call->opt, eopt);
    if (st < 0)
        return st;
    size_t need = sfmi_twoview_workspace_size(n, sample, max_models);
    if (need == 0)
        return SFM_E_ARGUMENT;
    if (ws_size < need)
        return SFM_E_WORKSPACE;
    sfmi_arena a;
    sfmi_arena_init(&a, ws, ws_size);
    layout(&a, n, engine_size(n, sample, max_models), w);
    if (!sfmi_arena_ok(&a))
        return SFM_E_WORKSPACE;
    st = sfm_camera_unproject_many(cam1, px1, n, w->b1);
    if (st < 0)
        return st;
    st = sfm_camera_unproject_many(cam2, px2, n, w->b2);
    if (st < 0)
        return st;
    double f = 0.25 * (fabs(cam1->fx) + fabs(cam1->fy) + fabs(cam2->fx) + fabs(cam2->fy));
    *focal = f;
    eopt->threshold = eopt->threshold / f;
    if (eopt->wide_mult == 0.0)
        eopt->wide_mult = SFM_RANSAC_WIDE_MULT;
    return SFM_OK;
}

double sfmi_twoview_residual(void *ctx, const double *model, int i)
{
    const twoview_ctx *c = ctx;
    const twoview_model *m = (const twoview_model *)model;
    return sfmi_sampson_bearing2(m->E, c->b1 + 3 * i, c->b2 + 3 * i);
}

#if SFMI_TWOVIEW_HAVE_BLOCK
typedef double tv_v2 __attribute__((vector_size(16)));

/* sfmi_sampson_bearing2 of the points idx[0..count), two at a time in the
 * lanes of a two-lane double: per lane the same operations in the same
 * order as the scalar form, so the same bits (GCC's vector extension, SSE2
 * or NEON; no contraction under -ffp-contract=off). The nine entries of E
 * are broadcast once per call instead of loaded once per point. */
void sfmi_twoview_residuals(void *ctx, const double *model, const int *idx, int count, double *r2)
{
    const twoview_ctx *c = ctx;
    const double *E = ((const twoview_model *)model)->E;
    const double *b1 = c->b1, *b2 = c->b2;
    const tv_v2 E0 = {E[0], E[0]}, E1 = {E[1], E[1]}, E2 = {E[2], E[2]};
    const tv_v2 E3 = {E[3], E[3]}, E4 = {E[4], E[4]}, E5 = {E[5], E[5]};
    const tv_v2 E6 = {E[6], E[6]}, E7 = {E[7], E[7]}, E8 = {E[8], E[8]};
    const tv_v2 two = {2.0, 2.0};
    int q = 0;
    for (; q + 1 < count; q += 2) {
        const double *xa = b1 + 3 * idx[q], *xb = b1 + 3 * idx[q + 1];
        const double *ya = b2 + 3 * idx[q], *yb = b2 + 3 * idx[q + 1];
        const tv_v2 x0 = {xa[0], xb[0]}, x1 = {xa[1], xb[1]}, x2 = {xa[2], xb[2]};
        const tv_v2 y0 = {ya[0], yb[0]}, y1 = {ya[1], yb[1]}, y2 = {ya[2], yb[2]};
        const tv_v2 e0 = E0 * x0 + E1 * x1 + E2 * x2;
        const tv_v2 e1 = E3 * x0 + E4 * x1 + E5 * x2;
        const tv_v2 e2 = E6 * x0 + E7 * x1 + E8 * x2;
        const tv_v2 f0 = E0 * y0 + E3 * y1 + E6 * y2;
        const tv_v2 f1 = E1 * y0 + E4 * y1 + E7 * y2;
        const tv_v2 f2 = E2 * y0 + E5 * y1 + E8 * y2;
        const tv_v2 C = y0 * e0 + y1 * e1 + y2 * e2;
        const tv_v2 D = e0 * e0 + e1 * e1 + e2 * e2 + f0 * f0 + f1 * f1 + f2 * f2 - two * C * C;
        const tv_v2 r = C * C / D;
        r2[q] = D[0] > 1e-300 ? r[0] : SFM_ROBUST_HUGE;
        r2[q + 1] = D[1] > 1e-300 ? r[1] : SFM_ROBUST_HUGE;
    }
    if (q < count)
        r2[q] = sfmi_sampson_bearing2(E, b1 + 3 * idx[q], b2 + 3 * idx[q]);
}
#endif

void sfmi_twoview_set_pose(twoview_model *m, const double R[9], const double t[3])
{
    sfmi_essential_from_pose(R, t, m->E);
    sfmi_normalize9(m->E);
    memmove(m->R, R, 9 * sizeof(double));
    memmove(m->t, t, 3 * sizeof(double));
    m->pose_valid = 1;
    m->unused = 0;
}

/* Upright: keep R, pick the sign of t with most points in front. */
static int upright_sign(const twoview_ctx *c, const int *idx, int n, const double *R, double *t)
{
    double tn[3] = {-t[0], -t[1], -t[2]};
    int cp = 0, cn = 0;
    for (int j = 0; j < n; j++) {
        int i = idx ? idx[j] : j;
        cp += sfmi_robust_in_front(R, t, c->b1 + 3 * i, c->b2 + 3 * i);
        cn += sfmi_robust_in_front(R, tn, c->b1 + 3 * i, c->b2 + 3 * i);
    }
    if (cn > cp) {
        memcpy(t, tn, sizeof tn);
        return cn;
    }
    return cp;
}

void sfmi_twoview_set_scale(void *ctx, double scale)
{
    ((twoview_ctx *)ctx)->scale = scale;
}

/* Cook's distance from which the polish drops a band point: 16 / n, four
 * times the usual 4 / n rule of thumb (Cook 1977), on n band points. On the
 * relative-pose bench (200 scenes per row) it drops the few chance outliers
 * of a small baseline that hold the direction along the valley (about 40 of
 * 750 band points at 25 % outliers, points of high leverage and some
 * residual). A least-squares refit at 4 / n from the polished model gives
 * p90 0.65 deg against 0.60 at 16 / n (small class, 25 %, 2 px, 100 scenes). */
#define PRUNE_COOK 16.0

int sfmi_twoview_prune(void *ctx, const double *model, int *list, int n, double sigma2)
{
    const twoview_ctx *c = ctx;
    const twoview_model *m = (const twoview_model *)model;
    if (!m->pose_valid || n < 1)
        return n;
    return sfmi_sampson_prune(c->b1, c->b2, list, n, c->d2, m->R, m->t, sigma2,
                              PRUNE_COOK / (double)n);
}

int sfmi_twoview_refine(void *ctx, const int *inliers, int n_inliers, double *model)
{
    const twoview_ctx *c = ctx;
    twoview_model *m = (twoview_model *)model;
    double R[9], t[3];
    if (!m->pose_valid) {
        if (sfmi_robust_pose_from_essential(m->E, c->b1, c->b2, inliers, n_inliers, R, t) < 0)
            return -1;
    } else {
        memcpy(R, m->R, sizeof R);
        memcpy(t, m->t, sizeof t);
        if (c->d2 != NULL)
            upright_sign(c, inliers, n_inliers, R, t);
    }
    int st = sfmi_robust_sampson_lm(c->b1, c->b2, inliers, n_inliers, c->d2, c->scale,
                                   SFM_TWOVIEW_LM_STEPS, R, t);
    if (st < 0)
        return -1;
    sfmi_twoview_set_pose(m, R, t);
    return 0;
}

/* z = 1 projections of all bearings scaled by the focal length (pixels of
 * an ideal camera); a bearing at or behind the image plane gets a far
 * sentinel the box and the spread tests skip. */
static void ideal_pixels(const double *b, int n, double f, double *p)
{
    for (int i = 0; i < n; i++) {
        const double *x = b + 3 * i;
        if (x[2] > 1e-3) {
            p[2 * i] = f * x[0] / x[2];
            p[2 * i + 1] = f * x[1] / x[2];
        } else {
            p[2 * i] = 1e9;
            p[2 * i + 1] = 1e9;
        }
    }
}

/* Inliers of idx[0..m) in front of both image planes, compacted into sel. */
static int in_view(const double *p1, const double *p2, const int *idx, int m, int *sel)
{
    int k = 0;
    for (int j = 0; j < m; j++)
        if (p1[2 * idx[j]] < 1e8 && p2[2 * idx[j]] < 1e8)
            sel[k++] = idx[j];
    return k;
}

/* The support checks of sfm_ransac.h on the inliers idx[0..m) of (R, t):
 * SFM_OK with *flags updated (LOW_PARALLAX) and cov6 the pose covariance,
 * or SFM_E_NO_MODEL / SFM_E_DEGENERATE. tau: angular threshold. */
static int support(const twoview_ctx *c, twoview_ws *w, int sample, int m, const double *R,
                   const double *t, double tau, double focal, int *flags, double *cov6)
{
    const double tau_px = tau * focal;
    ideal_pixels(c->b1, c->n, focal, w->p1);
    ideal_pixels(c->b2, c->n, focal, w->p2);
    double diag;
    double area = sfmi_bbox_area(w->p2, 2, c->n, &diag);
    if (!sfmi_above_chance(c->n, sample, m, sfmi_chance_band(area, diag, 2.0 * 1.4142135623730951 * tau_px)))
        return SFM_E_NO_MODEL;
    int k = in_view(w->p1, w->p2, w->idx, m, w->sel);
    if (k >= sample) {
        double lo1, hi1, lo2, hi2;
        sfmi_spread(w->p1, 2, w->sel, k, &lo1, &hi1);
        sfmi_spread(w->p2, 2, w->sel, k, &lo2, &hi2);
        if (sfmi_spread_collinear(lo1, hi1, tau_px) || sfmi_spread_collinear(lo2, hi2, tau_px))
            return SFM_E_DEGENERATE;
        if (hi1 < SFMI_CLUSTER_ANGLE * focal || hi2 < SFMI_CLUSTER_ANGLE * focal)
            return SFM_E_DEGENERATE;
    }
    /* the covariance for a unit residual variance, scaled for the test by
     * the inliers' variance, floored at (tau / 3)^2 */
    double cov1[36], ssr;
    const int np = c->d2 ? 3 : 5;
    if (sfmi_relpose_covariance(c->b1, c->b2, w->idx, m, R, t, c->d2, cov1, &ssr) < 0)
        return SFM_E_DEGENERATE;
    double s2 = m > np ? ssr / (m - np) : ssr;
    double s2_test = s2 > tau * tau / 9.0 ? s2 : tau * tau / 9.0;
    double cov_test[36];
    for (int j = 0; j < 36; j++) {
        cov_test[j] = cov1[j] >= 1e30 ? cov1[j] : s2_test * cov1[j];
        cov6[j] = cov1[j] >= 1e30 ? cov1[j] : s2 * cov1[j];
    }
    if (sfmi_block_sd(cov_test, 0) > SFMI_ROT_SD_MAX)
        return SFM_E_DEGENERATE;
    if (sfmi_block_sd(cov_test, 3) > SFMI_TDIR_SD_MAX)
        *flags |= SFM_RANSAC_FLAG_LOW_PARALLAX;
    return SFM_OK;
}

/* Points of the plane the sign tests of the decomposition average over. */
#define TWIN_POINTS 32

/* The dominant plane's second pose: of the two decompositions of its
 * homography H (z = 1 points p1, p2, the plane's indexed by sel[0..np)),
 * the one farther from the returned pose (R, t) (the other is that pose up
 * to noise). Returns 1 with *twin written, 0 when H yields fewer than two. */
static int plane_twin(const double *H, const double *p1, const double *p2, const int *sel, int np,
                      const double *R, const double *t, sfm_pose *twin)
{
    double q1[2 * TWIN_POINTS], q2[2 * TWIN_POINTS], Rs[2][9], ts[2][3];
    const int k = np < TWIN_POINTS ? np : TWIN_POINTS;
    for (int j = 0; j < k; j++) {
        int i = sel[(int)(((long long)j * np) / k)];
        q1[2 * j] = p1[2 * i];
        q1[2 * j + 1] = p1[2 * i + 1];
        q2[2 * j] = p2[2 * i];
        q2[2 * j + 1] = p2[2 * i + 1];
    }
    if (sfmi_homography_decompose(H, q1, q2, k, Rs, ts) != 2)
        return 0;
    /* closeness: trace(R^T R_k) (3 for the same rotation) plus t . t_k */
    double near[2];
    for (int s = 0; s < 2; s++) {
        double tr = 0.0;
        for (int j = 0; j < 9; j++)
            tr += R[j] * Rs[s][j];
        near[s] = tr + t[0] * ts[s][0] + t[1] * ts[s][1] + t[2] * ts[s][2];
    }
    const int far = near[0] < near[1] ? 0 : 1;
    memcpy(twin->R, Rs[far], sizeof twin->R);
    memcpy(twin->t, ts[far], sizeof twin->t);
    return 1;
}

static int finish(const twoview_call *call, const twoview_ctx *c, twoview_ws *w,
                  const twoview_model *model, double tau, double focal, int n_inl,
                  const sfm_ransac_stats *est, int want_cov)
{
    const double tau2 = tau * tau;
    const int upright = c->d2 != NULL;
    int m = 0;
    for (int i = 0; i < c->n; i++)
        if (sfmi_sampson_bearing2(model->E, c->b1 + 3 * i, c->b2 + 3 * i) < tau2)
            w->idx[m++] = i;
    double R[9], t[3];
    if (upright) {
        memcpy(R, model->R, sizeof R);
        memcpy(t, model->t, sizeof t);
        upright_sign(c, w->idx, m, R, t);
    } else if (sfmi_robust_pose_from_essential(model->E, c->b1, c->b2, w->idx, m, R, t) < 0) {
        return SFM_E_NO_CONVERGENCE;
    }
    double H[9];
    int n_plane = 0;
    int flags = sfmi_robust_twoview_degeneracy(c->b1, c->b2, w->idx, m, R, t, tau, est->seed, w->p1,
                                              w->p2, w->sel, H, &n_plane);
    sfm_pose twin;
    int has_twin = (flags & SFM_RANSAC_FLAG_PLANAR) && !upright &&
                   plane_twin(H, w->p1, w->p2, w->sel, n_plane, R, t, &twin);
    /* the decomposition of a homography fitted on the z = 1 plane, refined
     * on the inliers as the pose was (both poses fit the plane's points) */
    if (has_twin)
        has_twin = sfmi_robust_sampson_lm(c->b1, c->b2, w->idx, m, NULL, tau,
                                          4 * SFM_TWOVIEW_LM_STEPS, twin.R, twin.t) >= 0;
    double cov6[36];
    int st = support(c, w, call->sample, m, R, t, tau, focal, &flags, cov6);
    if (st < 0)
        return st;
    /* outputs from here on: nothing can fail any more */
    memcpy(call->pose->R, R, sizeof R);
    memcpy(call->pose->t, t, sizeof t);
    if (call->E != NULL) {
        sfmi_essential_from_pose(R, t, call->E);
        sfmi_normalize9(call->E);
    }
    if (call->mask != NULL)
        for (int i = 0; i < c->n; i++)
            call->mask[i] =
                (uint8_t)(sfmi_sampson_bearing2(model->E, c->b1 + 3 * i, c->b2 + 3 * i) < tau2);
    if (call->stats != NULL) {
        *call->stats = *est;
        call->stats->score = est->score * focal * focal;
        call->stats->flags = flags;
        call->stats->has_twin = has_twin;
        if (has_twin)
            call->stats->twin = twin;
        call->stats->cov_dim = want_cov ? 6 : 0;
        if (want_cov)
            memcpy(call->stats->covariance, cov6, sizeof cov6);
    }
    return n_inl;
}

int sfmi_twoview_run(const twoview_call *call, twoview_ctx *c, twoview_ws *w,
                    const sfm_ransac_options *eopt, double focal)
{
    sfm_ransac_estimator est = {call->sample,
                                call->max_models,
                                SFM_RANSAC_RELPOSE_MODEL,
                                call->solve,
                                sfmi_twoview_residual,
                                sfmi_twoview_refine,
                                NULL,
                                NULL,
                                c,
                                sfmi_twoview_set_scale,
#if SFMI_TWOVIEW_HAVE_BLOCK
                                sfmi_twoview_residuals,
#else
                                NULL,
#endif
                                sfmi_twoview_prune};
    twoview_model model;
    sfm_ransac_stats es;
    int ni = sfm_ransac_run(&est, c->n, eopt, (double *)&model, NULL, &es, w->eng, w->eng_size);
    if (ni < 0)
        return ni;
    return finish(call, c, w, &model, eopt->threshold, focal, ni, &es, eopt->want_covariance != 0);
}
