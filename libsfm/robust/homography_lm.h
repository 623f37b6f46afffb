/* Internal: Levenberg-Marquardt on the Sampson error of a homography. */
#ifndef SFM_ROBUST_HOMOGRAPHY_LM_H
#define SFM_ROBUST_HOMOGRAPHY_LM_H

#include "core/lm.h"

/* Squared Sampson error in pixels of the pair (x, y) under H (Hartley &
 * Zisserman 4.2.6): the first-order squared distance of (x, y) to the
 * variety y ~ H x; SFM_ROBUST_HUGE when it is undefined. */
double sfmi_robust_homography_sampson2(const double H[9], const double *x, const double *y);

/* Robust cost of H over the n pixel pairs p1, p2 (n x 2): the sum of the
 * Cauchy loss of scale `scale` (pixels; plain squares when scale <= 0) of
 * the squared Sampson errors. */
double sfmi_robust_homography_cost(const double *p1, const double *p2, int n, double scale,
                                  const double H[9]);

/* Minimises that cost in at most `iters` LM steps (n >= 4), 8 degrees of
 * freedom. H is updated in place (unit Frobenius norm). Returns 0 when the
 * cost went down, 1 when no step lowered it, -1 on a numerical failure (H
 * unchanged). Stack: under 2 KB; no workspace. */
int sfmi_robust_homography_lm(const double *p1, const double *p2, int n, double scale, int iters,
                             double H[9]);

/* The LM driver problem sfmi_robust_homography_lm solves from H: Hartley
 * normalisations, H_n held in the struct with its largest entry fixed (a
 * custom block of 8 free entries), one 2-residual per pair. Returns 0, -1
 * when H or the points cannot be normalised. For a Jacobian check; N must
 * outlive its use. */
#define SFMI_HOMOGRAPHY_NP 8
typedef struct sfmi_homography_problem {
    double t1[3], t2[3];
    const double *p1, *p2;
    int ent[SFMI_HOMOGRAPHY_NP]; /* the free entries of H_n; the ninth is held */
    double Hn[9];
    sfmi_lm_block block;
    sfmi_lm_problem prob;
} sfmi_homography_problem;

int sfmi_homography_lm_problem(const double *p1, const double *p2, int n, double scale,
                               const double H[9], sfmi_homography_problem *N);

#endif
