/* Internal: Gauss-Newton normal matrices of the final pose refits, for the
 * pose covariance and the degeneracy tests of support_check.h. */
#ifndef SFM_ROBUST_SUPPORT_POSE_H
#define SFM_ROBUST_SUPPORT_POSE_H

/*
 * Relative pose, signed bearing Sampson residuals of the points idx[0..m)
 * at (R, t), |t| = 1. Parameters: axis NULL: w (3, R <- exp([w]x) R) and
 * the tangent coordinates of t in the basis (e1, e2) of sfmi_tangent_basis
 * (np = 5); axis set (upright): the angle about axis and the same two
 * (np = 3). Writes JtJ (np x np, lower triangle and upper), G (6 x np: the
 * map to (w, t)), returns np; *ssr gets the sum of squared residuals.
 */
int sfmi_relpose_normal(const double *b1, const double *b2, const int *idx, int m,
                        const double *R, const double *t, const double *axis, double *JtJ,
                        double *G, double *ssr);

/*
 * Absolute pose, tangent-plane reprojection residuals (2 per point) of the
 * points idx[0..m) at (R, t). Parameters w (R <- exp([w]x) R) and t (np = 6,
 * G = I). Returns 6; *ssr as above; *mean_depth the mean depth of the
 * points in front.
 */
int sfmi_abspose_normal(const double *b, const double *X, const int *idx, int m,
                        const double *R, const double *t, double *JtJ, double *G, double *ssr,
                        double *mean_depth);

#endif
