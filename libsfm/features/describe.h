/* Internal: intensity-centroid orientation and steered BRIEF descriptor. */
#ifndef SFM_FEATURES_DESCRIBE_H
#define SFM_FEATURES_DESCRIBE_H

#include <stdint.h>

/* The disc of radius 15 as 31 rows (v = -15..15) of 32 bytes (u = -16..15),
 * 0xFF inside, 0 outside: fills mask[SFM_FEAT_DISC_MASK_LEN]. */
#define SFM_FEAT_DISC_MASK_LEN (31 * 32)
void sfmi_feat_disc_mask(uint8_t *mask);

/* Orientation of the patch around integer (x, y) as a unit vector (c, s):
 * the direction from the centre to the intensity centroid of the disc of
 * radius 15 (mask from sfmi_feat_disc_mask). A flat patch gives (1, 0).
 * Needs 16 pixels left of x and 15 around otherwise. */
void sfmi_feat_orientation(const uint8_t *img, int stride, int x, int y, const uint8_t *mask, double *c, double *s);

/* Orientations are quantised to this many bins (5.6 degrees) so that the
 * steered pattern comes from a table built per pyramid level (a bin at its
 * first use). */
#define SFM_FEAT_ANGLE_BINS 64
#define SFM_FEAT_STEER_TABLE_LEN (SFM_FEAT_ANGLE_BINS * 512)

/* Fills table[SFM_FEAT_STEER_TABLE_LEN]: for bin b, the 256 + 256 pixel
 * offsets (for this stride) of the pattern rotated by 2 pi b / BINS. */
void sfmi_feat_steer_table(int stride, int32_t *table);
/* One bin of that table (the same entries sfmi_feat_steer_table writes). */
void sfmi_feat_steer_bin(int stride, int bin, int32_t *table);

/* Nearest bin of the direction (c, s). */
int sfmi_feat_angle_bin(double c, double s);

/* 256-bit descriptor at integer (x, y) from one bin of the steering table:
 * bit i (byte i/8, bit i%8) is 1 when I(R p_i) < I(R q_i). Needs 15 pixels
 * around (x, y). */
void sfmi_feat_describe(const uint8_t *img, int stride, int x, int y, const int32_t *offsets, uint8_t *out);

#endif
