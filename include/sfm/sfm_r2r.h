/*
 * Robot-to-robot relative pose from distance and bearing measurements
 * (Zhou & Roumeliotis, "Determining 3-D relative transformations for any
 * combination of range and bearing measurements", IEEE T-RO 2013).
 *
 * Conventions (every function of this header):
 *  - Frame {1} is robot 1 at the first time step, frame {2} robot 2 at the
 *    first time step. The unknown is (C, p) with x_{1} = C x_{2} + p: p is
 *    robot 2's first position in {1}, C rotates robot 2's axes into robot 1's
 *    (C row-major, proper rotation).
 *  - Ego-motion at step k (k = 0 is the first step, where it is the identity):
 *    robot 1's orientation R1 and position t1 in {1}, x_{1} = R1 x_{1,k} + t1;
 *    robot 2's R2, t2 in {2}, x_{2} = R2 x_{2,k} + t2.
 *  - Measurements at step k, any subset (sfm_r2r_step.has):
 *      distance  d  = |C t2 + p - t1|                       (one equation)
 *      bearing   b1 = R1^T (C t2 + p - t1) / d               (two equations)
 *                     unit vector from robot 1 to robot 2 in robot 1's frame
 *      bearing   b2 = R2^T (C^T (t1 - p) - t2) / d           (two equations)
 *                     unit vector from robot 2 to robot 1 in robot 2's frame
 *    Bearings need not have unit length (they are normalised) but must be
 *    nonzero; a distance must be positive.
 *  - Six scalar equations determine (C, p) up to a finite set. Every sequence
 *    of exactly six reduces, by exchanging the robots and re-referencing the
 *    steps, to one of the 14 base systems of sfm_r2r_system (the pattern of
 *    measurements per step, steps with more equations first).
 */
#ifndef SFM_R2R_H
#define SFM_R2R_H

#include "sfm/sfm_common.h"
#include "sfm/sfm_ransac.h"

