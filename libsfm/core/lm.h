/*
 * Internal: the one Levenberg-Marquardt driver of the library.
 *
 * Every refiner (the estimators' local optimisations, trifocal gold
 * standard, bundle adjustment, and the refiners built on them) describes its
 * problem and lets this driver own damping, acceptance, stopping and the
 * covariance at the solution. Two ways in:
 *
 *  - sfmi_lm_dense_solve: a small problem (at most SFMI_LM_DENSE_MAX_TANGENT
 *    free parameters) given as parameter blocks with their manifolds and a
 *    callback filling one residual block and its Jacobian; the normal
 *    equations are formed densely and solved by Cholesky.
 *  - sfmi_lm_run: the loop alone, over a caller-implemented linear system
 *    (sfmi_lm_system): a problem with structure (bundle adjustment's Schur
 *    complement, the trifocal refinement's eliminated points) forms and
 *    solves its own damped normal equations, the driver does the rest.
 *
 * Cost. For residual blocks r_i (pixels, whitened) with s_i = |r_i|^2,
 *     cost = 1/2 sum_i rho(s_i),
 * rho one of the losses below (a = loss_scale):
 *     SFMI_LM_LOSS_SQUARED    rho(s) = s
 *     SFMI_LM_LOSS_HUBER      rho(s) = s if s <= a^2, else 2 a sqrt(s) - a^2
 *     SFMI_LM_LOSS_CAUCHY     rho(s) = a^2 log(1 + s / a^2)
 *     SFMI_LM_LOSS_TRUNCATED  rho(s) = min(s, a^2)
 * (Ceres' convention), minimised by iteratively reweighted Gauss-Newton:
 * each block enters the normal equations with weight rho'(s_i), so the
 * gradient is exact (the first-order corrector; for rho'' <= 0, as for Huber
 * and Cauchy, what Ceres does too).
 *
 * Damping (Marquardt 1963) with a trust-region radius update after Nielsen
 * (1999), the schedule of Ceres' LEVENBERG_MARQUARDT strategy:
 *     (H + D) h = -g,   D = diag(clamp(diag H, 1e-6, 1e32)) / radius,
 * a step is accepted when the achieved over predicted decrease
 * rho = (cost - cost') / pred exceeds 1e-3; then
 * radius /= max(1/3, 1 - (2 rho - 1)^3) (capped at 1e16) and the shrink
 * factor resets to 2; a rejected (or non positive definite) step divides the
 * radius by the shrink factor, which then doubles.
 *
 * Stopping: the one contract of every refiner. Checked in this order:
 *  - SFMI_LM_STOP_NO_PARAMETERS  nothing free to refine;
 *  - SFMI_LM_STOP_GRADIENT       max |g| <= gradient_tolerance (at the
 *                                current point, before a step);
 *  - SFMI_LM_STOP_MAX_ITERATIONS max_iterations steps tried (accepted or
 *                                rejected; 0 evaluates the cost only);
 *  - SFMI_LM_STOP_STEP           |h| <= step_tolerance (|x| + step_tolerance),
 *                                |x| the norm of the non-rotation values;
 *  - SFMI_LM_STOP_FUNCTION       |cost - cost'| <= function_tolerance * cost
 *                                after a step (accepted or not);
 *  - SFMI_LM_STOP_TRUST_REGION   the radius fell below 1e-32.
 *
 * Covariance (want_covariance): the inverse of the undamped Gauss-Newton
 * matrix J^T W J at the solution (robust weights included), in the tangent
 * coordinates of the free blocks; constant blocks have no rows. A gauge left
 * free makes it singular: covariance_status SFM_E_SINGULAR (also when the
 * factorisation only survives by rounding: sfmi_lm_factor_full_rank).
 *
 * Reentrant, no globals, no allocation; sfmi_lm_dense_solve works on its
 * workspace copy of the values and writes the blocks only when it returns
 * SFM_OK.
 */
