/*
 * Winner-take-all disparity selection with the three usual filters: a
 * uniqueness margin against every cost more than one disparity from the
 * best, the left-right consistency check (the right image's own winner
 * along the same costs, as in Hirschmüller, Innocent, Garibaldi 2002), and
 * sub-pixel interpolation by a parabola through the best cost and its
 * neighbours. Ties go to the smallest disparity index. Near the image
 * border, where part of the range has no match in the other image, the
 * disparities without a match are masked out of the scan and the winner
 * must lie a quarter of the range inside what is left.
 *
 * The right image's winners are kept reversed (slot off + w - 1 - xr), so
 * that the right pixels of consecutive disparities of one left pixel are
 * consecutive slots.
 */
#include <math.h>

#include "stereo/stereo_internal.h"
#include "stereo/stereo_select.h"

#define NONE SFMI_STEREO_NONE
#define span_of sfmi_stereo_span
#define valid_range sfmi_stereo_valid_range

void sfmi_stereo_scratch_layout(sfmi_arena *a, sfmi_stereo_scratch *s, int w, int D, int dmin)
{
    s->len = w + 2 * span_of(D, dmin);
    s->best_r_cost = SFM_ARENA_ARRAY(a, int16_t, s->len);
    s->best_r_d = SFM_ARENA_ARRAY(a, int16_t, s->len);
    s->best_d = SFM_ARENA_ARRAY(a, int16_t, w);
    s->best_c = SFM_ARENA_ARRAY(a, int16_t, w);
    s->second = SFM_ARENA_ARRAY(a, int16_t, w);
}

static const sfmi_v16 lane_index = {0, 1, 2, 3, 4, 5, 6, 7};

static inline sfmi_v16 pick(sfmi_v16 m, sfmi_v16 a, sfmi_v16 b)
{
    return (a & m) | (b & ~m);
}

void sfmi_stereo_scan_begin(const sfmi_stereo_scratch *s, const sfmi_stereo_select_params *p)
{
    if (p->lr_max_diff >= 0)
        for (int k = 0; k < s->len; k++) {
            s->best_r_cost[k] = NONE;
            s->best_r_d[k] = -1;
        }
}

/* The match range [*dlo, *dhi] of left pixel x; 0, with x marked as
 * having no winner, when no disparity of x has a match. */
static inline __attribute__((always_inline)) int pixel_range(const sfmi_stereo_scratch *s, int w,
                                                              int D, int dmin, int x, int *dlo,
                                                              int *dhi)
{
    valid_range(x, w, D, dmin, dlo, dhi);
    if (*dlo > *dhi) {
        s->best_d[x] = -1;
        return 0;
    }
    return 1;
}

/* The right-winner slot of left pixel x at disparity index 0 in the array
 * r (that of index d is d further on). */
static inline int16_t *right_slot(int16_t *r, int off, int w, int x, int dmin)
{
    return r + off + w - 1 - (x - dmin);
}

/* One left pixel of scan_row; partial and lr are constants where it is
 * inlined, so that each of the four loops is free of their tests. */
static inline __attribute__((always_inline)) void scan_pixel(const int16_t *c, int D, int dlo,
                                                             int dhi, int16_t *rc, int16_t *rd,
                                                             const int partial, const int lr,
                                                             int16_t *best_d, int16_t *best_c,
                                                             int16_t *second)
{
    const sfmi_v16 vlo = sfmi_v16_splat(dlo), vhi = sfmi_v16_splat(dhi);
    sfmi_stereo_lanes a;
    sfmi_stereo_lanes_init(&a);
    for (int d = 0; d < D; d += 8) {
        sfmi_v16 v = sfmi_v16_load(c + d);
        if (partial)
            v |= sfmi_stereo_outside(a.idx, vlo, vhi);
        sfmi_stereo_lanes_step(&a, v, rc + d, rd + d, lr);
    }
    sfmi_stereo_lanes_finish(&a, best_d, best_c, second);
}

/* One pass over the costs of a row: the right image's winners (when
 * lr_max_diff >= 0) and, for every left pixel with a match, the left
 * winner and the smallest cost more than one disparity from it (the
 * indices without a match masked out); see sfmi_stereo_lanes. */
