/*
 * The trifocal tensor of three views.
 *
 * Storage: T[i*9 + j*3 + k] = T_i^{jk} (Hartley & Zisserman, 2nd ed., ch. 15),
 * i.e. numpy's T[i, j, k]; T_i is the 3x3 matrix T[i, :, :]. View 1 is the
 * reference: point-line-line incidence l_i = l'_j l''_k T_i^{jk}, and point
 * triplets satisfy [x']_x (sum_i x^i T_i) [x'']_x = 0.
 * Cameras are 3x4 row-major projection matrices, x ~ P [X; 1]. Epipoles e'
 * (e2) and e'' (e3) are the images of the first camera centre in views 2
 * and 3. Fundamental matrices: x2^T F21 x1 = 0, x3^T F31 x1 = 0,
 * x3^T F32 x2 = 0.
 *
 * Tensors are defined up to scale; functions that return one normalize it to
 * unit Frobenius norm unless stated. Points are pixels (n x 2 row-major).
 */
#ifndef SFM_TRIFOCAL_H
#define SFM_TRIFOCAL_H

#include "sfm/sfm_common.h"

#ifdef __cplusplus
extern "C" {
#endif

/* Minimal number of point triplets for the linear estimate (27 unknowns, 4
 * independent equations per triplet). */
#define SFM_TRIFOCAL_MIN_POINTS 7

/* T from three cameras, by the 4x4 determinant formula (H&Z eq. 17.12);
 * valid for any cameras, not only P1 = [I | 0]. Unit Frobenius norm.
 * Statuses: SFM_OK, SFM_E_ARGUMENT, SFM_E_NONFINITE, SFM_E_SINGULAR (the
 * tensor vanishes: coincident camera centres or rank-deficient cameras). */
SFM_API int sfm_trifocal_from_cameras(const double P1[12], const double P2[12], const double P3[12],
                                      double T[27]);

/* Epipoles e2 = e', e3 = e'' (unit norm, sign fixed so the largest-magnitude
 * entry is positive), from the null vectors of the T_i (H&Z alg. 15.1).
 * Statuses: SFM_OK, SFM_E_ARGUMENT, SFM_E_NONFINITE, SFM_E_SINGULAR. */
SFM_API int sfm_trifocal_epipoles(const double T[27], double e2[3], double e3[3]);

/* Fundamental matrices from T (any may be NULL; unit Frobenius norm):
 * F21 = [e']_x [T1, T2, T3] e'', F31 = [e'']_x [T1^T, T2^T, T3^T] e', and
 * F32 from the cameras of sfm_trifocal_cameras.
 * Statuses: as sfm_trifocal_epipoles. */
SFM_API int sfm_trifocal_fundamentals(const double T[27], sfm_mat3 *F21, sfm_mat3 *F31,
                                      sfm_mat3 *F32);

/* Compatible projective cameras from T, with P1 = [I | 0] implied:
 * P2 = [[T1, T2, T3] e'' | e'], P3 = [(e'' e''^T - I)[T1^T, T2^T, T3^T] e' | e''].
 * Statuses: as sfm_trifocal_epipoles. */
SFM_API int sfm_trifocal_cameras(const double T[27], double P2[12], double P3[12]);

/* Point transfer: the point in view 3 predicted from x1 (view 1) and x2
 * (view 2), through the line in view 2 perpendicular to the epipolar line of
 * x1 (H&Z 16.3). F21 may be NULL (it is then computed from T; pass it when
 * transferring many points).
 * Statuses: SFM_OK, SFM_E_ARGUMENT, SFM_E_NONFINITE, SFM_E_SINGULAR (the
 * transferred point is at infinity or x2 is at the epipole). */
SFM_API int sfm_trifocal_transfer(const double T[27], const sfm_mat3 *F21, const double x1[2],
                                  const double x2[2], double x3[2]);

/* Line transfer: l1_i = l2_j l3_k T_i^{jk} (homogeneous lines, output not
 * normalized). Statuses: SFM_OK, SFM_E_ARGUMENT, SFM_E_NONFINITE. */
SFM_API int sfm_trifocal_transfer_line(const double T[27], const double l2[3], const double l3[3],
                                       double l1[3]);

/* Estimate T from n >= 7 pixel triplets: the Hartley-normalized linear
 * solution, then algebraic minimization with the epipoles fixed and
 * re-estimated (H&Z alg. 16.2), so that T is geometrically valid (it comes
 * from three cameras). Memory: the design matrix is reduced to its 27 x 27
 * Gram matrix as the triplets come, so the workspace does not grow with n.
 * Statuses: SFM_OK, SFM_E_ARGUMENT (n < 7, NULL), SFM_E_NONFINITE,
 * SFM_E_WORKSPACE, SFM_E_SINGULAR (degenerate configuration),
 * SFM_E_NO_CONVERGENCE. */
SFM_API size_t sfm_trifocal_7pt_workspace_size(void);
SFM_API int sfm_trifocal_7pt(const double *x1, const double *x2, const double *x3, int n,
                             double T[27], void *ws, size_t ws_size);

/* Three-view reprojection error of one triplet given cameras: the point is
 * triangulated linearly from the three views, refined by Gauss-Newton on the
 * reprojection error, and the sum of squared pixel errors over the three
 * views is returned in *err2 (X, 4 homogeneous entries, may be NULL).
 * Statuses: SFM_OK, SFM_E_ARGUMENT, SFM_E_NONFINITE, SFM_E_SINGULAR. */
SFM_API int sfm_trifocal_point_error(const double P1[12], const double P2[12], const double P3[12],
                                     const double x1[2], const double x2[2], const double x3[2],
                                     double *err2, double X[4]);

#ifdef __cplusplus
}
#endif
#endif
