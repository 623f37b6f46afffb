/* Internal: pose covariances of the final refits from the core LM driver,
 * for the degeneracy tests of support_check.h and for the covariance a
 * caller asks for (sfm_ransac_options.want_covariance). */
#ifndef SFM_ROBUST_SUPPORT_POSE_H
#define SFM_ROBUST_SUPPORT_POSE_H

/*
 * The inverse of the core LM driver's undamped Gauss-Newton matrix
 * (core/lm.h, want_covariance) of the refit's least-squares problem on the
 * inliers idx[0..m) at (R, t), no step taken, mapped to 6 x 6 row-major
 * (w, t), w the left rotation increment R <- exp([w]x) R: the pose
 * covariance for a unit residual variance (multiply by s2). *ssr gets the
 * inliers' sum of squared residuals.
 *
 * Relative pose: the refit's bearing Sampson residuals (sampson_lm.h), t on
 * the unit sphere (rank 5; axis set, the upright case: the angle about axis,
 * rank 3). Returns 0; 1 when t is not determined (no parallax): R alone with
 * t held, the t diagonal 1e30; -1 when R is not determined either (every
 * diagonal entry 1e30).
 *
 * Absolute pose: the tangent-plane reprojection residuals (reproj_lm.h;
 * points behind the camera left out), *mean_depth the inliers' mean depth
 * along their bearings. Returns 0, or -1 (every diagonal entry 1e30).
 */
int sfmi_relpose_covariance(const double *b1, const double *b2, const int *idx, int m,
                            const double *R, const double *t, const double *axis, double *cov6,
                            double *ssr);
int sfmi_abspose_covariance(const double *b, const double *X, const int *idx, int m,
                            const double *R, const double *t, double *cov6, double *ssr,
                            double *mean_depth);

#endif