static void scan_row(const sfmi_stereo_scratch *s, const sfmi_stereo_select_params *p, int w,
                     const int16_t *cost)
{
    const int D = p->D, dmin = p->dmin, off = span_of(D, dmin), lr = p->lr_max_diff >= 0;
    sfmi_stereo_scan_begin(s, p);
    for (int x = 0; x < w; x++) {
        const int16_t *c = cost + (size_t)x * D;
        int dlo, dhi;
        if (!pixel_range(s, w, D, dmin, x, &dlo, &dhi))
            continue;
        int16_t *rc = right_slot(s->best_r_cost, off, w, x, dmin);
        int16_t *rd = right_slot(s->best_r_d, off, w, x, dmin);
        int16_t *bd = s->best_d + x, *bc = s->best_c + x, *sc = s->second + x;
        if (dlo > 0 || dhi < D - 1) {
            if (lr)
                scan_pixel(c, D, dlo, dhi, rc, rd, 1, 1, bd, bc, sc);
            else
                scan_pixel(c, D, dlo, dhi, rc, rd, 1, 0, bd, bc, sc);
        } else if (lr) {
            scan_pixel(c, D, dlo, dhi, rc, rd, 0, 1, bd, bc, sc);
        } else {
            scan_pixel(c, D, dlo, dhi, rc, rd, 0, 0, bd, bc, sc);
        }
    }
}

void sfmi_stereo_scan_pixel(const sfmi_stereo_scratch *s, const sfmi_stereo_select_params *p,
                            int w, int x, const int16_t *c)
{
    const int D = p->D, dmin = p->dmin, off = span_of(D, dmin);
    int dlo, dhi;
    if (!pixel_range(s, w, D, dmin, x, &dlo, &dhi))
        return;
    int16_t *rc = right_slot(s->best_r_cost, off, w, x, dmin);
    int16_t *rd = right_slot(s->best_r_d, off, w, x, dmin);
    scan_pixel(c, D, dlo, dhi, rc, rd, dlo > 0 || dhi < D - 1, p->lr_max_diff >= 0,
               s->best_d + x, s->best_c + x, s->second + x);
}

/* scan_row with each cost and its index packed into one lane, key =
 * cost << kb | d, when the largest key stays below NONE: one min then
 * finds the smallest cost and, among equal costs, the smallest index (the
 * ties rule above), and the two smallest keys per lane come from a min and
 * a max. The right image's winners are kept as keys in best_r_cost. Every
 * output equals scan_row's. */
static void scan_row_keyed(const sfmi_stereo_scratch *s, const sfmi_stereo_select_params *p,
                           int w, const int16_t *cost, int kb)
{
    const int D = p->D, dmin = p->dmin, off = span_of(D, dmin), lr = p->lr_max_diff >= 0;
    const int mask = (1 << kb) - 1;
    const sfmi_v16 vmask = sfmi_v16_splat(mask), none = sfmi_v16_splat(NONE);
    const sfmi_v16 eight = sfmi_v16_splat(8);
    if (lr)
        for (int k = 0; k < s->len; k++)
            s->best_r_cost[k] = NONE;
    for (int x = 0; x < w; x++) {
        const int16_t *c = cost + (size_t)x * D;
        int dlo, dhi;
        if (!pixel_range(s, w, D, dmin, x, &dlo, &dhi))
            continue;
        int16_t *rk = right_slot(s->best_r_cost, off, w, x, dmin);
        const int partial = dlo > 0 || dhi < D - 1;
        const sfmi_v16 vlo = sfmi_v16_splat(dlo), vhi = sfmi_v16_splat(dhi);
        sfmi_v16 m1 = none, m2 = none, idx = lane_index;
        for (int d = 0; d < D; d += 8) {
            sfmi_v16 key = (sfmi_v16)((sfmi_u16)sfmi_v16_load(c + d) << kb) | idx;
            if (partial)
                key |= sfmi_stereo_outside(idx, vlo, vhi);
            idx += eight;
            m2 = sfmi_v16_min(m2, sfmi_v16_max(m1, key));
            m1 = sfmi_v16_min(m1, key);
            if (lr)
                sfmi_v16_store(rk + d, sfmi_v16_min(key, sfmi_v16_load(rk + d)));
        }
        int bk = sfmi_v16_hmin(m1), bd = bk & mask;
        sfmi_v16 i1 = m1 & vmask;
        sfmi_v16 near = (i1 >= sfmi_v16_splat(bd - 1)) & (i1 <= sfmi_v16_splat(bd + 1));
        int sk = sfmi_v16_hmin(pick(near, m2, m1));
        s->best_d[x] = (int16_t)bd;
        s->best_c[x] = (int16_t)(bk >> kb);
        s->second[x] = (int16_t)(sk == NONE ? NONE : sk >> kb);
    }
}

/* Bits of a disparity index: the keyed scan applies when every key
 * (cost_max << kb | D - 1) stays below NONE. */
