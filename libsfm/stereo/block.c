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
 * corner windows, so memory grows with the width only. One pass over a row
 * does it all for each column and eight disparities at a time: the row
 * entering the column sums and the row leaving them, the running window
 * sum along the row, the combined cost of the pixel 2r rows up and 3r
 * columns back (whose lower right corner window is the one just summed),
 * and that pixel's selection scan (stereo_select.h); the combined costs
 * are kept for one row, for the sub-pixel fit.
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
    int16_t *rrev;     /* ring of 2r + 2 right rows reversed, rrev_len each */
    int rrev_len;
    int16_t *col;      /* column sums, w x D */
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
    if (o->texture < 0 || o->texture > 255 * 16)
        return 0;
    return sfmi_stereo_select_options_ok(o->uniqueness, o->lr_max_diff, o->subpixel);
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
    b->rrev = SFM_ARENA_ARRAY(a, int16_t, (size_t)(2 * o->radius + 2) * b->rrev_len);
    b->col = SFM_ARENA_ARRAY(a, int16_t, (size_t)w * D);
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

static const uint8_t *image_row(const bm *b, const uint8_t *img, int stride, int v)
{
    return img + (size_t)clampi(v, 0, b->h - 1) * stride;
}

/* Virtual row v (-r <= v < h + r, clamped into the image) of the right
 * image reversed into its ring slot: rrev[off + k] = R[w - 1 - k] inside
 * the row, FAR_VALUE outside, so that the right pixel of x at index d,
 * R[x - dmin - d], is slot[off + w - 1 - x + dmin + d], contiguous in d. A
 * row enters the column sums and leaves them 2r + 1 rows later: 2r + 2
 * slots hold every row in between. */
static const int16_t *reversed_row(bm *b, const uint8_t *right, int stride, int v)
{
    int16_t *q = b->rrev + (size_t)((v + b->r) % (2 * b->r + 2)) * b->rrev_len;
    const uint8_t *R = image_row(b, right, stride, v);
    const int w = b->w, off = (b->rrev_len - w) / 2;
    for (int k = 0; k < off; k++)
        q[k] = FAR_VALUE;
    for (int k = 0; k < w; k++)
        q[off + k] = R[w - 1 - k];
    for (int k = off + w; k < b->rrev_len; k++)
        q[k] = FAR_VALUE;
    return q + off + w - 1 + b->dmin;
}

/* |l - r| truncated at AD_MAX for eight disparities. */
static inline sfmi_v16 ad8(sfmi_v16 l, const int16_t *r)
{
    sfmi_v16 v = sfmi_v16_load(r);
    return sfmi_v16_min(sfmi_v16_max(l, v) - sfmi_v16_min(l, v), sfmi_v16_splat(AD_MAX));
}

static inline int absdiff(int a, int c)
{
    return a > c ? a - c : c - a;
}

/* |dI/dx| of the left image (central difference, clamped) of row `add`
 * into the gradient column sums, and of row `sub` (may be NULL) out. */
static void grad_update(bm *b, const uint8_t *add, const uint8_t *sub)
{
    const int w = b->w;
    int32_t *g = b->gcol;
    g[0] += absdiff(add[1], add[0]);
    g[w - 1] += absdiff(add[w - 1], add[w - 2]);
    for (int x = 1; x < w - 1; x++)
        g[x] += absdiff(add[x + 1], add[x - 1]);
    if (!sub)
        return;
    g[0] -= absdiff(sub[1], sub[0]);
    g[w - 1] -= absdiff(sub[w - 1], sub[w - 2]);
    for (int x = 1; x < w - 1; x++)
        g[x] -= absdiff(sub[x + 1], sub[x - 1]);
}

/* The differences of one left row (its reversed right row rr, from
 * reversed_row) into the column sums. */
static void col_add(bm *b, const uint8_t *L, const int16_t *rr)
{
    const int w = b->w, D = b->D;
    for (int x = 0; x < w; x++) {
        sfmi_v16 l = sfmi_v16_splat(L[x]);
        int16_t *c = b->col + (size_t)x * D;
        for (int d = 0; d < D; d += 8)
            sfmi_v16_store(c + d, sfmi_v16_load(c + d) + ad8(l, rr - x + d));
    }
}

/* The two smallest of the four corner windows. Two of the four are both
 * upper, both lower, or one of each, then the smaller of each pair: the
 * smallest of those three sums is the sum of the two smallest. */
