/* Internal: winner-take-all disparity selection shared by the matchers. */
#ifndef SFM_STEREO_SELECT_H
#define SFM_STEREO_SELECT_H

#include <stdint.h>

#include "core/arena.h"

typedef struct sfmi_stereo_select_params {
    int dmin, D;       /* disparity of index 0, number of disparities */
    int uniqueness;    /* percent, 0 off */
    int lr_max_diff;   /* < 0 off */
    int subpixel;
    int cost_max;      /* largest cost the matcher can produce; 0 unknown */
} sfmi_stereo_select_params;

typedef struct sfmi_stereo_scratch {
    int16_t *best_r_cost, *best_r_d; /* per right-image column, reversed */
    int len;
    int16_t *best_d, *best_c, *second; /* per left pixel of the row */
} sfmi_stereo_scratch;

void sfmi_stereo_scratch_layout(sfmi_arena *a, sfmi_stereo_scratch *s, int w, int D, int dmin);

/* Disparities of one row from its costs (w x D, index d = disparity
 * dmin + d); pixels with invalid[x] set (may be NULL) are NaN. Returns the
 * number of valid pixels written to out. */
int sfmi_stereo_select_row(const sfmi_stereo_scratch *s, const sfmi_stereo_select_params *p,
                           int w, const int16_t *cost, const uint8_t *invalid, float *out);

#endif
