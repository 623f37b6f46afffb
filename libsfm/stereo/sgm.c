/*
 * Semi-global matching: Hirschmüller, "Stereo processing by semiglobal
 * matching and mutual information", IEEE PAMI 30(2), 2008, with the census
 * Hamming cost of stereo_census.h in place of mutual information.
 *
 * Along each path direction r the aggregated cost is
 *   L_r(p, d) = C(p, d) + min(L_r(p-r, d), L_r(p-r, d-1) + P1,
 *                             L_r(p-r, d+1) + P1, min_k L_r(p-r, k) + P2)
 *               - min_k L_r(p-r, k),
 * and S(p, d) = sum_r L_r(p, d); the disparity minimises S. Subtracting the
 * minimum bounds L_r by C_max + P2, so 16-bit lanes never overflow.
 *
 * Five paths (left, right and the three from the row above) run in one
 * top-down pass with row buffers only, as OpenCV's StereoSGBM does; four and
 * eight paths add a bottom-up pass over a cost volume held in the
 * workspace. Costs and sums are integers: every target gets the same
 * disparities. The disparity range is vectorised eight lanes at a time.
 */
#include <math.h>
#include <string.h>

#include "core/arena.h"
#include "sfm/sfm_stereo.h"
#include "stereo/stereo_census.h"
#include "stereo/stereo_internal.h"
#include "stereo/stereo_select.h"

#define PAD 8            /* lanes of padding on each side of a cost block */
#define BIG 0x3000       /* padding value: never the minimum, no overflow */
#define OUT_COST 32      /* cost of a disparity whose match leaves the image */

typedef struct sgm {
    int w, h, D, dmin, Dp, p1, p2, paths;
    const uint8_t *left, *right;
    int stride;
    uint16_t *cl_lo, *cl_hi, *cr_lo, *cr_hi; /* census of left, right: one row
                                                (5 paths) or every row */
    int16_t *rrev_lo, *rrev_hi; /* one right row reversed and padded */
    int rrev_len, rrev_off;
    int16_t *C;         /* cost row, w x D */
    int16_t *h0, *h1;   /* horizontal path: previous and current block */
    int16_t *vp[3], *vc[3]; /* vertical paths (dx -1, 0, +1): (w + 2) blocks */
    int16_t *mp[3], *mc[3]; /* their minima per column, w + 2 */
    int16_t *S;         /* sums: one row (5 paths) or the volume */
    sfmi_stereo_scratch sel;
} sgm;

void sfm_stereo_sgm_default_options(sfm_stereo_sgm_options *opt)
{
    if (!opt)
        return;
    opt->min_disparity = 0;
    opt->num_disparities = 64;
    opt->p1 = 5;
    opt->p2 = 60;
    opt->paths = SFM_STEREO_PATHS_5;
    opt->uniqueness = 10;
    opt->lr_max_diff = 1;
    opt->subpixel = 1;
}

static int options_ok(int width, int height, const sfm_stereo_sgm_options *o)
{
    if (!o || !sfmi_stereo_range_ok(width, height, o->min_disparity, o->num_disparities))
        return 0;
    if (o->p1 < 1 || o->p2 <= o->p1 || o->p2 > 1000)
        return 0;
    if (o->paths != SFM_STEREO_PATHS_4 && o->paths != SFM_STEREO_PATHS_5 &&
        o->paths != SFM_STEREO_PATHS_8)
        return 0;
    return sfmi_stereo_select_options_ok(o->uniqueness, o->lr_max_diff, o->subpixel);
}

