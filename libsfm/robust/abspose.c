/*
 * Absolute pose by RANSAC over P3P samples (Persson & Nordberg, "Lambda
 * Twist", ECCV 2018), scored on the tangent-plane reprojection error with
 * SPRT + MSAC, LO by Levenberg-Marquardt on that error over the inliers.
 */
#include <math.h>
#include <string.h>

#include "core/arena.h"
#include "core/linalg_util.h"
#include "robust/epipolar.h"
#include "robust/estimator.h"
#include "robust/reproj_lm.h"
#include "robust/support_check.h"
#include "robust/support_pose.h"
#include "sfm/sfm_pose.h"
#include "sfm/sfm_ransac.h"

#define ABS_LM_STEPS 4

/* The model the engine carries (it copies models as bytes,
 * SFM_RANSAC_ABSPOSE_MODEL doubles): the pose x_cam = R X + t. */
typedef sfm_pose abs_model;
_Static_assert(sizeof(abs_model) == SFM_RANSAC_ABSPOSE_MODEL * sizeof(double),
               "abs_model is the engine's model size");

typedef struct abs_ctx {
    const double *b; /* unit bearings n x 3 */
    const double *X; /* world points n x 3 */
    double scale;    /* robust scale of the refit: the threshold (normalised) */
} abs_ctx;

static int solve_p3p(void *ctx, const int *s, double *models)
{
    const abs_ctx *c = ctx;
    double x[9], X[9];
    sfm_pose P[SFM_P3P_MAX_SOLUTIONS];
    sfmi_robust_gather(c->b, 3, s, 3, x);
    sfmi_robust_gather(c->X, 3, s, 3, X);
    int ns = sfm_p3p(x, X, P);
    if (ns < 0)
        return ns == SFM_E_NONFINITE ? 0 : ns;
    abs_model *m = (abs_model *)models;
    for (int k = 0; k < ns; k++)
        m[k] = P[k];
    return ns;
}

static double pose_residual(const abs_ctx *c, const abs_model *m, int i)
{
    return sfmi_robust_reproj2(m->R, m->t, c->b + 3 * i, c->X + 3 * i);
}

static double residual(void *ctx, const double *model, int i)
{
    return pose_residual(ctx, (const abs_model *)model, i);
}

static int refine(void *ctx, const int *inl, int n, double *model)
{
    const abs_ctx *c = ctx;
    abs_model *m = (abs_model *)model;
    if (n < 3)
        return -1;
    return sfmi_robust_reproj_lm(c->b, c->X, inl, n, c->scale, ABS_LM_STEPS, m->R, m->t) < 0 ? -1 : 0;
}

/* The support checks of sfm_ransac.h on the inliers of model (tau: the
 * normalised threshold, f: the focal length in pixels). */
static int support(const abs_ctx *c, const double *px, int n, const abs_model *m, double tau,
                   double f, int *idx, double *cov6)
{
    const double tau2 = tau * tau;
    int k = 0;
    for (int i = 0; i < n; i++)
        if (pose_residual(c, m, i) < tau2)
            idx[k++] = i;
    double diag;
    double area = sfmi_bbox_area(px, 2, n, &diag);
    if (!sfmi_above_chance(n, 3, k, sfmi_chance_disc(area, tau * f)))
        return SFM_E_NO_MODEL;
    double lo, hi;
    sfmi_spread(px, 2, idx, k, &lo, &hi);
    if (sfmi_spread_collinear(lo, hi, tau * f) || hi < SFMI_CLUSTER_ANGLE * f)
        return SFM_E_DEGENERATE;
    double cov1[36], ssr, depth;
    if (sfmi_abspose_covariance(c->b, c->X, idx, k, m->R, m->t, cov1, &ssr, &depth) < 0)
        return SFM_E_DEGENERATE;
    double s2 = k > 6 ? ssr / (2 * k - 6) : ssr;
    double s2_test = s2 > tau2 / 9.0 ? s2 : tau2 / 9.0;
    double cov_test[36];
    for (int j = 0; j < 36; j++) {
        cov_test[j] = s2_test * cov1[j];
        cov6[j] = s2 * cov1[j];
    }
    if (sfmi_block_sd(cov_test, 0) > SFMI_ROT_SD_MAX ||
        !(sfmi_block_sd(cov_test, 3) <= SFMI_TREL_SD_MAX * depth))
        return SFM_E_DEGENERATE;
    return SFM_OK;
}

