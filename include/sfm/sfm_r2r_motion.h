/*
 * Leader-follower formations: the follower's next-step motion that best
 * localizes it relative to the leader (Zhou, Zhou, Roumeliotis, "Optimized
 * motion strategies for localization in leader-follower formations", IROS
 * 2011), and the extended Kalman filter it is optimal for.
 *
 * Conventions (every function of this header):
 *  - Planar, as the paper: both robots move in one plane. Units are metres
 *    and radians; angles are counter-clockwise, wrapped to (-pi, pi].
 *  - Frames: {F} is the follower's body frame at the current step, {L} the
 *    leader's. The state x = (p_x, p_y, phi) is the leader's position p in
 *    {F} and its heading phi relative to the follower: x_{F} = R(phi) x_{L}
 *    + p, R(a) = [cos a, -sin a; sin a, cos a].
 *  - One step of motion (sfm_r2r_motion_step): the leader translates by
 *    leader_d (in its own frame at the step's start) and turns by leader_w;
 *    the follower first turns by follower_w, then translates by follower_d,
 *    expressed in its turned frame (the frame of the next step). So
 *      p'   = R(-follower_w) (p + R(phi) leader_d) - follower_d
 *      phi' = phi + leader_w - follower_w.
 *    c = R(-follower_w) (p + R(phi) leader_d) is where the leader would be
 *    seen at the next step if the follower did not translate; the follower's
 *    translation picks the next relative position q = c - follower_d.
 *  - Noise (sfm_r2r_motion_noise): each odometry input carries independent
 *    zero-mean Gaussian noise of the given standard deviation per step (per
 *    axis for translations), constant, not proportional to the motion. The
 *    follower measures the leader at each step by range |p| (metres) or by
 *    bearing atan2(p_y, p_x) (radians, in {F}), with standard deviation
 *    sigma_meas.
 *  - Covariances are 3x3, row-major, symmetric positive definite, in the
 *    order (p_x, p_y, phi). Every function linearises at the estimate (EKF).
 *
 * The optimal next motion (sfm_r2r_motion_next): among follower
 * translations with |follower_d - d0| <= radius (d0 = 0: a speed bound;
 * d0 = c - q_des: stay within radius of a desired formation position q_des),
 * the one minimising the trace of the covariance after the next propagation
 * and update. The propagated covariance does not depend on follower_d (the
 * follower turns before it translates), so the cost is tr(P') - g(q) with
 *   range:   g = q^T B q / (q^T (A + s^2 I) q)
 *   bearing: g = v^T B v / (v^T A v + s^2 |q|^4),   v = (-q_y, q_x),
 * A the position block of P', B that of P'^2, s = sigma_meas. Every
 * critical point of the KKT conditions is found: on the circle |q - m| =
 * radius (m = c - d0), the stationarity condition with the multiplier
 * eliminated, under the rational parametrisation of the circle by the
 * tangent of the half angle, is one univariate polynomial of degree 6, whose
 * real roots are all found (Sturm sequence, sfm_poly_real_roots), plus the
 * one point the parametrisation misses; inside the disk, range has critical
 * rays (g depends only on the direction of q: the directions stationary for
 * the generalised Rayleigh quotient of (B, A + s^2 I), a quadratic), bearing
 * has none (g is homogeneous of degree -2 in q, so its gradient never
 * vanishes). The minimum over these candidates is the global one. Where the
 * minimum is a whole segment of a ray (range), the point nearest m (least
 * deviation from the nominal motion) is returned. Under a pure speed bound
 * a bearing-only follower is drawn towards the leader (the information
 * grows as 1/|q|^2): min_distance > 0 adds |q| >= min_distance, whose
 * circle inside the disk gives a Rayleigh quotient of the direction again
 * (a quadratic), and the circles' two crossings; a formation disk keeps the
 * follower at its station without it.
 *
 * Memory: no workspace; stack use under 8 KB (the Sturm root finder).
 * Deterministic and reentrant. Outputs may not alias inputs.
 */
#ifndef SFM_R2R_MOTION_H
#define SFM_R2R_MOTION_H

#include "sfm/sfm_common.h"

