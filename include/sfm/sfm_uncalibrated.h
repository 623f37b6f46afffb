/*
 * Uncalibrated reconstruction: metric cameras (K, R, t) and points from
 * pixel matches of an unknown camera (zero skew, unit aspect ratio,
 * principal point at the image centre ((width - 1) / 2, (height - 1) / 2),
 * one focal length shared by the views) and, with three views, up to
 * options.radial radial distortion terms about the centre: Brown's
 * x_d = x_n (1 + k1 r^2 + k2 r^4), r = |x_n|, in normalized coordinates
 * (sfm_camera.h, SFM_CAMERA_BROWN with p1 = p2 = k3 = 0). A lens with
 * k1 = -0.26 moves the corners of a 640x480 image by about 30 px; modelled
 * as a pinhole, the focal length absorbs it (mono_wall of the BoofCV
 * triplets: 1790 px against a chessboard 701 px).
 *
 * Three views (sfm_recon_three_view_uncalibrated):
 *  1. trifocal RANSAC on the centred pixels (sfm_ransac_trifocal: projective
 *     cameras refined on the inliers by the gold-standard method);
 *  2. linear self-calibration by the absolute dual quadric
 *     (sfm_selfcal_linear) on those cameras, with the triangulated inliers
 *     for its cheirality test; its focal length, when usable, is one start;
 *  3. a focal sweep: for each of options.sweep_steps focal lengths spaced
 *     logarithmically over [focal_min, focal_max] * max(width, height), the
 *     metric cameras of that K (essential matrices K^T F21 K, K^T F31 K of
 *     the tensor, decomposed with the cheirality choice, the third view
 *     scaled by least squares) refined by a metric bundle adjustment with the
 *     focal length held (options.sweep_iterations steps), scored by its
 *     final cost; then a golden-section
 *     search on log f around the best candidate;
 *  4. metric bundle adjustment with the focal length free from the linear
 *     start and from the sweep's best (Huber loss at 2 thresholds, view 1
 *     fixed, |t2| = 1); the lower cost wins and names the path. The radial
 *     terms (from 0) are free in every adjustment of steps 3-6, so the
 *     fixed-focal costs are profiles over them and sigma f below accounts
 *     for their correlation with f; the answer is then tested against the
 *     nested smaller models (k2 held at 0, then k1): a term whose removal
 *     raises the cost by less than 9 noise variances is dropped and the
 *     smaller fit is the answer (report.k1, k2 = 0). A distortion under
 *     which an inlier lies outside the region where the map is invertible
 *     fails step 6. Steps 3-6 run first with the pinhole model; from its
 *     accepted answer k1, then k1 and k2, are fitted with the same rule,
 *     and the pinhole answer stands when neither term is significant;
 *     otherwise the answer is refitted and checked with the terms free,
 *     and steps 3-6 run with the terms free (as above) when that or the
 *     pinhole answer is refused (per_view_focal: always);
 *  5. the observability of f: the sweep's cost at focal lengths more than a
 *     factor 1.5 away must exceed the best by options.min_profile times the
 *     noise variance; otherwise (pure translation, parallel optical axes,
 *     motion along the optical axis) f is not determined: SFM_E_SINGULAR;
 *     the same when the standard deviation of f (below) is above
 *     options.max_focal_sigma (relative). The candidates of step 4 are
 *     checked in order of cost, and one refused for its sigma ends the run:
 *     a costlier candidate is a local optimum that does not see the better
 *     basin, and its own curvature could pass the bound;
 *  6. the inliers re-collected under the metric cameras (three-view error
 *     below the threshold), one more bundle adjustment on them, and the
 *     physical checks: f > 0, at least options.min_front of the inlier
 *     points in front of every camera, RMS reprojection error at most
 *     options.max_rms. A failed check is SFM_E_NO_CONVERGENCE, never an
 *     answer. A median triangulation angle below options.min_parallax_deg
 *     (rotation without translation: the focal length is then determined
 *     but the translations are fitted to noise) is SFM_E_SINGULAR.
 * The standard deviation of f (report.focal_sigma, of log f) adds in
 * quadrature two parts. The noise's (report.focal_sigma_noise): the profile
 * likelihood's curvature at the answer, the fixed-focal optima at
 * f e^{+-0.05} (poses, points and the free radial terms re-optimized, the
 * noise variance from the answer's residuals with the points' and poses'
 * degrees of freedom removed, and at least 0.2 px squared) against the
 * free optimum, the flatter side. The floor is the localisation error's
 * systematic part, which the residuals of sub-pixel aligned points (0.07-
 * 0.14 px) do not show: on the rendered demo loop (f known, the model
 * exact) z had RMS 2.32 without it, 1.06 with it.
 * The model's: the principal point is held at the centre and the aspect
 * ratio at 1, which no real camera meets exactly; each is moved by one
 * standard deviation of its prior (options.principal_sigma per axis,
 * options.aspect_sigma) and the change of log f of the refitted answer
 * counts as one more standard deviation. On synthetic scenes with the
 * intrinsics drawn from those priors and Gaussian noise, z = log(f /
 * f_true) / sigma spreads as a standard normal (std 0.98 two views, 1.12
 * three; the noise's part alone gives 1.60 and 3.67 there, and 1.00 / 1.14
 * with the model exact). On Herz-Jesu-P8 (principal point 15 and 17 px off
 * the centre, fy / fx 1.0017) the median |z| is 0.63 (two views) and 0.58
 * (three); the noise's part alone gave 1.43 and 1.32, and 0.96 / 0.98 on
 * the same matches with the ground-truth principal point and aspect moved
 * to the model's. The rest of that overconfidence is not explained: the
 * real features' errors under the ground-truth cameras are heavy-tailed
 * (kurtosis 5-10) and not white, neither of which is modelled.
 * When the metric stage fails (SFM_E_SINGULAR or SFM_E_NO_CONVERGENCE) the
 * run is repeated from RANSAC with the seeds seed + 1 and seed + 2, the last
 * with twice the threshold (a tensor fitted to part of the scene; the RMS
 * accepted stays options.max_rms, or the first threshold); the report is the
 * last run's.
 * Two views (sfm_recon_two_view_uncalibrated): fundamental RANSAC with
 * DEGENSAC, the focal length of F by Bougnoux's formula (S. Bougnoux, "From
 * projective to Euclidean space under any practical situation, a criticism
 * of self-calibration", ICCV 1998) as the linear start, then steps 3-6 with
 * one essential matrix. Two views carry far less information on f than
 * three (one constraint from the Kruppa equations with the priors): expect
 * more failures, reported as such. Two views stay pinhole (options.radial
 * is ignored): the one constraint on f would be shared with the radial
 * terms (not attempted).
 *
 * Poses map view-1 coordinates to each camera, x_cam = R X + t; pose 0 is
 * the identity, |t2| = 1. Points X (n x 3) in view-1 coordinates, written
 * for the final inliers (zero for the others). Pixels: n x 2 row-major.
 */