static inline sfmi_v16 two_smallest(sfmi_v16 ul, sfmi_v16 ur, sfmi_v16 dl, sfmi_v16 dr)
{
    return sfmi_v16_min(sfmi_v16_min(ul + ur, dl + dr), sfmi_v16_min(ul, ur) + sfmi_v16_min(dl, dr));
}

/* Window rows of an output row y: centre, upper and lower corners. */
static void corner_rows(const bm *b, int y, const int16_t **wc, const int16_t **wu,
                        const int16_t **wd)
{
    const size_t row = (size_t)b->w * b->D;
    const int r2 = 2 * b->r;
    *wc = b->win + (size_t)(y % b->ring) * row;
    *wu = b->win + (size_t)(clampi(y - r2, 0, b->h - 1) % b->ring) * row;
    *wd = b->win + (size_t)(clampi(y + r2, 0, b->h - 1) % b->ring) * row;
}

/* Combined cost of pixel x of an output row (corner columns clamped):
 * centre window plus the two smallest corner windows. */
static void combine_pixel(bm *b, int x, const int16_t *wc, const int16_t *wu, const int16_t *wd)
{
    const int w = b->w, D = b->D, r2 = 2 * b->r;
    size_t xl = (size_t)clampi(x - r2, 0, w - 1) * D, xr = (size_t)clampi(x + r2, 0, w - 1) * D;
    int16_t *o = b->cost + (size_t)x * D;
    const int16_t *c = wc + (size_t)x * D;
    for (int d = 0; d < D; d += 8)
        sfmi_v16_store(o + d, sfmi_v16_load(c + d) +
                                  two_smallest(sfmi_v16_load(wu + xl + d), sfmi_v16_load(wu + xr + d),
                                               sfmi_v16_load(wd + xl + d), sfmi_v16_load(wd + xr + d)));
}

/* Columns [xa, xb) of the common case, each in one loop over the
 * disparities: rows in and out of column x, window x - r of row yy (into
 * out), and the combined cost and scan of pixel xc = x - 3 r of the output
 * row, whose lower right corner is that window; the corner columns of xc
 * are inside the image. Without partial, the whole range of each xc has a
 * match. partial and lr are constants where inlined. */
static inline __attribute__((always_inline)) void
columns_fused(bm *b, const sfmi_stereo_select_params *sp, int xa, int xb, const uint8_t *Ln,
              const int16_t *rn, const uint8_t *Lo, const int16_t *ro, int16_t *out,
              const int16_t *wc, const int16_t *wu, const int partial, const int lr)
{
    const int w = b->w, D = b->D, r = b->r;
    const size_t step = (size_t)D;
    int16_t *c = b->col + (size_t)xa * step, *o = out + (size_t)(xa - r) * step;
    const int16_t *cout = b->col + (size_t)(xa - 2 * r - 1) * step;
    const int16_t *pn = rn - xa, *po = ro - xa;
    int xc = xa - 3 * r;
    const int16_t *ul = wu + (size_t)(xc - 2 * r) * step, *ur = wu + (size_t)(xc + 2 * r) * step;
    const int16_t *dl = out + (size_t)(xc - 2 * r) * step, *cc = wc + (size_t)xc * step;
    int16_t *co = b->cost + (size_t)xc * step;
    const int slot = sfmi_stereo_span(D, sp->dmin) + w - 1 - (xc - sp->dmin);
    int16_t *rc = b->sel.best_r_cost + slot, *rd = b->sel.best_r_d + slot;
    for (int x = xa; x < xb; x++, xc++) {
        const sfmi_v16 ln = sfmi_v16_splat(Ln[x]), lo = sfmi_v16_splat(Lo[x]);
        int dlo = 0, dhi = D - 1;
        if (partial)
            sfmi_stereo_valid_range(xc, w, D, sp->dmin, &dlo, &dhi);
        const sfmi_v16 vlo = sfmi_v16_splat(dlo), vhi = sfmi_v16_splat(dhi);
        sfmi_stereo_lanes a;
        sfmi_stereo_lanes_init(&a);
        for (int d = 0; d < D; d += 8) {
            sfmi_v16 cv = sfmi_v16_load(c + d) + ad8(ln, pn + d) - ad8(lo, po + d);
            sfmi_v16_store(c + d, cv);
            sfmi_v16 sv = sfmi_v16_load(o - D + d) + cv - sfmi_v16_load(cout + d);
            sfmi_v16_store(o + d, sv);
            sfmi_v16 v = sfmi_v16_load(cc + d) + two_smallest(sfmi_v16_load(ul + d),
                                                              sfmi_v16_load(ur + d),
                                                              sfmi_v16_load(dl + d), sv);
            sfmi_v16_store(co + d, v);
            if (partial)
                v |= sfmi_stereo_outside(a.idx, vlo, vhi);
            sfmi_stereo_lanes_step(&a, v, rc + d, rd + d, lr);
        }
        sfmi_stereo_lanes_finish(&a, b->sel.best_d + xc, b->sel.best_c + xc, b->sel.second + xc);
        if (partial && dlo > dhi)
            b->sel.best_d[xc] = -1;
        c += step;
        o += step;
        cout += step;
        pn--;
        po--;
        ul += step;
        ur += step;
        dl += step;
        cc += step;
        co += step;
        rc--;
        rd--;
    }
}