#ifdef __cplusplus
extern "C" {
#endif

/* The follower's sensor. */
typedef enum sfm_r2r_motion_sensor {
    SFM_R2R_MOTION_RANGE = 1,  /* distance |p|, metres */
    SFM_R2R_MOTION_BEARING = 2 /* direction atan2(p_y, p_x) in {F}, radians */
} sfm_r2r_motion_sensor;

/* One step of both robots' odometry (see the conventions above). */
typedef struct sfm_r2r_motion_step {
    sfm_vec2 leader_d;   /* leader translation, in the leader's frame, m */
    double leader_w;     /* leader rotation, rad */
    double follower_w;   /* follower rotation, applied first, rad */
    sfm_vec2 follower_d; /* follower translation, in its turned frame, m */
} sfm_r2r_motion_step;

/* Standard deviations per step, all >= 0 (sigma_meas > 0). */
typedef struct sfm_r2r_motion_noise {
    double sigma_leader_d;   /* leader translation, m, per axis */
    double sigma_leader_w;   /* leader rotation, rad */
    double sigma_follower_d; /* follower translation, m, per axis */
    double sigma_follower_w; /* follower rotation, rad */
    double sigma_meas;       /* range (m) or bearing (rad) measurement */
} sfm_r2r_motion_noise;

/* What sfm_r2r_motion_next chose. */
typedef struct sfm_r2r_motion_plan {
    sfm_vec2 follower_d; /* the follower's translation (in its turned frame) */
    sfm_vec2 q;          /* the predicted next relative position, c - follower_d */
    double trace;        /* trace of the covariance after propagation and update */
    double trace_prior;  /* trace of the propagated covariance (before update) */
    double multiplier;   /* KKT multiplier of the active constraint at the optimum
                            (>= 0; the disk's at a corner; 0 inside) */
    int on_boundary;     /* 0 inside; 1 on the disk's circle |follower_d - d0| =
                            radius; 2 on the distance circle |q| = min_distance;
                            3 at a corner where the two meet */
    int n_critical;      /* KKT critical points found (boundary roots + rays) */
} sfm_r2r_motion_plan;

/* EKF propagation of (x, P) through one step u. x_out is the predicted
 * state (phi wrapped), P_out the propagated covariance Phi P Phi^T + G Q G^T.
 * Statuses: SFM_OK; SFM_E_ARGUMENT (NULL, a negative sigma, P not symmetric
 * positive definite); SFM_E_NONFINITE (NaN/Inf in any input, or a result that overflows). Nothing is
 * written on failure. */
SFM_API int sfm_r2r_motion_propagate(const double x[3], const double P[9],
                                     const sfm_r2r_motion_step *u,
                                     const sfm_r2r_motion_noise *noise,
                                     double x_out[3], double P_out[9]);

/* EKF update of (x, P) with one measurement z of the given sensor
 * (noise->sigma_meas; the other sigmas are not read). The bearing
 * innovation is wrapped to (-pi, pi]; the covariance update is in Joseph
 * form. Statuses: SFM_OK; SFM_E_ARGUMENT (NULL, unknown sensor,
 * sigma_meas <= 0, P not symmetric positive definite, a range z < 0);
 * SFM_E_NONFINITE (also an overflowing result); SFM_E_SINGULAR (|p| too small for the Jacobian:
 * below 1e-9 m). Nothing is written on failure. */
SFM_API int sfm_r2r_motion_update(const double x[3], const double P[9], int sensor, double z,
                                  const sfm_r2r_motion_noise *noise,
                                  double x_out[3], double P_out[9]);

/* The trace of the covariance after propagating through u and updating with
 * one measurement at the predicted state (what sfm_r2r_motion_next
 * minimises; it does not depend on the measured value). Statuses as
 * sfm_r2r_motion_propagate and sfm_r2r_motion_update. */
SFM_API int sfm_r2r_motion_cost(const double x[3], const double P[9],
                                const sfm_r2r_motion_step *u,
                                const sfm_r2r_motion_noise *noise, int sensor,
                                double *trace);

/* The follower's next translation: u's leader_d, leader_w and follower_w
 * are given (u->follower_d is not read), d0 is the nominal translation the
 * admissible disk is centred on (NULL: the origin, a pure speed bound) and
 * radius > 0 its radius in metres; min_distance >= 0 (metres) keeps the
 * next relative position at |q| >= min_distance (0: no such constraint;
 * its circle and the two circles' crossings are then KKT candidates too).
 * Statuses: SFM_OK; SFM_E_ARGUMENT (NULL x, P, u, noise or out, unknown
 * sensor, radius <= 0, min_distance < 0, a negative sigma, sigma_meas <= 0,
 * P not symmetric positive definite); SFM_E_NONFINITE (also an overflowing result); SFM_E_SINGULAR
 * (min_distance 0 and the admissible disk reaches within 1e-6 m of the
 * leader's predicted position, where the measurement Jacobian is singular;
 * or no admissible translation keeps min_distance). Nothing is written on
 * failure. */
SFM_API int sfm_r2r_motion_next(const double x[3], const double P[9],
                                const sfm_r2r_motion_step *u, const double d0[2],
                                double radius, double min_distance,
                                const sfm_r2r_motion_noise *noise, int sensor,
                                sfm_r2r_motion_plan *out);

#ifdef __cplusplus
}
#endif
#endif
