/* Internal: the census transform the semi-global matcher compares. */
#ifndef SFM_STEREO_CENSUS_H
#define SFM_STEREO_CENSUS_H

#include <stddef.h>
#include <stdint.h>

/* 31-bit centre-symmetric census of every pixel of row y (w of them) of a
 * w x h image, bits 0-15 of the pattern in lo, 16-30 in hi. */
void sfmi_stereo_census_row(const uint8_t *img, int w, int h, int stride, int y, uint16_t *lo,
                            uint16_t *hi);

#endif
