/* Plumbing shared by the robust estimators (see estimator.h). */
#define SFMI_INLINE_EXTERN /* this file emits sfmi_robust_gather (core/inline.h) */
#include "robust/estimator.h"

#include <math.h>

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

size_t sfmi_robust_engine_size(int n, int sample, int max_models, int model_size)
{
    sfm_ransac_dims d = {n, sample, max_models, model_size};
    return sfm_ransac_workspace_size(&d);
}

/* the one external copy of the header's inline definition (core/inline.h) */
extern inline void sfmi_robust_gather(const double *src, int dim, const int *idx, int k,
                                      double *dst);
