/* Internal: is a set of two-view inliers explained by a pure rotation or by
 * one homography? */
#ifndef SFM_ROBUST_TWOVIEW_DEGENERACY_H
#define SFM_ROBUST_TWOVIEW_DEGENERACY_H

#include <stdint.h>

/* Fraction of inliers a rotation or homography must explain to raise a flag. */
#define SFM_DEGENERACY_FRACTION 0.85
/* Threshold multiplier for the rotation / homography fits (their errors are
 * two-dimensional transfer errors, the Sampson error one-dimensional). */
#define SFM_DEGENERACY_TAU_MULT 3.0

/* 4-point homographies tried for the plane test. When the flag is due the
 * plane holds at least SFM_DEGENERACY_FRACTION of the inliers, so a sample
 * lies on it with probability >= 0.85^4 = 0.52 and 16 samples all miss it
 * with probability below 1e-5. */
#define SFM_DEGENERACY_H_TRIALS 16

/*
 * b1, b2: unit bearings; idx[0..n): inliers of the relative pose; R_pose,
 * t_pose: its rotation and translation (t_pose may be NULL); tau: the angular inlier threshold; seed: for the homography
 * samples. p1, p2: scratch of 2 n doubles each, sel: n ints.
 * Returns SFM_RANSAC_FLAG_* bits (PURE_ROTATION, PLANAR) or 0. With PLANAR,
 * H (9 doubles, may be NULL) gets the plane's homography on the z = 1
 * plane (x2 ~ H x1), and p1, p2 hold the inliers' z = 1 points, the
 * plane's first: sel[0..*n_plane) indexes them (n_plane may be NULL).
 */
int sfmi_robust_twoview_degeneracy(const double *b1, const double *b2, const int *idx, int n,
                                  const double *R_pose, const double *t_pose, double tau,
                                  uint64_t seed, double *p1, double *p2, int *sel, double *H,
                                  int *n_plane);

#endif
