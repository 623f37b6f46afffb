/*
 * Bundle adjustment for small problems (a few to a few tens of cameras, up to
 * some thousands of points) on caller memory.
 *
 * Levenberg-Marquardt with the Schur complement: point blocks (3x3) are
 * eliminated, the dense reduced camera system is solved by Cholesky, points
 * are recovered by back-substitution. Jacobians are analytic.
 *
 * Model. Poses map world to camera, x_cam = R * X_world + t (R row-major 3x3).
 * Camera i projects x_cam = (x, y, z) with its intrinsics row
 * {fx, fy, cx, cy, k1, k2} as
 *     xn = x / z, yn = y / z, r2 = xn^2 + yn^2, d = 1 + k1 r2 + k2 r2^2,
 *     u = fx d xn + cx,  v = fy d yn + cy     (pixels, y down).
 * Rotations are updated on SO(3) by R <- exp([w]_x) R (w in the camera
 * frame, applied through sfm_rot_from_axis_angle); translations, points and
 * intrinsics additively. When the focal length is refined, fx is the free
 * parameter and fy keeps its ratio fy/fx from the input.
 *
 * Cost. With r_k = projection - observed (pixels), w_k the observation's weight
 * (an inverse variance, 1 when weights are NULL) and s_k = w_k |r_k|^2,
 *     cost = 1/2 sum_k rho(s_k)
 * with rho one of
 *     SFM_BA_LOSS_SQUARED    rho(s) = s
 *     SFM_BA_LOSS_HUBER      rho(s) = s if s <= a^2, else 2 a sqrt(s) - a^2
 *     SFM_BA_LOSS_CAUCHY     rho(s) = a^2 log(1 + s / a^2)
 *     SFM_BA_LOSS_TRUNCATED  rho(s) = min(s, a^2)
 * (a = loss_scale, in whitened pixels). This is the cost Ceres reports for the
 * residual sqrt(w) r with the same loss function.
 *
 * Memory: sfm_ba_workspace_size(dims) bytes, any alignment; the solve never
 * allocates. The arrays of sfm_ba_problem marked in/out are overwritten with
 * the refined values only when sfm_ba_solve returns SFM_OK; on any error
 * nothing is written (problem arrays, result, covariance).
 */
#ifndef SFM_BA_H
#define SFM_BA_H

#include "sfm/sfm_common.h"

