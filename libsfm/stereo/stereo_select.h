/* Internal: winner-take-all disparity selection shared by the matchers. */
#ifndef SFM_STEREO_SELECT_H
#define SFM_STEREO_SELECT_H

#include <stdint.h>

#include "core/arena.h"
#include "stereo/stereo_internal.h"

#define SFMI_STEREO_NONE 0x7fff /* above every cost: no candidate */

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

/* The selection options both matchers take: uniqueness a percentage in
 * [0, 100], lr_max_diff at most 1000 (negative: no left-right check),
 * subpixel 0 or 1. */
static inline int sfmi_stereo_select_options_ok(int uniqueness, int lr_max_diff, int subpixel)
{
    return uniqueness >= 0 && uniqueness <= 100 && lr_max_diff <= 1000 &&
           (subpixel == 0 || subpixel == 1);
}

void sfmi_stereo_scratch_layout(sfmi_arena *a, sfmi_stereo_scratch *s, int w, int D, int dmin);

/* Disparities of one row from its costs (w x D, index d = disparity
 * dmin + d, every cost in [0, SFMI_STEREO_NONE)); pixels with invalid[x]
 * set (may be NULL) are NaN. Returns the number of valid pixels written to
 * out. */
int sfmi_stereo_select_row(const sfmi_stereo_scratch *s, const sfmi_stereo_select_params *p,
                           int w, const int16_t *cost, const uint8_t *invalid, float *out);

/* ---- The same in three steps, for a matcher that scans each pixel's
 * costs as it computes them: sfmi_stereo_scan_begin, then for x = 0 ..
 * w - 1 in this order the sfmi_stereo_lanes steps of pixel x (its costs
 * also stored in the cost row), then sfmi_stereo_decide_row. Equal to
 * sfmi_stereo_select_row on the same cost row. */

void sfmi_stereo_scan_begin(const sfmi_stereo_scratch *s, const sfmi_stereo_select_params *p);
/* The steps of pixel x from its costs c (D of them), any range. */
void sfmi_stereo_scan_pixel(const sfmi_stereo_scratch *s, const sfmi_stereo_select_params *p,
                            int w, int x, const int16_t *c);
int sfmi_stereo_decide_row(const sfmi_stereo_scratch *s, const sfmi_stereo_select_params *p,
                           int w, const int16_t *cost, const uint8_t *invalid, float *out);

/* Reversed slots of the right-image winners: the right pixel xr is slot
 * sfmi_stereo_span + w - 1 - xr, so that the right pixels of consecutive
 * disparities of one left pixel are consecutive slots. */
static inline int sfmi_stereo_span(int D, int dmin)
{
    return D + 8 + (dmin > 0 ? dmin : -dmin);
}

/* The disparity indices of left pixel x that have a match in the right
 * image: [*dlo, *dhi], empty when *dlo > *dhi. */
static inline void sfmi_stereo_valid_range(int x, int w, int D, int dmin, int *dlo, int *dhi)
{
    int xr0 = x - dmin;
    *dlo = xr0 - (w - 1) > 0 ? xr0 - (w - 1) : 0;
    *dhi = xr0 < D - 1 ? xr0 : D - 1;
}

/* SFMI_STEREO_NONE in the lanes of indices idx outside [lo, hi], 0
 * elsewhere: or-ed into a cost (or key) it turns the lanes without a match
 * into NONE, which neither wins nor updates a right-image winner. */
static inline sfmi_v16 sfmi_stereo_outside(sfmi_v16 idx, sfmi_v16 lo, sfmi_v16 hi)
{
    return ((idx < lo) | (idx > hi)) & sfmi_v16_splat(SFMI_STEREO_NONE);
}

/* The scan of one left pixel, eight disparities per step. Each lane holds
 * the disparities d = lane (mod 8): its smallest cost m1 at index i1 and
 * its second smallest m2. Indices grow along a lane, and along the
 * candidates of one right pixel (x grows with d), so the index of a
 * strictly smaller cost is also the largest so far: a max keeps the first
 * index of the smallest cost, the ties rule. */
typedef struct sfmi_stereo_lanes {
    sfmi_v16 m1, m2, i1, idx;
} sfmi_stereo_lanes;

static inline void sfmi_stereo_lanes_init(sfmi_stereo_lanes *a)
{
    const sfmi_v16 lane_index = {0, 1, 2, 3, 4, 5, 6, 7};
    a->m1 = a->m2 = sfmi_v16_splat(SFMI_STEREO_NONE);
    a->i1 = sfmi_v16_splat(0);
    a->idx = lane_index;
}

/* Costs v of the next eight indices; with lr, the right-image winners of
 * their right pixels (rc, rd: the pixel's slots, as in scan_row) too. */
static inline __attribute__((always_inline)) void
sfmi_stereo_lanes_step(sfmi_stereo_lanes *a, sfmi_v16 v, int16_t *rc, int16_t *rd, const int lr)
{
    a->i1 = sfmi_v16_max(a->i1, (v < a->m1) & a->idx);
    a->m2 = sfmi_v16_min(a->m2, sfmi_v16_max(a->m1, v));
    a->m1 = sfmi_v16_min(a->m1, v);
    if (lr) {
        sfmi_v16 cur = sfmi_v16_load(rc);
        sfmi_v16_store(rd, sfmi_v16_max(sfmi_v16_load(rd), (v < cur) & a->idx));
        sfmi_v16_store(rc, sfmi_v16_min(v, cur));
    }
    a->idx += sfmi_v16_splat(8);
}

/* Lane reduction: the smallest cost, the smallest index holding it, and
 * the smallest cost more than one index from it (three consecutive
 * indices fall in three different lanes, so a lane whose best is next to
 * the winner offers its second best instead, and that one is at least
 * eight away). */
static inline void sfmi_stereo_lanes_finish(const sfmi_stereo_lanes *a, int16_t *best_d,
                                            int16_t *best_c, int16_t *second)
{
    const sfmi_v16 none = sfmi_v16_splat(SFMI_STEREO_NONE);
    sfmi_v16 bc = sfmi_v16_hmin_all(a->m1);
    sfmi_v16 at = a->m1 == bc;
    sfmi_v16 bd = sfmi_v16_hmin_all((a->i1 & at) | (none & ~at));
    sfmi_v16 t = a->i1 - bd;
    sfmi_v16 near = (t >= sfmi_v16_splat(-1)) & (t <= sfmi_v16_splat(1));
    *best_d = bd[0];
    *best_c = bc[0];
    *second = (int16_t)sfmi_v16_hmin((a->m2 & near) | (a->m1 & ~near));
}

#endif
