/*
 * Correlation stereo with multiple supporting windows: Hirschmüller,
 * Innocent, Garibaldi, "Real-time correlation-based stereo vision with
 * reduced border errors", IJCV 47 (2002). The cost of a disparity is the SAD
 * of the (2r+1)^2 window around the pixel plus the two smallest SADs of the
 * four windows touching its corners (centres shifted by 2r diagonally), so
 * that near a depth edge the support comes from the side of the pixel's own
 * surface; then winner-take-all with a uniqueness margin, the left-right
 * check and a sub-pixel parabola (stereo_select.h).
 *
 * Absolute differences are truncated at 63 so that the sums of three
 * windows of up to 11x11 fit 16-bit lanes. Rows stream through: column sums
 * are updated incrementally and a ring of 4r+1 rows of window sums feeds the
 * corner windows, so memory grows with the width only.
 */
#include <string.h>

#include "core/arena.h"
#include "sfm/sfm_stereo.h"
#include "stereo/stereo_internal.h"
#include "stereo/stereo_select.h"

#define AD_MAX 63
#define FAR_VALUE (-1000) /* right-image padding: its difference saturates */

typedef struct bm {
    int w, h, D, dmin, r, ring;
    int16_t *rrev;     /* one right row reversed, padded by D + |dmin| + w */
    int rrev_len;
    int16_t *col;      /* column sums, w x D */
    int16_t *ad;       /* one row of absolute differences, w x D */
    int16_t *win;      /* ring of `ring` rows of window sums, w x D each */
    int16_t *cost;     /* combined cost row, w x D */
    uint8_t *flat;     /* ring of `ring` rows of flags: texture too weak */
    int32_t *gcol;     /* column sums of |dI/dx| over the window, w */
    sfmi_stereo_scratch sel;
} bm;

void sfm_stereo_block_default_options(sfm_stereo_block_options *opt)
{
    if (!opt)
        return;
    opt->min_disparity = 0;
    opt->num_disparities = 64;
    opt->radius = 2;
    opt->uniqueness = 15;
    opt->lr_max_diff = 1;
    opt->texture = 8;
    opt->subpixel = 1;
}

static int options_ok(int width, int height, const sfm_stereo_block_options *o)
{
    if (!o || !sfmi_stereo_range_ok(width, height, o->min_disparity, o->num_disparities))
        return 0;
    if (o->radius < 1 || o->radius > 5 || 4 * o->radius + 1 > height)
        return 0;
    if (o->uniqueness < 0 || o->uniqueness > 100 || o->lr_max_diff > 1000 || o->texture < 0 ||
        o->texture > 255 * 16 || (o->subpixel != 0 && o->subpixel != 1))
        return 0;
    return 1;
}

static void layout(sfmi_arena *a, bm *b, int w, int h, const sfm_stereo_block_options *o)
{
    int D = o->num_disparities;
    b->w = w;
    b->h = h;
    b->D = D;
    b->r = o->radius;
    b->ring = 4 * o->radius + 1;
    b->rrev_len = w + 2 * (D + 8 + (o->min_disparity > 0 ? o->min_disparity : -o->min_disparity));
    b->rrev = SFM_ARENA_ARRAY(a, int16_t, b->rrev_len);
    b->col = SFM_ARENA_ARRAY(a, int16_t, (size_t)w * D);
    b->ad = SFM_ARENA_ARRAY(a, int16_t, (size_t)w * D);
    b->win = SFM_ARENA_ARRAY(a, int16_t, (size_t)b->ring * w * D);
    b->cost = SFM_ARENA_ARRAY(a, int16_t, (size_t)w * D);
    b->flat = SFM_ARENA_ARRAY(a, uint8_t, (size_t)b->ring * w);
    b->gcol = SFM_ARENA_ARRAY(a, int32_t, w);
    sfmi_stereo_scratch_layout(a, &b->sel, w, D, o->min_disparity);
}

size_t sfm_stereo_block_workspace_size(int width, int height, const sfm_stereo_block_options *opt)
{
    if (!options_ok(width, height, opt))
        return 0;
    sfmi_arena a;
    bm b;
    sfmi_arena_measure(&a);
    layout(&a, &b, width, height, opt);
    return a.failed ? 0 : sfmi_arena_required(&a);
}

