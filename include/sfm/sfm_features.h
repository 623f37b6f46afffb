/*
 * libsfm features: corners, oriented binary descriptors, Hamming matching and
 * three-view cyclic association.
 *
 * Images are 8-bit gray views {data, width, height, stride} (row y starts at
 * data + y*stride). Keypoint coordinates are level-0 pixels with the origin at
 * the centre of the top-left pixel, x right, y down.
 *
 * Pipeline (sfm_features_detect): an image pyramid with a fixed scale step is
 * built in the caller's workspace; on every level FAST-9 corners (segment test
 * on the 16-pixel Bresenham circle of radius 3, 9 contiguous pixels) pass a
 * 3x3 non-maximum suppression on the FAST score, are bucketed in a grid, ranked
 * by the Harris measure and refined to sub-pixel accuracy (Foerstner: the point
 * closest in the least-squares sense to all gradient lines of a window). Each
 * level is then smoothed (5-tap Gaussian, sigma 1.5) and every kept corner
 * gets the intensity-centroid orientation (Rosin 1999) and a 256-bit steered
 * BRIEF descriptor (Calonder et al. 2010, steered as in Rublee et al., "ORB",
 * ICCV 2011) whose sampling pattern comes from tools/gen_brief_pattern.py.
 *
 * No allocation, no I/O, no globals but constant tables; deterministic.
 */
#ifndef SFM_FEATURES_H
#define SFM_FEATURES_H

#include "sfm/sfm_common.h"

