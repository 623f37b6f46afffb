/* Internal: Levenberg-Marquardt on the Sampson error of a relative pose. */
#ifndef SFM_ROBUST_SAMPSON_LM_H
#define SFM_ROBUST_SAMPSON_LM_H

#include "core/lm.h"

/*
 * Minimises sum over idx[0..n) of the squared bearing Sampson error of
 * E = [t]x R in (R, t), |t| = 1. The rotation is updated on the left,
 * R <- exp([w]x) R; with axis == NULL w is free (5 degrees of freedom in
 * all), else w = theta * axis (axis a unit vector in camera 2: the upright
 * case, which keeps R d1 = axis; 3 degrees of freedom). At most 2 iters LM
 * steps (accepted or rejected; core/lm.h). scale > 0: Cauchy loss
 * scale^2 log(1 + r^2 / scale^2) instead of r^2 (IRLS weights
 * 1 / (1 + r^2 / scale^2)). R, t are updated in place; returns 0 when the
 * cost went down, 1 when it could not, -1 on a numerical failure (R, t
 * unchanged).
 */
int sfmi_robust_sampson_lm(const double *b1, const double *b2, const int *idx, int n,
                          const double *axis, double scale, int iters, double R[9], double t[3]);

/* Drops from idx[0..n) (in place, order kept) the pairs whose Cook's
 * distance under (R, t) (the Sampson residuals' linearisation, the same
 * parameters as sfmi_robust_sampson_lm) is cut or more, for a residual
 * variance sigma2; returns the count left. n unchanged when the normal
 * matrix is singular or sigma2 is not positive. */
int sfmi_sampson_prune(const double *b1, const double *b2, int *idx, int n, const double *axis,
                       const double R[9], const double t[3], double sigma2, double cut);

/* The LM driver problem sfmi_robust_sampson_lm solves (blocks R on SO(3), or
 * the upright rotation, and t on S^2 over R, t in place; one residual per
 * listed pair): for a Jacobian check. sp must outlive its use. */
typedef struct sfmi_sampson_problem {
    const double *b1, *b2, *axis;
    const int *idx;
    sfmi_lm_block blocks[2];
    sfmi_lm_problem prob;
    /* the tangent basis of blocks[1] at t, one for every residual of an
     * evaluation: the residual callback sees the problem as const and keeps
     * the basis through this pointer (to memo_store) */
    struct sfmi_sampson_basis {
        double t[3], B[6];
        int valid;
    } *memo, memo_store;
} sfmi_sampson_problem;

void sfmi_sampson_lm_problem(const double *b1, const double *b2, const int *idx, int n,
                             const double *axis, double scale, double R[9], double t[3],
                             sfmi_sampson_problem *sp);

#endif