#ifdef __cplusplus
extern "C" {
#endif

/* sfm_r2r_step.has: which measurements the step carries */
#define SFM_R2R_D 1u  /* distance d */
#define SFM_R2R_B1 2u /* bearing b1, robot 1 sees robot 2 */
#define SFM_R2R_B2 4u /* bearing b2, robot 2 sees robot 1 */

typedef struct sfm_r2r_step {
    sfm_mat3 R1; /* robot 1 orientation at this step, in {1} */
    sfm_vec3 t1; /* robot 1 position at this step, in {1} */
    sfm_mat3 R2; /* robot 2 orientation at this step, in {2} */
    sfm_vec3 t2; /* robot 2 position at this step, in {2} */
    unsigned has; /* SFM_R2R_D | SFM_R2R_B1 | SFM_R2R_B2 */
    double d;     /* distance, > 0, when has & SFM_R2R_D */
    sfm_vec3 b1;  /* bearing from robot 1, when has & SFM_R2R_B1 */
    sfm_vec3 b2;  /* bearing from robot 2, when has & SFM_R2R_B2 */
} sfm_r2r_step;

/* x_{1} = C x_{2} + p */
typedef struct sfm_r2r_transform {
    sfm_mat3 C;
    sfm_vec3 p;
} sfm_r2r_transform;

/* The 14 classes of six-equation sequences: per step, the measurements in
 * canonical form (after exchanging the robots so that b1 is the more
 * frequent bearing, and ordering the steps by their number of equations).
 * Two of them are not minimal: {d,b1} at two steps fixes robot 2's position
 * in {1} at both, and C may still turn about the second (likewise {d,b1}
 * {d,b2}); their six equations have rank five and sfm_r2r_solve says
 * SFM_E_DEGENERATE. */
typedef enum sfm_r2r_system {
    SFM_R2R_SYS_NONE = 0,
    SFM_R2R_SYS_DB1B2_D = 1,     /* {d,b1,b2} {d} */
    SFM_R2R_SYS_B1B2_B1 = 2,     /* {b1,b2} {b1} */
    SFM_R2R_SYS_B1B2_D_D = 3,    /* {b1,b2} {d} {d} */
    SFM_R2R_SYS_DB1_DB1 = 4,     /* {d,b1} {d,b1}: rank 5, SFM_E_DEGENERATE */
    SFM_R2R_SYS_DB1_DB2 = 5,     /* {d,b1} {d,b2}: rank 5, SFM_E_DEGENERATE */
    SFM_R2R_SYS_DB1_B1_D = 6,    /* {d,b1} {b1} {d} */
    SFM_R2R_SYS_DB1_B2_D = 7,    /* {d,b1} {b2} {d} */
    SFM_R2R_SYS_DB1_D_D_D = 8,   /* {d,b1} {d} {d} {d}: the paper's System 10 */
    SFM_R2R_SYS_B1_B1_B1 = 9,    /* {b1} {b1} {b1} */
    SFM_R2R_SYS_B1_B1_B2 = 10,   /* {b1} {b1} {b2} */
    SFM_R2R_SYS_B1_B1_D_D = 11,  /* {b1} {b1} {d} {d} */
    SFM_R2R_SYS_B1_B2_D_D = 12,  /* {b1} {b2} {d} {d} */
    SFM_R2R_SYS_B1_D_D_D_D = 13, /* {b1} {d} {d} {d} {d} */
    SFM_R2R_SYS_D6 = 14,         /* six distances */
    SFM_R2R_SYS_COUNT_ = 15
} sfm_r2r_system;

/* The most solutions any base system has (six distances: 40 complex). */
#define SFM_R2R_MAX_SOLUTIONS 40

/* ---- The measurement model ---------------------------------------------
 * Predicted distance and bearings of one step under (C, p), as defined
 * above (unit bearings). Any output may be NULL; step->has is ignored and
 * R1, R2 are used as given (not checked to be rotations).
 * Returns: SFM_OK, SFM_E_ARGUMENT (NULL step or T), SFM_E_NONFINITE,
 * SFM_E_SINGULAR (the robots coincide: no bearing; a distance alone is
 * still written, 0). Nothing is written on failure. */
SFM_API int sfm_r2r_predict(const sfm_r2r_step *step, const sfm_r2r_transform *T,
                            double *d, sfm_vec3 *b1, sfm_vec3 *b2);

/* ---- Minimal solvers -----------------------------------------------------
 * Input checks of both functions: steps != NULL, n_steps >= 1; has only
 * SFM_R2R_D | SFM_R2R_B1 | SFM_R2R_B2 bits (a step with has == 0 is
 * ignored); R1, R2 rotations (|R R^T - I| <= 1e-6 entrywise, det > 0);
 * distances > 0; bearings nonzero. steps[0] is usually the identity
 * ego-motion (it defines frames {1}, {2}), but nothing requires it: the
 * answer is (C, p) in the frames the ego-motions are expressed in.
 * Steps where both robots are at the same positions (t1 and t2 within 1e-9
 * of the scene's scale) observe one relative vector and are merged first: a
 * measurement repeated there adds no equation.
 *
 * sfm_r2r_classify: the base system a sequence of exactly six scalar
 * equations reduces to. Returns the sfm_r2r_system (>= 1), SFM_E_ARGUMENT
 * (bad input, not six equations), SFM_E_NONFINITE, SFM_E_DEGENERATE (fewer
 * than six once repeated measurements at the same positions are merged).
 *
 * sfm_r2r_solve: every real (C, p) consistent with the measurements, best
 * first (RMS of the residuals (d_pred - d) / d and |b_pred - b| over the
 * scalar equations, through sfm_r2r_predict). With exactly six equations,
 * the base system's real solutions (a candidate scoring above 1e-4 is a
 * numerical artefact and dropped). With more, a minimal subset is solved
 * (base systems in enum order, each step the one farthest from the steps
 * already chosen: see libsfm/solvers/r2r_solve.c) and its candidates are
 * kept when they score at most 0.05 and at most 4 times the best; when none
 * is kept the next subset is tried, and 0 is returned when no subset
 * yields one. Degenerate motion is SFM_E_DEGENERATE, never an answer:
 * fewer than six equations once steps at the same positions are merged
 * (both robots standing still, only turning), robot 2's positions on one
 * straight line (or still) with no b2 measured, or robot 1's with no b1 (a
 * turn of C about that line keeps every measurement: distances only on
 * parallel lines, bearings from one robot while the other stands still), a base
 * system whose equations are rank-deficient (DB1_DB1, DB1_DB2) or whose
 * template is singular for these data. All 14 base systems are built
 * (SFM_E_UNSUPPORTED stays in the list for a registry without one).
 * Cost: six distances alone (D6, the Stewart-Gough forward kinematics, 40
 * complex solutions) are a parameter homotopy of 40 paths, about 67 M
 * instructions (x86-64); every other base system is below 0.5 M except
 * B1_D_D_D_D (33 M). With more equations than six D6 is tried last.
 * out must hold SFM_R2R_MAX_SOLUTIONS; ws at least
 * sfm_r2r_solve_workspace_size(n_steps) bytes (0 for n_steps < 1, and
 * for a count whose memory would overflow size_t: SFM_E_CAPACITY); out may
 * not alias steps or ws. Nothing is written to out on failure. Stack:
 * under 4 KiB plus the base solver's (at most 16 KiB).
 * Returns: the number of transforms written (0..SFM_R2R_MAX_SOLUTIONS),
 * SFM_E_ARGUMENT (bad input, NULL out or ws, fewer than six equations),
 * SFM_E_NONFINITE, SFM_E_DEGENERATE, SFM_E_WORKSPACE, SFM_E_CAPACITY,
 * SFM_E_UNSUPPORTED. */
SFM_API int sfm_r2r_classify(const sfm_r2r_step *steps, int n_steps);
SFM_API size_t sfm_r2r_solve_workspace_size(int n_steps);
SFM_API int sfm_r2r_solve(const sfm_r2r_step *steps, int n_steps,
                          sfm_r2r_transform out[SFM_R2R_MAX_SOLUTIONS],
                          void *ws, size_t ws_size);

/* ---- Refinement ------------------------------------------------------------
 * sfm_r2r_refine: maximum-likelihood (C, p) from an initial transform over
 * every measurement of a sequence (any number of steps, at least six scalar
 * equations in all), by Levenberg-Marquardt through the library's one driver.
 * Residuals, whitened by the measurement's standard deviation:
 *   distance  (|w| - d) / sigma_d,                w = C t2 + p - t1;
 *   bearing   (e1 . u, e2 . u) / sigma_b,          u the predicted unit
 *             bearing (R1^T w / |w| for b1, R2^T (C^T (t1 - p) - t2) / |w|
 *             for b2), e1, e2 an orthonormal basis of the tangent plane of
 *             the measured bearing: two residuals per bearing, the sine of
 *             the angular error along each (radians for small errors).
 * Parameters: C on SO(3), updated on the left, C <- exp([w]x) C (w radians,
 * expressed in {1}); p in R^3 (units of the positions).
 * cov (may be NULL): the 6 x 6 row-major covariance of (w, p) in that order,
 * the inverse of the Gauss-Newton matrix J^T J of the whitened residuals at
 * the solution (so it is in the units of sigma_d and sigma_b; with squared
 * loss and correct sigmas it is the Cramer-Rao bound at the estimate).
 * The truth then lies at w = log(C_true C^T), p_true - p.
 * opt may be NULL (sfm_r2r_refine_default_options). out may alias init;
 * cov and stats may be NULL.
 * Returns: SFM_OK; SFM_E_ARGUMENT (NULL steps/init/out, n_steps < 1, a has
 * mask with other bits, fewer than six equations, a zero bearing, a distance
 * not positive, R1, R2 or init->C not a rotation within 1e-6, sigma_d or
 * sigma_b not positive, a bad option); SFM_E_NONFINITE (NaN/Inf in a
 * measured step, init or options); SFM_E_SINGULAR (the robots coincide at a
 * step under init: no bearing, no distance gradient); SFM_E_NO_CONVERGENCE
 * (the result left SO(3)); SFM_E_DEGENERATE (the measurements do
 * not determine (C, p) at the solution: the Gauss-Newton matrix is singular,
 * as when the robots stand still); nothing is written on failure.
 * Stack: about 4 KiB (x86-64, gcc -O2: 2 KiB in the function, the rest the
 * driver's and the residual's frames); no workspace. */

/* Why the refinement stopped (values pinned, the driver's order). */
typedef enum sfm_r2r_stop {
    SFM_R2R_STOP_NONE = 0,
    SFM_R2R_STOP_GRADIENT = 1,       /* max |gradient| <= gradient_tolerance */
    SFM_R2R_STOP_FUNCTION = 2,       /* relative cost change <= function_tolerance */
    SFM_R2R_STOP_STEP = 3,           /* relative step <= step_tolerance */
    SFM_R2R_STOP_MAX_ITERATIONS = 4, /* max_iterations steps tried */
    SFM_R2R_STOP_TRUST_REGION = 5,   /* the damping could not be lowered further */
    SFM_R2R_STOP_INT_SIZE_ = 0x7fffffff
} sfm_r2r_stop;

/* Robust losses of the refinement (values pinned, as sfm_ba_options.loss). */
#define SFM_R2R_LOSS_SQUARED 0
#define SFM_R2R_LOSS_HUBER 1
#define SFM_R2R_LOSS_CAUCHY 2

typedef struct sfm_r2r_refine_options {
    double sigma_d;            /* distance standard deviation, > 0 (units of t1, t2) */
    double sigma_b;            /* bearing standard deviation, > 0 (radians) */
    int max_iterations;        /* >= 0 (0: cost and covariance at init) */
    double function_tolerance; /* >= 0, relative cost change */
    double gradient_tolerance; /* >= 0, max |gradient| of the whitened cost */
    double step_tolerance;     /* >= 0, relative step */
    int loss;                  /* SFM_R2R_LOSS_* on the whitened residuals of a
                                  measurement (|r|^2: 1 or 2 entries) */
    double loss_scale;         /* > 0 for a robust loss (in sigmas) */
} sfm_r2r_refine_options;

typedef struct sfm_r2r_refine_stats {
    int iterations;        /* steps tried */
    int successful_steps;  /* steps accepted */
    double initial_cost;   /* 1/2 sum of rho(|r|^2) over the measurements, at init */
    double final_cost;     /* the same at the result */
    sfm_r2r_stop stop_reason;
    int n_equations;       /* scalar residuals (1 per distance, 2 per bearing) */
} sfm_r2r_refine_stats;

/* sigma_d 0.01, sigma_b 0.01 rad, 50 iterations, tolerances 1e-12 (function),
 * 1e-12 (gradient), 1e-12 (step), squared loss, loss_scale 3.
 * Returns SFM_OK, SFM_E_ARGUMENT (NULL). */
SFM_API int sfm_r2r_refine_default_options(sfm_r2r_refine_options *opt);
SFM_API int sfm_r2r_refine(const sfm_r2r_step *steps, int n_steps, const sfm_r2r_transform *init,
                           const sfm_r2r_refine_options *opt, sfm_r2r_transform *out,
                           double *cov, sfm_r2r_refine_stats *stats);

/* ---- Robust estimation -----------------------------------------------------
 * sfm_r2r_ransac: (C, p) from a sequence whose measurements may hold gross
 * outliers, by the library's RANSAC engine (sfm_ransac.h: SPRT, MSAC, LO).
 * A datum is one measurement of one step (a distance, a bearing b1 or a
 * bearing b2). A sample draws six distinct measurements (all of them when
 * there are fewer) and takes them, bearings first and each kind in drawn
 * order, while their equations add up to at most six, skipping a bearing
 * that would overshoot; a sample that does not reach exactly six is
 * degenerate. (Bearings first: the bearing-only base systems are the
 * cheapest to solve.) The measurements taken form the
 * sub-sequence handed to sfm_r2r_solve, whose every solution is a hypothesis.
 * Scoring: the normalised residual of each measurement under the
 * hypothesis, |d_pred - d| / sigma_d for a distance, |b_pred - b| / sigma_b
 * for a bearing (unit vectors; the angle for small errors), against
 * opt->ransac.threshold (in sigmas). Local optimisation: sfm_r2r_refine on
 * the inliers under a Cauchy loss of scale threshold. Final model:
 * sfm_r2r_refine (squared loss) on the inliers of the winner, inliers
 * re-collected and refit until they stop changing (at most 4 refits).
 * The engine's stopping rule counts samples of six measurements, which
 * overestimates the draws needed when fewer are taken (bearings): the
 * iteration count errs on the safe side.
 * inliers (may be NULL): n_steps has-masks, the inlier measurements of each
 * step. cov (may be NULL): the final refit's 6 x 6 covariance of (w, p) as
 * for sfm_r2r_refine; stats->covariance holds it too (cov_dim 6), and
 * stats->num_inliers counts inlier measurements.
 * opt may be NULL (sfm_r2r_ransac_default_options).
 * Returns the number of inlier measurements (>= 1), or SFM_E_ARGUMENT (as for
 * sfm_r2r_refine, bad RANSAC options), SFM_E_NONFINITE, SFM_E_WORKSPACE,
 * SFM_E_UNSUPPORTED (every sample fell on a base system this build does not
 * solve), SFM_E_NO_CONVERGENCE (no hypothesis found), SFM_E_NO_MODEL (the
 * winner's inliers carry no equation beyond a minimal sample: nothing
 * confirms it), SFM_E_DEGENERATE (the inliers do not determine (C, p), or
 * sfm_r2r_solve found every sample degenerate: robots standing still,
 * distances along parallel lines). Nothing is written on failure.
 * Stack: 3.2 KiB of its own (x86-64, gcc -O2), plus the engine's 1 KiB,
 * plus the deeper of sfm_r2r_solve with its base solver and
 * sfm_r2r_refine. */
typedef struct sfm_r2r_ransac_options {
    sfm_r2r_refine_options refine; /* sigmas; the refits' iterations and tolerances
                                      (refine.loss is ignored) */
    sfm_ransac_options ransac;     /* threshold in sigmas; wide_mult and polish
                                      are not used; quality (PROSAC), when given,
                                      holds one value per measurement in step
                                      order, each step's d, b1, b2 in that
                                      order (those it carries) */
} sfm_r2r_ransac_options;

/* refine: sfm_r2r_refine_default_options; ransac: sfm_ransac_default_options
 * with threshold 3 sigmas and 2000 iterations at most.
 * Returns SFM_OK, SFM_E_ARGUMENT (NULL). */
SFM_API int sfm_r2r_ransac_default_options(sfm_r2r_ransac_options *opt);
/* Bytes of ws for n_steps steps (any has masks); 0 when n_steps is out of
 * range (1..SFM_R2R_RANSAC_MAX_STEPS). */
#define SFM_R2R_RANSAC_MAX_STEPS 100000
SFM_API size_t sfm_r2r_ransac_workspace_size(int n_steps);
SFM_API int sfm_r2r_ransac(const sfm_r2r_step *steps, int n_steps,
                           const sfm_r2r_ransac_options *opt, sfm_r2r_transform *out,
                           unsigned *inliers, double *cov, sfm_ransac_stats *stats, void *ws,
                           size_t ws_size);

#ifdef __cplusplus
}
#endif

#endif