#ifndef SFM_CORE_LM_H
#define SFM_CORE_LM_H

#include <stddef.h>

/* Parameter-block manifolds. */
typedef enum sfmi_lm_manifold {
    SFMI_LM_EUCLIDEAN = 0, /* x <- x + d; tangent = size */
    SFMI_LM_SO3 = 1,       /* size 9, a row-major rotation; R <- exp([d]x) R; tangent 3 */
    SFMI_LM_SO3_RIGHT = 2, /* size 9; R <- R exp([d]x); tangent 3 */
    SFMI_LM_SPHERE = 3,    /* unit vector (size 2..SFMI_LM_SPHERE_MAX: a direction,
                            * a homogeneous point); x <- (x + B d) / |x + B d| with
                            * B = sfmi_lm_sphere_basis(x); tangent size - 1 */
    SFMI_LM_CONSTANT = 4,  /* held; tangent 0 */
    SFMI_LM_CUSTOM = 5     /* the block's plus(); tangent as given */
} sfmi_lm_manifold;

#define SFMI_LM_SPHERE_MAX 8

/* Robust losses (values pinned: sfm_ba_options.loss uses the same numbers). */
typedef enum sfmi_lm_loss {
    SFMI_LM_LOSS_SQUARED = 0,
    SFMI_LM_LOSS_HUBER = 1,
    SFMI_LM_LOSS_CAUCHY = 2,
    SFMI_LM_LOSS_TRUNCATED = 3
} sfmi_lm_loss;

typedef enum sfmi_lm_stop {
    SFMI_LM_STOP_NONE = 0,
    SFMI_LM_STOP_GRADIENT = 1,
    SFMI_LM_STOP_FUNCTION = 2,
    SFMI_LM_STOP_STEP = 3,
    SFMI_LM_STOP_MAX_ITERATIONS = 4,
    SFMI_LM_STOP_TRUST_REGION = 5,
    SFMI_LM_STOP_NO_PARAMETERS = 6
} sfmi_lm_stop;

typedef struct sfmi_lm_options {
    int max_iterations;        /* >= 0; steps tried, accepted or rejected */
    double function_tolerance; /* >= 0, relative cost change */
    double gradient_tolerance; /* >= 0, max |gradient| */
    double step_tolerance;     /* >= 0, relative step */
    double initial_radius;     /* > 0: the first damping is 1 / radius */
    int want_covariance;       /* sfmi_lm_dense_solve only */
} sfmi_lm_options;

/* max_iterations 50, function 1e-6, gradient 1e-10, step 1e-8, radius 1e4,
 * no covariance (the defaults of sfm_ba_options). */
void sfmi_lm_default_options(sfmi_lm_options *o);

typedef struct sfmi_lm_summary {
    double initial_cost;
    double final_cost;
    int iterations;       /* steps tried */
    int successful_steps; /* steps accepted */
    sfmi_lm_stop stop;
    int covariance_status; /* SFM_OK, SFM_E_SINGULAR, or 1 when not asked */
} sfmi_lm_summary;

/* rho(s) and rho'(s) of a loss at s >= 0 with a2 = loss_scale^2 > 0. */
void sfmi_lm_loss_eval(sfmi_lm_loss loss, double a2, double s, double *rho, double *rho1);

/* ---- the loop over a structured system ------------------------------------ */

/*
 * A problem that forms and solves its own normal equations. The driver calls
 * linearize once at the start and after every accepted step, then for each
 * step solve, trial, and accept when the step is taken.
 */
