/*
 * Rotations. Matrices are 3x3 row-major. Axis-angle vectors are angle * unit
 * axis (radians). Quaternions are w-first (w, x, y, z), unit norm, and the
 * returned ones have w >= 0. A rotation R maps vectors: y = R x.
 * Every function returns SFM_OK, SFM_E_ARGUMENT (NULL) or SFM_E_NONFINITE
 * (NaN/Inf in an input), unless stated otherwise below; on failure nothing is
 * written. Outputs may not alias inputs unless stated.
 */
#ifndef SFM_ROTATION_H
#define SFM_ROTATION_H

#include "sfm/sfm_common.h"

#ifdef __cplusplus
extern "C" {
#endif

/* Rodrigues formula, exact for small angles (Taylor branch). |aa| above
 * about 1e154 (its square overflows) is SFM_E_NONFINITE. */
SFM_API int sfm_rot_from_axis_angle(const double aa[3], double R[9]);
/* Inverse, stable near 0 and near pi: the angle comes back in [0, pi] with
 * full relative accuracy near 0 and absolute accuracy ~eps near pi (at pi
 * exactly the sign of the axis is arbitrary). R must be a rotation (not
 * checked). */
SFM_API int sfm_rot_to_axis_angle(const double R[9], double aa[3]);
/* q need not be unit: it is normalized; zero q is SFM_E_ARGUMENT. */
SFM_API int sfm_rot_from_quat(const double q[4], double R[9]);
SFM_API int sfm_rot_to_quat(const double R[9], double q[4]);
/* Closest rotation in Frobenius norm (SVD, det = +1). SFM_E_SINGULAR when M
 * has rank below 2 (second singular value <= 8 eps times the first), where
 * the answer is not unique; SFM_E_NO_CONVERGENCE if the SVD fails. Stack use
 * about 1.3 KB. */
SFM_API int sfm_rot_nearest(const double M[9], double R[9]);
/* S = [v]_x so that S w = v x w. */
SFM_API int sfm_skew(const double v[3], double S[9]);
/* Geodesic angle (radians, [0, pi]) between two rotations: |log(R1^T R2)|,
 * accurate for tiny angles (no acos). */
SFM_API int sfm_rot_angle_between(const double R1[9], const double R2[9], double *angle);

#ifdef __cplusplus
}
#endif
#endif
