/* Internal: Harris measure and sub-pixel corner refinement. */
#ifndef SFM_FEATURES_CORNER_H
#define SFM_FEATURES_CORNER_H

#include <stdint.h>

/* Harris measure det(M) - 0.04 trace(M)^2 of the structure tensor M summed
 * over the 7x7 window centred on (x, y) (central differences). Needs 4 pixels
 * of image around (x, y). */
double sfmi_feat_harris(const uint8_t *img, int stride, int x, int y);

/* Sub-pixel corner location near integer (x, y), in the same level's pixel
 * coordinates (Foerstner, iterated up to 3 times, re-centred on the rounded
 * estimate). Returns 1 and writes (*rx, *ry) on success; returns 0 (and
 * writes (x, y)) when the window is edge-like, the estimate wanders more than
 * 3 pixels, or the gradient lines miss it by more than max_residual (weighted
 * mean squared distance, level pixels squared). Needs 8 pixels of image
 * around (x, y). */
int sfmi_feat_refine(const uint8_t *img, int stride, int x, int y, double max_residual, double *rx, double *ry);

#endif
