/* Internal: input handling shared by the uncalibrated two-view estimators
 * (fundamental matrix, homography): checks, workspace, ideal pixels. */
#ifndef SFM_ROBUST_PIXEL_PAIRS_H
#define SFM_ROBUST_PIXEL_PAIRS_H

#include "core/arena.h"
#include "sfm/sfm_ransac.h"

typedef struct pixel_pairs {
    double *p1, *p2;   /* ideal pixels n x 2 */
    double *g1, *g2;   /* gather scratch n x 2 (LO refits) */
    int *idx;          /* n ints */
    void *eng;
    size_t eng_size;
} pixel_pairs;

size_t sfmi_pixel_pairs_workspace_size(int n, int sample, int max_models, int model_size);
/* Checks inputs and options, carves ws, writes ideal pixels: with cameras,
 * unproject (undoing distortion) and project with the cameras' pinhole part;
 * without, copy. Returns SFM_OK or a status. */
int sfmi_pixel_pairs_setup(const double *px1, const double *px2, int n, const sfm_camera *cam1,
                          const sfm_camera *cam2, const sfm_ransac_options *opt, int sample,
                          int max_models, int model_size, void *ws, size_t ws_size,
                          pixel_pairs *pp, sfm_ransac_options *eopt);

/* The linear refit that starts an LO step of the fundamental and homography
 * estimators: the inliers inl[0..n) of p1, p2 are gathered into g1, g2 (n x
 * 2 each), and M (9 entries, in and out) becomes fit's model of them when
 * fit returns 1 with a model that scales to unit norm and whose robust cost
 * (scale tau) is below M's; else M stays. */
typedef int (*sfmi_pair_fit_fn)(const double *p1, const double *p2, int n, sfm_mat3 *M);
typedef double (*sfmi_pair_cost_fn)(const double *p1, const double *p2, int n, double scale,
                                    const double M[9]);
void sfmi_pixel_pairs_refit(const double *p1, const double *p2, const int *inl, int n,
                            double tau, sfmi_pair_fit_fn fit, sfmi_pair_cost_fn cost,
                            double *g1, double *g2, double M[9]);

/* The support checks of sfm_ransac.h on the inliers pp->idx[0..m) of a
 * model of sample size k over n pairs: chance (p: the probability that a
 * random pair lands in the model's inlier band), spread in each image
 * (collinear, clustered against the input box) and the design test
 * (homography or fundamental rows). Overwrites pp->g1, pp->g2. Returns
 * SFM_OK, SFM_E_NO_MODEL or SFM_E_DEGENERATE. */
int sfmi_pixel_pairs_support(const pixel_pairs *pp, int n, int k, int m, double p, int homography,
                            double tau);

#endif
