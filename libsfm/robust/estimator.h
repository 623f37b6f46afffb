/* Internal: the plumbing every robust estimator repeats around the engine:
 * options (defaults and checks), the engine's workspace size, and gathering
 * the rows of a sample or an inlier set. */
#ifndef SFM_ROBUST_ESTIMATOR_H
#define SFM_ROBUST_ESTIMATOR_H

#include <stddef.h>

#include "sfm/sfm_camera.h"
#include "sfm/sfm_ransac.h"
#include "core/inline.h"

/* eopt = *opt, or the defaults when opt is NULL; then checks that threshold
 * and confidence are finite (SFM_E_NONFINITE) and threshold > 0
 * (SFM_E_ARGUMENT). Returns SFM_OK or that status. */
int sfmi_robust_options(const sfm_ransac_options *opt, sfm_ransac_options *eopt);

/* The checks of a two-view estimator's pixel pairs, in this order: n in
 * [sample, SFM_RANSAC_MAX_POINTS] (SFM_E_ARGUMENT), the options
 * (sfmi_robust_options into eopt), both cameras when cam1 is not NULL
 * (sfm_camera_validate; cam2 must then be given too), every coordinate of
 * px1 and px2 (n x 2) finite (SFM_E_NONFINITE). Returns SFM_OK or the first
 * failing status. */
int sfmi_robust_pair_inputs(const double *px1, const double *px2, int n, int sample,
                            const sfm_camera *cam1, const sfm_camera *cam2,
                            const sfm_ransac_options *opt, sfm_ransac_options *eopt);

/* The robust cost of a two-view model M (9 entries) over n pixel pairs p1,
 * p2 (n x 2): the sum over the pairs of the Cauchy loss at scale of
 * r2(M, x, y), the squared error of the pair (the plain r2 when scale <= 0),
 * leaving out the pairs where r2 reaches SFM_ROBUST_HUGE (robust/epipolar.h:
 * no error defined). */
double sfmi_robust_pair_cost(const double *p1, const double *p2, int n, double scale,
                             const double M[9],
                             double (*r2)(const double *M, const double *x, const double *y));

/* sfm_ransac_workspace_size for these dimensions (0 when they are invalid). */
size_t sfmi_robust_engine_size(int n, int sample, int max_models, int model_size);

/* dst[j] = src[idx[j]] for j < k, rows of dim doubles. */
SFMI_INLINE void sfmi_robust_gather(const double *src, int dim, const int *idx, int k,
                                     double *dst)
{
    for (int j = 0; j < k; j++)
        for (int d = 0; d < dim; d++)
            dst[(size_t)dim * j + d] = src[(size_t)dim * idx[j] + d];
}

#endif
