/*
 * Upright relative pose by RANSAC over 3-point samples with a direction known
 * in both frames (Fraundorfer, Tanskanen & Pollefeys, ECCV 2010), scored on
 * the bearing Sampson error; LO keeps R d1 = d2 (rotation about d2 only).
 */
#include <math.h>
#include <string.h>

#include "robust/epipolar.h"
#include "robust/estimator.h"
#include "robust/twoview.h"
#include "sfm/sfm_pose.h"

static int solve3(void *ctx, const int *s, double *models)
{
    twoview_ctx *c = ctx;
    double x1[9], x2[9];
    sfm_pose P[SFM_RELPOSE_UPRIGHT_3PT_MAX_SOLUTIONS];
    sfmi_robust_gather(c->b1, 3, s, 3, x1);
    sfmi_robust_gather(c->b2, 3, s, 3, x2);
    int ns = sfm_relpose_upright_3pt(x1, x2, c->d1, c->d2, P);
    if (ns < 0)
        return ns == SFM_E_NONFINITE ? 0 : ns;
    int kept = 0;
    for (int k = 0; k < ns; k++) {
        twoview_model m;
        sfmi_twoview_set_pose(&m, P[k].R, P[k].t);
        if (sfmi_oriented_epipolar(m.E, x1, x2, 3))
            memcpy(models + (size_t)kept++ * SFM_RANSAC_RELPOSE_MODEL, &m, sizeof m);
    }
    return kept;
}

size_t sfm_ransac_relpose_upright_workspace_size(int n)
{
    return sfmi_twoview_workspace_size(n, 3, SFM_RELPOSE_UPRIGHT_3PT_MAX_SOLUTIONS);
}

static int unit(const double *d, double *u)
{
    if (!isfinite(d[0]) || !isfinite(d[1]) || !isfinite(d[2]))
        return SFM_E_NONFINITE;
    double l = sqrt(d[0] * d[0] + d[1] * d[1] + d[2] * d[2]);
    if (!(l > 0.0))
        return SFM_E_ARGUMENT;
    u[0] = d[0] / l;
    u[1] = d[1] / l;
    u[2] = d[2] / l;
    return SFM_OK;
}

int sfm_ransac_relpose_upright(const double *px1, const double *px2, int n,
                               const sfm_camera *cam1, const sfm_camera *cam2, const double d1[3],
                               const double d2[3], const sfm_ransac_options *opt, sfm_pose *pose,
                               sfm_mat3 *E_out, uint8_t *inlier_mask, sfm_ransac_stats *stats,
                               void *ws, size_t ws_size)
{
    double *E = E_out ? E_out->m : NULL;
    if (pose == NULL || d1 == NULL || d2 == NULL)
        return SFM_E_ARGUMENT;
    double u1[3], u2[3];
    int st = unit(d1, u1);
    if (st < 0)
        return st;
    st = unit(d2, u2);
    if (st < 0)
        return st;
    twoview_call call = {px1, px2, n, cam1, cam2, opt, 3, SFM_RELPOSE_UPRIGHT_3PT_MAX_SOLUTIONS, solve3,
                         ws, ws_size, pose, E, inlier_mask, stats};
    twoview_ws w;
    sfm_ransac_options eopt;
    double focal;
    st = sfmi_twoview_setup(&call, &w, &eopt, &focal);
    if (st < 0)
        return st;
    twoview_ctx c = {w.b1, w.b2, n, u1, u2, eopt.threshold};
    return sfmi_twoview_run(&call, &c, &w, &eopt, focal);
}
