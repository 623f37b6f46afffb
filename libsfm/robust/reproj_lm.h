/* Internal: Levenberg-Marquardt on the tangent-plane reprojection error of an
 * absolute pose. */
#ifndef SFM_ROBUST_REPROJ_LM_H
#define SFM_ROBUST_REPROJ_LM_H

#include "core/lm.h"

/* Squared tangent-plane error of world point X against unit bearing b under
 * (R, t): tan^2 of the angle between b and R X + t; SFM_ROBUST_HUGE behind
 * the camera. */
double sfmi_robust_reproj2(const double R[9], const double t[3], const double *b,
                          const double *X);

/* Minimises the sum over idx[0..n) of the squared residuals
 * r_k = (e_k . Xc) / (b . Xc), k = 1, 2 (e_1, e_2 a basis of the tangent
 * plane at b, Xc = R X + t), in (R, t) with R <- exp([w]x) R. At most `iters`
 * steps. scale > 0: Cauchy loss of scale `scale` on each point's squared
 * error (IRLS). Returns 0 when the cost went down, 1 otherwise, -1 on failure
 * (R, t unchanged). */
int sfmi_robust_reproj_lm(const double *b, const double *X, const int *idx, int n, double scale,
                         int iters, double R[9], double t[3]);

/* The LM driver problem sfmi_robust_reproj_lm solves (R on SO(3), t in R^3,
 * over R, t in place; one 2-residual per listed point): for a Jacobian
 * check. rp must outlive its use. */
typedef struct sfmi_reproj_problem {
    const double *b, *X;
    const int *idx;
    sfmi_lm_block blocks[2];
    sfmi_lm_problem prob;
} sfmi_reproj_problem;

void sfmi_reproj_lm_problem(const double *b, const double *X, const int *idx, int n, double scale,
                            double R[9], double t[3], sfmi_reproj_problem *rp);

#endif
