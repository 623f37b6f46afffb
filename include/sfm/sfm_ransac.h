/*
 * Robust estimation: one RANSAC engine driven by an estimator table.
 *
 * The engine draws minimal samples (uniformly, or PROSAC-ordered when points
 * carry quality scores), asks the estimator for up to max_models models per
 * sample, verifies each with SPRT (Chum & Matas, "Optimal randomized RANSAC",
 * PAMI 2008) and Capel's bail-out test (BMVC 2005) so that bad models are
 * dropped after a few points, scores the survivors with MSAC (truncated
 * quadratic: sum of min(r^2, tau^2)), runs local optimisation on every new
 * best model, and stops at a confidence level, an iteration cap or a time
 * budget read from a caller-supplied clock.
 *
 * Local optimisation (LO-RANSAC, Chum, Matas & Kittler 2003): a few
 * nonlinear refinement rounds on the inliers, or on the points within the
 * LO band (at most 128 of them, evenly spread), kept while the MSAC cost
 * drops. Every new best model (from a sample or from an LO) then gets an
 * inner RANSAC of the paper: 40 minimal samples from its points within the
 * band, solved, scored on all points and the winner refined, repeated while
 * it improves (at most 3 times in a row). A model from a noisy sample often
 * fits only part of the inliers (at small parallax: a wrong rotation and
 * translation along the valley that still explains 75-87 % of the points),
 * and the refits alone cannot leave that local minimum.
 *
 * The LO band: the whole band of wide_mult thresholds, or, for estimators
 * with set_scale (relative and upright pose below), 3 robust standard
 * deviations of the model's own residuals (1.4826 times their median within
 * wide_mult thresholds), between tau and wide_mult tau, with the refit's
 * Cauchy scale at 2.385 of those deviations, at most tau.
 *
 * Stopping: the samples needed at opt->confidence follow from the inlier
 * ratio counted within wide_mult thresholds (when wide_mult > 1), not at tau:
 * with noise near tau the count at tau misses a third or more of the true
 * inliers, and the rule would ask for 2^k times the samples an all-inlier
 * draw needs. They are counted from the sample at which the best model last
 * improved (a second test: the run stops only once the best model has stood
 * that many samples), and the inner RANSAC above does not depend on the
 * forecast, so a run that reaches its confidence after a dozen samples on a
 * plausible wrong model still searches that model's support.
 * stats->stop_share and stats->samples_needed report the ratio the rule used
 * and the count it asked for.
 *
 * With opt->wide_mult > 1 the winner is then polished to a fixed point:
 * refine() on every point within the polish band (the LO band above, from
 * the current model's residuals; for estimators without set_scale 3.5
 * robust deviations between tau and wide_mult tau), re-collected after each
 * refit, until the set of points in the band stops changing and the last
 * refit moved no model entry by more than 1e-7 (1e-5, about 6e-4 deg for
 * unit-norm models, for estimators with set_scale, whose loss scale follows
 * the residuals), at most opt->polish_rounds refits (with 1 px noise a 1 px threshold keeps only
 * about half of the true inliers; the polish uses nearly all of them, while
 * the band and the loss keep the outliers out). For estimators with
 * set_scale the polish refits only on the band's points that at least half
 * of the models close to the best hold within 2 robust deviations of their
 * own residuals (each new best and each inner-RANSAC candidate within 35 %
 * of what the best saves, n tau^2 minus its MSAC cost; the count starts
 * again when a new best leaves the old one out of that margin): at a small
 * baseline the lowest-cost model of the rotation-translation valley is the
 * one that gathered a few chance outliers into its band, and those points
 * alone hold the refit degrees off. The polished model is kept
 * unless it loses more than 5 % of the inliers.
 *
 * Memory: the run call works in caller memory only. Its size comes from
 * sfm_ransac_workspace_size(dims) or, for a static buffer, from the macro
 * SFM_RANSAC_WS_SIZE(n, sample_size, max_models, model_size); both describe
 * the same carving (a unit test holds them equal).
 *
 * Determinism: all randomness comes from an sfm_rng seeded with opt->seed; the
 * same seed, inputs and build give the same model and inlier mask bit for bit.
 * There is no global state: concurrent calls on distinct workspaces are safe.
 *
 * Poses, where estimators return them, map world (or first camera) to camera:
 * x_cam = R X + t, R row-major.
 */
#ifndef SFM_RANSAC_H
#define SFM_RANSAC_H

