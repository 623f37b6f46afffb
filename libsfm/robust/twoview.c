/* Shared two-view estimator machinery (see twoview.h). */
#include "robust/twoview.h"

#include <math.h>
#include <string.h>

#include "core/linalg_util.h"
#include "robust/cheirality.h"
#include "robust/estimator.h"
#include "robust/epipolar.h"
#include "robust/sampson_lm.h"
#include "robust/twoview_degeneracy.h"
#include "solvers/normalize.h"

static void layout(sfm_arena *a, int n, size_t eng_size, twoview_ws *w)
{
    w->b1 = SFM_ARENA_ARRAY(a, double, 3 * (size_t)n);
    w->b2 = SFM_ARENA_ARRAY(a, double, 3 * (size_t)n);
    w->p1 = SFM_ARENA_ARRAY(a, double, 2 * (size_t)n);
    w->p2 = SFM_ARENA_ARRAY(a, double, 2 * (size_t)n);
    w->idx = SFM_ARENA_ARRAY(a, int, n);
    w->sel = SFM_ARENA_ARRAY(a, int, n);
    w->eng = sfm_arena_alloc(a, eng_size);
    w->eng_size = eng_size;
}

static size_t engine_size(int n, int sample, int max_models)
{
    return sfm_robust_engine_size(n, sample, max_models, SFM_RANSAC_RELPOSE_MODEL);
}

size_t sfm_twoview_workspace_size(int n, int sample, int max_models)
{
    if (n < sample || n > SFM_RANSAC_MAX_POINTS)
        return 0;
    size_t es = engine_size(n, sample, max_models);
    if (es == 0)
        return 0;
    sfm_arena a;
    twoview_ws w;
    sfm_arena_measure(&a);
    layout(&a, n, es, &w);
    return sfm_arena_required(&a);
}