#ifdef __cplusplus
extern "C" {
#endif

/* Compile-time capacities. */
#define SFM_FEATURES_MAX_LEVELS 8
#define SFM_FEATURES_MAX_FEATURES 65536
#define SFM_FEATURES_DESC_BYTES 32
/* Pixels kept free at each level's border (descriptor patch radius + 1). */
#define SFM_FEATURES_BORDER 16

/* A borrowed 8-bit gray image. */
typedef struct sfm_image_u8 {
    const uint8_t *data;
    int width;
    int height;
    int stride; /* bytes between rows, >= width */
} sfm_image_u8;

/* One keypoint. x, y: level-0 pixels (origin at the centre of the top-left
 * pixel). angle: descriptor orientation in radians, (-pi, pi], measured from
 * +x towards +y (image axes). response: Harris measure on its level.
 * scale: level-0 pixels per level pixel. level: pyramid level. */
typedef struct sfm_keypoint {
    double x;
    double y;
    double angle;
    double response;
    double scale;
    int level;
    int reserved; /* always 0 */
} sfm_keypoint;

typedef struct sfm_features_params {
    int max_features;    /* budget over all levels, 1..SFM_FEATURES_MAX_FEATURES */
    int n_levels;        /* 1..SFM_FEATURES_MAX_LEVELS (fewer are used when a level would be too small) */
    double scale_factor; /* linear size ratio between levels, in [1.05, 2] */
    int fast_threshold;  /* segment-test intensity threshold, 1..254 */
    int cell_size;       /* grid cell side in level pixels for bucketing, 8..1024 */
} sfm_features_params;

/* Defaults: 2000 features, 6 levels, scale 1.25, FAST threshold 20, cells of
 * 48 pixels. Returns SFM_OK, or SFM_E_ARGUMENT when p is NULL. */
SFM_API int sfm_features_default_params(sfm_features_params *p);

/* Workspace bytes sfm_features_detect needs for an image of this size with
 * these parameters (alignment slack included), or 0 when the parameters or
 * sizes are invalid. */
SFM_API size_t sfm_features_workspace_size(const sfm_features_params *p, int width, int height);

/* Detects up to p->max_features keypoints and their descriptors.
 *   kps:   capacity entries; desc: capacity * SFM_FEATURES_DESC_BYTES bytes.
 *   capacity must be >= p->max_features.
 * Returns the number of keypoints written (0 when the image is too small to
 * hold any), or
 *   SFM_E_ARGUMENT   NULL pointer, width/height < 1, stride < width, invalid params;
 *   SFM_E_CAPACITY   capacity < p->max_features;
 *   SFM_E_WORKSPACE  ws_size < sfm_features_workspace_size(p, width, height).
 * On failure nothing is written to kps or desc. Outputs must not alias the
 * image or the workspace. */
SFM_API int sfm_features_detect(const sfm_image_u8 *image, const sfm_features_params *p,
                                sfm_keypoint *kps, uint8_t *desc, int capacity,
                                void *ws, size_t ws_size);

/* Hamming distance between two 256-bit descriptors (portable popcount). */
SFM_API int sfm_features_hamming(const uint8_t *a, const uint8_t *b);

typedef struct sfm_match_params {
    double ratio;     /* Lowe ratio test best < ratio * second; 1.0 disables; in (0, 1] */
    int mutual;       /* 1: keep i->j only when i is also j's nearest neighbour */
    int max_distance; /* drop matches with a larger Hamming distance; 0..256 */
} sfm_match_params;

/* Defaults: ratio 0.8, mutual 1, max_distance 256 (no limit). */
SFM_API int sfm_features_default_match_params(sfm_match_params *p);

/* Workspace bytes sfm_features_match needs for n2 train descriptors. */
SFM_API size_t sfm_features_match_workspace_size(int n1, int n2);

/* Brute-force Hamming matching of n1 query descriptors d1 against n2 train
 * descriptors d2 (32 bytes each). Nearest neighbours break ties by the lower
 * index. Writes pairs (i1, i2) to matches[2*k], matches[2*k+1] in increasing
 * i1, and, when distances is not NULL, their Hamming distances.
 * capacity (pairs) must be >= n1. n1 or n2 may be 0 (no matches).
 * Returns the number of matches, or
 *   SFM_E_ARGUMENT   NULL pointer (d1/d2 may be NULL only with a zero count),
 *                    negative count, bad params;
 *   SFM_E_CAPACITY   capacity < n1;
 *   SFM_E_WORKSPACE  ws_size < sfm_features_match_workspace_size(n1, n2).
 * On failure nothing is written. */
SFM_API int sfm_features_match(const uint8_t *d1, int n1, const uint8_t *d2, int n2,
                               const sfm_match_params *p, int *matches, int *distances, int capacity,
                               void *ws, size_t ws_size);

/* Workspace bytes sfm_features_associate_three_views needs. */
SFM_API size_t sfm_features_associate_workspace_size(int n1, int n2, int n3);

/* Three-view cyclic association. m12 holds n12 pairs (i1, i2) (feature i1 of
 * view 1 matched to i2 of view 2), m23 pairs (i2, i3), m31 pairs (i3, i1);
 * n1, n2, n3 are the feature counts of the views. A view-1 feature is kept
 * when following 1->2->3->1 returns to it; triplets (i1, i2, i3) are written
 * to out[3*k..3*k+2] in increasing i1. capacity (triplets) must be >= the
 * smallest of n12, n23, n31.
 * Returns the number of triplets, or
 *   SFM_E_ARGUMENT   NULL pointer (a list may be NULL when its count is 0),
 *                    negative count, an index out of range, or a source index
 *                    repeated within one list (each list must be a function);
 *   SFM_E_CAPACITY   capacity too small;
 *   SFM_E_WORKSPACE  workspace too small.
 * On failure nothing is written. */
SFM_API int sfm_features_associate_three_views(const int *m12, int n12, const int *m23, int n23,
                                               const int *m31, int n31, int n1, int n2, int n3,
                                               int *out, int capacity, void *ws, size_t ws_size);

/* Largest patch radius of sfm_features_align_points. */
#define SFM_FEATURES_ALIGN_MAX_RADIUS 8

typedef struct sfm_align_params {
    int radius;             /* patch half side in pixels, 2..SFM_FEATURES_ALIGN_MAX_RADIUS */
    int max_iterations;     /* Gauss-Newton steps, 1..100 */
    double max_shift;       /* largest move from the start on either axis, pixels, > 0 */
    double min_zncc;        /* the aligned patches' normalised correlation must reach this, in [-1, 1] */
    double min_eigen_ratio; /* the template's gradient matrix: smaller eigenvalue / larger, in [0, 1] */
} sfm_align_params;

/* Defaults: radius 7, 20 iterations, max_shift 3 px, min_zncc 0.8,
 * min_eigen_ratio 0.05. Returns SFM_OK, or SFM_E_ARGUMENT when p is NULL. */
SFM_API int sfm_features_default_align_params(sfm_align_params *p);

/* Photometric refinement of correspondences (Lucas-Kanade, translation with
 * gain and bias): for each k the square patch of ref around x_ref[2k],
 * x_ref[2k+1] (pixels, origin at the centre of the top-left pixel, sampled
 * bilinearly) is found in img starting from x[2k], x[2k+1]; the result goes
 * to out[2k], out[2k+1] and refined[k] = 1. A point whose patch has no
 * corner-like gradient structure, leaves either image, does not settle,
 * moves more than max_shift, or correlates below min_zncc keeps its start
 * (refined[k] = 0). The reference points stay where they are: aligning
 * views 2 and 3 to view 1 makes each triplet one surface point, wherever
 * the detector put it in view 1.
 * out may be x (in place); nothing else may alias. Bounded stack (5.5 KB),
 * no workspace.
 * Returns the number of points refined, or
 *   SFM_E_ARGUMENT   NULL pointer (arrays may be NULL when n is 0), n < 0,
 *                    an invalid image view or invalid params;
 *   SFM_E_NONFINITE  NaN or Inf in x_ref or x.
 * On failure nothing is written. */
SFM_API int sfm_features_align_points(const sfm_image_u8 *ref, const double *x_ref, const sfm_image_u8 *img,
                                      const double *x, int n, const sfm_align_params *p, double *out,
                                      uint8_t *refined);

#ifdef __cplusplus
}
#endif
#endif
