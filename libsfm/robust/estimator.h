/* Internal: the plumbing every robust estimator repeats around the engine:
 * options (defaults and checks), the engine's workspace size, and gathering
 * the rows of a sample or an inlier set. */
#ifndef SFM_ROBUST_ESTIMATOR_H
#define SFM_ROBUST_ESTIMATOR_H

#include <stddef.h>

#include "sfm/sfm_ransac.h"
#include "core/inline.h"

/* eopt = *opt, or the defaults when opt is NULL; then checks that threshold
 * and confidence are finite (SFM_E_NONFINITE) and threshold > 0
 * (SFM_E_ARGUMENT). Returns SFM_OK or that status. */
int sfmi_robust_options(const sfm_ransac_options *opt, sfm_ransac_options *eopt);

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
