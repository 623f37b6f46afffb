/* Internal: trifocal RANSAC with a choice of final support checks, for the
 * calibrated three-view pose, which judges the support of its own metric
 * result (a dominant plane makes the projective tensor of RANSAC a
 * plane-induced one; the calibrated path recovers from it). */
#ifndef SFM_ROBUST_TRIFOCAL_RANSAC_H
#define SFM_ROBUST_TRIFOCAL_RANSAC_H

#include "sfm/sfm_ransac_trifocal.h"

/* Checks beyond the spread in each view, which always runs. */
#define SFMI_TF_CHECK_CHANCE 1 /* support against chance */
#define SFMI_TF_CHECK_DESIGN 2 /* one null direction of the normalised design */

/* sfm_ransac_trifocal with the given checks. */
int sfmi_ransac_trifocal(const double *x1, const double *x2, const double *x3, int n,
                         const sfm_ransac_options *opt, double T[27], double *P,
                         uint8_t *inlier_mask, sfm_ransac_stats *stats, void *ws, size_t ws_size,
                         int checks);

/* Probability that a random triplet is an inlier of a trifocal model at
 * threshold tau (pixels, per view), over the boxes of the input views. */
double sfmi_trifocal_chance(const double *x2, const double *x3, int n, double tau);

#endif
