/* Internal: intensity-centroid orientation and steered BRIEF descriptor. */
#ifndef SFM_FEATURES_DESCRIBE_H
#define SFM_FEATURES_DESCRIBE_H

#include <stdint.h>

/* Orientation of the patch around integer (x, y) as a unit vector (c, s):
 * the direction from the centre to the intensity centroid of the disc of
 * radius 15. A flat patch gives (1, 0). Needs 15 pixels around (x, y). */
void sfm_feat_orientation(const uint8_t *img, int stride, int x, int y, double *c, double *s);

/* 256-bit descriptor at integer (x, y) with the pattern rotated by (c, s):
 * bit i (byte i/8, bit i%8) is 1 when I(R p_i) < I(R q_i). Needs 15 pixels
 * around (x, y). */
void sfm_feat_describe(const uint8_t *img, int stride, int x, int y, double c, double s, uint8_t *out);

#endif