static int key_bits(const sfmi_stereo_select_params *p)
{
    int kb = 0;
    while ((1 << kb) < p->D)
        kb++;
    return p->cost_max > 0 && ((long)(p->cost_max + 1) << kb) <= NONE ? kb : -1;
}

/* Winner, filters and sub-pixel offset of the left pixels [x0, x1), after
 * the scan; border: whether their range may be cut by the image border
 * (a constant where inlined). Returns the number of valid pixels. */
static inline __attribute__((always_inline)) int decide(const sfmi_stereo_scratch *s,
                                                        const sfmi_stereo_select_params *p, int w,
                                                        int kb, const int16_t *cost,
                                                        const uint8_t *invalid, float *out, int x0,
                                                        int x1, const int border)
{
    const int D = p->D, dmin = p->dmin, off = span_of(D, dmin);
    /* The right image's winner for the match of x at index bd sits at
     * rw[bd - x]: slot off + w - 1 - (x - dmin - bd). */
    const int16_t *rw = (kb >= 0 ? s->best_r_cost : s->best_r_d) + off + w - 1 + dmin;
    const int16_t *best_d = s->best_d, *best_c = s->best_c, *second_c = s->second;
    const int uniq = p->uniqueness, lr = p->lr_max_diff, subpixel = p->subpixel;
    const int quarter = D / 4, kmask = kb >= 0 ? (1 << kb) - 1 : 0;
    int valid = 0;
    for (int x = x0; x < x1; x++) {
        out[x] = NAN;
        const int bd = best_d[x];
        if (bd < 0 || (invalid && invalid[x]))
            continue;
        int dlo = 0, dhi = D - 1;
        if (border) {
            valid_range(x, w, D, dmin, &dlo, &dhi);
            /* A range cut by the image border: the true disparity may lie
             * beyond the cut, where no cost exists, and the winner inside
             * it is then a wrong match. Kept only with a quarter of the
             * range to spare. */
            if ((dlo > 0 && bd - dlo < quarter) || (dhi < D - 1 && dhi - bd < quarter))
                continue;
        }
        const int bc = best_c[x], second = second_c[x];
        if (uniq > 0 && second != NONE && (int32_t)second * 100 <= (int32_t)bc * (100 + uniq))
            continue;
        if (lr >= 0) {
            int rd = rw[bd - x];
            if (kb >= 0)
                rd = rd == NONE ? -1 : rd & kmask;
            if (rd < 0 || (rd > bd ? rd - bd : bd - rd) > lr)
                continue;
        }
        float dv = (float)(dmin + bd);
        if (subpixel && bd > dlo && bd < dhi) {
            const int16_t *c = cost + (size_t)x * D;
            int c0 = c[bd - 1], c2 = c[bd + 1];
            int den = c0 + c2 - 2 * bc;
            if (den > 0)
                dv += (float)(c0 - c2) / (float)(2 * den);
        }
        out[x] = dv;
        valid++;
    }
    return valid;
}

/* Pixels [x0, x1) split by whether their range has a match everywhere. */
static int decide_row(const sfmi_stereo_scratch *s, const sfmi_stereo_select_params *p, int w,
                      int kb, const int16_t *cost, const uint8_t *invalid, float *out)
{
    const int D = p->D, dmin = p->dmin;
    /* x in [x0, x1): the whole range has a match */
    int x0 = dmin + D - 1, x1 = dmin + w;
    x0 = x0 < 0 ? 0 : (x0 > w ? w : x0);
    x1 = x1 < x0 ? x0 : (x1 > w ? w : x1);
    return decide(s, p, w, kb, cost, invalid, out, 0, x0, 1) +
           decide(s, p, w, kb, cost, invalid, out, x0, x1, 0) +
           decide(s, p, w, kb, cost, invalid, out, x1, w, 1);
}

int sfmi_stereo_decide_row(const sfmi_stereo_scratch *s, const sfmi_stereo_select_params *p,
                           int w, const int16_t *cost, const uint8_t *invalid, float *out)
{
    return decide_row(s, p, w, -1, cost, invalid, out);
}

int sfmi_stereo_select_row(const sfmi_stereo_scratch *s, const sfmi_stereo_select_params *p,
                           int w, const int16_t *cost, const uint8_t *invalid, float *out)
{
    const int kb = key_bits(p);
    if (kb >= 0)
        scan_row_keyed(s, p, w, cost, kb);
    else
        scan_row(s, p, w, cost);
    return decide_row(s, p, w, kb, cost, invalid, out);
}