#ifndef SFM_UNCALIBRATED_H
#define SFM_UNCALIBRATED_H

#include "sfm/sfm_common.h"
#include "sfm/sfm_ransac.h"

#ifdef __cplusplus
extern "C" {
#endif

/* report.path */
#define SFM_UNCAL_PATH_NONE 0
#define SFM_UNCAL_PATH_LINEAR 1 /* the linear (dual quadric or Bougnoux) start won */
#define SFM_UNCAL_PATH_SWEEP 2  /* the focal sweep won (or the linear start was unusable) */

/* report.stage: the last stage reached (where a failure happened) */
#define SFM_UNCAL_STAGE_RANSAC 1
#define SFM_UNCAL_STAGE_SELFCAL 2
#define SFM_UNCAL_STAGE_SWEEP 3
#define SFM_UNCAL_STAGE_BA 4
#define SFM_UNCAL_STAGE_VALIDATE 5
#define SFM_UNCAL_STAGE_DONE 6

#define SFM_UNCAL_MAX_SWEEP 64

typedef struct sfm_uncal_options {
    sfm_ransac_options ransac; /* threshold: pixels per view */
    int sweep_steps;           /* 2..SFM_UNCAL_MAX_SWEEP, default 17 */
    int sweep_iterations;      /* 1..50, default 4: bundle adjustment steps per
                                  fixed-focal candidate of the sweep (the
                                  candidates are ranked, not reported: the
                                  free-focal adjustments from the best
                                  converge: on the 56 Herz-Jesu-P8 triplets 4
                                  and 8 give the same answers, f within
                                  4e-11) */
    double focal_min;          /* multiples of max(width, height), default 0.2 */
    double focal_max;          /* default 5 */
    double max_rms;            /* px, default 0 = the RANSAC threshold */
    double min_front;          /* default 0.95 */
    double min_profile;        /* default 100: the far rise, in noise variances, below
                                  which a second focal length explains the data (the
                                  Huber loss makes far costs grow slower than a parabola) */
    double max_focal_sigma;    /* default 0.05 / 3 (three sigma within 5 %): largest
                                  relative standard deviation of f answered */
    int per_view_focal;        /* default 0; 1: after the shared answer, one more
                                  adjustment with a focal length per view, kept
                                  when it passes the same checks */
    double min_parallax_deg;   /* default 0.5: median triangulation angle below it
                                  (rotation only) is SFM_E_SINGULAR */
    int radial;                /* radial distortion terms estimated with the focal
                                  length (three views; see above): 0 pinhole, 1 k1,
                                  2 (default) k1 and k2 */
    double principal_sigma;    /* default 0.01: prior standard deviation of the
                                  principal point about the centre, per axis, in
                                  multiples of max(width, height); 0: none */
    double aspect_sigma;       /* default 0.0025: prior standard deviation of the
                                  aspect ratio fy / fx about 1; 0: none */
} sfm_uncal_options;

typedef struct sfm_uncal_report {
    int stage;                 /* SFM_UNCAL_STAGE_* reached */
    int attempts;              /* runs from RANSAC (a failed metric stage is retried
                                  with the next seeds, at most 3 runs) */
    int n_input;
    int ransac_inliers;
    sfm_ransac_stats ransac;
    double projective_rms;     /* px, RANSAC inliers under the projective cameras */
    int linear_status;         /* status of the linear start (SFM_OK when usable) */
    int linear_flags;          /* SFM_SELFCAL_FLAG_* of the dual quadric (three views) */
    double focal_linear;       /* px, 0 when unusable */
    double focal_sweep;        /* px, best of the coarse sweep and its refinement */
    int evaluations;           /* metric bundle adjustments run */
    int path;                  /* SFM_UNCAL_PATH_* */
    double profile_rise;       /* cost rise at f off by > 1.5x, in noise variances */
    double focal_sigma;        /* relative standard deviation of f: the profile's
                                  and the priors' in quadrature (see above) */
    double focal_sigma_noise;  /* the profile's part alone (the noise) */
    double focal;              /* px, final (with k1, k2, inliers, rms and
                                  front_fraction: the last candidate's when it is
                                  refused at the validation stage) */
    int inliers;               /* final inliers */
    double rms;                /* px, final inliers, sqrt(mean squared error per view) */
    double front_fraction;     /* final inlier points in front of every camera */
    double parallax_deg;       /* median over the points of the largest ray angle */
    double focal_view[3];      /* px, the final focal length of each view */
    double k1, k2;             /* Brown k1, k2 of the answer (0: the term dropped) */
    double radial_rise[2];     /* cost rise, in noise variances, with k1 ([0],
                                  against the pinhole) or k2 ([1], against k1
                                  alone) held at 0; a term is dropped below 9;
                                  0 when not tested */
} sfm_uncal_report;

/* Defaults listed above (ransac: sfm_ransac_default_options, threshold 1).
 * Statuses: SFM_OK, SFM_E_ARGUMENT (NULL). */
SFM_API int sfm_uncal_default_options(sfm_uncal_options *opt);

/* Workspace bytes for n triplets and the default options (the largest:
 * radial 2); 0 when n is out of range. */
SFM_API size_t sfm_recon_three_view_uncalibrated_workspace_size(int n);
/* The same for options.radial = radial (0..2; 0 when out of range): with
 * radial 0, 13 % less at 500 triplets. */
SFM_API size_t sfm_recon_three_view_uncalibrated_workspace_size_radial(int n, int radial);

/* On success returns the final inlier count and writes K (3 x 9: one 3x3
 * per view, equal unless options.per_view_focal), poses[3],
 * X (n x 3, may be NULL), inlier_mask (n, may be NULL); report (may be
 * NULL) is written on success and on the failures after the argument
 * checks. opt may be NULL.
 * Statuses: SFM_E_ARGUMENT (NULL, n < 7, width or height < 2, bad option),
 * SFM_E_NONFINITE, SFM_E_WORKSPACE, SFM_E_NO_CONVERGENCE (no tensor, or
 * the metric answer failed a physical check), SFM_E_SINGULAR (the focal
 * length or the poses are not determined by the data).
 * Nothing but the report is written on failure. */
SFM_API int sfm_recon_three_view_uncalibrated(const double *px1, const double *px2, const double *px3,
                                              int n, int width, int height,
                                              const sfm_uncal_options *opt, double *K,
                                              sfm_pose poses[3], double *X, uint8_t *inlier_mask,
                                              sfm_uncal_report *report, void *ws, size_t ws_size);

/* The same from pairs (n >= 8), K (2 x 9), poses[2]. */
SFM_API size_t sfm_recon_two_view_uncalibrated_workspace_size(int n);
SFM_API int sfm_recon_two_view_uncalibrated(const double *px1, const double *px2, int n, int width,
                                            int height, const sfm_uncal_options *opt, double *K,
                                            sfm_pose poses[2], double *X, uint8_t *inlier_mask,
                                            sfm_uncal_report *report, void *ws, size_t ws_size);

#ifdef __cplusplus
}
#endif
#endif
