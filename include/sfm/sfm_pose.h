/*
 * Minimal pose solvers: absolute pose from three points (P3P), relative pose
 * from three points and a known direction (upright 3-point), and the four
 * decompositions of an essential matrix with a cheirality choice.
 *
 * Conventions:
 *  - a pose is world-to-camera, x_cam = R * X_world + t (R row-major 3x3);
 *    for a relative pose, frame 1 plays the world: x_cam2 = R x_cam1 + t;
 *  - bearings are 3-vectors pointing from the camera centre towards the
 *    point, rows of a row-major (n x 3) array; they need not have unit length
 *    (they are normalized internally) but must be nonzero;
 *  - relative translations have unit norm (the scale is unobservable);
 *  - a solver returns the number of solutions written, from index 0
 *    (0 for a degenerate sample: nothing is then written), or a negative
 *    sfm_status when the arguments break the contract (nothing written).
 *    No solver ever writes NaN or Inf.
 *  - Stack: each solver uses at most 1.5 KiB of stack (measured with
 *    -fstack-usage, gcc 12 -O2 x86-64), no workspace, no heap.
 *  - Outputs must not alias inputs.
 */
#ifndef SFM_POSE_H
#define SFM_POSE_H

#include "sfm/sfm_common.h"

#ifdef __cplusplus
extern "C" {
#endif

/* Capacities: the most solutions each solver can write. */
#define SFM_P3P_MAX_SOLUTIONS 4
#define SFM_RELPOSE_UPRIGHT_3PT_MAX_SOLUTIONS 4
#define SFM_ESSENTIAL_POSES 4

/* ---- P3P ----------------------------------------------------------------
 * Absolute pose from three bearing / world point pairs: x[3*3] bearings (row
 * i = bearing of point i), X[3*3] world points. Writes up to 4 poses with
 * x_cam = R X + t and every point in front of the camera (positive depth).
 * Lambda Twist (Persson & Nordberg, ECCV 2018), with Gauss-Newton polishing
 * of the depths. Degenerate samples (coincident or collinear world points,
 * coincident bearings) give 0.
 * Returns: 0..4, SFM_E_ARGUMENT (NULL), SFM_E_NONFINITE (NaN/Inf input). */
SFM_API int sfm_p3p(const double x[9], const double X[9],
                    sfm_pose poses[SFM_P3P_MAX_SOLUTIONS]);

/* ---- Upright / known-direction 3-point relative pose -------------------
 * Relative pose from three bearing pairs x1[3*3], x2[3*3] (row i in camera 1
 * and camera 2) and one direction known in both frames, d1 in camera 1 and
 * d2 = R d1 in camera 2 (gravity from an IMU, a vanishing direction). Any
 * direction, not only a coordinate axis; d1 and d2 need not be unit.
 * Writes up to 4 poses x_cam2 = R x_cam1 + t with |t| = 1. The sign of t is
 * the one that puts most of the three points in front of camera 1; a
 * solution that then leaves any of the three points behind either camera
 * (negative depth) is not returned.
 * Method: rotate each frame so that its direction becomes the y axis; the
 * remaining rotation about y and the translation satisfy the three epipolar
 * constraints, whose determinant is a trigonometric polynomial of degree 2 in
 * the angle (Fraundorfer, Tanskanen & Pollefeys, ECCV 2010; Kalantari et al.
 * 2011). It is turned into a quartic by a tangent half-angle substitution
 * whose pole is placed at whichever of four angles 90 degrees apart is
 * farthest from a root, so there is no singular angle (180 degrees included).
 * Returns: 0..4, SFM_E_ARGUMENT (NULL, zero direction), SFM_E_NONFINITE. */
SFM_API int sfm_relpose_upright_3pt(const double x1[9], const double x2[9],
                                    const double d1[3], const double d2[3],
                                    sfm_pose poses[SFM_RELPOSE_UPRIGHT_3PT_MAX_SOLUTIONS]);

/* ---- Essential matrix to poses ------------------------------------------
 * E = [t]x R (x2^T E x1 = 0 for bearings x1, x2 of one point), any scale and
 * sign; E need not be exactly essential (it is projected through its SVD).
 * Writes the four decompositions (R, t), R proper, |t| = 1, and for each the
 * number of the n bearing pairs (x1, x2: n x 3 each) that lie in front of
 * both cameras (positive depth in both; points at infinity or exactly on the
 * baseline are not counted) into n_front[4]. The poses are ordered by that
 * count, largest first (ties keep the fixed order (R1, t), (R1, -t), (R2, t),
 * (R2, -t)), so poses[0] is the cheirality choice and n_front[0] its count.
 * n may be 0 (x1, x2 may then be NULL): all counts are 0, fixed order.
 * n_front may be NULL.
 * Returns: 4; 0 when E has rank below 2 (nothing written); SFM_E_ARGUMENT
 * (NULL E or poses, n < 0, NULL points with n > 0); SFM_E_NONFINITE. */
SFM_API int sfm_essential_to_poses(const sfm_mat3 *E, const double *x1, const double *x2,
                                   int n, sfm_pose poses[SFM_ESSENTIAL_POSES],
                                   int n_front[SFM_ESSENTIAL_POSES]);

#ifdef __cplusplus
}
#endif
#endif
