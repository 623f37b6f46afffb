/*
 * Trifocal RANSAC estimator: 7-triplet samples, three-view reprojection
 * error after optimal triangulation for scoring (the error BoofCV's study of
 * trifocal estimation found most reliable), gold-standard LO.
 * Model layout: T (27) | P2 (12) | P3 (12).
 */
#include <math.h>
#include <string.h>

#include "core/linalg_util.h"
#include "core/arena.h"
#include "robust/trifocal_refine.h"
#include "sfm/sfm_ransac_trifocal.h"
#include "sfm/sfm_trifocal.h"

enum { MODEL = 51, SAMPLE = SFM_TRIFOCAL_MIN_POINTS, LO_ITERS = 8 };

typedef struct tf_ctx {
    const double *x1, *x2, *x3;
    void *solver_ws;
    size_t solver_size;
    sfm_tf_refine_ws refine;
} tf_ctx;

typedef struct tf_layout_out {
    void *ransac_ws;
    size_t ransac_size;
    void *solver_ws;
    size_t solver_size;
    sfm_tf_refine_ws refine;
} tf_layout_out;

static void layout(sfm_arena *a, int n, tf_layout_out *o)
{
    sfm_ransac_dims d = {n, SAMPLE, 1, MODEL};
    o->ransac_size = sfm_ransac_workspace_size(&d);
    o->ransac_ws = sfm_arena_alloc(a, o->ransac_size);
    o->solver_size = sfm_trifocal_7pt_workspace_size();
    o->solver_ws = sfm_arena_alloc(a, o->solver_size);
    sfm_tf_refine_layout(a, n, &o->refine);
}

size_t sfm_ransac_trifocal_workspace_size(int n)
{
    if (n < SAMPLE || n > SFM_RANSAC_MAX_POINTS)
        return 0;
    sfm_arena a;
    tf_layout_out o;
    sfm_arena_measure(&a);
    layout(&a, n, &o);
    return sfm_arena_required(&a);
}

static const double P1[12] = {1, 0, 0, 0, 0, 1, 0, 0, 0, 0, 1, 0};

static int tf_solve(void *vctx, const int *sample, double *models)
{
    tf_ctx *c = (tf_ctx *)vctx;
    double y1[2 * SAMPLE], y2[2 * SAMPLE], y3[2 * SAMPLE];
    for (int k = 0; k < SAMPLE; k++) {
        memcpy(&y1[2 * k], &c->x1[2 * sample[k]], 2 * sizeof(double));
        memcpy(&y2[2 * k], &c->x2[2 * sample[k]], 2 * sizeof(double));
        memcpy(&y3[2 * k], &c->x3[2 * sample[k]], 2 * sizeof(double));
    }
    double T[27];
    int st = sfm_trifocal_7pt(y1, y2, y3, SAMPLE, T, c->solver_ws, c->solver_size);
    if (st == SFM_E_SINGULAR || st == SFM_E_NO_CONVERGENCE)
        return 0; /* a degenerate sample */
    if (st < 0)
        return st;
    if (sfm_trifocal_cameras(T, &models[27], &models[39]) != SFM_OK)
        return 0;
    memcpy(models, T, sizeof T);
    return 1;
}

static double tf_residual(void *vctx, const double *model, int i)
{
    tf_ctx *c = (tf_ctx *)vctx;
    double e;
    if (sfm_trifocal_point_error(P1, &model[27], &model[39], &c->x1[2 * i], &c->x2[2 * i],
                                 &c->x3[2 * i], &e, NULL) != SFM_OK)
        return HUGE_VAL;
    return e / 3.0;
}

static int tf_refine(void *vctx, const int *inliers, int n_inliers, double *model)
{
    tf_ctx *c = (tf_ctx *)vctx;
    if (n_inliers < SAMPLE)
        return -1;
    double P2[12], P3[12], T[27];
    memcpy(P2, &model[27], sizeof P2);
    memcpy(P3, &model[39], sizeof P3);
    int st;
    sfm_tf_refine(c->x1, c->x2, c->x3, inliers, n_inliers, P2, P3, LO_ITERS, &c->refine, &st);
    if (st < 0)
        return st;
    if (sfm_trifocal_from_cameras(P1, P2, P3, T) != SFM_OK)
        return -1;
    memcpy(model, T, sizeof T);
    memcpy(&model[27], P2, sizeof P2);
    memcpy(&model[39], P3, sizeof P3);
    return 0;
}

int sfm_ransac_trifocal(const double *x1, const double *x2, const double *x3, int n,
                        const sfm_ransac_options *opt, double T[27], double *P,
                        uint8_t *inlier_mask, sfm_ransac_stats *stats, void *ws, size_t ws_size)
{
    if (x1 == NULL || x2 == NULL || x3 == NULL || T == NULL || ws == NULL || n < SAMPLE ||
        n > SFM_RANSAC_MAX_POINTS)
        return SFM_E_ARGUMENT;
    if (!sfm_la_all_finite(x1, 2 * n) || !sfm_la_all_finite(x2, 2 * n) || !sfm_la_all_finite(x3, 2 * n))
        return SFM_E_NONFINITE;
    sfm_ransac_options o;
    if (opt != NULL)
        o = *opt;
    else
        sfm_ransac_default_options(&o);
    sfm_arena a;
    tf_layout_out lay;
    sfm_arena_init(&a, ws, ws_size);
    layout(&a, n, &lay);
    if (!sfm_arena_ok(&a))
        return SFM_E_WORKSPACE;
    tf_ctx ctx = {x1, x2, x3, lay.solver_ws, lay.solver_size, lay.refine};
    sfm_ransac_estimator est = {SAMPLE, 1, MODEL, tf_solve, tf_residual, tf_refine, NULL, NULL, &ctx, NULL};
    double model[MODEL];
    int cnt = sfm_ransac_run(&est, n, &o, model, inlier_mask, stats, lay.ransac_ws, lay.ransac_size);
    if (cnt < 0)
        return cnt;
    memcpy(T, model, 27 * sizeof(double));
    if (P != NULL) {
        memcpy(P, P1, sizeof P1);
        memcpy(&P[12], &model[27], 24 * sizeof(double));
    }
    return cnt;
}
