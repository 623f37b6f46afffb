/*
 * Winner-take-all disparity selection with the three usual filters: a
 * uniqueness margin against every cost more than one disparity from the
 * best, the left-right consistency check (the right image's own winner
 * along the same costs, as in Hirschmüller, Innocent, Garibaldi 2002), and
 * sub-pixel interpolation by a parabola through the best cost and its
 * neighbours. Ties go to the smallest disparity index, in the vector and
 * the scalar paths alike. Near the image border, where part of the range
 * has no match in the other image, the winner must lie a quarter of the
 * range inside what is left.
 *
 * The right image's winners are kept reversed (slot off + w - 1 - xr), so
 * that the right pixels of consecutive disparities of one left pixel are
 * consecutive slots.
 */
#include <math.h>

#include "stereo/stereo_internal.h"
#include "stereo/stereo_select.h"

#define NONE 0x7fff

static int span_of(int D, int dmin)
{
    return D + 8 + (dmin > 0 ? dmin : -dmin);
}

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

/* One pass over the costs of a row: the right image's winners (when
 * lr_max_diff >= 0) and, for pixels whose whole disparity range lies in the
 * image, the left winner and the smallest cost more than one disparity from
 * it. Each lane holds the disparities d = lane (mod 8): three consecutive
 * disparities fall in three different lanes, so a lane whose best is next to
 * the winner offers its second best instead, and that one is at least eight
 * away. */
