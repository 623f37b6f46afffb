/* Internal: the tests every estimator runs on the support set of its final
 * model (see support_check.c for the rules and sfm_ransac.h for the
 * thresholds as callers see them). */
#ifndef SFM_ROBUST_SUPPORT_CHECK_H
#define SFM_ROBUST_SUPPORT_CHECK_H

#include <stddef.h>

/* Chance support. A model of sample size k fits its k sample points
 * exactly; each of the other n - k points falls within the inlier band of
 * a wrong model with probability p (band area over image area). The count
 * a random-match input reaches is about k + mu, mu = (n - k) p, and the
 * search (many samples, each refined) pushes it a few standard deviations
 * above that; a model is accepted when n_inl >= k + SFMI_CHANCE_MULT mu +
 * SFMI_CHANCE_SD sqrt(mu) + SFMI_CHANCE_ADD. */
#define SFMI_CHANCE_MULT 3.0
#define SFMI_CHANCE_SD 6.0
#define SFMI_CHANCE_ADD 5.0
/* The inlier count the chance rule asks for; 1 when n_inl is above it. */
double sfmi_chance_count(int n, int k, double p);
int sfmi_above_chance(int n, int k, int n_inl, double p);

/* Area (pixels^2) of the bounding box of n 2-vectors (row stride `stride`
 * doubles), at least 1; *diag gets its diagonal. */
double sfmi_bbox_area(const double *p, int stride, int n, double *diag);
/* Probability that a uniform point of that box falls within a band of full
 * width w across it (an epipolar band), or within a disc of radius r. */
double sfmi_chance_band(double area, double diag, double w);
double sfmi_chance_disc(double area, double r);

/* Principal standard deviations (sd_min <= sd_max) of the 2-vectors
 * p[stride * idx[j]] (idx NULL: j itself), j < m. */
void sfmi_spread(const double *p, int stride, const int *idx, int m, double *sd_min,
                 double *sd_max);

/* Collinear: the minor principal deviation of the support in an image below
 * SFMI_LINE_MULT thresholds, or below SFMI_LINE_RATIO of the major one
 * (points on one image line leave two-view and three-view models
 * undetermined off that line). Clustered (projective models only, where no
 * focal length says how wide the view is): the major deviation below
 * SFMI_CLUSTER_RATIO of the diagonal of all the input points' box. */
#define SFMI_LINE_MULT 3.0
#define SFMI_LINE_RATIO 0.02
#define SFMI_CLUSTER_RATIO 0.02
/* Clustered, calibrated models: the major angular deviation of the
 * support's bearings below SFMI_CLUSTER_ANGLE radians (2 deg). Within so
 * narrow a view a translation moves the points as a rotation does (the
 * difference is of second order in the angle), so neither R nor t is
 * determined, whatever the covariance of the linearised refit says. */
#define SFMI_CLUSTER_ANGLE 0.035
int sfmi_spread_collinear(double sd_min, double sd_max, double tau);

/* Conditioning of a linear model on its support: AtA (d x d, symmetric,
 * d <= 27) is the normal matrix of the m Hartley-normalised design rows.
 * A determined model has one null direction; a second eigenvalue of no
 * more than SFMI_DESIGN_RHO times m s2 (s2: the variance of one normalised
 * coordinate, (tau / 3)^2 times the normalising scale squared) is a second
 * null direction drowned in noise: the support does not determine the
 * model. ws: sfm_sym_eig_workspace_size(d) bytes, V: d x d, w: d doubles.
 * small2 (may be NULL) receives the two smallest eigenvalues, smallest
 * first. Returns 1 when degenerate, 0 when determined, < 0 on failure. */
#define SFMI_DESIGN_RHO 10.0
int sfmi_design_degenerate(const double *AtA, int d, int m, double s2, double *V, double *w,
                           void *ws, size_t ws_size, double small2[2]);

/* The design test above for a two-view linear model on the pairs
 * g1[j], g2[j] (pixels, j < m, contiguous): homography rows (two per pair,
 * homography = 1) or fundamental rows (one per pair), Hartley-normalised
 * per image. tau: the pixel threshold. Returns 1 degenerate, 0 determined,
 * < 0 on failure. */
int sfmi_pairs_design_degenerate(const double *g1, const double *g2, int m, int homography,
                                 double tau);

/* sqrt of the trace of a 3x3 block (r0, r0) of a 6x6 matrix. */
double sfmi_block_sd(const double *cov6, int r0);

/* Pose thresholds: with the residuals' variance at (threshold / 3)^2 (the
 * inlier threshold as three standard deviations), a rotation standard
 * deviation above SFMI_ROT_SD_MAX radians means the inliers do not fix R:
 * SFM_E_DEGENERATE. A translation-direction deviation above
 * SFMI_TDIR_SD_MAX radians (relative pose) leaves R usable and t not:
 * SFM_RANSAC_FLAG_LOW_PARALLAX. Absolute pose: a translation deviation
 * above SFMI_TREL_SD_MAX times the mean depth of the inliers is
 * degenerate. */
#define SFMI_ROT_SD_MAX 0.026  /* 1.5 deg */
#define SFMI_TDIR_SD_MAX 0.052 /* 3 deg */
#define SFMI_TREL_SD_MAX 0.05

#endif
