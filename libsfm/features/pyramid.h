/* Internal: pyramid levels, bilinear downsampling and Gaussian smoothing. */
#ifndef SFM_FEATURES_PYRAMID_H
#define SFM_FEATURES_PYRAMID_H

#include <stdint.h>

/* One level: pixels plus the affine map to level 0,
 * x0 = (x + 0.5) * sx - 0.5 (pixel centres at integer coordinates). */
typedef struct sfmi_feat_level {
    const uint8_t *data;
    int w, h, stride;
    double sx, sy;
} sfmi_feat_level;

/* Level sizes for an image w0 x h0: fills w[], h[] for up to n_levels levels
 * and returns how many are large enough to hold a corner away from the border
 * (at least 1 level is always returned when the image itself is, else 0). */
int sfmi_feat_level_sizes(int w0, int h0, int n_levels, double scale_factor, int *w, int *h);

/* Bilinear resampling of src (sw x sh) to dst (dw x dh, stride dw), pixel
 * centres mapped as xs = (xd + 0.5) * sw / dw - 0.5, 8-bit weights. xofs and
 * xw hold dw entries of scratch, row sw entries. Requires sw, sh >= 2. */
void sfmi_feat_resize(const uint8_t *src, int sw, int sh, int sstride,
                     uint8_t *dst, int dw, int dh, int32_t *xofs, uint16_t *xw, uint16_t *row);

/* Separable 5-tap Gaussian (sigma 1.5, integer weights summing to 256),
 * borders replicated, vertical pass first (rounded to 8 bits), then
 * horizontal. dst has stride w; tmp holds w bytes. */
void sfmi_feat_smooth(const uint8_t *src, int w, int h, int sstride, uint8_t *dst, uint8_t *tmp);

#endif