static void layout(sfmi_arena *a, sgm *s, int w, int h, const sfm_stereo_sgm_options *o)
{
    int D = o->num_disparities, Dp = D + 2 * PAD;
    s->w = w;
    s->h = h;
    s->D = D;
    s->Dp = Dp;
    int span = D + 8 + (o->min_disparity > 0 ? o->min_disparity : -o->min_disparity);
    s->rrev_off = span;
    s->rrev_len = w + 2 * span;
    s->rrev_lo = SFM_ARENA_ARRAY(a, int16_t, s->rrev_len);
    s->rrev_hi = SFM_ARENA_ARRAY(a, int16_t, s->rrev_len);
    /* The two-pass modes visit each row twice: their census is computed
     * once into planes. */
    size_t crows = o->paths == SFM_STEREO_PATHS_5 ? 1 : (size_t)h;
    s->cl_lo = SFM_ARENA_ARRAY(a, uint16_t, crows * w);
    s->cl_hi = SFM_ARENA_ARRAY(a, uint16_t, crows * w);
    s->cr_lo = SFM_ARENA_ARRAY(a, uint16_t, crows * w);
    s->cr_hi = SFM_ARENA_ARRAY(a, uint16_t, crows * w);
    s->C = SFM_ARENA_ARRAY(a, int16_t, (size_t)w * D);
    s->h0 = SFM_ARENA_ARRAY(a, int16_t, Dp);
    s->h1 = SFM_ARENA_ARRAY(a, int16_t, Dp);
    for (int k = 0; k < 3; k++) {
        s->vp[k] = SFM_ARENA_ARRAY(a, int16_t, (size_t)(w + 2) * Dp);
        s->vc[k] = SFM_ARENA_ARRAY(a, int16_t, (size_t)(w + 2) * Dp);
        s->mp[k] = SFM_ARENA_ARRAY(a, int16_t, w + 2);
        s->mc[k] = SFM_ARENA_ARRAY(a, int16_t, w + 2);
    }
    size_t rows = o->paths == SFM_STEREO_PATHS_5 ? 1 : (size_t)h;
    s->S = SFM_ARENA_ARRAY(a, int16_t, rows * w * D);
    sfmi_stereo_scratch_layout(a, &s->sel, w, D, o->min_disparity);
}

size_t sfm_stereo_sgm_workspace_size(int width, int height, const sfm_stereo_sgm_options *opt)
{
    if (!options_ok(width, height, opt))
        return 0;
    sfmi_arena a;
    sgm s;
    sfmi_arena_measure(&a);
    layout(&a, &s, width, height, opt);
    return a.failed ? 0 : sfmi_arena_required(&a);
}

/* Census Hamming costs of row y for every x and disparity dmin + d. The
 * five-path pass computes the census of the row here (the workspace holds
 * rows only); the others read it from the planes. The right row is
 * reversed so that the pixels x - dmin - d of consecutive d are
 * consecutive in memory. */
static void cost_row(const sgm *s, int y)
{
    const int D = s->D, w = s->w, dmin = s->dmin, off = s->rrev_off;
    const size_t at = s->paths == SFM_STEREO_PATHS_5 ? 0 : (size_t)y * w;
    if (s->paths == SFM_STEREO_PATHS_5) {
        sfmi_stereo_census_row(s->left, w, s->h, s->stride, y, s->cl_lo, s->cl_hi);
        sfmi_stereo_census_row(s->right, w, s->h, s->stride, y, s->cr_lo, s->cr_hi);
    }
    const uint16_t *Llo = s->cl_lo + at, *Lhi = s->cl_hi + at;
    const uint16_t *Rlo = s->cr_lo + at, *Rhi = s->cr_hi + at;
    memset(s->rrev_lo, 0, sizeof(int16_t) * (size_t)s->rrev_len);
    memset(s->rrev_hi, 0, sizeof(int16_t) * (size_t)s->rrev_len);
    for (int k = 0; k < w; k++) {
        s->rrev_lo[off + k] = (int16_t)Rlo[w - 1 - k];
        s->rrev_hi[off + k] = (int16_t)Rhi[w - 1 - k];
    }
    for (int x = 0; x < w; x++) {
        int16_t *c = s->C + (size_t)x * D;
        const int16_t *rl = s->rrev_lo + off + w - 1 - x + dmin;
        const int16_t *rh = s->rrev_hi + off + w - 1 - x + dmin;
        sfmi_v16 ll = sfmi_v16_splat(Llo[x]), lh = sfmi_v16_splat(Lhi[x]);
        for (int d = 0; d < D; d += 8)
            sfmi_v16_store(c + d, sfmi_v16_popcount2(ll ^ sfmi_v16_load(rl + d),
                                                     lh ^ sfmi_v16_load(rh + d)));
        int xr0 = x - dmin; /* right x of disparity index 0; index d is xr0 - d */
        if (xr0 - (D - 1) < 0 || xr0 > w - 1)
            for (int d = 0; d < D; d++)
                if (xr0 - d < 0 || xr0 - d > w - 1)
                    c[d] = OUT_COST;
    }
}

