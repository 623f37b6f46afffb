/*
 * Internal: the per-model halves of sfm_camera_project / _unproject. The
 * dispatcher (camera.c) has checked the arguments; X and px are finite.
 * Normalised coordinates are pixels with the intrinsics removed:
 * ((u - cx) / fx, (v - cy) / fy).
 */
#ifndef SFM_CORE_CAMERA_INTERNAL_H
#define SFM_CORE_CAMERA_INTERNAL_H

#include "sfm/sfm_camera.h"

/* Distorted normalised point of X and, when D is not NULL, its 2x3 Jacobian
 * d(xd)/dX. Pinhole is Brown with all coefficients zero. */
int sfmi_cam_brown_project(const double *k, const double X[3], double xd[2], double *D);
int sfmi_cam_fisheye_project(const double *k, const double X[3], double xd[2], double *D);

/* Unit bearing of a distorted normalised point. */
int sfmi_cam_brown_unproject(const double *k, const double xd[2], double b[3]);
int sfmi_cam_fisheye_unproject(const double *k, const double xd[2], double b[3]);

/* Residual the iterative undistortion must reach, normalised units. */
#define SFM_CAM_UNDISTORT_TOL 1e-10
#define SFM_CAM_MAX_ITERS 50

#endif
