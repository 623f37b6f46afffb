/*
 * Internal: pieces of the absolute-dual-quadric self-calibration shared by
 * the linear method (selfcal.c) and the focal search (selfcal_sweep.c).
 * Q* is held as a symmetric 4x4; its 10 unknowns are the upper-triangular
 * entries in the order (00, 01, 02, 03, 11, 12, 13, 22, 23, 33). Not API.
 */
#ifndef SFM_RECON_SELFCAL_INTERNAL_H
#define SFM_RECON_SELFCAL_INTERNAL_H

#include <stddef.h>

#include "sfm/sfm_selfcal.h"

/* Ps (m x 12) = P with each camera scaled by a power of two (exact) when
 * its largest |entry| lies outside [2^-20, 2^40], into [1, 2): a projective
 * camera's scale is arbitrary, and one of 1e-15 or 1e180 underflowed or
 * overflowed the squared sums (refused, or SFM_E_NONFINITE for a finite
 * input). Cameras inside the band are copied as they are (same bits). */
void sfmi_selfcal_scale_cameras(int m, const double *P, double *Ps);
/* out = diag(1/s, 1/s, 1) [1 0 -cx; 0 1 -cy; 0 0 1] P, the camera in the
 * coordinates of K^{-1} x for K = [s 0 cx; 0 s cy; 0 0 1]; out may be P. */
void sfmi_selfcal_condition(const double P[12], double cx, double cy, double s, double out[12]);
/* Coefficients r (10) of w_ab = (P Q P^T)_ab in the 10 entries of Q. */
void sfmi_selfcal_omega_row(const double P[12], int a, int b, double r[10]);
/* The six rows of w*_i ~ diag(a, a, 1) in the 10 entries of Q: r[0..2]
 * the off-diagonal w_01, w_02, w_12, r[3..5] the differences w_00 - w_11,
 * w_00 - w_22, w_11 - w_22. */
void sfmi_selfcal_adq_rows(const double P[12], double r[6][10]);
/* A (10x10, lower triangle) += w^2 r r^T. */
void sfmi_selfcal_add_row(double A[100], const double r[10], double w);
/* W = P Q P^T (3x3). */
void sfmi_selfcal_omega(const double P[12], const double Q[16], double W[9]);
/* Q (4x4, symmetric) from its 10 upper-triangular entries q, signed so that
 * its trace is positive (Q* is positive semi-definite), and each view's
 * |w*_22| into nu (m; 1 where it vanishes), the reweighting of the second
 * pass. */
void sfmi_selfcal_set_q(const double q[10], int m, const double Pc[][12], double Q[16], double *nu);
/* Upper-triangular K with K K^T = W / W_22; 0 when W is not positive
 * definite. */
int sfmi_selfcal_upper_cholesky(const double W[9], double K[9]);
/* det M (3x3). */
double sfmi_selfcal_det3(const double M[9]);
/* C = A B (4x4). */
void sfmi_selfcal_mul44(const double A[16], const double B[16], double C[16]);
void sfmi_selfcal_mul34_44(const double P[12], const double H[16], double out[12]);
/* A = B^{-1} (4x4, LU); 0 when singular. */
int sfmi_selfcal_inv44(const double B[16], double A[16]);

/* Q <- its nearest rank-3 matrix (the eigenvalue of smallest magnitude
 * zeroed), of the sign of the majority of the other three;
 * SFM_SELFCAL_FLAG_NOT_PSD into *flags when those differ in sign. ews: a
 * sfm_sym_eig workspace for n = 4. */
int sfmi_selfcal_rank3(double Q[16], int *flags, void *ews, size_t ews_size);

/* Conditioned cameras Pc (m, in place) moved to the frame where Pc[0] =
 * [I | 0], the fourth coordinate balanced against the first three, each
 * camera scaled to unit norm; H0 the frame change (Pc_i ~ Pc_i,in H0).
 * SFM_E_SINGULAR when the first camera is rank-deficient. */
int sfmi_selfcal_frame(int m, double Pc[][12], double H0[16], void *ews, size_t ews_size);

/* The rectifying H (P_i H ~ K_i [R_i | t_i]) of the original cameras P
 * from Q* (rank 3, in the frame of sfmi_selfcal_frame), K1 (the upper
 * Cholesky factor of w*_1 there) and H0; with points X (n x 4, zero rows
 * skipped) the mirror is resolved by cheirality (res->flags MIRRORED,
 * res->front_fraction). SFM_E_SINGULAR when the plane at infinity is
 * undetermined, or fewer than 90 % of the (point, view) pairs are in front
 * (res->flags CHEIRALITY). */
int sfmi_selfcal_rectify(int m, const double *P, const double Q[16], const double K1[9], const double H0[16],
                         int n, const double *X, double H[16], sfm_selfcal_result *res);

#endif
