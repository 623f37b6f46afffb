/*
 * Calibrated three-view relative pose: the poses of views 2 and 3 relative to
 * view 1 with one consistent scale, from pixel triplets with outliers and the
 * three cameras' intrinsics (distortion included).
 *
 * Method: pixels are undistorted to each camera's ideal pinhole pixels;
 * trifocal RANSAC (sfm_ransac_trifocal) finds the triplets consistent with
 * three projective cameras. Two calibrated starts are then built, each
 * scaled (t3 relative to |t2| = 1 by linear least squares on points
 * triangulated in views 1 and 2) and polished by metric bundle adjustment:
 * (a) the essential matrices E21 = K2^T F21 K1, E31 = K3^T F31 K1 of the
 * tensor, decomposed with the cheirality choice; (b) calibrated 5-point
 * RANSAC on the pairs (1, 2) and (1, 3) of all triplets, which has no
 * plane-induced ambiguity. The start whose metric cameras explain more
 * triplets wins; its inliers are re-collected under the metric cameras and
 * polished once more. When rotation alone explains views 1 and 2 the
 * translation is unobservable: SFM_E_SINGULAR.
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
 * bytes, may be NULL) and stats (may be NULL): stats->num_inliers is the
 * returned count, the triplets within the threshold under the metric cameras
 * (the mask's ones); the other counters, the score and the stop reason are
 * those of the trifocal RANSAC search. opt may be NULL (defaults;
 * threshold 1 px, per view, on the three-view reprojection error).
 * Statuses: SFM_E_ARGUMENT (NULL, n < 7, invalid camera), SFM_E_NONFINITE,
 * SFM_E_WORKSPACE, SFM_E_NO_CONVERGENCE (no tensor found, or a pixel that
 * cannot be undistorted), SFM_E_SINGULAR (the inliers do not determine the
 * poses: no translation between views 1 and 2, or all points at infinity),
 * SFM_E_DEGENERATE (the triplets lie on one line or in one cluster in a
 * view, or the 5-point support of views 1 and 2 is degenerate: see the
 * support checks of sfm_ransac.h), SFM_E_NO_MODEL (the metric inliers are
 * no more than random triplets would give).
 * Support checks: trifocal RANSAC runs with its spread checks only (a
 * dominant plane may make its tensor plane-induced; the calibrated start
 * recovers from that); stats->flags carries SFM_RANSAC_FLAG_PLANAR and
 * SFM_RANSAC_FLAG_LOW_PARALLAX from the 5-point pose of views 1 and 2.
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
