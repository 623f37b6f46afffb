/*
 * Bundle adjustment for small problems (a few to a few tens of cameras, up to
 * some thousands of points) on caller memory.
 *
 * Levenberg-Marquardt with the Schur complement: point blocks (3x3) are
 * eliminated, the dense reduced camera system is solved by Cholesky, points
 * are recovered by back-substitution. Jacobians are analytic.
 *
 * Model. Poses map world to camera, x_cam = R * X_world + t (R row-major 3x3).
 * Camera i projects x_cam through its sfm_camera (sfm_camera.h: pinhole,
 * Brown-Conrady, Kannala-Brandt fisheye), pixels y down. Rotations are
 * updated on SO(3) by R <- exp([w]_x) R (w in the camera frame, applied
 * through sfm_rot_from_axis_angle); translations, points and intrinsics
 * additively. When the focal length is refined, fx is the free parameter and
 * fy keeps its ratio fy/fx from the input. Pinhole and Brown cameras cannot
 * see points at or behind their plane (z <= 0): a step that would move one
 * there is rejected.
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
 * residual sqrt(w) r with the same loss function. The minimisation is the
 * library's one Levenberg-Marquardt driver (damping after Nielsen, as Ceres'
 * LEVENBERG_MARQUARDT; the stopping rule of result.stop_reason below).
 *
 * Arguments follow the library's order: inputs, then each output beside its
 * capacity, then the workspace (ws, ws_size). Every count is checked against
 * the workspace before any array is read.
 *
 * Memory: sfm_ba_workspace_size(dims) bytes, any alignment; the solve never
 * allocates. The arrays of sfm_ba_problem marked in/out are overwritten with
 * the refined values only when sfm_ba_solve returns SFM_OK; on any error
 * nothing is written (problem arrays, result, covariance).
 */
#ifndef SFM_BA_H
#define SFM_BA_H

#include "sfm/sfm_camera.h"
#include "sfm/sfm_common.h"