typedef struct sfmi_lm_system {
    void *self;
    /* Linearise at the current point: cost (+Inf when undefined) and the
     * largest |gradient| entry, kept for the next solve. */
    double (*linearize)(void *self, double *grad_max);
    /* Solve (H + mu diag(clamp(diag H, 1e-6, 1e32))) h = -g. Returns 1 and
     * |h|^2, |x|^2 (non-rotation values) and the model decrease
     * pred = -(g.h + h^T H h / 2); 0 when the damped matrix is not positive
     * definite. */
    int (*solve)(void *self, double mu, double *step2, double *x2, double *pred);
    /* Cost at the current point moved by the last step (+Inf when
     * undefined); the trial is kept for accept. */
    double (*trial)(void *self);
    /* The trial becomes the current point. */
    void (*accept)(void *self);
    int n_free; /* free parameters; 0 stops with SFMI_LM_STOP_NO_PARAMETERS */
} sfmi_lm_system;

/* Runs Levenberg-Marquardt on sys. Returns SFM_OK (summary filled, the
 * system left at the best point), SFM_E_ARGUMENT (NULL, bad option),
 * SFM_E_NONFINITE (the initial cost is not finite). */
int sfmi_lm_run(const sfmi_lm_system *sys, const sfmi_lm_options *opt, sfmi_lm_summary *summary);

/* 1 when the Cholesky factor L (n x n, row-major lower, of a matrix whose
 * diagonal was diag) has every pivot L_ii^2 above SFMI_LM_COV_RANK_TOL
 * diag_i: the relative share of row i not explained by the rows before it.
 * A gauge direction left free leaves a pivot at rounding level (that
 * factorisation may still succeed): its covariance is SFM_E_SINGULAR, not a
 * number. */
#define SFMI_LM_COV_RANK_TOL 1e-12
int sfmi_lm_factor_full_rank(const double *L, const double *diag, int n);

/* Damping diagonal entry of a normal-matrix diagonal value. */
double sfmi_lm_clamp_diag(double d);

/* ---- small dense problems ------------------------------------------------- */

#define SFMI_LM_DENSE_MAX_TANGENT 32
#define SFMI_LM_DENSE_MAX_BLOCKS 8
#define SFMI_LM_DENSE_MAX_RESIDUAL 16

/* x <- x (+) d on the block's manifold (custom blocks). */
typedef void (*sfmi_lm_plus_fn)(const double *x, const double *d, double *out, const void *user);

typedef struct sfmi_lm_block {
    double *x;                /* values; read at the start, written on SFM_OK */
    int size;                 /* number of values */
    sfmi_lm_manifold manifold;
    int tangent;              /* SFMI_LM_CUSTOM only */
    sfmi_lm_plus_fn plus;     /* SFMI_LM_CUSTOM only */
    const void *plus_user;
} sfmi_lm_block;

/*
 * Residual block i (0 <= i < n_residuals) at the values x[b] of each block b:
 * writes its residual_size residuals to r and, when J is not NULL, the
 * residual_size x n_tangent Jacobian (row-major, zeroed by the driver) in the
 * tangent coordinates of the free blocks, in block order (constant blocks
 * have no columns). Returns 1; 0 when the block is undefined here and is left
 * out (a point at the epipole: it contributes neither cost nor gradient);
 * -1 when the whole cost is undefined here (a point behind a camera that must
 * not cross it: the step is rejected).
 */
typedef int (*sfmi_lm_residual_fn)(const void *user, const double *const *x, int i, double *r,
                                    double *J);

/*
 * Optional, for residual_size 1 and at most SFMI_LM_BATCH_TANGENT free
 * parameters: residual blocks i0 .. i0 + count - 1 (1 <= count <=
 * SFMI_LM_BATCH) at once, as residual would give them one by one, bit for
 * bit: ok[k] its return value, r[k] the residual and, when J is not NULL,
 * the Jacobian row by columns, entry c at J[c * SFMI_LM_BATCH + k] (every
 * entry written when ok[k] is 1; the driver does not zero J). Lets a
 * problem compute its blocks in loops over k the compiler can vectorise.
 * Used only where the target has double-precision vector units
 * (SFMI_LM_HAVE_BATCH): elsewhere a batch saves nothing but costs stack.
 */