/* One path step: out = C + min(P(d), P(d -+ 1) + p1, minP + p2) - minP over
 * the D lanes, also stored to copy; returns min_d out. pred points at the predecessor's first
 * lane, with PAD lanes of BIG on both sides. */
static inline int step(const int16_t *c, const int16_t *pred, int minp, int D, sfmi_v16 vp1,
                       int p2, int16_t *out, int16_t *copy)
{
    sfmi_v16 base = sfmi_v16_splat(minp + p2), sub = sfmi_v16_splat(minp);
    sfmi_v16 mn = sfmi_v16_splat(0x7fff);
    for (int d = 0; d < D; d += 8) {
        sfmi_v16 p = sfmi_v16_load(pred + d);
        sfmi_v16 pm = sfmi_v16_load(pred + d - 1) + vp1;
        sfmi_v16 pp = sfmi_v16_load(pred + d + 1) + vp1;
        sfmi_v16 m = sfmi_v16_min(sfmi_v16_min(p, pm), sfmi_v16_min(pp, base));
        sfmi_v16 o = sfmi_v16_load(c + d) + m - sub;
        sfmi_v16_store(out + d, o);
        sfmi_v16_store(copy + d, o);
        mn = sfmi_v16_min(mn, o);
    }
    return sfmi_v16_hmin(mn);
}

/* n path steps at one pixel in one sweep over the lanes, adding all n
 * outputs into S; called with a constant n so that the loop over paths
 * unrolls. mn[k] receives min_d of path k's output. */
static inline void steps(int n, const int16_t *c, const int16_t *const *pred, const int *minp,
                         int16_t *const *out, int *mn, int D, sfmi_v16 vp1, int p2, int16_t *S)
{
    sfmi_v16 base[4], sub[4], m[4];
    for (int k = 0; k < n; k++) {
        base[k] = sfmi_v16_splat(minp[k] + p2);
        sub[k] = sfmi_v16_splat(minp[k]);
        m[k] = sfmi_v16_splat(0x7fff);
    }
    for (int d = 0; d < D; d += 8) {
        sfmi_v16 cv = sfmi_v16_load(c + d), acc = sfmi_v16_load(S + d);
        for (int k = 0; k < n; k++) {
            const int16_t *p = pred[k] + d;
            sfmi_v16 t = sfmi_v16_min(sfmi_v16_min(sfmi_v16_load(p), sfmi_v16_load(p - 1) + vp1),
                                      sfmi_v16_min(sfmi_v16_load(p + 1) + vp1, base[k]));
            sfmi_v16 o = cv + t - sub[k];
            sfmi_v16_store(out[k] + d, o);
            m[k] = sfmi_v16_min(m[k], o);
            acc += o;
        }
        sfmi_v16_store(S + d, acc);
    }
    for (int k = 0; k < n; k++)
        mn[k] = sfmi_v16_hmin(m[k]);
}

/* The update of one path inside steps4: o = C + min(...) - minP. */
#define SFMI_SGM_PATH(p, base, sub, out, m)                                                   \
    do {                                                                                      \
        sfmi_v16 t_ = sfmi_v16_min(                                                           \
            sfmi_v16_min(sfmi_v16_load((p) + d), sfmi_v16_load((p) + d - 1) + vp1),           \
            sfmi_v16_min(sfmi_v16_load((p) + d + 1) + vp1, (base)));                          \
        sfmi_v16 o_ = cv + t_ - (sub);                                                        \
        sfmi_v16_store((out) + d, o_);                                                        \
        (m) = sfmi_v16_min((m), o_);                                                          \
        acc += o_;                                                                            \
    } while (0)

/* steps(4, ...) written out: the five-path pass's hot loop, with every
 * pointer and constant in a register. */
