/* Internal: Levenberg-Marquardt on the Sampson error of a fundamental matrix
 * in the orthonormal representation (rank 2 kept exactly). */
#ifndef SFM_ROBUST_FUNDAMENTAL_LM_H
#define SFM_ROBUST_FUNDAMENTAL_LM_H

#include "core/lm.h"

/* Robust cost of F over the n pixel pairs p1, p2 (n x 2): the sum of the
 * Cauchy loss of scale `scale` (pixels; plain squares when scale <= 0) of the
 * pixel Sampson errors. */
double sfmi_robust_fundamental_cost(const double *p1, const double *p2, int n, double scale,
                                   const double F[9]);

/* Minimises that cost over rank-2 F in at most `iters` LM steps (n >= 7).
 * F is updated in place (unit Frobenius norm). Returns 0 when the cost went
 * down, 1 when no step lowered it, -1 on a numerical failure (F unchanged).
 * Stack: under 2 KB; no workspace. */
int sfmi_robust_fundamental_lm(const double *p1, const double *p2, int n, double scale, int iters,
                              double F[9]);

/* The LM driver problem sfmi_robust_fundamental_lm solves from F: Hartley
 * normalisations, the blocks U, V (SO(3), right update) and (cos, sin) on
 * S^1 held in the struct, one residual per pair. Returns 0, -1 when F or the
 * points cannot be normalised. For a Jacobian check; N must outlive its
 * use. */
typedef struct sfmi_fundamental_problem {
    double t1[3], t2[3]; /* Hartley normalisations (s, -s cx, -s cy) */
    const double *p1, *p2;
    double U[9], V[9], cs[2];
    sfmi_lm_block blocks[3];
    sfmi_lm_problem prob;
} sfmi_fundamental_problem;

int sfmi_fundamental_lm_problem(const double *p1, const double *p2, int n, double scale,
                                const double F[9], sfmi_fundamental_problem *N);

#endif