#ifdef __cplusplus
extern "C" {
#endif

/* Intrinsics per camera: {fx, fy, cx, cy, k1, k2}. */
#define SFM_BA_INTRINSICS_STRIDE 6

/* options.mode */
#define SFM_BA_MODE_FULL 0        /* cameras (as flagged) and points */
#define SFM_BA_MODE_POSE_ONLY 1   /* every point held constant */
#define SFM_BA_MODE_POINTS_ONLY 2 /* every camera (pose, intrinsics) held */

/* options.intrinsics: how refined intrinsics are shared */
#define SFM_BA_INTRINSICS_FIXED 0      /* all intrinsics constant */
#define SFM_BA_INTRINSICS_SHARED 1     /* one block for every camera */
#define SFM_BA_INTRINSICS_PER_CAMERA 2 /* one block per camera */

/* options.refine_intrinsics: which entries are free (ignored when FIXED) */
#define SFM_BA_REFINE_FOCAL 1     /* fx (fy follows with its ratio) */
#define SFM_BA_REFINE_PRINCIPAL 2 /* cx, cy */
#define SFM_BA_REFINE_RADIAL 4    /* k1, k2 */

/* options.loss */
#define SFM_BA_LOSS_SQUARED 0
#define SFM_BA_LOSS_HUBER 1
#define SFM_BA_LOSS_CAUCHY 2
#define SFM_BA_LOSS_TRUNCATED 3

/* options.gauge and options.scale_gauge act in SFM_BA_MODE_FULL only: in
 * POSE_ONLY the held points fix the frame (so a single camera, camera 0
 * included, is refined as RANSAC refinement needs), in POINTS_ONLY every
 * camera is held. */
#define SFM_BA_GAUGE_NONE 0
#define SFM_BA_GAUGE_FIRST_CAMERA 1 /* pose of camera 0 held constant */

/* options.scale_gauge (needs SFM_BA_GAUGE_FIRST_CAMERA) */
#define SFM_BA_SCALE_NONE 0
/* translations[scale_camera * 3 + scale_coordinate] held constant */
#define SFM_BA_SCALE_COORDINATE 1
/* distance between the centres of camera 0 and camera scale_camera fixed to
 * scale_distance. Solved as SFM_BA_SCALE_COORDINATE on the best-conditioned
 * coordinate, then the scene is scaled about camera 0's centre (the cost is
 * invariant to that scaling, so the minimum is exact); needs every other
 * camera and point free. The covariance is that of the coordinate gauge,
 * before the scaling. */
#define SFM_BA_SCALE_DISTANCE 2

/* camera_flags bits */
#define SFM_BA_FIX_POSE 1       /* rotation and translation held constant */
#define SFM_BA_FIX_INTRINSICS 2 /* this camera's intrinsics (PER_CAMERA mode) held */

/* result.stop_reason */
#define SFM_BA_STOP_GRADIENT 1       /* max |gradient| <= gradient_tolerance */
#define SFM_BA_STOP_FUNCTION 2       /* |cost change| <= function_tolerance * cost */
#define SFM_BA_STOP_PARAMETER 3      /* |step| <= parameter_tolerance * (|x| + tol) */
#define SFM_BA_STOP_MAX_ITERATIONS 4 /* iteration limit reached */
#define SFM_BA_STOP_TRUST_REGION 5   /* trust region collapsed below 1e-32 */
#define SFM_BA_STOP_NO_PARAMETERS 6  /* nothing free to refine */

typedef struct sfm_ba_problem {
    int n_cameras;      /* m >= 1 */
    int n_points;       /* n >= 0 */
    int n_observations; /* >= 1 */
    double *rotations;    /* in/out, m x 9 row-major rotation matrices */
    double *translations; /* in/out, m x 3 */
    double *intrinsics;   /* in/out, m x 6 {fx, fy, cx, cy, k1, k2}, fx, fy != 0 */
    double *points;       /* in/out, n x 3 world points */
    const int *obs_camera;      /* n_observations camera indices */
    const int *obs_point;       /* n_observations point indices */
    const double *obs_xy;       /* n_observations x 2 pixels */
    const double *obs_weight;   /* n_observations weights >= 0, or NULL (all 1) */
    const unsigned char *camera_flags; /* m SFM_BA_FIX_* masks, or NULL */
    const unsigned char *point_fixed;  /* n, non-zero = held constant, or NULL */
} sfm_ba_problem;

typedef struct sfm_ba_options {
    int mode;              /* SFM_BA_MODE_*, default FULL */
    int intrinsics;        /* SFM_BA_INTRINSICS_*, default FIXED */
    int refine_intrinsics; /* SFM_BA_REFINE_* mask, default 0 */
    int loss;              /* SFM_BA_LOSS_*, default SQUARED */
    double loss_scale;     /* a > 0 for the robust losses, default 1 */
    int gauge;             /* default SFM_BA_GAUGE_FIRST_CAMERA */
    int scale_gauge;       /* default SFM_BA_SCALE_NONE */
    int scale_camera;      /* 1..m-1 */
    int scale_coordinate;  /* 0..2 (SFM_BA_SCALE_COORDINATE) */
    double scale_distance; /* > 0 (SFM_BA_SCALE_DISTANCE) */
    int max_iterations;    /* >= 0, default 50 */
    double function_tolerance;  /* default 1e-6 */
    double gradient_tolerance;  /* default 1e-10 */
    double parameter_tolerance; /* default 1e-8 */
    double initial_trust_radius; /* default 1e4 (damping 1 / radius) */
    int want_covariance;   /* non-zero: fill pose_covariance, default 0 */
} sfm_ba_options;

/* Sizes the workspace depends on. intrinsics and refine_intrinsics as in the
 * options that will be used. */
typedef struct sfm_ba_dims {
    int n_cameras;
    int n_points;
    int n_observations;
    int intrinsics;
    int refine_intrinsics;
} sfm_ba_dims;

typedef struct sfm_ba_result {
    double initial_cost;
    double final_cost;
    int iterations;        /* LM steps tried (successful or not) */
    int successful_steps;
    int stop_reason;       /* SFM_BA_STOP_* */
    int n_camera_params;   /* free camera-side parameters (reduced system size) */
    int n_point_params;    /* free point coordinates */
    int covariance_status; /* SFM_OK, or SFM_E_SINGULAR when the undamped
                            * system is not positive definite (gauge left free,
                            * a point seen once); 1 when not requested */
} sfm_ba_result;

/* Fills the defaults listed above. Statuses: SFM_OK, SFM_E_ARGUMENT (NULL). */
SFM_API int sfm_ba_default_options(sfm_ba_options *options);

/* Bytes of workspace for a problem of these dimensions (alignment slack
 * included); 0 when dims is NULL or invalid (counts < 0, m < 1, nobs < 1,
 * unknown intrinsics mode) or the size overflows. */
SFM_API size_t sfm_ba_workspace_size(const sfm_ba_dims *dims);

/* Refines the problem in place. pose_covariance (m x 36, may be NULL; used
 * when options->want_covariance) receives for each camera the 6x6 marginal
 * covariance of its pose in the update coordinates (w, dt) (rotation first),
 * the block of the inverse of the undamped normal matrix J^T W J at the
 * solution (robust weights included), taken from the inverse of the reduced
 * camera system; rows and columns of held coordinates are zero.
 * Statuses: SFM_OK (also when stopped by the iteration limit: see
 * result->stop_reason), SFM_E_ARGUMENT (NULL, counts, index out of range,
 * negative weight, zero focal length, bad option, a free camera or point with
 * no observation, want_covariance with pose_covariance NULL),
 * SFM_E_NONFINITE (NaN/Inf in an input, or a non-finite initial cost),
 * SFM_E_WORKSPACE (ws NULL or smaller than sfm_ba_workspace_size for the
 * problem's dims). */
SFM_API int sfm_ba_solve(sfm_ba_problem *problem, const sfm_ba_options *options,
                         void *ws, size_t ws_size, sfm_ba_result *result,
                         double *pose_covariance);

#ifdef __cplusplus
}
#endif
#endif
