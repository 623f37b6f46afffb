/* Internal: the census transform the semi-global matcher compares. */
#ifndef SFM_STEREO_CENSUS_H
#define SFM_STEREO_CENSUS_H

#include <stddef.h>
#include <stdint.h>

/* 31-bit centre-symmetric census of every pixel (w x h, row-major), bits
 * 0-15 of the pattern in lo, 16-30 in hi. */
void sfmi_stereo_census(const uint8_t *img, int w, int h, int stride, uint16_t *lo,
                        uint16_t *hi);

#endif
