/*
 * Internal: the metric stage shared by the uncalibrated pipelines (see
 * sfm_uncalibrated.h): metric cameras of a candidate focal length from the
 * fundamental matrices, metric bundle adjustment, the focal sweep, inlier
 * re-collection and the physical checks. All pixels are centred on the
 * principal point. Not API.
 */
#ifndef SFM_RECON_METRIC_UPGRADE_H
#define SFM_RECON_METRIC_UPGRADE_H

#include "core/arena.h"
#include "sfm/sfm_common.h"
#include "sfm/sfm_uncalibrated.h"

typedef struct sfmi_mu {
    int nv;           /* 2 or 3 views */
    int nmax;         /* capacity (input count) */
    int m;            /* current inliers, compacted into x */
    double *x[3];     /* m x 2 centred pixels per view */
    int *idx;         /* m: input index of each inlier */
    sfm_mat3 F[2];    /* F21, F31 (x_v^T F x_1 = 0, centred pixels) */
    double thr;       /* pixels per view */
    double *bear;     /* nv x m x 3 */
    double *X;        /* m x 3 (BA points, compacted) */
    double *Xkeep;    /* m x 3 copy of X */
    int *flags;       /* m */
    int *pidx;        /* m: inlier index of BA point k */
    int np;           /* BA points */
    int *obs_cam, *obs_pt;
    double *obs_xy;
    void *ba_ws;
    size_t ba_size;
    int evaluations;
    int radial_max;   /* radial terms the layout has room for (0..2) */
    int radial;       /* radial terms free in the adjustments (0..2: k1, k2) */
    double kr[2];     /* Brown k1, k2 of the working candidate (normalized
                         coordinates about the centre); 0, 0: pinhole */
    double *xu[3];    /* nmax x 2 scratch: undistorted centred pixels */
    int *idx0;        /* nmax: the inliers the solve started from (radial > 0) */
    double cost;      /* final free-focal cost of the last validated answer */
    double pp_sigma;  /* px: prior standard deviation of the principal point per axis */
    double aspect_sigma; /* prior standard deviation of the aspect ratio */
    int sweep_iters;  /* bundle adjustment steps per fixed-focal sweep candidate */
    int undetermined; /* the last validation refused f for its sigma */
} sfmi_mu;

/* Carves the stage for up to `radial` radial terms (0..2; the solve then
 * estimates at most min(radial, o->radial)). */
void sfmi_mu_layout(sfmi_arena *a, int nv, int nmax, int radial, sfmi_mu *c);

/* Runs sweep, starts and the final checks; fills report fields focal_sweep,
 * evaluations, path, profile_rise, focal, k1, k2, radial_rise, inliers,
 * rms, front_fraction and stage. o->radial radial terms (at most those the
 * layout has room for) are estimated with three views (none with two). xall: the nv full centred arrays (nmax x 2) for re-collection.
 * On success writes poses[nv], f[nv] (equal unless per_view_focal), and leaves the final inliers in c (x,
 * idx, m) and their points in c->X / c->pidx / c->np. */
int sfmi_mu_solve(sfmi_mu *c, const double *const xall[3], int n, double f_linear, double diag,
                  const sfm_uncal_options *o, sfm_pose poses[3], double *f, sfm_uncal_report *rep);

/* Options of a pipeline: *o = *opt, or the defaults when opt is NULL;
 * SFM_E_ARGUMENT when they are invalid. */
int sfmi_uncal_options(const sfm_uncal_options *opt, sfm_uncal_options *o);

/* Input pixels (nv views, n each) checked finite and centred on the
 * principal point ((width - 1) / 2, (height - 1) / 2) into xc; the report
 * started. SFM_E_NONFINITE on NaN/Inf. */
int sfmi_uncal_centre(int nv, const double *const px[3], int n, int width, int height, double *const xc[3],
                      sfm_uncal_report *rep);

/* One run of a pipeline from RANSAC to the checked answer. */
typedef int (*sfmi_uncal_once_fn)(void *ctx, const sfm_uncal_options *o, sfm_pose est[3], double *f,
                                  sfm_uncal_report *rep);

/* Runs once() up to 3 times while the metric stage fails (SFM_E_SINGULAR
 * or SFM_E_NO_CONVERGENCE after RANSAC succeeded): with the seeds seed,
 * seed + 1, seed + 2, the last at twice the threshold (the accepted RMS
 * stays the caller's). rep is the last run's, rep->attempts the runs. */
int sfmi_uncal_attempts(sfmi_uncal_once_fn once, void *ctx, const sfm_uncal_options *o, int n,
                        sfm_pose est[3], double *f, sfm_uncal_report *rep);

/* The answer's K per view (nv x 9, focal lengths f[nv], pixels, principal
 * point (cx, cy)), X (n x 3 at the input
 * indices of the final inliers, zero elsewhere; may be NULL) and mask (n,
 * may be NULL) after a successful sfmi_mu_solve. */
void sfmi_mu_outputs(const sfmi_mu *c, int n, const double *f, double cx, double cy, double *K, double *X,
                     uint8_t *mask);

#endif