static inline void steps4(const int16_t *c, const int16_t *const *pred, const int *minp,
                          int16_t *const *out, int *mn, int D, sfmi_v16 vp1, int p2, int16_t *S)
{
    const int16_t *p0 = pred[0], *p1 = pred[1], *p2p = pred[2], *p3 = pred[3];
    int16_t *o0 = out[0], *o1 = out[1], *o2 = out[2], *o3 = out[3];
    const sfmi_v16 b0 = sfmi_v16_splat(minp[0] + p2), s0 = sfmi_v16_splat(minp[0]);
    const sfmi_v16 b1 = sfmi_v16_splat(minp[1] + p2), s1 = sfmi_v16_splat(minp[1]);
    const sfmi_v16 b2 = sfmi_v16_splat(minp[2] + p2), s2 = sfmi_v16_splat(minp[2]);
    const sfmi_v16 b3 = sfmi_v16_splat(minp[3] + p2), s3 = sfmi_v16_splat(minp[3]);
    sfmi_v16 m0 = sfmi_v16_splat(0x7fff), m1 = m0, m2 = m0, m3 = m0;
    for (int d = 0; d < D; d += 8) {
        sfmi_v16 cv = sfmi_v16_load(c + d), acc = sfmi_v16_load(S + d);
        SFMI_SGM_PATH(p0, b0, s0, o0, m0);
        SFMI_SGM_PATH(p1, b1, s1, o1, m1);
        SFMI_SGM_PATH(p2p, b2, s2, o2, m2);
        SFMI_SGM_PATH(p3, b3, s3, o3, m3);
        sfmi_v16_store(S + d, acc);
    }
    mn[0] = sfmi_v16_hmin(m0);
    mn[1] = sfmi_v16_hmin(m1);
    mn[2] = sfmi_v16_hmin(m2);
    mn[3] = sfmi_v16_hmin(m3);
}

static void fill_block(int16_t *blk, int Dp, int16_t v)
{
    for (int i = 0; i < Dp; i++)
        blk[i] = BIG;
    for (int i = PAD; i < Dp - PAD; i++)
        blk[i] = v;
}

/* Reset the vertical path rows: no predecessor (zeros, minimum zero). */
static void reset_vertical(sgm *s)
{
    for (int k = 0; k < 3; k++) {
        for (int x = 0; x < s->w + 2; x++) {
            fill_block(s->vp[k] + (size_t)x * s->Dp, s->Dp, 0);
            fill_block(s->vc[k] + (size_t)x * s->Dp, s->Dp, 0);
            s->mp[k][x] = 0;
            s->mc[k][x] = 0;
        }
    }
}

/* The enabled vertical paths of column x appended to pred/out/mp from
 * index n: column x lives at block x + 1, its predecessor at x + 1 + dx.
 * Returns the new count. */
static inline int vertical_paths(const sgm *s, int x, int vmask, const int16_t **pred, int16_t **out,
                          int *mp, int n)
{
    for (int k = 0; k < 3; k++) {
        if (!(vmask & (1 << k)))
            continue;
        int dx = k - 1;
        pred[n] = s->vp[k] + (size_t)(x + 1 + dx) * s->Dp + PAD;
        out[n] = s->vc[k] + (size_t)(x + 1) * s->Dp + PAD;
        mp[n] = s->mp[k][x + 1 + dx];
        n++;
    }
    return n;
}

/* Aggregate row y into Srow (w x D): horizontal paths when `horizontal`
 * (which initialises Srow; otherwise Srow is added to), and the vertical
 * paths whose dx in {-1, 0, 1} is set in vmask (bit dx + 1), coming from the
 * previous row of this pass. */
