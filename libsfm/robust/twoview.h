/* Internal: the parts shared by the calibrated two-view estimators (relative
 * pose and upright relative pose): input checks, workspace layout, bearings,
 * the estimator callbacks on (E, R, t) models, the final pose, its support
 * checks and flags. */
#ifndef SFM_ROBUST_TWOVIEW_H
#define SFM_ROBUST_TWOVIEW_H

#include "core/arena.h"
#include "sfm/sfm_ransac.h"

/* The model the engine carries (it copies models as bytes, model_size
 * doubles): E (unit Frobenius norm) and, once decomposed, the pose. */
typedef struct twoview_model {
    double E[9];
    double R[9];
    double t[3];
    int32_t pose_valid; /* R, t hold the pose of E */
    int32_t unused;
} twoview_model;
_Static_assert(sizeof(twoview_model) == SFM_RANSAC_RELPOSE_MODEL * sizeof(double),
               "twoview_model is the engine's model size");

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

/* One estimator call: its inputs, minimal solver and outputs. */
typedef struct twoview_call {
    const double *px1, *px2;
    int n;
    const sfm_camera *cam1, *cam2;
    const sfm_ransac_options *opt;
    int sample, max_models;
    int (*solve)(void *ctx, const int *s, double *models);
    void *ws;
    size_t ws_size;
    sfm_pose *pose;
    double *E;
    uint8_t *mask;
    sfm_ransac_stats *stats;
} twoview_call;

size_t sfmi_twoview_workspace_size(int n, int sample, int max_models);
/* Checks inputs, carves ws, unprojects; returns SFM_OK or a status. eopt
 * gets the options in angular units, *focal the mean focal length. */
int sfmi_twoview_setup(const twoview_call *call, twoview_ws *w, sfm_ransac_options *eopt,
                      double *focal);

double sfmi_twoview_residual(void *ctx, const double *model, int i);
/* The engine's block residual (sfm_ransac_estimator.residuals), where the
 * target has two-lane doubles and the build is for speed; elsewhere the
 * engine calls residual point by point (the same bits either way). */
#if (defined(__SSE2__) || defined(__ARM_NEON)) && defined(__GNUC__) && !defined(__OPTIMIZE_SIZE__)
#define SFMI_TWOVIEW_HAVE_BLOCK 1
void sfmi_twoview_residuals(void *ctx, const double *model, const int *idx, int count, double *r2);
#else
#define SFMI_TWOVIEW_HAVE_BLOCK 0
#endif
int sfmi_twoview_refine(void *ctx, const int *inliers, int n_inliers, double *model);
/* The engine's set_scale: the Cauchy scale of the next refits (radians). */
void sfmi_twoview_set_scale(void *ctx, double scale);
int sfmi_twoview_prune(void *ctx, const double *model, int *list, int n, double sigma2);
/* Sets m's E from R, t (unit Frobenius norm) and marks the pose valid. */
void sfmi_twoview_set_pose(twoview_model *m, const double R[9], const double t[3]);

/* After a successful setup: runs the engine with call->solve, the shared
 * residual and LO, then the final pose by cheirality over the inliers
 * (upright when c->d2 is set: only the sign of t is chosen), the support
 * checks of sfm_ransac.h and the outputs. Returns the inlier count or a
 * status. */
int sfmi_twoview_run(const twoview_call *call, twoview_ctx *c, twoview_ws *w,
                    const sfm_ransac_options *eopt, double focal);

#endif
