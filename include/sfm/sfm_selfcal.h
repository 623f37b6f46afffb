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
 * squares). The strong equations alone give the answer; with the weak ones
 * added only when the strong solution is unusable (below).
 *
 * Critical motion: SFM_SELFCAL_FLAG_AMBIGUOUS when the strong equations
 * have a second null direction (null_ratio > 0.2), or when the weak prior
 * chose the answer: its solution leaves the strong equations more than 2
 * times above their minimum residual where it rescued an unusable strong
 * solution, or more than 4 times with the focal lengths moved by more than
 * 5 % per unit of that ratio where the strong solution was usable
 * (result.weak_ratio). Orbital motion (optical axes through one point, a
 * turntable) is such a case: the image of a sphere about that point meets
 * the strong equations as the absolute conic does, and the prior used to
 * choose f ((w + h) / 2: 558-559 px for 800 answered as success).
 * Measured on factorized tracks (3-8 views, 0.1-2 px): 432 turntables over
 * 17-172 deg all refused, 144 general scenes all answered.
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
 * A camera's scale is free: one whose largest |entry| lies outside
 * [2^-20, 2^40] is first scaled by a power of two (exact) into [1, 2), so
 * that squared sums neither underflow nor overflow (1e-15 was refused,
 * 1e180 answered SFM_E_NONFINITE).
 *
 * Memory: no workspace; a bounded stack of about 13 KiB (two 4x4 and one
 * 10x10 symmetric eigensolve, the conditioned and the scaled cameras; 13.1
 * KiB measured by gcc -fstack-usage at -O2 on x86-64: 9.7 KiB and 3.3 KiB
 * in the solve it calls). Two solves (with and without the
 * weak equations) run every call. sfm_selfcal_solve below, with one shared
 * focal length and the observations, determines a turntable's f.
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
#define SFM_SELFCAL_FLAG_AMBIGUOUS 8    /* the strong equations have a second
                                           (nearly) null direction: a critical
                                           motion */
#define SFM_SELFCAL_FLAG_MIRRORED 16    /* H was flipped by cheirality (not an error) */

