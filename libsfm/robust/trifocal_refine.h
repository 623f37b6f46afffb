/* Internal: gold-standard refinement of three projective cameras. */
#ifndef SFM_ROBUST_TRIFOCAL_REFINE_H
#define SFM_ROBUST_TRIFOCAL_REFINE_H

#include <stddef.h>

#include "core/arena.h"

/* P1 = [I | 0], the first camera of the projective frame. */
extern const double sfmi_tf_P1[12];

typedef struct sfmi_tf_refine_ws {
    double *X;    /* 4n: current homogeneous points */
    double *Xold; /* 4n: points of the trial step */
    double *U, *S; /* 24 x 24: camera block, reduced system */
    int cap;      /* n the buffers hold */
} sfmi_tf_refine_ws;

/* Per-point blocks: Jp (6x3, along the tangent basis B = sfmi_lm_sphere_basis
 * of X, 4x3), residual r (6: views 1, 2, 3), and for views 2 and 3 the
 * factors (iw, u, v) of the camera Jacobian d r_v / d P_v (2 x 12, P_v's
 * entries row-major) = iw [X^T 0 -u X^T; 0 X^T -v X^T]
 * (sfmi_trifocal_residual). */
typedef struct sfmi_tf_point_blocks {
    double Jp[18], r[6], cam[6], B[12];
} sfmi_tf_point_blocks;

/* The residuals and Jacobians of point p (x1..x3 in xs) at X (unit
 * homogeneous) under P1 = [I | 0], P2, P3. Returns 0 when a view cannot
 * project X. */
int sfmi_tf_point_jacobians(const double *const xs[3], int p, const double *P2, const double *P3,
                            const double X[4], sfmi_tf_point_blocks *b);

/* Carves buffers for up to n points (measuring or real arena). */
void sfmi_tf_refine_layout(sfmi_arena *a, int n, sfmi_tf_refine_ws *w);

/*
 * Levenberg-Marquardt on the reprojection error of the listed triplets over
 * P2, P3 (P1 = [I | 0] fixed) and the points (homogeneous, updated in their
 * tangent space), with the points eliminated by the Schur complement: the
 * reduced 24x24 camera system is solved by Cholesky. H&Z alg. 16.2's gold
 * standard step, run by the LM driver (core/lm.h: at most max_iters steps,
 * relative cost tolerance 1e-10). The points start at X0[4 p] for the
 * listed triplets p (unit homogeneous, the optimal triangulation under P2,
 * P3 up to their scale), or at that triangulation (sfm_trifocal_point_error)
 * when X0 is NULL. P2, P3 are written
 * (unit Frobenius norm; the input when no step lowered the cost). Returns
 * the final cost (sum of squared pixel errors), or INFINITY with *status
 * negative.
 */
double sfmi_tf_refine(const double *x1, const double *x2, const double *x3, const int *idx, int n,
                     const double *X0, double P2[12], double P3[12], int max_iters,
                     sfmi_tf_refine_ws *w, int *status);

#endif