static int clampi(int v, int lo, int hi)
{
    return v < lo ? lo : (v > hi ? hi : v);
}

static inline sfmi_v16 vabs(sfmi_v16 v)
{
    return -sfmi_v16_min(v, -v);
}

/* Absolute differences of row y (clamped into the image) for every x and
 * disparity index, truncated at AD_MAX. */
static void ad_row(bm *b, const uint8_t *left, const uint8_t *right, int stride, int y)
{
    const int w = b->w, D = b->D, dmin = b->dmin;
    y = clampi(y, 0, b->h - 1);
    const uint8_t *L = left + (size_t)y * stride, *R = right + (size_t)y * stride;
    /* rrev[off + k] = R[w - 1 - k] inside the row, FAR_VALUE outside: the
     * right pixel of x at index d, R[x - dmin - d], is
     * rrev[off + w - 1 - x + dmin + d], contiguous in d. */
    const int off = (b->rrev_len - w) / 2;
    for (int k = 0; k < b->rrev_len; k++) {
        int src = w - 1 - (k - off);
        b->rrev[k] = (int16_t)(src >= 0 && src < w ? R[src] : FAR_VALUE);
    }
    const sfmi_v16 cap = sfmi_v16_splat(AD_MAX);
    for (int x = 0; x < w; x++) {
        sfmi_v16 l = sfmi_v16_splat(L[x]);
        const int16_t *r = b->rrev + off + w - 1 - x + dmin;
        int16_t *o = b->ad + (size_t)x * D;
        for (int d = 0; d < D; d += 8)
            sfmi_v16_store(o + d, sfmi_v16_min(vabs(l - sfmi_v16_load(r + d)), cap));
    }
}

static void add_rows(int16_t *dst, const int16_t *src, size_t n, int sign)
{
    for (size_t i = 0; i < n; i += 8) {
        sfmi_v16 v = sfmi_v16_load(src + i);
        sfmi_v16_store(dst + i, sign > 0 ? sfmi_v16_load(dst + i) + v : sfmi_v16_load(dst + i) - v);
    }
}

static int grad_at(const uint8_t *row, int x, int w)
{
    int a = row[clampi(x + 1, 0, w - 1)], c = row[clampi(x - 1, 0, w - 1)];
    return a > c ? a - c : c - a;
}

static void grad_col(bm *b, const uint8_t *left, int stride, int y, int sign)
{
    const uint8_t *row = left + (size_t)clampi(y, 0, b->h - 1) * stride;
    for (int x = 0; x < b->w; x++)
        b->gcol[x] += sign * grad_at(row, x, b->w);
}

/* Window sums of row yy (from the column sums) into ring slot yy % ring,
 * with the texture flags of that row. */
static void window_row(bm *b, int yy, int texture)
{
    const int w = b->w, D = b->D, r = b->r;
    int16_t *out = b->win + (size_t)(yy % b->ring) * w * D;
    uint8_t *flat = b->flat + (size_t)(yy % b->ring) * w;
    int16_t *acc = b->cost; /* scratch: the running horizontal sum */
    memset(acc, 0, sizeof(int16_t) * (size_t)D);
    int32_t g = 0;
    for (int x = -r; x <= r; x++) {
        add_rows(acc, b->col + (size_t)clampi(x, 0, w - 1) * D, (size_t)D, 1);
        g += b->gcol[clampi(x, 0, w - 1)];
    }
    const int32_t area = (2 * r + 1) * (2 * r + 1);
    for (int x = 0; x < w; x++) {
        memcpy(out + (size_t)x * D, acc, sizeof(int16_t) * (size_t)D);
        flat[x] = (uint8_t)(texture > 0 && g * 16 < (int32_t)texture * area * 2);
        add_rows(acc, b->col + (size_t)clampi(x + r + 1, 0, w - 1) * D, (size_t)D, 1);
        add_rows(acc, b->col + (size_t)clampi(x - r, 0, w - 1) * D, (size_t)D, -1);
        g += b->gcol[clampi(x + r + 1, 0, w - 1)] - b->gcol[clampi(x - r, 0, w - 1)];
    }
}