typedef struct sfm_selfcal_result {
    int flags;           /* SFM_SELFCAL_FLAG_* */
    double null_ratio;   /* smallest / second smallest singular value of the
                            weighted system (near 1: ambiguous) */
    double focal[SFM_SELFCAL_MAX_VIEWS]; /* f_i in pixels, per view */
    double front_fraction; /* share of (point, view) pairs in front, with points */
    double weak_ratio;   /* strong residual of the solution with the weak
                            equations over the strong minimum (floored at
                            1e-6 of the largest singular value; large: the
                            weak prior chose the answer) */
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

/*
 * m-view self-calibration with points (sfm_selfcal_solve): one unknown
 * focal length shared by the views (principal point at the image centre,
 * zero skew, unit aspect), then optionally one per view.
 *
 *  1. the linear dual quadric above; when usable its H and focal lengths
 *     are one start;
 *  2. a focal search (options.sweep): for each of options.sweep_steps focal
 *     lengths f spaced logarithmically over [focal_min, focal_max] * s
 *     (s = (width + height) / 2 of view 1), the metric cameras of K(f):
 *     with K known the dual-quadric constraints are w*_i ~ I in the
 *     coordinates K_i^{-1} x, six linear equations per view on Q*
 *     (least squares over the views, reweighted by w*_22 once), Q* made
 *     rank 3, the plane at infinity and H as in the linear method, the
 *     mirror by cheirality; the cameras K^{-1} P_i H projected to
 *     [R_i | t_i] (nearest rotation), the points H^{-1} X; then a metric
 *     bundle adjustment (sfm_ba_solve) over every observation with f held,
 *     scored by its final cost (Huber at options.loss_scale px) plus
 *     loss_scale^2 per observation of a point that was behind a camera or
 *     at infinity (dropped). Then a golden-section search on log f between
 *     the neighbours of the best candidate;
 *  3. bundle adjustment with the focal length free (one shared) from each
 *     start; the lower cost wins and names the path (report.path; a tie,
 *     both reaching one minimum, is "linear": report.focal_linear keeps
 *     what the linear method itself said, which may be far off);
 *  4. the observability of f: the profile of the fixed-focal cost over
 *     log f near the answer (f e^{+-0.05}, warm starts) gives the noise
 *     variance's count of the curvature, hence report.focal_sigma (the
 *     relative standard deviation of f: sigma^2 / curvature, sigma^2 =
 *     2 cost / (2 observations - free parameters)); the far rise is the
 *     least cost, in noise variances above the answer, of a focal length
 *     more than a factor 1.5 away (the sweep's candidates and warm starts
 *     at f * 1.5 and f / 1.5). A far rise below options.min_profile (the
 *     profile is flat: pure translation, rotation about the optical axis
 *     only, a critical motion) or focal_sigma above options.max_focal_sigma
 *     is SFM_E_SINGULAR;
 *  5. the larger models, each adjustment kept when it passes the checks
 *     below: options.principal SHARED, the principal point free (one for
 *     every view, which must then share the image size); per_view_focal,
 *     a focal length per view (report.per_view); principal PER_VIEW, a
 *     focal length and a principal point per view (report.principal says
 *     which principal point model was kept; K carries the answer);
 *  6. the physical checks: every f > 0, at least options.min_front of the
 *     points seen twice or more in front of every camera that sees them,
 *     RMS reprojection error (per observation, both axes) at most
 *     options.max_rms. A failed check is SFM_E_NO_CONVERGENCE, never an
 *     answer.
 *
 * Outputs (on SFM_OK only): K (m x 9), H (16) of the winning start with
 * P_i H ~ K_i [R_i | t_i] before the adjustments (frame: camera 1 at the
 * identity, the farthest camera centre at distance 1 from it), poses (m;
 * x_cam = R X + t, metric frame of camera 1: pose 0 the identity), Xm
 * (n x 3 metric points; zero for points not adjusted, also given in
 * report.points). The report is written on SFM_OK, SFM_E_SINGULAR and
 * SFM_E_NO_CONVERGENCE (with the refused candidate's figures).
 *
 * Memory: sfm_selfcal_workspace_size(m, n, n_obs) bytes (the bundle
 * adjustment's workspace and the observations compacted per candidate:
 * 1.6 MiB for the Oxford house, 10 views, 672 points, 2846 observations);
 * a bounded stack of about 20 KiB besides sfm_ba_solve's (gcc
 * -fstack-usage, -O2, x86-64). Deterministic: no random numbers.
 *
 * Measured (bench/README): Oxford house, f 726 px shared, sigma 0.3 %,
 * the linear method refusing; the ground truth's intrinsics break the
 * priors (principal point up to 96 px off-centre, skew), so the shared
 * answer is 9-22 % above its fx; principal = PER_VIEW brings it within
 * 3.5 % of its fy.
 */
#define SFM_SELFCAL_MAX_SWEEP 64

/* options.sweep */
#define SFM_SELFCAL_SWEEP_WHEN_NEEDED 0 /* only when the linear solution is unusable */
#define SFM_SELFCAL_SWEEP_ALWAYS 1      /* also as a second start (default) */

/* options.principal, report.principal */
#define SFM_SELFCAL_PRINCIPAL_CENTRE 0   /* held at ((width - 1) / 2, (height - 1) / 2) */
#define SFM_SELFCAL_PRINCIPAL_SHARED 1   /* one free for every view */
#define SFM_SELFCAL_PRINCIPAL_PER_VIEW 2 /* one free per view, with a focal length per view */

/* report.path */
#define SFM_SELFCAL_PATH_NONE 0
#define SFM_SELFCAL_PATH_LINEAR 1
#define SFM_SELFCAL_PATH_SWEEP 2

typedef struct sfm_selfcal_options {
    int sweep;              /* SFM_SELFCAL_SWEEP_*, default ALWAYS */
    int sweep_steps;        /* 3..SFM_SELFCAL_MAX_SWEEP, default 17 */
    double focal_min;       /* multiples of (width + height) / 2, default 0.25 */
    double focal_max;       /* default 4 */
    int per_view_focal;     /* default 0; 1 a focal length per view (step 5) */
    int principal;          /* SFM_SELFCAL_PRINCIPAL_*, default CENTRE (step 5) */
    double loss_scale;      /* Huber scale in px, default 2 */
    double max_rms;         /* px, default 1 */
    double min_front;       /* default 0.95 */
    double min_profile;     /* far rise in noise variances, default 100 */
    double max_focal_sigma; /* relative, default 0.05 / 3 */
    int max_iterations;     /* of the free-focal adjustments, default 100 */
} sfm_selfcal_options;

typedef struct sfm_selfcal_report {
    int path;               /* SFM_SELFCAL_PATH_* */
    int linear_status;      /* status of sfm_selfcal_linear */
    int linear_flags;       /* its SFM_SELFCAL_FLAG_* */
    double focal_linear;    /* px, mean of its focal lengths, 0 when unusable */
    double focal_sweep;     /* px, best fixed-focal candidate after the search, 0 without */
    double focal;           /* px, the shared answer (with the shared principal
                               point when that was kept) */
    double focal_view[SFM_SELFCAL_MAX_VIEWS]; /* px, per view (= focal unless per_view) */
    int per_view;           /* 1 when the per-view answer was kept */
    int principal;          /* SFM_SELFCAL_PRINCIPAL_* of the answer */
    double focal_sigma;     /* relative standard deviation of f from the profile */
    double profile_rise;    /* far rise in noise variances */
    double noise_sigma;     /* px per axis, from the final cost */
    int evaluations;        /* bundle adjustments run */
    int sweep_count;        /* coarse candidates (sweep_focal, sweep_cost) */
    double sweep_focal[SFM_SELFCAL_MAX_SWEEP]; /* px */
    double sweep_cost[SFM_SELFCAL_MAX_SWEEP];  /* fixed-focal score, HUGE_VAL when no
                                                  metric cameras follow */
    int points;             /* points adjusted (seen twice or more, in front) */
    int observations;       /* their observations */
    double rms;             /* px, per observation */
    double front_fraction;  /* points in front of every camera that sees them,
                               of those seen twice or more */
} sfm_selfcal_report;

/* Fills the defaults above. Statuses: SFM_OK, SFM_E_ARGUMENT (NULL). */
SFM_API int sfm_selfcal_default_options(sfm_selfcal_options *options);

/* Workspace bytes for m views, n points and n_obs observations; 0 when the
 * counts are invalid (m < 3 or > SFM_SELFCAL_MAX_VIEWS, n < 1, n_obs < 1)
 * or the size overflows. */
SFM_API size_t sfm_selfcal_workspace_size(int m, int n, int n_obs);

/* Self-calibration of m projective cameras P (m x 12, pixels) with image
 * sizes wh (m x 2), points X (n x 4 in the same frame; zero rows unused)
 * and their observations: n_obs triples (obs_camera[k], obs_point[k],
 * obs_xy[2k..2k+1] pixels). options may be NULL (defaults). Outputs
 * above; poses and Xm may be NULL. Statuses: SFM_OK; SFM_E_ARGUMENT
 * (NULL, counts, an index out of range, a (view, point) pair given twice,
 * a bad option); SFM_E_NONFINITE;
 * SFM_E_WORKSPACE (ws NULL or smaller than sfm_selfcal_workspace_size);
 * SFM_E_SINGULAR (no start gives metric cameras, or f is not determined:
 * see report.profile_rise, focal_sigma); SFM_E_NO_CONVERGENCE (a physical
 * check failed). */
SFM_API int sfm_selfcal_solve(int m, const double *P, const double *wh, int n, const double *X, int n_obs,
                              const int *obs_camera, const int *obs_point, const double *obs_xy,
                              const sfm_selfcal_options *options, double *K, double H[16],
                              sfm_pose *poses, double *Xm, sfm_selfcal_report *report, void *ws,
                              size_t ws_size);

#ifdef __cplusplus
}
#endif
#endif
