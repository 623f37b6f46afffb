/* Internal: the parts shared by the calibrated two-view estimators (relative
 * pose and upright relative pose): input checks, workspace layout, bearings,
 * the estimator callbacks on (E, R, t) models, the final pose and flags. */
#ifndef SFM_ROBUST_TWOVIEW_H
#define SFM_ROBUST_TWOVIEW_H

#include "core/arena.h"
#include "sfm/sfm_ransac.h"

/* Model layout: E[9] (unit Frobenius norm), R[9], t[3], pose_valid. */
#define TV_E 0
#define TV_R 9
#define TV_T 18
#define TV_VALID 21

/* LM steps per local-optimisation round. */
#define SFM_TWOVIEW_LM_STEPS 4

typedef struct twoview_ctx {
    const double *b1, *b2; /* unit bearings, n x 3 */
    int n;
    const double *d1, *d2; /* upright: unit known directions; NULL otherwise */
    double scale;          /* robust scale of the refit (radians): the angular
                              threshold until the engine sets it from the noise */
} twoview_ctx;

typedef struct twoview_ws {
    double *b1, *b2, *p1, *p2;
    int *idx, *sel;
    void *eng;
    size_t eng_size;
} twoview_ws;

size_t sfm_twoview_workspace_size(int n, int sample, int max_models);
/* Checks inputs, carves ws, unprojects; returns SFM_OK or a status. */
int sfm_twoview_setup(const double *px1, const double *px2, int n, const sfm_camera *cam1,
                      const sfm_camera *cam2, const sfm_ransac_options *opt, int sample,
                      int max_models, void *ws, size_t ws_size, twoview_ws *w,
                      sfm_ransac_options *eopt, double *focal);

double sfm_twoview_residual(void *ctx, const double *model, int i);
int sfm_twoview_refine(void *ctx, const int *inliers, int n_inliers, double *model);
/* The engine's set_scale: the Cauchy scale of the next refits (radians). */
void sfm_twoview_set_scale(void *ctx, double scale);
/* Sets model E from its R, t (unit Frobenius norm) and marks the pose valid. */
void sfm_twoview_set_pose(double *model, const double R[9], const double t[3]);

/* After a successful run: final pose by cheirality over the inliers, flags,
 * outputs. upright: only the sign of t is chosen (R keeps the known
 * direction). Returns the inlier count. */
int sfm_twoview_finish(const twoview_ctx *c, twoview_ws *w, const double *model, double tau,
                       double focal, int upright, int n_inl, const sfm_ransac_stats *est,
                       sfm_pose *pose, double E[9], uint8_t *mask, sfm_ransac_stats *stats);

/* After a successful setup: runs the engine with solve over samples of
 * `sample` bearings (at most max_models models each), the shared residual
 * and LO, then sfm_twoview_finish (upright when c->d2 is set). Returns the
 * inlier count or a status. */
int sfm_twoview_run(twoview_ctx *c, twoview_ws *w, const sfm_ransac_options *eopt, int sample,
                    int max_models, int (*solve)(void *ctx, const int *s, double *models),
                    double focal, sfm_pose *pose, double E[9], uint8_t *mask,
                    sfm_ransac_stats *stats);

#endif