int sfm_twoview_setup(const double *px1, const double *px2, int n, const sfm_camera *cam1,
                      const sfm_camera *cam2, const sfm_ransac_options *opt, int sample,
                      int max_models, void *ws, size_t ws_size, twoview_ws *w,
                      sfm_ransac_options *eopt, double *focal)
{
    if (px1 == NULL || px2 == NULL || cam1 == NULL || cam2 == NULL || ws == NULL)
        return SFM_E_ARGUMENT;
    if (n < sample || n > SFM_RANSAC_MAX_POINTS)
        return SFM_E_ARGUMENT;
    int st = sfm_robust_options(opt, eopt);
    if (st < 0)
        return st;
    st = sfm_camera_validate(cam1);
    if (st < 0)
        return st;
    st = sfm_camera_validate(cam2);
    if (st < 0)
        return st;
    if (!sfm_la_all_finite(px1, 2 * (size_t)n) || !sfm_la_all_finite(px2, 2 * (size_t)n))
        return SFM_E_NONFINITE;
    size_t need = sfm_twoview_workspace_size(n, sample, max_models);
    if (need == 0)
        return SFM_E_ARGUMENT;
    if (ws_size < need)
        return SFM_E_WORKSPACE;
    sfm_arena a;
    sfm_arena_init(&a, ws, ws_size);
    layout(&a, n, engine_size(n, sample, max_models), w);
    if (!sfm_arena_ok(&a))
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

double sfm_twoview_residual(void *ctx, const double *model, int i)
{
    const twoview_ctx *c = ctx;
    return sfm_sampson_bearing2(model + TV_E, c->b1 + 3 * i, c->b2 + 3 * i);
}

void sfm_twoview_set_pose(double *model, const double R[9], const double t[3])
{
    sfm_essential_from_pose(R, t, model + TV_E);
    sfm__normalize9(model + TV_E);
    memmove(model + TV_R, R, 9 * sizeof(double));
    memmove(model + TV_T, t, 3 * sizeof(double));
    model[TV_VALID] = 1.0;
}

/* Upright: keep R, pick the sign of t with most points in front. */
static int upright_sign(const twoview_ctx *c, const int *idx, int n, const double *R, double *t)
{
    double tn[3] = {-t[0], -t[1], -t[2]};
    int cp = 0, cn = 0;
    for (int j = 0; j < n; j++) {
        int i = idx ? idx[j] : j;
        cp += sfm_robust_in_front(R, t, c->b1 + 3 * i, c->b2 + 3 * i);
        cn += sfm_robust_in_front(R, tn, c->b1 + 3 * i, c->b2 + 3 * i);
    }
    if (cn > cp) {
        memcpy(t, tn, sizeof tn);
        return cn;
    }
    return cp;
}

void sfm_twoview_set_scale(void *ctx, double scale)
{
    ((twoview_ctx *)ctx)->scale = scale;
}

int sfm_twoview_refine(void *ctx, const int *inliers, int n_inliers, double *model)
{
    const twoview_ctx *c = ctx;
    double R[9], t[3];
    if (model[TV_VALID] == 0.0) {
        if (sfm_robust_pose_from_essential(model + TV_E, c->b1, c->b2, inliers, n_inliers, R, t) < 0)
            return -1;
    } else {
        memcpy(R, model + TV_R, sizeof R);
        memcpy(t, model + TV_T, sizeof t);
        if (c->d2 != NULL)
            upright_sign(c, inliers, n_inliers, R, t);
    }
    int st = sfm_robust_sampson_lm(c->b1, c->b2, inliers, n_inliers, c->d2, c->scale,
                                   SFM_TWOVIEW_LM_STEPS, R, t);
    if (st < 0)
        return -1;
    sfm_twoview_set_pose(model, R, t);
    return 0;
}

int sfm_twoview_finish(const twoview_ctx *c, twoview_ws *w, const double *model, double tau,
                       double focal, int upright, int n_inl, const sfm_ransac_stats *est,
                       sfm_pose *pose, double E[9], uint8_t *mask, sfm_ransac_stats *stats)
{
    const double tau2 = tau * tau;
    int m = 0;
    for (int i = 0; i < c->n; i++)
        if (sfm_sampson_bearing2(model + TV_E, c->b1 + 3 * i, c->b2 + 3 * i) < tau2)
            w->idx[m++] = i;
    double R[9], t[3];
    if (upright) {
        memcpy(R, model + TV_R, sizeof R);
        memcpy(t, model + TV_T, sizeof t);
        upright_sign(c, w->idx, m, R, t);
    } else if (sfm_robust_pose_from_essential(model + TV_E, c->b1, c->b2, w->idx, m, R, t) < 0) {
        return SFM_E_NO_CONVERGENCE;
    }
    int flags = sfm_robust_twoview_degeneracy(c->b1, c->b2, w->idx, m, R, tau, est->seed, w->p1,
                                              w->p2, w->sel);
    /* outputs from here on: nothing can fail any more */
    memcpy(pose->R, R, sizeof R);
    memcpy(pose->t, t, sizeof t);
    if (E != NULL) {
        sfm_essential_from_pose(R, t, E);
        sfm__normalize9(E);
    }
    if (mask != NULL)
        for (int i = 0; i < c->n; i++)
            mask[i] = (uint8_t)(sfm_sampson_bearing2(model + TV_E, c->b1 + 3 * i, c->b2 + 3 * i) < tau2);
    if (stats != NULL) {
        *stats = *est;
        stats->score = est->score * focal * focal;
        stats->flags = flags;
    }
    return n_inl;
}

int sfm_twoview_run(twoview_ctx *c, twoview_ws *w, const sfm_ransac_options *eopt, int sample,
                    int max_models, int (*solve)(void *ctx, const int *s, double *models),
                    double focal, sfm_pose *pose, double E[9], uint8_t *mask,
                    sfm_ransac_stats *stats)
{
    sfm_ransac_estimator est = {sample,
                                max_models,
                                SFM_RANSAC_RELPOSE_MODEL,
                                solve,
                                sfm_twoview_residual,
                                sfm_twoview_refine,
                                NULL,
                                NULL,
                                c,
                                sfm_twoview_set_scale};
    double model[SFM_RANSAC_RELPOSE_MODEL];
    sfm_ransac_stats es;
    int ni = sfm_ransac_run(&est, c->n, eopt, model, NULL, &es, w->eng, w->eng_size);
    if (ni < 0)
        return ni;
    return sfm_twoview_finish(c, w, model, eopt->threshold, focal, c->d2 != NULL, ni, &es, pose,
                              E, mask, stats);
}
