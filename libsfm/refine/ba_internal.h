/*
 * Internal: the pieces of bundle adjustment, one concept per file.
 *
 *   ba_layout.c      the workspace, the parameter layout and the gauge: which
 *                    coordinates are free and where they sit in the reduced
 *                    camera system; observations grouped by point
 *   ba_schur.c       the LM system over that layout (core/lm.h): residuals
 *                    and Jacobians through the camera models, the Schur
 *                    complement step, the trial point
 *   ba_covariance.c  the pose covariance at the solution
 *   ba.c             the public entry: argument checks, the driver's use,
 *                    the distance gauge's rescaling, the outputs
 *
 * Camera-side local columns of one observation's Jacobian (SFMI_BA_NLOC):
 * 0-2 rotation w (R <- exp([w]x) R), 3-5 translation, 6 focal fx (fy follows
 * with its ratio), 7-8 cx, cy, 9.. the model's distortion coefficients in
 * sfm_camera.dist order.
 */
#ifndef SFM_REFINE_BA_INTERNAL_H
#define SFM_REFINE_BA_INTERNAL_H

#include "core/arena.h"
#include "sfm/sfm_ba.h"
#include "sfm/sfm_camera.h"

#define SFMI_BA_NDIST 5
#define SFMI_BA_NLOC (9 + SFMI_BA_NDIST)

typedef struct sfmi_ba_ws {
    int *cam_q;    /* m: camera-side parameters of an observation of camera c */
    int *cam_col;  /* m x qmax: local column of each */
    int *cam_gi;   /* m x qmax: index in the reduced system */
    int *cam_base; /* m: cam_gi[0] when the indices are consecutive, else -1 */
    int *pt_start; /* n + 1 */
    int *pt_obs;   /* nobs, observations grouped by point */
    int *pt_free;  /* n */
    double *R, *t, *X;  /* current estimate */
    double *R2, *t2, *X2; /* trial estimate */
    sfm_camera *K, *K2;   /* current and trial cameras */
    double *res; /* 2 nobs: scaled residuals */
    double *Jc;  /* nobs x 2 x qmax */
    double *Jp;  /* nobs x 6 */
    double *F;   /* nobs x qmax x 3 */
    double *U, *S, *gc, *dc, *Dc; /* nc x nc, nc x nc, nc, nc, nc */
    double *V, *gp, *L, *zp, *dp, *Dp; /* 9n, 3n, 9n, 3n, 3n, 3n */
    double *aspect; /* m: fy / fx */
} sfmi_ba_ws;

typedef struct sfmi_ba_ctx {
    const sfm_ba_problem *p;
    const sfm_ba_options *o;
    sfmi_ba_ws w;
    int m, n, nobs, qmax, nc, nic;
    int scale_gauge, scale_cam, scale_coord;
    double a2;
} sfmi_ba_ctx;

/* ba_layout.c */
int sfmi_ba_n_intrinsics(const sfm_ba_dims *d);
int sfmi_ba_dims_valid(const sfm_ba_dims *d);
/* Carves the workspace; *qmax, *ncmax: the largest camera-side parameter
 * count of an observation and of the reduced system. */
void sfmi_ba_carve(sfmi_arena *a, const sfm_ba_dims *d, sfmi_ba_ws *w, int *qmax, int *ncmax);
/* Free flags, the observations by point, the camera-side columns and the
 * gauge, the working copies. Returns SFM_OK or SFM_E_ARGUMENT (a free point
 * or camera nobody sees, an unobservable distance gauge). */
int sfmi_ba_setup(sfmi_ba_ctx *c, int ncmax);

/* ba_schur.c */
double sfmi_ba_linearize(void *self, double *grad_max);
int sfmi_ba_solve_step(void *self, double mu, double *step2, double *x2, double *pred);
double sfmi_ba_trial(void *self);
void sfmi_ba_accept(void *self);
/* Forms the reduced system (lower triangle in S, right-hand side in dc) with
 * damping mu (0: undamped). Returns 0 when a point block is not positive
 * definite. */
int sfmi_ba_form_reduced(sfmi_ba_ctx *c, double mu);
/* Projection of X (world) by camera (R, t, cam) and, when J is not NULL,
 * the 2 x SFMI_BA_NLOC local camera-side Jacobian and Jp = d(px)/d(X)
 * (2 x 3). aspect = fy / fx (the focal column moves both). Returns 0 when
 * the point cannot be projected. */
int sfmi_ba_project(const sfm_camera *cam, double aspect, const double *R, const double *t,
                    const double *X, double uv[2], double *J, double *Jp);

/* ba_covariance.c: the pose covariance (see sfm_ba_solve). Returns SFM_OK or
 * SFM_E_SINGULAR; uses U as the inverse. */
int sfmi_ba_covariance(sfmi_ba_ctx *c);
void sfmi_ba_write_covariance(const sfmi_ba_ctx *c, double *pose_covariance);

#endif