/* Column x outside columns_fused: the column and window sums (border
 * columns replicated) and, with yo >= 0, the combined cost and scan of
 * pixel x - 3 r of the output row. */
static void column(bm *b, const sfmi_stereo_select_params *sp, int x, const uint8_t *Ln,
                   const int16_t *rn, const uint8_t *Lo, const int16_t *ro, int16_t *out, int yo,
                   const int16_t *wc, const int16_t *wu, const int16_t *wd)
{
    const int w = b->w, D = b->D, r = b->r;
    if (Ln && x < w) {
        sfmi_v16 ln = sfmi_v16_splat(Ln[x]), lo = sfmi_v16_splat(Lo[x]);
        int16_t *c = b->col + (size_t)x * D;
        const int16_t *pn = rn - x, *po = ro - x;
        for (int d = 0; d < D; d += 8)
            sfmi_v16_store(c + d, sfmi_v16_load(c + d) + ad8(ln, pn + d) - ad8(lo, po + d));
    }
    const int xo = x - r;
    if (xo == 0) {
        const sfmi_v16 k = sfmi_v16_splat(r + 1);
        for (int d = 0; d < D; d += 8) {
            sfmi_v16 sv = k * sfmi_v16_load(b->col + d);
            for (int i = 1; i <= r; i++)
                sv += sfmi_v16_load(b->col + (size_t)i * D + d);
            sfmi_v16_store(out + d, sv);
        }
    } else if (xo > 0 && xo < w) {
        int16_t *o = out + (size_t)xo * D;
        const int16_t *cin = b->col + (size_t)(x < w ? x : w - 1) * D;
        const int16_t *cout = b->col + (size_t)(xo - r - 1 > 0 ? xo - r - 1 : 0) * D;
        for (int d = 0; d < D; d += 8) {
            sfmi_v16 sv = sfmi_v16_load(o - D + d) + sfmi_v16_load(cin + d) - sfmi_v16_load(cout + d);
            sfmi_v16_store(o + d, sv);
        }
    }
    if (yo >= 0 && x >= 3 * r) {
        combine_pixel(b, x - 3 * r, wc, wu, wd);
        sfmi_stereo_scan_pixel(&b->sel, sp, w, x - 3 * r, b->cost + (size_t)(x - 3 * r) * D);
    }
}

/* columns_fused over [xa, xb) when not empty, with partial a constant and
 * lr turned into one, so that each call is one of its four loops. */
static inline __attribute__((always_inline)) void
fused_span(bm *b, const sfmi_stereo_select_params *sp, int xa, int xb, const uint8_t *Ln,
           const int16_t *rn, const uint8_t *Lo, const int16_t *ro, int16_t *out,
           const int16_t *wc, const int16_t *wu, const int partial, int lr)
{
    if (xb <= xa)
        return;
    if (lr)
        columns_fused(b, sp, xa, xb, Ln, rn, Lo, ro, out, wc, wu, partial, 1);
    else
        columns_fused(b, sp, xa, xb, Ln, rn, Lo, ro, out, wc, wu, partial, 0);
}

/* Window sums of row yy into ring slot yy % ring, in one pass over x: when
 * Ln is given, column x first takes row (Ln, rn) in and row (Lo, ro) out;
 * the horizontal running sum trails r columns behind. Then the texture
 * flags of the row. With yo >= 0 (then yy = yo + 2 r and Ln is given) the
 * same pass, 2 r columns further behind, combines and selects output row
 * yo into disp_row; returns its number of valid pixels. */
