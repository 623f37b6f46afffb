/*
 * Triangulation of points seen in several views: linear (DLT), midpoint, and
 * optimal two-view (Lindstrom's niter2).
 *
 * Conventions:
 *  - a projection matrix P is 3x4 row-major, x ~ P [X; 1]: K [R | t] for
 *    pixel inputs, [R | t] for normalized image coordinates (any scale and
 *    sign; depths are signed with det(P[:, :3]) as in Hartley & Zisserman);
 *  - poses map world to camera, x_cam = R X + t;
 *  - per-view observations are stored view-major: observation of point j in
 *    view v is x[(v * npoints + j) * 2 + k] (2D) or f[(v * npoints + j) * 3 + k]
 *    (bearings);
 *  - X is (npoints x 3), world coordinates;
 *  - each function returns the number of points triangulated with no flag
 *    set (0..npoints), or a negative status; on a negative status nothing is
 *    written (argument checks come first). flags may be NULL; else flags[j]
 *    receives the bits below.
 *
 * A point is never dropped silently: a point behind a camera is written and
 * flagged SFM_TRI_BEHIND; a point at infinity (parallel rays, numerically)
 * is flagged SFM_TRI_INFINITY and X then holds the unit direction towards it
 * (oriented to lie in front of as many cameras as possible), not a position.
 * Stack: at most 3 KiB per call (-fstack-usage, gcc 12 -O2 x86-64, the 4x4
 * SVD fallback included), no workspace, no heap. Outputs must not alias
 * inputs.
 */
#ifndef SFM_TRIANGULATE_H
#define SFM_TRIANGULATE_H

#include "sfm/sfm_common.h"

#ifdef __cplusplus
extern "C" {
#endif

/* Per-point flag bits. */
#define SFM_TRI_BEHIND 1   /* negative depth in at least one view */
#define SFM_TRI_INFINITY 2 /* at infinity: X is a unit direction */

/* ---- Linear (DLT) ---------------------------------------------------------
 * nviews >= 2 projection matrices P (nviews x 12) and 2D observations x.
 * Minimizes the algebraic error of the stacked equations x P3 - P1 and
 * y P3 - P2 (each row scaled to unit norm), by a streaming QR and the SVD of
 * the 4x4 triangular factor (any number of views, fixed stack).
 * At infinity: |w| <= 1e-12 * |(X, Y, Z)| for the homogeneous solution.
 * Returns: count of unflagged points; SFM_E_ARGUMENT (NULL, nviews < 2,
 * npoints < 0), SFM_E_NONFINITE, SFM_E_NO_CONVERGENCE (the 4x4 SVD did not
 * converge: the points before the failing one are then already written). */
SFM_API int sfm_triangulate_dlt(int nviews, const double *P, int npoints, const double *x,
                                double *X, int *flags);

/* ---- Midpoint -------------------------------------------------------------
 * nviews >= 2 camera poses and bearings f (any nonzero length). The point
 * minimizing the sum of squared distances to the rays.
 * At infinity: the rays' normal matrix sum(I - d d^T) has
 * det <= 1e-20 (tr / 3)^3 (for two views, rays within about 1e-10 rad).
 * Returns: count of unflagged points; SFM_E_ARGUMENT (NULL, nviews < 2,
 * npoints < 0, a zero bearing), SFM_E_NONFINITE. */
SFM_API int sfm_triangulate_midpoint(int nviews, const sfm_pose *poses, int npoints,
                                     const double *f, double *X, int *flags);

/* ---- Optimal two-view -----------------------------------------------------
 * P. Lindstrom, "Triangulation made easy", CVPR 2010 (niter2): both
 * observations are moved the least (in the coordinates of x1, x2) so that
 * they satisfy the epipolar constraint of the fundamental matrix of (P1, P2);
 * the corrected pair is then triangulated linearly and flagged as
 * sfm_triangulate_dlt. A point at an epipole is triangulated uncorrected.
 * x1, x2: npoints x 2 each.
 * Returns: count of unflagged points; SFM_E_ARGUMENT (NULL, npoints < 0,
 * cameras with a common centre), SFM_E_NONFINITE, SFM_E_NO_CONVERGENCE (as
 * sfm_triangulate_dlt). */
SFM_API int sfm_triangulate_optimal2(const double P1[12], const double P2[12], int npoints,
                                     const double *x1, const double *x2, double *X, int *flags);

/* Fundamental matrix of two projection matrices, x2^T F x1 = 0 (Hartley &
 * Zisserman eq. 17.3), scaled to unit Frobenius norm.
 * Returns: SFM_OK, SFM_E_ARGUMENT (NULL; F zero: common centre),
 * SFM_E_NONFINITE. */
SFM_API int sfm_fundamental_from_projections(const double P1[12], const double P2[12],
                                             sfm_mat3 *F);

#ifdef __cplusplus
}
#endif
#endif
