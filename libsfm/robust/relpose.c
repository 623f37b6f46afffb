/*
 * Relative pose by RANSAC over 5-point samples (Nister, "An efficient
 * solution to the five-point relative pose problem", PAMI 2004), scored on
 * the bearing Sampson error, with LO on (R, t) and the final pose by
 * cheirality (see sfm_ransac.h). Essential matrices are verified as they come
 * from the solver; the pose is only decomposed for models that become the
 * best so far, which keeps SVDs out of the sampling loop.
 */
#include <string.h>

#include "robust/epipolar.h"
#include "robust/estimator.h"
#include "robust/twoview.h"
#include "sfm/sfm_solvers.h"

static int solve5(void *ctx, const int *s, double *models)
{
    twoview_ctx *c = ctx;
    double x1[15], x2[15];
    sfm_mat3 E[SFM_RELPOSE_5PT_MAX_SOLUTIONS];
    sfmi_robust_gather(c->b1, 3, s, 5, x1);
    sfmi_robust_gather(c->b2, 3, s, 5, x2);
    int ns = sfm_relpose_5pt(x1, x2, E);
    if (ns < 0)
        return ns == SFM_E_NONFINITE ? 0 : ns;
    int kept = 0;
    for (int k = 0; k < ns; k++) {
        if (!sfmi_oriented_epipolar(E[k].m, x1, x2, 5))
            continue;
        twoview_model m;
        memset(&m, 0, sizeof m);
        memcpy(m.E, E[k].m, sizeof E[k].m);
        memcpy(models + (size_t)kept * SFM_RANSAC_RELPOSE_MODEL, &m, sizeof m);
        kept++;
    }
    return kept;
}

size_t sfm_ransac_relpose_workspace_size(int n)
{
    return sfmi_twoview_workspace_size(n, 5, SFM_RELPOSE_5PT_MAX_SOLUTIONS);
}

int sfm_ransac_relpose(const double *px1, const double *px2, int n, const sfm_camera *cam1,
                       const sfm_camera *cam2, const sfm_ransac_options *opt, sfm_pose *pose,
                       sfm_mat3 *E_out, uint8_t *inlier_mask, sfm_ransac_stats *stats, void *ws,
                       size_t ws_size)
{
    double *E = E_out ? E_out->m : NULL;
    if (pose == NULL)
        return SFM_E_ARGUMENT;
    twoview_call call = {px1, px2, n, cam1, cam2, opt, 5, SFM_RELPOSE_5PT_MAX_SOLUTIONS, solve5,
                         ws, ws_size, pose, E, inlier_mask, stats};
    twoview_ws w;
    sfm_ransac_options eopt;
    double focal;
    int st = sfmi_twoview_setup(&call, &w, &eopt, &focal);
    if (st < 0)
        return st;
    twoview_ctx c = {w.b1, w.b2, n, NULL, NULL, eopt.threshold};
    return sfmi_twoview_run(&call, &c, &w, &eopt, focal);
}
