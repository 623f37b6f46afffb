/*
 * Calibrated three-view relative pose: the poses of views 2 and 3 relative to
 * view 1 with one consistent scale, from pixel triplets with outliers and the
 * three cameras' intrinsics (distortion included).
 *
 * Method: pixels are undistorted to each camera's ideal pinhole pixels;
 * trifocal RANSAC (sfm_ransac_trifocal) finds the inliers and three
 * consistent projective cameras; the essential matrices E21 = K2^T F21 K1 and
 * E31 = K3^T F31 K1 of that tensor are decomposed with the cheirality choice
 * over the inliers; the scale of t3 relative to t2 comes from the inliers
 * triangulated in views 1 and 2 and observed in view 3 (linear least squares).
 *
 * Poses map view-1 coordinates to each camera: x_cam = R x_cam1 + t; pose 0
 * is the identity, |t2| = 1 (the overall scale is unobservable).
 */
#ifndef SFM_THREE_VIEW_H
#define SFM_THREE_VIEW_H

#include "sfm/sfm_camera.h"
#include "sfm/sfm_common.h"
#include "sfm/sfm_ransac.h"

#ifdef __cplusplus
extern "C" {
#endif

/* Workspace bytes for n triplets; 0 when n is out of range. */
SFM_API size_t sfm_recon_three_view_pose_workspace_size(int n);

/* On success returns the inlier count and writes poses[3], inlier_mask (n
 * bytes, may be NULL) and stats (may be NULL). opt may be NULL (defaults;
 * threshold 1 px, per view, on the three-view reprojection error).
 * Statuses: SFM_E_ARGUMENT (NULL, n < 7, invalid camera), SFM_E_NONFINITE,
 * SFM_E_WORKSPACE, SFM_E_NO_CONVERGENCE (no tensor found, or a pixel that
 * cannot be undistorted), SFM_E_SINGULAR (the inliers do not determine the
 * poses: no translation between views 1 and 2, or all points at infinity).
 * Nothing is written on failure. */
SFM_API int sfm_recon_three_view_pose(const double *px1, const double *px2, const double *px3, int n,
                                      const sfm_camera *cam1, const sfm_camera *cam2,
                                      const sfm_camera *cam3, const sfm_ransac_options *opt,
                                      sfm_pose poses[3], uint8_t *inlier_mask,
                                      sfm_ransac_stats *stats, void *ws, size_t ws_size);

#ifdef __cplusplus
}
#endif
#endif