#ifdef __cplusplus
extern "C" {
#endif

/* options.mode */
typedef enum sfm_ba_mode {
    SFM_BA_MODE_FULL = 0,       /* cameras (as flagged) and points */
    SFM_BA_MODE_POSE_ONLY = 1,  /* every point held constant */
    SFM_BA_MODE_POINTS_ONLY = 2 /* every camera (pose, intrinsics) held */
} sfm_ba_mode;

/* options.intrinsics: how refined intrinsics are shared */
typedef enum sfm_ba_intrinsics {
    SFM_BA_INTRINSICS_FIXED = 0,     /* all intrinsics constant */
    SFM_BA_INTRINSICS_SHARED = 1,    /* one block for every camera (one model for all) */
    SFM_BA_INTRINSICS_PER_CAMERA = 2 /* one block per camera */
} sfm_ba_intrinsics;

/* options.refine_intrinsics: which entries are free (ignored when FIXED), a
 * mask. Distortion flags act on the coefficients the camera's model has (a
 * pinhole camera has none). */
#define SFM_BA_REFINE_FOCAL 1      /* fx (fy follows with its ratio) */
#define SFM_BA_REFINE_PRINCIPAL 2  /* cx, cy */
#define SFM_BA_REFINE_RADIAL 4     /* dist[0], dist[1]: k1, k2 (Brown and fisheye) */
#define SFM_BA_REFINE_DISTORTION 8 /* every coefficient: Brown k1 k2 p1 p2 k3, fisheye k1..k4 */
#define SFM_BA_REFINE_ALL 15
#define SFM_BA_REFINE_K1 16        /* dist[0] alone: k1 (Brown and fisheye), the one
                                      radial term a self-calibration can determine;
                                      RADIAL and DISTORTION include it */

/* options.loss */
typedef enum sfm_ba_loss {
    SFM_BA_LOSS_SQUARED = 0,
    SFM_BA_LOSS_HUBER = 1,
    SFM_BA_LOSS_CAUCHY = 2,
    SFM_BA_LOSS_TRUNCATED = 3
} sfm_ba_loss;

/* options.gauge and options.scale_gauge act in SFM_BA_MODE_FULL only: in
 * POSE_ONLY the held points fix the frame (so a single camera, camera 0
 * included, is refined as RANSAC refinement needs), in POINTS_ONLY every
 * camera is held. */
typedef enum sfm_ba_gauge {
    SFM_BA_GAUGE_NONE = 0,
    SFM_BA_GAUGE_FIRST_CAMERA = 1 /* pose of camera 0 held constant */
} sfm_ba_gauge;

/* options.scale_gauge (needs SFM_BA_GAUGE_FIRST_CAMERA) */
typedef enum sfm_ba_scale_gauge {
    SFM_BA_SCALE_NONE = 0,
    /* translations[scale_camera * 3 + scale_coordinate] held constant */
    SFM_BA_SCALE_COORDINATE = 1,
    /* distance between the centres of camera 0 and camera scale_camera fixed
     * to scale_distance. Solved as SFM_BA_SCALE_COORDINATE on the
     * best-conditioned coordinate, then the scene is scaled about camera 0's
     * centre (the cost is invariant to that scaling, so the minimum is
     * exact); needs every other camera and point free. The covariance is
     * that of the coordinate gauge, before the scaling. */
    SFM_BA_SCALE_DISTANCE = 2
} sfm_ba_scale_gauge;

/* camera_flags bits */
#define SFM_BA_FIX_POSE 1       /* rotation and translation held constant */
#define SFM_BA_FIX_INTRINSICS 2 /* this camera's intrinsics (PER_CAMERA mode) held */

/* result.stop_reason: the LM driver's stopping rule, checked in this order
 * before each step (the first two) and after it (the others). */
typedef enum sfm_ba_stop {
    SFM_BA_STOP_GRADIENT = 1,       /* max |gradient| <= gradient_tolerance */
    SFM_BA_STOP_FUNCTION = 2,       /* |cost change| <= function_tolerance * cost */
    SFM_BA_STOP_PARAMETER = 3,      /* |step| <= parameter_tolerance * (|x| + tol) */
    SFM_BA_STOP_MAX_ITERATIONS = 4, /* max_iterations steps tried */
    SFM_BA_STOP_TRUST_REGION = 5,   /* trust region collapsed below 1e-32 */
    SFM_BA_STOP_NO_PARAMETERS = 6   /* nothing free to refine */
} sfm_ba_stop;

typedef struct sfm_ba_problem {
    int n_cameras;      /* m >= 1 */
    int n_points;       /* n >= 0 */
    int n_observations; /* >= 1 */
    double *rotations;    /* in/out, m x 9 row-major rotation matrices */
    double *translations; /* in/out, m x 3 */
    sfm_camera *cameras;  /* in/out, m camera models (intrinsics refined in place) */
    double *points;       /* in/out, n x 3 world points */
    const int *obs_camera;      /* n_observations camera indices */
    const int *obs_point;       /* n_observations point indices */
    const double *obs_xy;       /* n_observations x 2 pixels */
    const double *obs_weight;   /* n_observations weights >= 0, or NULL (all 1) */
    const unsigned char *camera_flags; /* m SFM_BA_FIX_* masks, or NULL */
    const unsigned char *point_fixed;  /* n, non-zero = held constant, or NULL */
} sfm_ba_problem;

typedef struct sfm_ba_options {
    sfm_ba_mode mode;             /* default FULL */
    sfm_ba_intrinsics intrinsics; /* default FIXED */
    int refine_intrinsics;        /* SFM_BA_REFINE_* mask, default 0 */
    sfm_ba_loss loss;             /* default SQUARED */
    double loss_scale;            /* a > 0 for the robust losses, default 1 */
    sfm_ba_gauge gauge;           /* default SFM_BA_GAUGE_FIRST_CAMERA */
    sfm_ba_scale_gauge scale_gauge; /* default SFM_BA_SCALE_NONE */
    int scale_camera;      /* 1..m-1 */
    int scale_coordinate;  /* 0..2 (SFM_BA_SCALE_COORDINATE) */
    double scale_distance; /* > 0 (SFM_BA_SCALE_DISTANCE) */
    int max_iterations;    /* >= 0, default 50 */
    double function_tolerance;  /* >= 0, default 1e-6 */
    double gradient_tolerance;  /* >= 0, default 1e-10 */
    double parameter_tolerance; /* >= 0, default 1e-8 */
    double initial_trust_radius; /* > 0, default 1e4 (damping 1 / radius) */
    int want_covariance;   /* non-zero: fill pose_covariance, default 0 */
} sfm_ba_options;

/* Sizes the workspace depends on. intrinsics and refine_intrinsics as in the
 * options that will be used. */
typedef struct sfm_ba_dims {
    int n_cameras;
    int n_points;
    int n_observations;
    sfm_ba_intrinsics intrinsics;
    int refine_intrinsics;
} sfm_ba_dims;

typedef struct sfm_ba_result {
    double initial_cost;
    double final_cost;
    int iterations;        /* LM steps tried (successful or not) */
    int successful_steps;
    sfm_ba_stop stop_reason;
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

/* Refines the problem in place. pose_covariance (room for
 * pose_covariance_len doubles, at least 36 m; may be NULL with length 0
 * unless options->want_covariance) receives for each camera the 6x6
 * marginal covariance of its pose in the update coordinates (w, dt)
 * (rotation first), the block of the inverse of the undamped normal matrix
 * J^T W J at the solution (robust weights included), taken from the inverse
 * of the reduced camera system; rows and columns of held coordinates are
 * zero.
 * Statuses: SFM_OK (also when stopped by the iteration limit: see
 * result->stop_reason), SFM_E_ARGUMENT (NULL, counts, index out of range,
 * negative weight, invalid camera (sfm_camera_validate), shared intrinsics
 * over cameras of different models, bad option, a free camera or point with
 * no observation, want_covariance with pose_covariance NULL or shorter than
 * 36 m), SFM_E_NONFINITE (NaN/Inf in an input or an option, or a
 * non-finite initial cost: an observed point its camera cannot project),
 * SFM_E_WORKSPACE (ws NULL or smaller than sfm_ba_workspace_size for the
 * problem's dims, checked before any array is read). */
SFM_API int sfm_ba_solve(sfm_ba_problem *problem, const sfm_ba_options *options,
                         sfm_ba_result *result, double *pose_covariance,
                         size_t pose_covariance_len, void *ws, size_t ws_size);

#ifdef __cplusplus
}
#endif
#endif