#if defined(__SSE2__) || defined(__aarch64__)
#define SFMI_LM_HAVE_BATCH 1
#else
#define SFMI_LM_HAVE_BATCH 0
#endif
#define SFMI_LM_BATCH 8
#define SFMI_LM_BATCH_TANGENT 5
typedef void (*sfmi_lm_batch_fn)(const void *user, const double *const *x, int i0, int count,
                                 int *ok, double *r, double *J);

typedef struct sfmi_lm_problem {
    const sfmi_lm_block *blocks;
    int n_blocks;      /* 1..SFMI_LM_DENSE_MAX_BLOCKS */
    int n_residuals;   /* >= 0 */
    int residual_size; /* 1..SFMI_LM_DENSE_MAX_RESIDUAL */
    sfmi_lm_residual_fn residual;
    const void *user;
    sfmi_lm_loss loss;
    double loss_scale; /* > 0 for the robust losses */
    sfmi_lm_batch_fn batch; /* optional (NULL): see above */
} sfmi_lm_problem;

/* Workspace bytes for a dense problem with n_values values in all, n_tangent
 * free parameters and residual blocks of residual_size; 0 when out of range. */
size_t sfmi_lm_dense_workspace_size(int n_values, int n_tangent, int residual_size);

/* Doubles of that workspace (a stack array for the small refiners). */
#define SFMI_LM_DENSE_WS_DOUBLES(n_values, n_tangent, residual_size)                               \
    (2 * (n_values) + 2 * (n_tangent) * (n_tangent) + 4 * (n_tangent) +                          \
     (residual_size) * ((n_tangent) + 1) + 24)

/* out = x (+) d on the block's manifold (the driver's update; also what a
 * finite-difference check of a residual's Jacobian must follow). Returns 1,
 * 0 when the result is not finite. */
int sfmi_lm_block_plus(const sfmi_lm_block *b, const double *x, const double *d, double *out);

/* Free parameters of the blocks (the column count of J); -1 when a block is
 * malformed. */
int sfmi_lm_tangent_size(const sfmi_lm_block *blocks, int n_blocks);

/*
 * Minimises the problem's cost from the blocks' values. cov (n_tangent^2,
 * row-major, may be NULL unless opt->want_covariance) receives the
 * covariance when covariance_status is SFM_OK (its content is unspecified
 * otherwise). Returns SFM_OK (blocks
 * updated, summary filled), SFM_E_ARGUMENT (NULL, malformed blocks, counts,
 * options), SFM_E_NONFINITE (the initial cost is not finite or a value is
 * NaN/Inf), SFM_E_WORKSPACE (ws NULL or smaller than
 * sfmi_lm_dense_workspace_size). Nothing written on failure.
 */
int sfmi_lm_dense_solve(const sfmi_lm_problem *prob, const sfmi_lm_options *opt, void *ws,
                        size_t ws_size, sfmi_lm_summary *summary, double *cov);

/* The estimators' local optimisation: sfmi_lm_dense_solve from the blocks'
 * values with at most max_iterations steps, the given relative cost
 * tolerance and no gradient test (their residuals are in radians or
 * normalised units). Returns 0 when a step was accepted (blocks updated),
 * 1 when none lowered the cost (blocks unchanged), -1 on failure. */
int sfmi_lm_refine(const sfmi_lm_problem *prob, int max_iterations, double function_tolerance,
                   void *ws, size_t ws_size);

/* An orthonormal basis of the tangent space of the unit vector x (size n,
 * 2 <= n <= SFMI_LM_SPHERE_MAX): B is n x (n - 1), row-major, the columns of
 * the Householder reflection taking x to a coordinate axis. The basis of
 * SFMI_LM_SPHERE blocks: Jacobians of residual callbacks are taken along
 * its columns. */
void sfmi_lm_sphere_basis(const double *x, int n, double *B);

#endif