static int window_row(bm *b, int yy, const uint8_t *Ln, const int16_t *rn, const uint8_t *Lo,
                      const int16_t *ro, int texture, int yo, const sfmi_stereo_select_params *sp,
                      float *disp_row)
{
    const int w = b->w, D = b->D, r = b->r;
    int16_t *out = b->win + (size_t)(yy % b->ring) * w * D;
    const int16_t *wc = NULL, *wu = NULL, *wd = NULL;
    int xs = 0, xa = 0, xb = 0, xe = 0, xend = w + r;
    if (yo >= 0) {
        corner_rows(b, yo, &wc, &wu, &wd);
        sfmi_stereo_scan_begin(&b->sel, sp);
        /* columns x of columns_fused, [xs, xe): x > r and x < w for the
         * column and window sums, pixel x - 3 r with its corners inside
         * (x >= 5 r); of those, [xa, xb) where the whole range of x - 3 r
         * has a match: x - 3 r - dmin in [D - 1, w - 1] */
        xs = 5 * r;
        xe = w > xs ? w : xs;
        xa = clampi(sp->dmin + D - 1 + 3 * r, xs, xe);
        xb = clampi(sp->dmin + w + 3 * r, xa, xe);
        xend += 2 * r;
    }
    const int lr = sp->lr_max_diff >= 0;
    for (int x = 0; x < xs; x++)
        column(b, sp, x, Ln, rn, Lo, ro, out, yo, wc, wu, wd);
    fused_span(b, sp, xs, xa, Ln, rn, Lo, ro, out, wc, wu, 1, lr);
    fused_span(b, sp, xa, xb, Ln, rn, Lo, ro, out, wc, wu, 0, lr);
    fused_span(b, sp, xb, xe, Ln, rn, Lo, ro, out, wc, wu, 1, lr);
    for (int x = xe; x < xend; x++)
        column(b, sp, x, Ln, rn, Lo, ro, out, yo, wc, wu, wd);
    uint8_t *flat = b->flat + (size_t)(yy % b->ring) * w;
    if (texture <= 0) {
        memset(flat, 0, (size_t)w);
    } else {
        const int32_t lim = (int32_t)texture * (2 * r + 1) * (2 * r + 1) * 2;
        int32_t g = 0;
        for (int x = -r; x <= r; x++)
            g += b->gcol[clampi(x, 0, w - 1)];
        const int32_t *gc = b->gcol;
        int x = 0;
        for (; x < r && x < w; x++) {
            flat[x] = (uint8_t)(g * 16 < lim);
            g += gc[clampi(x + r + 1, 0, w - 1)] - gc[0];
        }
        for (; x < w - r - 1; x++) {
            flat[x] = (uint8_t)(g * 16 < lim);
            g += gc[x + r + 1] - gc[x - r];
        }
        for (; x < w; x++) {
            flat[x] = (uint8_t)(g * 16 < lim);
            g += gc[w - 1] - gc[clampi(x - r, 0, w - 1)];
        }
    }
    if (yo < 0)
        return 0;
    return sfmi_stereo_decide_row(&b->sel, sp, w, b->cost, b->flat + (size_t)(yo % b->ring) * w,
                                  disp_row);
}

/* Combined cost of output row y (not fused: the last rows). */
static void combine_row(bm *b, int y)
{
    const int16_t *wc, *wu, *wd;
    corner_rows(b, y, &wc, &wu, &wd);
    for (int x = 0; x < b->w; x++)
        combine_pixel(b, x, wc, wu, wd);
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
        const uint8_t *L = image_row(&b, left, stride, y);
        col_add(&b, L, reversed_row(&b, right, stride, y));
        grad_update(&b, L, NULL);
    }
    int valid = 0;
    for (int yy = 0; yy < height; yy++) {
        const int yo = yy >= r2 ? yy - r2 : -1;
        float *drow = yo >= 0 ? disp + (size_t)yo * width : NULL;
        if (yy > 0) {
            const uint8_t *Ln = image_row(&b, left, stride, yy + r);
            const uint8_t *Lo = image_row(&b, left, stride, yy - r - 1);
            const int16_t *ro = b.rrev + (size_t)((yy - 1) % (2 * r + 2)) * b.rrev_len +
                                (b.rrev_len - width) / 2 + width - 1 + b.dmin;
            const int16_t *rn = reversed_row(&b, right, stride, yy + r);
            grad_update(&b, Ln, Lo);
            valid += window_row(&b, yy, Ln, rn, Lo, ro, opt->texture, yo, &sp, drow);
        } else {
            valid += window_row(&b, yy, NULL, NULL, NULL, NULL, opt->texture, yo, &sp, drow);
        }
    }
    /* the last 2 r rows: their lower corners are the last row's windows */
    for (int y = height - r2; y < height; y++) {
        combine_row(&b, y);
        valid += sfmi_stereo_select_row(&b.sel, &sp, width, b.cost,
                                        b.flat + (size_t)(y % b.ring) * width,
                                        disp + (size_t)y * width);
    }
    return valid;
}
