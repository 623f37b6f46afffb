/*
 * Self-calibration by the absolute dual quadric (M. Pollefeys, R. Koch,
 * L. Van Gool, "Self-calibrating and metric reconstruction in spite of
 * varying and unknown intrinsic camera parameters", IJCV 1999; Hartley &
 * Zisserman 2nd ed., 19.3).
 *
 * The image of the absolute dual quadric Q* (4x4, symmetric, rank 3) in
 * view i is the dual image of the absolute conic, w*_i = P_i Q* P_i^T ~
 * K_i K_i^T. With the principal point at the image centre, zero skew and
 * unit aspect ratio, w*_i (in coordinates centred on the image and scaled by
 * a focal guess) is diag(f_i^2, f_i^2, 1): the entries w_01, w_02, w_12 and
 * w_00 - w_11 vanish, four linear equations on the 10 entries of Q* per view
 * (Pollefeys' weights 1/0.1 and 1/0.2; two weak equations w_00 = w_22,
 * w_11 = w_22 of weight 1/9 pull f towards the guess, and one reweighted
 * pass divides each view's rows by its w*_22). Every view counts (least
 * squares).
 *
 * Conditioning: each view's pixels are centred on the image and divided by
 * the guess s = (width + height) / 2; the projective frame is then moved so
 * that the first camera is [I | 0] and its scale along the fourth
 * coordinate balanced, so the 10 unknowns have comparable magnitudes.
 *
 * Then: rank 3 is enforced (the eigenvalue of smallest magnitude set to
 * zero), Q* must be positive semi-definite (three eigenvalues of one sign)
 * and every w*_i positive definite, otherwise the linear solution is
 * unusable and SFM_E_SINGULAR is returned with the reason in
 * result.flags. K_1 follows from w*_1 by the upper-triangular Cholesky
 * factor and the plane at infinity from Q*'s last column (closed form with
 * P_1 = [I | 0]): H = [K_1 0; -p^T K_1 1] in the balanced frame. With
 * points the mirror ambiguity (H and H diag(1, 1, 1, -1) give the same
 * cameras up to a reflection of depth) is resolved by cheirality: the sign
 * that puts more points in front of the cameras is kept, and when fewer
 * than 90 % are then in front of every camera the plane at infinity cuts
 * the scene (SFM_SELFCAL_FLAG_CHEIRALITY).
 *
 * Outputs: K_i = [f_i 0 cx; 0 f_i cy; 0 0 1] (the priors applied, f_i from
 * the mean of the diagonal of w*_i), H (4x4) such that P_i H ~ K_i [R_i | t_i]
 * (metric cameras) and X_metric ~ H^{-1} X.
 *
 * Memory: no workspace; a bounded stack of about 6 KiB (two 4x4 and one
 * 10x10 symmetric eigensolve, the conditioned cameras).
 */
#ifndef SFM_SELFCAL_H
#define SFM_SELFCAL_H

#include "sfm/sfm_common.h"

#ifdef __cplusplus
extern "C" {
#endif

#define SFM_SELFCAL_MAX_VIEWS 32

/* result.flags: why the linear solution is unusable (or suspect) */
#define SFM_SELFCAL_FLAG_NOT_PSD 1      /* Q* not semi-definite after rank 3 */
#define SFM_SELFCAL_FLAG_OMEGA_NOT_PD 2 /* some w*_i not positive definite */
#define SFM_SELFCAL_FLAG_CHEIRALITY 4   /* the plane at infinity cuts the scene */
#define SFM_SELFCAL_FLAG_AMBIGUOUS 8    /* the linear system has a second null
                                           direction: a critical motion */
#define SFM_SELFCAL_FLAG_MIRRORED 16    /* H was flipped by cheirality (not an error) */

typedef struct sfm_selfcal_result {
    int flags;           /* SFM_SELFCAL_FLAG_* */
    double null_ratio;   /* smallest / second smallest singular value of the
                            weighted system (near 1: ambiguous) */
    double focal[SFM_SELFCAL_MAX_VIEWS]; /* f_i in pixels, per view */
    double front_fraction; /* share of (point, view) pairs in front, with points */
} sfm_selfcal_result;

/* Linear self-calibration of m >= 3 projective cameras P (m x 12, pixels)
 * with image sizes wh (m x 2: width, height; principal point prior at
 * ((width - 1) / 2, (height - 1) / 2)). X (n x 4 homogeneous points of the
 * same frame, may be NULL with n = 0) resolves the mirror ambiguity; rows
 * that are all zero are skipped. Writes K (m x 9), H (16) and result (may be
 * NULL); result is also written when the status is SFM_E_SINGULAR (flags
 * say why), K and H only on success.
 * Statuses: SFM_OK; SFM_E_ARGUMENT (NULL, m < 3 or > SFM_SELFCAL_MAX_VIEWS,
 * n < 0, a size <= 0); SFM_E_NONFINITE; SFM_E_SINGULAR (the linear solution
 * is unusable, see result->flags; or the first camera is rank-deficient);
 * SFM_E_NO_CONVERGENCE (an eigensolver failed). */
SFM_API int sfm_selfcal_linear(int m, const double *P, const double *wh, int n, const double *X,
                               double *K, double H[16], sfm_selfcal_result *result);

#ifdef __cplusplus
}
#endif
#endif