#include "sfm/sfm_common.h"
#include "sfm/sfm_camera.h"
#include "sfm/sfm_pose.h"
#include "sfm/sfm_rng.h"
#include "sfm/sfm_solvers.h"

#ifdef __cplusplus
extern "C" {
#endif

/* Engine capacities. */
#define SFM_RANSAC_MAX_SAMPLE 16      /* points in one minimal sample */
#define SFM_RANSAC_MAX_MODELS 64      /* models one solve may return */
#define SFM_RANSAC_MAX_MODEL_SIZE 64  /* doubles per model */
#define SFM_RANSAC_MAX_POINTS 16777216
/* The estimators below run local optimisation and the final polish on the
 * points within this many thresholds (under a robust loss of scale tau). */
#define SFM_RANSAC_WIDE_MULT 3

/* Why a run stopped (sfm_ransac_stats.stop_reason). The last value only
 * keeps the type int-sized on every ABI (arm-none-eabi packs small enums),
 * so the stats struct has one layout for C, C++ and the Python binding. */
typedef enum sfm_ransac_stop {
    SFM_RANSAC_STOP_CONFIDENCE = 0,     /* adaptive count reached at opt->confidence */
    SFM_RANSAC_STOP_MAX_ITERATIONS = 1, /* opt->max_iterations reached */
    SFM_RANSAC_STOP_TIME = 2,           /* opt->time_budget exhausted */
    SFM_RANSAC_STOP_INT_SIZE_ = 0x7fffffff
} sfm_ransac_stop;

/* Estimator flags (sfm_ransac_stats.flags). */
#define SFM_RANSAC_FLAG_PLANAR 1          /* relative pose: inliers dominated by one plane */
#define SFM_RANSAC_FLAG_PURE_ROTATION 2   /* relative pose: no measurable translation */
#define SFM_RANSAC_FLAG_DEGENSAC 4        /* fundamental: inliers dominated by one plane */
#define SFM_RANSAC_FLAG_LOW_PARALLAX 8    /* relative pose: R determined, t direction not
                                             (its standard deviation above 3 deg) */

/*
 * The estimator table. ctx is the estimator's own data (points, scratch); the
 * engine passes it back unchanged and never looks inside.
 *
 *  solve(ctx, sample, models): fit the minimal sample (sample_size point
 *      indices); write up to max_models models of model_size doubles each from
 *      models[0]; return how many (0 for a degenerate sample) or a negative
 *      status (the run then stops with it).
 *  residual(ctx, model, i): squared residual of point i, in the units of
 *      opt->threshold squared. Must be >= 0 (NaN counts as an outlier).
 *  refine(ctx, inliers, n_inliers, model): optional (may be NULL). A few
 *      nonlinear steps on the listed points, updating model in place; return
 *      >= 0 on success, < 0 to leave the model as it was. With
 *      opt->wide_mult > 1 the list reaches wide_mult thresholds and refine
 *      should apply a robust loss of scale tau (the estimators below use
 *      Cauchy weights 1 / (1 + r^2 / tau^2)).
 *  degenerate(ctx, sample): optional. Nonzero rejects the sample before solve.
 *  fix_best(ctx, sample, model, rng): optional. Called when a model becomes the
 *      best so far, before local optimisation (DEGENSAC's plane-and-parallax
 *      step); may overwrite model with a better one and return 1, else 0. May
 *      draw from rng.
 *  set_scale(ctx, scale): optional (last, so that older positional
 *      initialisers leave it NULL). When given, the engine estimates the
 *      noise from each model's residuals before a refit (sigma: 1.4826 times
 *      their median within wide_mult thresholds), refits on the points
 *      within 3 sigma (between tau and wide_mult tau) and calls
 *      set_scale(ctx, 2.385 sigma) (at most tau; threshold units, not
 *      squared) for refine's robust loss. Without it LO refits on the whole
 *      wide band at the estimator's own scale.
 *  residuals(ctx, model, idx, count, r2): optional (after set_scale, for
 *      the same reason). r2[q] = residual(ctx, model, idx[q]) for q <
 *      count (1..SFM_RANSAC_BLOCK), bit for bit the same values; the
 *      verification asks for blocks of points in its order and may use
 *      fewer of them than it asked for. Lets an estimator compute several
 *      points per instruction. Builds for size ignore it (residual is
 *      called instead, with the same results).
 *  prune(ctx, model, list, n, sigma2): optional (last, for the same
 *      reason). An influence test of the final polish: removes from
 *      list[0..n) (in place, order kept) the points whose influence on a
 *      refit from model is too high for a residual variance sigma2
 *      (threshold units squared) and returns the count left (n when it
 *      cannot tell). The relative-pose estimators drop
 *      the points of high Cook's distance.
 */
#define SFM_RANSAC_BLOCK 8
typedef struct sfm_ransac_estimator {
    int sample_size; /* 1..SFM_RANSAC_MAX_SAMPLE */
    int max_models;  /* 1..SFM_RANSAC_MAX_MODELS */
    int model_size;  /* 1..SFM_RANSAC_MAX_MODEL_SIZE */
    int (*solve)(void *ctx, const int *sample, double *models);
    double (*residual)(void *ctx, const double *model, int i);
    int (*refine)(void *ctx, const int *inliers, int n_inliers, double *model);
    int (*degenerate)(void *ctx, const int *sample);
    int (*fix_best)(void *ctx, const int *sample, double *model, sfm_rng *rng);
    void *ctx;
    void (*set_scale)(void *ctx, double scale);
    void (*residuals)(void *ctx, const double *model, const int *idx, int count, double *r2);
    int (*prune)(void *ctx, const double *model, int *list, int n, double sigma2);
} sfm_ransac_estimator;

/* Monotonic clock in seconds, supplied by the caller (a microcontroller has no
 * clock_gettime). */
typedef double (*sfm_ransac_clock_fn)(void *clock_ctx);

typedef struct sfm_ransac_options {
    double threshold;      /* inlier threshold tau, > 0 (estimator units; pixels
                              for the estimators below) */
    double confidence;     /* in (0, 1): stop when a better model is that unlikely */
    int min_iterations;    /* >= 0 */
    int max_iterations;    /* >= 1, >= min_iterations */
    uint64_t seed;         /* seeds the run's own sfm_rng */
    int lo_rounds;         /* refinement rounds per local optimisation (0: no
                              LO, no inner RANSAC) */
    double wide_mult;      /* <= 1: LO refines on the inliers at tau, no polish;
                              > 1: LO and the final polish refine on the points
                              within wide_mult thresholds. 0 (default) lets the
                              estimators below pick SFM_RANSAC_WIDE_MULT (their
                              refits are robust); sfm_ransac_run reads 0 as 1 */
    int polish_rounds;     /* at most this many refits in the final polish of
                              the winner, which stops earlier once its band
                              stops changing (0: none; only with
                              wide_mult > 1) */
    int use_sprt;          /* 1: early rejection (SPRT, bail-out); 0: full
                              MSAC scoring */
    const double *quality; /* optional per-point quality (higher is better):
                              PROSAC sampling; NULL: uniform sampling */
    sfm_ransac_clock_fn clock; /* optional; with time_budget > 0 bounds the run */
    void *clock_ctx;
    double time_budget;    /* seconds; <= 0 or clock NULL: no budget */
    int want_covariance;   /* pose estimators: 1 fills stats->covariance
                              (cov_dim 6), 0 (default) leaves cov_dim 0 and
                              skips its cost */
} sfm_ransac_options;

typedef struct sfm_ransac_stats {
    int iterations;       /* samples drawn */
    int models;           /* models verified */
    int sprt_rejected;    /* models dropped early (SPRT or bail-out) */
    int lo_runs;          /* local optimisations run */
    int polished;         /* 1 when the final polish was kept */
    int num_inliers;      /* inliers of the returned model (r^2 < tau^2) */
    double score;         /* MSAC cost of the returned model */
    uint64_t seed;        /* the seed used */
    sfm_ransac_stop stop_reason;
    int flags;            /* SFM_RANSAC_FLAG_* bits raised by the estimator */
    int inner_runs;       /* inner RANSACs of the LO run */
    int polish_rounds;    /* refits the final polish ran before its band
                             stopped changing (0: no polish kept) */
    double stop_share;    /* inlier share the stopping rule used last (of the
                             best model, in the band the rule counts) */
    double samples_needed; /* samples the stopping rule asked for at
                              opt->confidence for that share, before the
                              min/max iteration caps (may be +inf) */
    int cov_dim;          /* 6 when covariance holds the pose covariance, else 0
                             (always 0 unless opt->want_covariance) */
    double covariance[36]; /* pose estimators, on request (opt->want_covariance):
                              6 x 6 row-major covariance of
                              (w, t), w the rotation increment R <- exp([w]x) R
                              (radians), t the translation (units of t; for a
                              relative pose the tangent of the unit sphere, so
                              rank 5, rank 3 upright). The inverse of the core
                              LM driver's Gauss-Newton matrix of the refit's
                              least-squares problem on the inliers at the
                              returned pose, scaled by their residual variance
                              (normalised image units); a direction the
                              inliers do not fix shows as an entry of 1e30.
                              Unspecified when cov_dim is 0. */
    int has_twin;         /* relative pose with SFM_RANSAC_FLAG_PLANAR: 1 when
                             twin holds the plane's second pose */
    sfm_pose twin;        /* the other decomposition of the dominant plane's
                             homography (Faugeras & Lustman 1988): a plane
                             seen from two views fits two poses, the true
                             one is pose or twin. |t| = 1, x_cam2 = R x_cam1
                             + t; unspecified when has_twin is 0 */
} sfm_ransac_stats;

/* Defaults: threshold 1, confidence 0.999, min 0 / max 10000 iterations, seed
 * SFM_RNG_DEFAULT_SEED, 3 LO rounds, wide_mult 0, at most 8 polish rounds, SPRT on,
 * no quality, no clock.
 * Statuses: SFM_OK, SFM_E_ARGUMENT (opt NULL). */
SFM_API int sfm_ransac_default_options(sfm_ransac_options *opt);

typedef struct sfm_ransac_dims {
    int n;           /* number of points */
    int sample_size;
    int max_models;
    int model_size;
} sfm_ransac_dims;

/* Bytes of workspace sfm_ransac_run needs for these dimensions (alignment
 * slack included); 0 when a dimension is out of range. */
SFM_API size_t sfm_ransac_workspace_size(const sfm_ransac_dims *dims);

/* The same size as a constant expression, for static buffers. */
#define SFM_RANSAC_R16(b) ((((size_t)(b)) + 15u) & ~(size_t)15u)
#define SFM_RANSAC_WS_SIZE(n, k, m, s)                                          \
    (SFM_RANSAC_R16(sizeof(int) * (size_t)(n)) * 5u +                           \
     SFM_RANSAC_R16(sizeof(double) * (size_t)(n)) +                             \
     SFM_RANSAC_R16(sizeof(double) * (size_t)(m) * (size_t)(s)) +               \
     SFM_RANSAC_R16(sizeof(double) * (size_t)(s)) * 4u +                        \
     SFM_RANSAC_R16(sizeof(int) * (size_t)(k)) * 3u + 15u)

/*
 * Run RANSAC over n points with estimator est.
 * On success returns the inlier count (>= 1) and writes model (model_size
 * doubles), inlier_mask (n bytes, 1 = inlier; may be NULL) and stats (may be
 * NULL). model and inlier_mask must not overlap ws.
 * Statuses: count >= 1; SFM_E_ARGUMENT (NULL est/opt/model/ws or callbacks,
 * dimensions out of range, n < sample_size, bad options); SFM_E_NONFINITE
 * (NaN/Inf option or quality); SFM_E_WORKSPACE (ws_size too small);
 * SFM_E_NO_CONVERGENCE (no model with any inlier found); any negative status
 * returned by est->solve. On failure nothing is written.
 */
SFM_API int sfm_ransac_run(const sfm_ransac_estimator *est, int n, const sfm_ransac_options *opt,
                           double *model, uint8_t *inlier_mask, sfm_ransac_stats *stats,
                           void *ws, size_t ws_size);

/* ======================================================================
 * Estimators. All take pixels and camera models (sfm_camera, distortion
 * included: pixels are unprojected to bearings once per call). The inlier
 * threshold opt->threshold is in pixels; internally it is divided by the mean
 * focal length of the cameras involved. opt may be NULL (defaults, threshold
 * 1 px). Outputs: inlier_mask (n bytes, may be NULL) and stats (may be NULL)
 * as for sfm_ransac_run; stats->flags carries the SFM_RANSAC_FLAG_* bits.
 * Every estimator returns the inlier count (>= its sample size) or a negative
 * status: SFM_E_ARGUMENT (NULL inputs/outputs, n below the sample size, n
 * above SFM_RANSAC_MAX_POINTS, bad options), SFM_E_NONFINITE (NaN/Inf in
 * pixels, points, directions or options), SFM_E_WORKSPACE (ws_size below the
 * size function's value), SFM_E_NO_CONVERGENCE (no model found), or a camera
 * status (SFM_E_ARGUMENT for an invalid camera, SFM_E_NO_CONVERGENCE when a
 * pixel cannot be undistorted). Nothing is written on failure.
 * ====================================================================== */

/* ======================================================================
 * Final support checks. Every estimator below tests the support set of the
 * model it is about to return (its inliers at opt->threshold), not only its
 * samples, and returns a model only when that support determines it:
 *
 *  - chance: a model of sample size k fits its own k points; each other
 *    point of a wrong model lands in its inlier band with probability p,
 *    the band's area over the area of the bounding box of the input points
 *    (epipolar models: a band 2 sqrt(2) tau wide across the box diagonal;
 *    homography: a disc of radius sqrt(2) tau; absolute pose: radius tau;
 *    trifocal: an epipolar band in view 2 times a disc in view 3). With
 *    mu = (n - k) p the support must reach k + 3 mu + 6 sqrt(mu) + 5;
 *    below that: SFM_E_NO_MODEL (random matches: 4-15 of 200 points).
 *  - spread: in each image the minor principal standard deviation of the
 *    inliers must exceed 3 tau and 2 % of the major one (else the points lie
 *    on one line; a homography, which may map a plane seen edge-on onto a
 *    line, only when they lie on a line in both), and the major one must exceed 2 deg of view angle
 *    (calibrated estimators: the focal length converts) or 2 % of the
 *    diagonal of the input points' box (F, H, trifocal), else they form one
 *    cluster, within which a translation moves points as a rotation does:
 *    SFM_E_DEGENERATE.
 *  - determination. Poses: the covariance of the refit (computed for the
 *    test whether or not the caller asks for stats->covariance)
 *    with a residual variance of at least (tau / 3)^2; a rotation standard
 *    deviation above 1.5 deg: SFM_E_DEGENERATE (one tight cluster, a line in
 *    space); relative pose with R determined and a translation-direction
 *    deviation above 3 deg: the pose is returned with
 *    SFM_RANSAC_FLAG_LOW_PARALLAX (R usable, t not); absolute pose with a
 *    translation deviation above 5 % of the inliers' mean depth:
 *    SFM_E_DEGENERATE. Fundamental, homography, trifocal: the normal matrix
 *    of the inliers' Hartley-normalised design rows must have one null
 *    direction: a second eigenvalue below 10 m sigma^2 (m inliers, sigma =
 *    tau / 3 in normalised units) is SFM_E_DEGENERATE (all points on one
 *    plane for F and T, on one line for H).
 *  - dominant plane, pure rotation: SFM_RANSAC_FLAG_PLANAR (relative pose:
 *    the pose may be the twin of the true one, which stats->twin then
 *    holds, has_twin 1), SFM_RANSAC_FLAG_PURE_ROTATION
 *    (R without t), SFM_RANSAC_FLAG_DEGENSAC (fundamental), as before.
 * So each estimator below can also return SFM_E_DEGENERATE and
 * SFM_E_NO_MODEL; nothing is written then.
 * ====================================================================== */

/* Model sizes (doubles) the estimators hand to the engine. */
#define SFM_RANSAC_RELPOSE_MODEL 22
#define SFM_RANSAC_ABSPOSE_MODEL 12
#define SFM_RANSAC_MAT3_MODEL 9
#define SFM_RANSAC_FUNDAMENTAL_MODEL 10 /* F, plane-and-parallax mark */
#define SFM_RANSAC_HOMOGRAPHY_MODEL 9   /* H */

/*
 * Workspace sizes as constant expressions, for static buffers (a
 * microcontroller without a heap): SFM_RANSAC_<EST>_WS_SIZE(n) is at least
 * sfm_ransac_<est>_workspace_size(n) for every valid n (equal as the layouts
 * stand; a unit test holds each pair in step). Each is the engine's
 * workspace plus the estimator's own arrays, every block rounded to 16 bytes,
 * plus 15 bytes of alignment slack.
 */
/* two-view (calibrated): bearings 2 x 3n, pixels 2 x 2n, two index lists */
#define SFM_RANSAC_TWOVIEW_WS_SIZE(n, k, m)                                     \
    (SFM_RANSAC_R16(sizeof(double) * 3u * (size_t)(n)) * 2u +                   \
     SFM_RANSAC_R16(sizeof(double) * 2u * (size_t)(n)) * 2u +                   \
     SFM_RANSAC_R16(sizeof(int) * (size_t)(n)) * 2u +                           \
     SFM_RANSAC_R16(SFM_RANSAC_WS_SIZE(n, k, m, SFM_RANSAC_RELPOSE_MODEL)) + 15u)
/* uncalibrated pairs: pixels and gather scratch 4 x 2n, one index list */
#define SFM_RANSAC_PIXEL_PAIRS_WS_SIZE(n, k, m, s)                              \
    (SFM_RANSAC_R16(sizeof(double) * 2u * (size_t)(n)) * 4u +                   \
     SFM_RANSAC_R16(sizeof(int) * (size_t)(n)) +                                \
     SFM_RANSAC_R16(SFM_RANSAC_WS_SIZE(n, k, m, s)) + 15u)
#define SFM_RANSAC_RELPOSE_WS_SIZE(n)                                           \
    SFM_RANSAC_TWOVIEW_WS_SIZE(n, 5, SFM_RELPOSE_5PT_MAX_SOLUTIONS)
#define SFM_RANSAC_RELPOSE_UPRIGHT_WS_SIZE(n)                                   \
    SFM_RANSAC_TWOVIEW_WS_SIZE(n, 3, SFM_RELPOSE_UPRIGHT_3PT_MAX_SOLUTIONS)
/* absolute pose: bearings 3n, one index list */
#define SFM_RANSAC_ABSPOSE_WS_SIZE(n)                                           \
    (SFM_RANSAC_R16(sizeof(double) * 3u * (size_t)(n)) +                        \
     SFM_RANSAC_R16(sizeof(int) * (size_t)(n)) +                                \
     SFM_RANSAC_R16(SFM_RANSAC_WS_SIZE(n, 3, SFM_P3P_MAX_SOLUTIONS,             \
                                       SFM_RANSAC_ABSPOSE_MODEL)) + 15u)
#define SFM_RANSAC_FUNDAMENTAL_WS_SIZE(n)                                       \
    SFM_RANSAC_PIXEL_PAIRS_WS_SIZE(n, 7, SFM_FUNDAMENTAL_7PT_MAX_SOLUTIONS,         \
                                   SFM_RANSAC_FUNDAMENTAL_MODEL)
#define SFM_RANSAC_HOMOGRAPHY_WS_SIZE(n)                                        \
    SFM_RANSAC_PIXEL_PAIRS_WS_SIZE(n, 4, SFM_HOMOGRAPHY_4PT_MAX_SOLUTIONS,      \
                                   SFM_RANSAC_HOMOGRAPHY_MODEL)

/*
 * Relative pose from n >= 5 pixel pairs: 5-point samples (Nister), SPRT +
 * MSAC on the Sampson error of unit bearings (the first-order angular
 * distance to the epipolar constraint, converted to pixels through the mean
 * focal length), LO by Levenberg-Marquardt on the Sampson error over the
 * inliers in (R, t), final pose by cheirality over the inliers.
 * pose: x_cam2 = R x_cam1 + t, |t| = 1. E = [t]x R (unit Frobenius norm).
 * stats->flags: SFM_RANSAC_FLAG_PURE_ROTATION when the inliers are explained
 * by a rotation alone (t is then meaningless), SFM_RANSAC_FLAG_PLANAR when a
 * homography explains them (the pose may be one of two solutions: the other
 * goes to stats->twin with stats->has_twin 1; the truth is one of the two).
 * The pose is still written: check the flags before trusting t.
 */
/* Static size: SFM_RANSAC_RELPOSE_WS_SIZE(n). */
SFM_API size_t sfm_ransac_relpose_workspace_size(int n);
SFM_API int sfm_ransac_relpose(const double *px1, const double *px2, int n,
                               const sfm_camera *cam1, const sfm_camera *cam2,
                               const sfm_ransac_options *opt, sfm_pose *pose, sfm_mat3 *E,
                               uint8_t *inlier_mask, sfm_ransac_stats *stats, void *ws,
                               size_t ws_size);

/*
 * Upright relative pose from n >= 3 pixel pairs and one direction known in
 * both frames (d1 in camera 1, d2 = R d1 in camera 2, e.g. gravity): 3-point
 * samples, Sampson scoring as above, LO on the 3 remaining degrees of freedom
 * (rotation about d2 and the translation direction), final pose by
 * cheirality. Same flags as sfm_ransac_relpose.
 */
/* Static size: SFM_RANSAC_RELPOSE_UPRIGHT_WS_SIZE(n). */
SFM_API size_t sfm_ransac_relpose_upright_workspace_size(int n);
SFM_API int sfm_ransac_relpose_upright(const double *px1, const double *px2, int n,
                                       const sfm_camera *cam1, const sfm_camera *cam2,
                                       const double d1[3], const double d2[3],
                                       const sfm_ransac_options *opt, sfm_pose *pose,
                                       sfm_mat3 *E, uint8_t *inlier_mask,
                                       sfm_ransac_stats *stats, void *ws, size_t ws_size);

/*
 * Absolute pose from n >= 3 pixel / world point pairs (px n x 2, X n x 3):
 * P3P samples (Lambda Twist), SPRT + MSAC on the reprojection error measured
 * on the tangent plane of each bearing (pixels at the image centre of a
 * pinhole camera), LO by Levenberg-Marquardt on that error over the inliers.
 * pose: x_cam = R X + t.
 */
/* Static size: SFM_RANSAC_ABSPOSE_WS_SIZE(n). */
SFM_API size_t sfm_ransac_abspose_workspace_size(int n);
SFM_API int sfm_ransac_abspose(const double *px, const double *X, int n, const sfm_camera *cam,
                               const sfm_ransac_options *opt, sfm_pose *pose,
                               uint8_t *inlier_mask, sfm_ransac_stats *stats, void *ws,
                               size_t ws_size);

/*
 * Fundamental matrix from n >= 8 pixel pairs: 7-point samples, Sampson error
 * in pixels, LO by a normalized 8-point least-squares refit on the inliers
 * followed by a few Levenberg-Marquardt steps on their Sampson error (rank 2
 * kept by the orthonormal representation of Bartoli & Sturm, Cauchy loss of
 * scale threshold), on the points within two thresholds, and the same as a
 * final polish; DEGENSAC (Chum, Werner & Matas, CVPR 2005): when a
 * so-far-best sample has five or more points on one homography, F is
 * re-estimated by plane and parallax. SFM_RANSAC_FLAG_DEGENSAC is raised
 * when at least half of the returned F's inliers lie on one plane (a
 * dominant plane: F then rests on the few points off it).
 * cam1, cam2 may be NULL (pixels used as given); otherwise pixels are first
 * undistorted to the cameras' ideal pinhole pixels (F then relates those).
 * F: p2h^T F p1h = 0, unit Frobenius norm. opt->wide_mult is ignored (2).
 */
/* Static size: SFM_RANSAC_FUNDAMENTAL_WS_SIZE(n). */
SFM_API size_t sfm_ransac_fundamental_workspace_size(int n);
SFM_API int sfm_ransac_fundamental(const double *px1, const double *px2, int n,
                                   const sfm_camera *cam1, const sfm_camera *cam2,
                                   const sfm_ransac_options *opt, sfm_mat3 *F,
                                   uint8_t *inlier_mask, sfm_ransac_stats *stats, void *ws,
                                   size_t ws_size);

/*
 * Homography from n >= 4 pixel pairs: 4-point samples, Sampson error in
 * pixels (Hartley & Zisserman 4.2.6: the first-order distance of a pair to
 * the homography, noise in both images), LO and final polish by a
 * normalized DLT refit followed by a few Levenberg-Marquardt steps on the
 * Sampson error (8 degrees of freedom, Cauchy loss of scale twice the
 * threshold).
 * cam1, cam2 may be NULL, as for the fundamental matrix. H: p2h ~ H p1h,
 * unit Frobenius norm. opt->wide_mult is ignored (2: LO and polish refit on
 * the points within two thresholds).
 */
/* Static size: SFM_RANSAC_HOMOGRAPHY_WS_SIZE(n). */
SFM_API size_t sfm_ransac_homography_workspace_size(int n);
SFM_API int sfm_ransac_homography(const double *px1, const double *px2, int n,
                                  const sfm_camera *cam1, const sfm_camera *cam2,
                                  const sfm_ransac_options *opt, sfm_mat3 *H,
                                  uint8_t *inlier_mask, sfm_ransac_stats *stats, void *ws,
                                  size_t ws_size);

#ifdef __cplusplus
}
#endif
#endif
