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
 * template is singular for these data. A base system not built in this
 * library is SFM_E_UNSUPPORTED.
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

#ifdef __cplusplus
}
#endif

#endif
