/* Internal: the damped normal-equation step, the robust loss and the
 * damping schedule shared by the small Levenberg-Marquardt refinements of
 * the estimators (sampson_lm.c, reproj_lm.c, fundamental_lm.c,
 * homography_lm.c). */
#ifndef SFM_ROBUST_LM_SMALL_H
#define SFM_ROBUST_LM_SMALL_H

#include <math.h>

#include "sfm/sfm_linalg.h"
#include "core/dmath.h"

/* Largest parameter count of these refinements. */
#define SFM_LM_SMALL_MAXP 8

/* IRLS weight of the Cauchy loss below: 1 / (1 + r2 / s2); 1 when s2 <= 0. */
static inline double sfm_lm_cauchy_weight(double r2, double s2)
{
    return s2 > 0.0 ? 1.0 / (1.0 + r2 / s2) : 1.0;
}

/* Cauchy loss s2 log(1 + r2 / s2) of a squared residual; plain r2 when
 * s2 <= 0. */
static inline double sfm_lm_cauchy_loss(double r2, double s2)
{
    return s2 > 0.0 ? s2 * sfmi_log1p(r2 / s2) : r2;
}

/* x = -(JtJ + lambda diag(JtJ))^-1 g for np parameters; JtJ holds the lower
 * triangle (row-major np x np). Returns 0, or -1 when the damped matrix is
 * not positive definite. */
static inline int sfm_lm_small_step(const double *JtJ, const double *g, int np, double lambda,
                                    double *x)
{
    double A[SFM_LM_SMALL_MAXP * SFM_LM_SMALL_MAXP];
    for (int p = 0; p < np; p++) {
        for (int q = 0; q <= p; q++)
            A[p * np + q] = JtJ[p * np + q];
        double d = JtJ[p * np + p];
        A[p * np + p] += lambda * (d > 1e-12 ? d : 1e-12);
        x[p] = -g[p];
    }
    if (sfm_cholesky_factor(A, np) != SFM_OK || sfm_cholesky_solve(A, np, x, 1) != SFM_OK)
        return -1;
    return 0;
}

/* After an accepted step: ten times less damping, down to 1e-10. */
static inline double sfm_lm_small_relax(double lambda)
{
    return lambda * 0.1 > 1e-10 ? lambda * 0.1 : 1e-10;
}

#endif
