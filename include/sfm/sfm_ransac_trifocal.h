/*
 * Trifocal RANSAC: the trifocal tensor and three consistent projective
 * cameras from pixel triplets with outliers, on the engine of sfm_ransac.h.
 *
 * Minimal samples of 6 triplets are solved exactly (Quan 1995; Hartley &
 * Zisserman alg. 20.1: up to three projective reconstructions each, every
 * one verified); each triplet is
 * scored by its three-view reprojection error after optimal triangulation
 * (sfm_trifocal_point_error), as the mean over the three views of the squared
 * pixel error, so opt->threshold is a per-view pixel distance (a triplet
 * whose distance to the epipolar geometry of views 1-2 or 1-3 already puts
 * that error beyond every band is not triangulated: the scores are the
 * same). Local
 * optimisation is the gold-standard refinement of P2, P3 and the points on
 * the inliers (Levenberg-Marquardt with the points eliminated by the Schur
 * complement). Pixels are n x 2 row-major; cameras 3x4, P1 = [I | 0].
 */
#ifndef SFM_RANSAC_TRIFOCAL_H
#define SFM_RANSAC_TRIFOCAL_H

#include "sfm/sfm_common.h"
#include "sfm/sfm_ransac.h"

#ifdef __cplusplus
extern "C" {
#endif

/* Workspace bytes for n triplets; 0 when n is out of range. */
SFM_API size_t sfm_ransac_trifocal_workspace_size(int n);

/*
 * On success returns the inlier count (>= 7) and writes T (27, unit norm,
 * T[i*9 + j*3 + k] = T_i^{jk}), P (3 cameras, 36 doubles, P1 = [I | 0], may
 * be NULL), inlier_mask (n bytes, may be NULL) and stats (may be NULL).
 * opt may be NULL (defaults, threshold 1 px).
 * Statuses: SFM_E_ARGUMENT (NULL inputs or T, n < 7), SFM_E_NONFINITE,
 * SFM_E_WORKSPACE, SFM_E_NO_CONVERGENCE (no model found), SFM_E_DEGENERATE
 * and SFM_E_NO_MODEL (the support checks of sfm_ransac.h: the inliers on one
 * line or in one cluster in a view, a normalised design with a second null
 * direction -- all points on one plane, no baseline --, or a support no
 * larger than random triplets give). The line and cluster tests leave out
 * each view's 6 points farthest from the support's centroid (a tenth at
 * most), and the design's second direction is held without the 6 triplets
 * that weigh most on it: a minimal sample that holds a stray match fits it
 * exactly, and a stray or two must not make a cluster, a line, a plane or a
 * pure rotation look determined. Nothing is written on failure.
 */
SFM_API int sfm_ransac_trifocal(const double *x1, const double *x2, const double *x3, int n,
                                const sfm_ransac_options *opt, double T[27], double *P,
                                uint8_t *inlier_mask, sfm_ransac_stats *stats, void *ws,
                                size_t ws_size);

#ifdef __cplusplus
}
#endif
#endif