static void aggregate_row(sgm *s, int y, int horizontal, int vmask, int16_t *Srow)
{
    const int w = s->w, D = s->D, Dp = s->Dp, p2 = s->p2;
    const sfmi_v16 vp1 = sfmi_v16_splat(s->p1);
    cost_row(s, y);
    if (horizontal) {
        int16_t *prev = s->h0, *cur = s->h1;
        fill_block(prev, Dp, 0);
        fill_block(cur, Dp, 0);
        int minp = 0;
        for (int x = 0; x < w; x++) {
            minp = step(s->C + (size_t)x * D, prev + PAD, minp, D, vp1, p2, cur + PAD,
                        Srow + (size_t)x * D);
            int16_t *t = prev;
            prev = cur;
            cur = t;
        }
        fill_block(prev, Dp, 0);
        minp = 0;
        /* Right-to-left and the vertical paths share one sweep: the
         * vertical ones depend on the previous row only. */
        const int all3 = vmask == 7;
        for (int x = w - 1; x >= 0; x--) {
            const int16_t *pred[4];
            int16_t *out[4];
            int mp[4], mn[4], n = 1;
            pred[0] = prev + PAD;
            out[0] = cur + PAD;
            mp[0] = minp;
            n = vertical_paths(s, x, vmask, pred, out, mp, n);
            const int16_t *c = s->C + (size_t)x * D;
            int16_t *dst = Srow + (size_t)x * D;
            if (all3)
                steps4(c, pred, mp, out, mn, D, vp1, p2, dst);
            else
                steps(n, c, pred, mp, out, mn, D, vp1, p2, dst);
            minp = mn[0];
            for (int k = 0, j = 1; k < 3; k++)
                if (vmask & (1 << k))
                    s->mc[k][x + 1] = (int16_t)mn[j++];
            int16_t *t = prev;
            prev = cur;
            cur = t;
        }
    } else {
        for (int x = 0; x < w; x++) {
            const int16_t *pred[3];
            int16_t *out[3];
            int mp[3], mn[3], n = 0;
            n = vertical_paths(s, x, vmask, pred, out, mp, n);
            const int16_t *c = s->C + (size_t)x * D;
            int16_t *dst = Srow + (size_t)x * D;
            if (n == 3)
                steps(3, c, pred, mp, out, mn, D, vp1, p2, dst);
            else
                steps(n, c, pred, mp, out, mn, D, vp1, p2, dst);
            for (int k = 0, j = 0; k < 3; k++)
                if (vmask & (1 << k))
                    s->mc[k][x + 1] = (int16_t)mn[j++];
        }
    }
    for (int k = 0; k < 3; k++) {
        if (!(vmask & (1 << k)))
            continue;
        int16_t *t = s->vp[k];
        s->vp[k] = s->vc[k];
        s->vc[k] = t;
        t = s->mp[k];
        s->mp[k] = s->mc[k];
        s->mc[k] = t;
    }
}

int sfm_stereo_sgm(const uint8_t *left, const uint8_t *right, int width, int height, int stride,
                   const sfm_stereo_sgm_options *opt, float *disp, void *ws, size_t ws_size)
{
    if (!left || !right || !disp || !opt || stride < width)
        return SFM_E_ARGUMENT;
    if (!options_ok(width, height, opt))
        return SFM_E_ARGUMENT;
    if (!ws)
        return SFM_E_WORKSPACE;
    sfmi_arena a;
    sgm s;
    sfmi_arena_init(&a, ws, ws_size);
    layout(&a, &s, width, height, opt);
    if (!sfmi_arena_ok(&a))
        return SFM_E_WORKSPACE;
    s.dmin = opt->min_disparity;
    s.p1 = opt->p1;
    s.p2 = opt->p2;
    s.paths = opt->paths;
    s.left = left;
    s.right = right;
    s.stride = stride;
    if (opt->paths != SFM_STEREO_PATHS_5)
        for (int y = 0; y < height; y++) {
            sfmi_stereo_census_row(left, width, height, stride, y, s.cl_lo + (size_t)y * width,
                                   s.cl_hi + (size_t)y * width);
            sfmi_stereo_census_row(right, width, height, stride, y, s.cr_lo + (size_t)y * width,
                                   s.cr_hi + (size_t)y * width);
        }
    /* Each path's L is at most C + p2 <= OUT_COST + p2 (see the top). */
    int npaths = opt->paths == SFM_STEREO_PATHS_8 ? 8 : (opt->paths == SFM_STEREO_PATHS_4 ? 4 : 5);
    sfmi_stereo_select_params sp = {opt->min_disparity, opt->num_disparities, opt->uniqueness,
                                    opt->lr_max_diff, opt->subpixel, npaths * (OUT_COST + opt->p2)};
    const size_t row = (size_t)width * opt->num_disparities;
    int valid = 0;
    reset_vertical(&s);
    if (opt->paths == SFM_STEREO_PATHS_5) {
        for (int y = 0; y < height; y++) {
            aggregate_row(&s, y, 1, 7, s.S);
            valid += sfmi_stereo_select_row(&s.sel, &sp, width, s.S, NULL,
                                            disp + (size_t)y * width);
        }
        return valid;
    }
    int vmask = opt->paths == SFM_STEREO_PATHS_8 ? 7 : 2;
    for (int y = 0; y < height; y++)
        aggregate_row(&s, y, 1, vmask, s.S + (size_t)y * row);
    reset_vertical(&s);
    for (int y = height - 1; y >= 0; y--)
        aggregate_row(&s, y, 0, vmask, s.S + (size_t)y * row);
    for (int y = 0; y < height; y++)
        valid += sfmi_stereo_select_row(&s.sel, &sp, width, s.S + (size_t)y * row, NULL,
                                        disp + (size_t)y * width);
    return valid;
}
