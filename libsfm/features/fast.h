/* Internal: FAST-9 segment test and score. */
#ifndef SFM_FEATURES_FAST_H
#define SFM_FEATURES_FAST_H

#include <stdint.h>

/* Scores of row y for columns [x0, x1): score[x] = 0 when the pixel is not a
 * FAST-9 corner for threshold t, else the largest threshold for which it
 * still is one (>= t, clamped to 255). Needs 3 pixels of image on each side
 * of the scanned columns and of row y. Entries outside [x0, x1) are not
 * written. */
void sfmi_feat_fast_row(const uint8_t *img, int stride, int y, int x0, int x1, int t, uint8_t *score);

#endif