static void scan_row(const sfmi_stereo_scratch *s, const sfmi_stereo_select_params *p, int w,
                     const int16_t *cost, int16_t *best_d, int16_t *best_c, int16_t *second)
{
    const int D = p->D, dmin = p->dmin, off = span_of(D, dmin), lr = p->lr_max_diff >= 0;
    if (lr)
        for (int k = 0; k < s->len; k++) {
            s->best_r_cost[k] = NONE;
            s->best_r_d[k] = -1;
        }
    for (int x = 0; x < w; x++) {
        const int16_t *c = cost + (size_t)x * D;
        int xr0 = x - dmin;
        int16_t *rc = s->best_r_cost + off + w - 1 - xr0, *rd = s->best_r_d + off + w - 1 - xr0;
        if (xr0 - (D - 1) >= 0 && xr0 <= w - 1) {
            sfmi_v16 m1 = sfmi_v16_splat(NONE), m2 = m1, i1 = sfmi_v16_splat(0);
            for (int d = 0; d < D; d += 8) {
                sfmi_v16 v = sfmi_v16_load(c + d);
                sfmi_v16 idx = lane_index + sfmi_v16_splat(d);
                sfmi_v16 lt = v < m1;
                m2 = pick(lt, m1, sfmi_v16_min(m2, v));
                m1 = sfmi_v16_min(m1, v);
                i1 = pick(lt, idx, i1);
                if (lr) {
                    sfmi_v16 cur = sfmi_v16_load(rc + d);
                    sfmi_v16 m = v < cur;
                    sfmi_v16_store(rc + d, sfmi_v16_min(v, cur));
                    sfmi_v16_store(rd + d, pick(m, idx, sfmi_v16_load(rd + d)));
                }
            }
            /* Lane reduction in vector form: the smallest cost, the
             * smallest index holding it, then the second candidates. */
            int bc = sfmi_v16_hmin(m1);
            sfmi_v16 at = m1 == sfmi_v16_splat(bc);
            int bd = sfmi_v16_hmin(pick(at, i1, sfmi_v16_splat(NONE)));
            sfmi_v16 near = (i1 >= sfmi_v16_splat(bd - 1)) & (i1 <= sfmi_v16_splat(bd + 1));
            int sec = sfmi_v16_hmin(pick(near, m2, m1));
            best_d[x] = (int16_t)bd;
            best_c[x] = (int16_t)bc;
            second[x] = (int16_t)sec;
        } else {
            best_d[x] = -1; /* partial range: the scalar path decides */
            if (lr)
                for (int d = 0; d < D; d++) {
                    int xr = xr0 - d;
                    if (xr >= 0 && xr <= w - 1 && c[d] < rc[d]) {
                        rc[d] = c[d];
                        rd[d] = (int16_t)d;
                    }
                }
        }
    }
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
    if (lr)
        for (int k = 0; k < s->len; k++)
            s->best_r_cost[k] = NONE;
    for (int x = 0; x < w; x++) {
        const int16_t *c = cost + (size_t)x * D;
        int xr0 = x - dmin;
        int16_t *rk = s->best_r_cost + off + w - 1 - xr0;
        if (xr0 - (D - 1) >= 0 && xr0 <= w - 1) {
            sfmi_v16 m1 = none, m2 = none, idx = lane_index;
            const sfmi_v16 eight = sfmi_v16_splat(8);
            for (int d = 0; d < D; d += 8) {
                sfmi_v16 key = (sfmi_v16)((sfmi_u16)sfmi_v16_load(c + d) << kb) | idx;
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
        } else {
            s->best_d[x] = -1;
            if (lr)
                for (int d = 0; d < D; d++) {
                    int xr = xr0 - d, key = c[d] << kb | d;
                    if (xr >= 0 && xr <= w - 1 && key < rk[d])
                        rk[d] = (int16_t)key;
                }
        }
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

int sfmi_stereo_select_row(const sfmi_stereo_scratch *s, const sfmi_stereo_select_params *p,
                           int w, const int16_t *cost, const uint8_t *invalid, float *out)
{
    const int D = p->D, dmin = p->dmin, off = span_of(D, dmin);
    const int kb = key_bits(p);
    if (kb >= 0)
        scan_row_keyed(s, p, w, cost, kb);
    else
        scan_row(s, p, w, cost, s->best_d, s->best_c, s->second);
    int valid = 0;
    for (int x = 0; x < w; x++) {
        const int16_t *c = cost + (size_t)x * D;
        int xr0 = x - dmin;
        int dlo = xr0 - (w - 1) > 0 ? xr0 - (w - 1) : 0;
        int dhi = xr0 < D - 1 ? xr0 : D - 1;
        out[x] = NAN;
        if ((invalid && invalid[x]) || dlo > dhi)
            continue;
        int bd, bc, second = NONE;
        if (s->best_d[x] >= 0) {
            bd = s->best_d[x];
            bc = s->best_c[x];
            second = s->second[x];
        } else {
            bd = dlo;
            bc = c[dlo];
            for (int d = dlo + 1; d <= dhi; d++)
                if (c[d] < bc) {
                    bc = c[d];
                    bd = d;
                }
            for (int d = dlo; d <= dhi; d++)
                if ((d < bd - 1 || d > bd + 1) && c[d] < second)
                    second = c[d];
        }
        /* A range cut by the image border: the true disparity may lie
         * beyond the cut, where no cost exists, and the winner inside it is
         * then a wrong match. Kept only with a quarter of the range to spare. */
        if ((dlo > 0 && bd - dlo < D / 4) || (dhi < D - 1 && dhi - bd < D / 4))
            continue;
        if (p->uniqueness > 0 && second != NONE &&
            (long)second * 100 <= (long)bc * (100 + p->uniqueness))
            continue;
        if (p->lr_max_diff >= 0) {
            int rd;
            if (kb >= 0) {
                int k = s->best_r_cost[off + w - 1 - (xr0 - bd)];
                rd = k == NONE ? -1 : k & ((1 << kb) - 1);
            } else {
                rd = s->best_r_d[off + w - 1 - (xr0 - bd)];
            }
            if (rd < 0 || (rd > bd ? rd - bd : bd - rd) > p->lr_max_diff)
                continue;
        }
        float dv = (float)(dmin + bd);
        if (p->subpixel && bd > dlo && bd < dhi) {
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