static void layout(sfmi_arena *a, int n, size_t es, double **b, int **idx, void **eng)
{
    *b = SFM_ARENA_ARRAY(a, double, 3 * (size_t)n);
    *idx = SFM_ARENA_ARRAY(a, int, n);
    *eng = sfmi_arena_alloc(a, es);
}

static size_t engine_size(int n)
{
    return sfmi_robust_engine_size(n, 3, SFM_P3P_MAX_SOLUTIONS, SFM_RANSAC_ABSPOSE_MODEL);
}

size_t sfm_ransac_abspose_workspace_size(int n)
{
    if (n < 3 || n > SFM_RANSAC_MAX_POINTS)
        return 0;
    sfmi_arena a;
    double *b;
    int *idx;
    void *eng;
    sfmi_arena_measure(&a);
    layout(&a, n, engine_size(n), &b, &idx, &eng);
    return sfmi_arena_required(&a);
}

int sfm_ransac_abspose(const double *px, const double *X, int n, const sfm_camera *cam,
                       const sfm_ransac_options *opt, sfm_pose *pose, uint8_t *inlier_mask,
                       sfm_ransac_stats *stats, void *ws, size_t ws_size)
{
    if (px == NULL || X == NULL || cam == NULL || pose == NULL || ws == NULL)
        return SFM_E_ARGUMENT;
    if (n < 3 || n > SFM_RANSAC_MAX_POINTS)
        return SFM_E_ARGUMENT;
    sfm_ransac_options eopt;
    int st = sfmi_robust_options(opt, &eopt);
    if (st < 0)
        return st;
    st = sfm_camera_validate(cam);
    if (st < 0)
        return st;
    if (!sfmi_la_all_finite(px, 2 * (size_t)n) || !sfmi_la_all_finite(X, 3 * (size_t)n))
        return SFM_E_NONFINITE;
    size_t need = sfm_ransac_abspose_workspace_size(n);
    if (ws_size < need)
        return SFM_E_WORKSPACE;
    sfmi_arena a;
    double *b;
    int *idx;
    void *eng;
    size_t es = engine_size(n);
    sfmi_arena_init(&a, ws, ws_size);
    layout(&a, n, es, &b, &idx, &eng);
    if (!sfmi_arena_ok(&a))
        return SFM_E_WORKSPACE;
    st = sfm_camera_unproject_many(cam, px, n, b);
    if (st < 0)
        return st;
    const double f = 0.5 * (fabs(cam->fx) + fabs(cam->fy));
    eopt.threshold /= f;
    if (eopt.wide_mult == 0.0)
        eopt.wide_mult = SFM_RANSAC_WIDE_MULT;
    abs_ctx c = {b, X, eopt.threshold};
    sfm_ransac_estimator est = {3, SFM_P3P_MAX_SOLUTIONS, SFM_RANSAC_ABSPOSE_MODEL, solve_p3p,
                                residual, refine, NULL, NULL, &c, NULL, NULL, NULL};
    abs_model model;
    sfm_ransac_stats s;
    int ni = sfm_ransac_run(&est, n, &eopt, (double *)&model, NULL, &s, eng, es);
    if (ni == SFM_E_NO_CONVERGENCE) {
        /* P3P has no solution for points on one line (their image is a
         * line): name the degeneracy rather than the symptom */
        double lo, hi;
        sfmi_spread(px, 2, NULL, n, &lo, &hi);
        if (sfmi_spread_collinear(lo, hi, eopt.threshold * f))
            return SFM_E_DEGENERATE;
    }
    if (ni < 0)
        return ni;
    double cov6[36];
    st = support(&c, px, n, &model, eopt.threshold, f, idx, cov6);
    if (st < 0)
        return st;
    const int want_cov = eopt.want_covariance != 0;
    /* outputs from here on: nothing can fail any more */
    *pose = model;
    if (inlier_mask != NULL)
        for (int i = 0; i < n; i++)
            inlier_mask[i] = (uint8_t)(pose_residual(&c, &model, i) < eopt.threshold * eopt.threshold);
    if (stats != NULL) {
        *stats = s;
        stats->score = s.score * f * f;
        stats->cov_dim = want_cov ? 6 : 0;
        if (want_cov)
            memcpy(stats->covariance, cov6, sizeof cov6);
    }
    return ni;
}
