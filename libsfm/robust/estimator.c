/* Plumbing shared by the robust estimators (see estimator.h). */
#define SFMI_INLINE_EXTERN /* this file emits sfmi_robust_gather (core/inline.h) */
#include "robust/estimator.h"

#include <math.h>

#include "core/linalg_util.h"
#include "core/lm.h"
#include "robust/epipolar.h"

int sfmi_robust_options(const sfm_ransac_options *opt, sfm_ransac_options *eopt)
{
    if (opt != NULL)
        *eopt = *opt;
    else
        sfm_ransac_default_options(eopt);
    if (!isfinite(eopt->threshold) || !isfinite(eopt->confidence))
        return SFM_E_NONFINITE;
    if (!(eopt->threshold > 0.0))
        return SFM_E_ARGUMENT;
    return SFM_OK;
}

int sfmi_robust_pair_inputs(const double *px1, const double *px2, int n, int sample,
                            const sfm_camera *cam1, const sfm_camera *cam2,
                            const sfm_ransac_options *opt, sfm_ransac_options *eopt)
{
    if (n < sample || n > SFM_RANSAC_MAX_POINTS)
        return SFM_E_ARGUMENT;
    int st = sfmi_robust_options(opt, eopt);
    if (st < 0)
        return st;
    if (cam1 != NULL) {
        st = sfm_camera_validate(cam1);
        if (st < 0)
            return st;
        st = sfm_camera_validate(cam2);
        if (st < 0)
            return st;
    }
    if (!sfmi_la_all_finite(px1, 2 * (size_t)n) || !sfmi_la_all_finite(px2, 2 * (size_t)n))
        return SFM_E_NONFINITE;
    return SFM_OK;
}

double sfmi_robust_pair_cost(const double *p1, const double *p2, int n, double scale,
                             const double M[9],
                             double (*r2)(const double *M, const double *x, const double *y))
{
    const double s2 = scale > 0.0 ? scale * scale : 0.0;
    double c = 0.0;
    for (int i = 0; i < n; i++) {
        double e2 = r2(M, p1 + 2 * i, p2 + 2 * i);
        if (e2 < SFM_ROBUST_HUGE) {
            double rho = e2, rho1;
            if (s2 > 0.0)
                sfmi_lm_loss_eval(SFMI_LM_LOSS_CAUCHY, s2, e2, &rho, &rho1);
            c += rho;
        }
    }
    return c;
}

size_t sfmi_robust_engine_size(int n, int sample, int max_models, int model_size)
{
    sfm_ransac_dims d = {n, sample, max_models, model_size};
    return sfm_ransac_workspace_size(&d);
}

/* the one external copy of the header's inline definition (core/inline.h) */
extern inline void sfmi_robust_gather(const double *src, int dim, const int *idx, int k,
                                      double *dst);