/* Combined cost of output row y: centre window plus the two smallest of
 * the four corner windows. */
static void combine_row(bm *b, int y)
{
    const int w = b->w, D = b->D, r2 = 2 * b->r, h = b->h;
    const int16_t *wc = b->win + (size_t)(y % b->ring) * w * D;
    const int16_t *wu = b->win + (size_t)(clampi(y - r2, 0, h - 1) % b->ring) * w * D;
    const int16_t *wd = b->win + (size_t)(clampi(y + r2, 0, h - 1) % b->ring) * w * D;
    for (int x = 0; x < w; x++) {
        size_t xl = (size_t)clampi(x - r2, 0, w - 1) * D, xr = (size_t)clampi(x + r2, 0, w - 1) * D;
        int16_t *o = b->cost + (size_t)x * D;
        const int16_t *c = wc + (size_t)x * D;
        for (int d = 0; d < D; d += 8) {
            sfmi_v16 a = sfmi_v16_load(wu + xl + d), bb = sfmi_v16_load(wu + xr + d);
            sfmi_v16 cc = sfmi_v16_load(wd + xl + d), dd = sfmi_v16_load(wd + xr + d);
            sfmi_v16 m1 = sfmi_v16_min(a, bb), M1 = a + bb - m1;
            sfmi_v16 m2 = sfmi_v16_min(cc, dd), M2 = cc + dd - m2;
            sfmi_v16 lo = sfmi_v16_min(m1, m2), hi = m1 + m2 - lo;
            sfmi_v16 second = sfmi_v16_min(hi, sfmi_v16_min(M1, M2));
            sfmi_v16_store(o + d, sfmi_v16_load(c + d) + lo + second);
        }
    }
}

int sfm_stereo_block(const uint8_t *left, const uint8_t *right, int width, int height, int stride,
                     const sfm_stereo_block_options *opt, float *disp, void *ws, size_t ws_size)
{
    if (!left || !right || !disp || !opt || stride < width)
        return SFM_E_ARGUMENT;
    if (!options_ok(width, height, opt))
        return SFM_E_ARGUMENT;
    if (!ws)
        return SFM_E_WORKSPACE;
    sfmi_arena a;
    bm b;
    sfmi_arena_init(&a, ws, ws_size);
    layout(&a, &b, width, height, opt);
    if (!sfmi_arena_ok(&a))
        return SFM_E_WORKSPACE;
    b.dmin = opt->min_disparity;
    const int r = b.r, r2 = 2 * r, D = b.D;
    const size_t row = (size_t)width * D;
    sfmi_stereo_select_params sp = {opt->min_disparity, D, opt->uniqueness, opt->lr_max_diff,
                                    opt->subpixel, 0};
    memset(b.col, 0, sizeof(int16_t) * row);
    memset(b.gcol, 0, sizeof(int32_t) * (size_t)width);
    for (int y = -r; y <= r; y++) {
        ad_row(&b, left, right, stride, y);
        add_rows(b.col, b.ad, row, 1);
        grad_col(&b, left, stride, y, 1);
    }
    int valid = 0, next_out = 0;
    for (int yy = 0; yy < height; yy++) {
        if (yy > 0) {
            ad_row(&b, left, right, stride, yy + r);
            add_rows(b.col, b.ad, row, 1);
            ad_row(&b, left, right, stride, yy - r - 1);
            add_rows(b.col, b.ad, row, -1);
            grad_col(&b, left, stride, yy + r, 1);
            grad_col(&b, left, stride, yy - r - 1, -1);
        }
        window_row(&b, yy, opt->texture);
        int last = yy == height - 1 ? height - 1 : yy - r2;
        for (; next_out <= last; next_out++) {
            combine_row(&b, next_out);
            valid += sfmi_stereo_select_row(&b.sel, &sp, width, b.cost,
                                            b.flat + (size_t)(next_out % b.ring) * width,
                                            disp + (size_t)next_out * width);
        }
    }
    return valid;
}
