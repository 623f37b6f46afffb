/*
 * Internal: small projective-geometry pieces shared by the recon module
 * (factorization, self-calibration, the uncalibrated pipelines). Not API.
 */
#ifndef SFM_RECON_PROJECTIVE_H
#define SFM_RECON_PROJECTIVE_H

#include <stddef.h>

/* x /= |x| (n entries; sfmi_normalize4: 4); a zero vector is left as it is. */
void sfmi_normalize_vec(double *x, int n);
void sfmi_normalize4(double X[4]);

/* Hartley normalization of one view's n observations px (n x 2, NaN
 * missing): T (3x3) and xn = T px for the observed ones (NaN kept).
 * SFM_E_SINGULAR when fewer than 2 observations or all coincide. */
int sfmi_hartley_view(const double *px, int n, double T[9], double *xn);

/* P = T^{-1} Pn for a Hartley T. */
void sfmi_denormalize_camera(const double T[9], const double Pn[12], double P[12]);

/* Squared reprojection error of homogeneous X under P against x; 0 when the
 * projection is at infinity (|w| tiny against the point), 1 otherwise. */
int sfmi_reproj_err2(const double P[12], const double X[4], const double x[2], double *e2);

/* Homogeneous DLT point of track j from the views with view_ok (x: m x n x
 * 2 normalized, NaN missing; P: m x 12), unit norm. SFM_E_SINGULAR when the
 * track has fewer than 2 such views. ws: a sfm_sym_eig workspace for
 * n >= 4. */
int sfmi_triangulate_homog(int m, int n, const double *x, const double *P, const int *view_ok, int j,
                           double X[4], void *ws, size_t ws_size);

/* Projective DLT resection of a camera from the points with pt_ok observed
 * in this view (xv: n x 2 normalized, NaN missing; X: n x 4). ws: a
 * sfm_sym_eig workspace for n = 12. SFM_E_SINGULAR with fewer than 6
 * points or a rank-deficient system. */
int sfmi_resection_dlt(const double *xv, int n, const double *X, const int *pt_ok, double P[12],
                       void *ws, size_t ws_size);

/* Scale s of the third view's translation given the points X (m x 3,
 * triangulated in views 1 and 2, flags non-zero skipped) and the third
 * view's bearings b3 (m x 3): least squares on b3 x (R3 X + s t3) = 0.
 * NaN when the system is empty or degenerate. */
struct sfm_pose;
double sfmi_third_view_scale(const struct sfm_pose *p3, int m, const double *X, const int *flags,
                             const double *b3);

#endif
