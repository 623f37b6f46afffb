/*
 * Keypoint detection and description over an image pyramid (the public entry
 * sfm_features_detect).
 *
 * Per level: FAST-9 scores row by row in a 3-row ring, 3x3 non-maximum
 * suppression on the score, then every survivor goes into the bounded
 * min-heap of its grid cell (keeping the cell's strongest FAST scores). The
 * kept candidates are ranked within their cell by the Harris measure, and
 * the level's budget is filled rank by rank over all cells (all cells' best,
 * then all cells' second best, ...; the last, partial rank by Harris), so
 * features spread over the image while empty cells leave their share to busy
 * ones. Budgets are split over levels in proportion to level area; what a
 * level cannot fill passes to the next.
 *
 * Workspace layout (carved by one function, measured by the same one):
 * levels 1..L-1, the smoothed level, smoothing and resampling rows, the FAST
 * score ring, the cell heaps and a rank list.
 */
#include <math.h>
#include <string.h>

#include "core/arena.h"
#include "features/corner.h"
#include "features/describe.h"
#include "features/fast.h"
#include "features/pyramid.h"
#include "sfm/sfm_features.h"
#include "core/dmath.h"

#define MAX_SIDE 32768
/* A cell keeps at most this many times its fair share of a level's quota. */
#define CELL_CAP 3.0
/* Sub-pixel acceptance: rms distance of the gradient lines, level-0 pixels. */
#define REFINE_RMS 0.7

typedef struct cand {
    int32_t x, y;
    int32_t score;
    int32_t pad;
    double harris;
} cand;

typedef struct plan {
    int n_levels;
    int w[SFM_FEATURES_MAX_LEVELS], h[SFM_FEATURES_MAX_LEVELS];
    int quota[SFM_FEATURES_MAX_LEVELS];
    int gx[SFM_FEATURES_MAX_LEVELS], gy[SFM_FEATURES_MAX_LEVELS];
    int K[SFM_FEATURES_MAX_LEVELS]; /* heap capacity per cell */
    int max_slots;                  /* max over levels of cells * K */
    int max_cells;
} plan;

typedef struct layout {
    uint8_t *level[SFM_FEATURES_MAX_LEVELS]; /* [0] unused: level 0 is the caller's image */
    uint8_t *smooth;
    uint8_t *tmp;
    int32_t *xofs;
    uint16_t *xw;
    uint16_t *row;
    uint8_t *ring;
    cand *slots;
    int32_t *count;
    int32_t *rank;
    int32_t *steer; /* SFM_FEAT_STEER_TABLE_LEN */
} layout;

int sfm_features_default_params(sfm_features_params *p)
{
    if (p == NULL)
        return SFM_E_ARGUMENT;
    p->max_features = 2000;
    p->n_levels = 6;
    p->scale_factor = 1.25;
    p->fast_threshold = 20;
    p->cell_size = 48;
    return SFM_OK;
}

static int params_ok(const sfm_features_params *p)
{
    return p != NULL && p->max_features >= 1 && p->max_features <= SFM_FEATURES_MAX_FEATURES &&
           p->n_levels >= 1 && p->n_levels <= SFM_FEATURES_MAX_LEVELS && isfinite(p->scale_factor) &&
           p->scale_factor >= 1.05 && p->scale_factor <= 2.0 && p->fast_threshold >= 1 &&
           p->fast_threshold <= 254 && p->cell_size >= 8 && p->cell_size <= 1024;
}

static int dims_ok(int w, int h)
{
    return w >= 1 && h >= 1 && w <= MAX_SIDE && h <= MAX_SIDE;
}

static void make_plan(const sfm_features_params *p, int w0, int h0, plan *pl)
{
    memset(pl, 0, sizeof *pl);
    pl->n_levels = sfmi_feat_level_sizes(w0, h0, p->n_levels, p->scale_factor, pl->w, pl->h);
    const int L = pl->n_levels;
    if (L == 0)
        return;
    /* budget in proportion to level area: weights f^l, f = 1/s^2 */
    const double f = 1.0 / (p->scale_factor * p->scale_factor);
    double wsum = 0.0, wl = 1.0;
    for (int l = 0; l < L; l++, wl *= f)
        wsum += wl;
    int given = 0;
    wl = 1.0;
    for (int l = 0; l < L; l++, wl *= f) {
        pl->quota[l] = (int)((double)p->max_features * wl / wsum);
        given += pl->quota[l];
    }
    pl->quota[0] += p->max_features - given;
    for (int l = 0; l < L; l++) {
        const int span_x = pl->w[l] - 2 * SFM_FEATURES_BORDER, span_y = pl->h[l] - 2 * SFM_FEATURES_BORDER;
        pl->gx[l] = (span_x + p->cell_size - 1) / p->cell_size;
        pl->gy[l] = (span_y + p->cell_size - 1) / p->cell_size;
        const int cells = pl->gx[l] * pl->gy[l];
        /* a cell keeps at most CELL_CAP times its fair share of the level's
         * quota (plus 2), so strong texture cannot take the whole budget */
        int K = (int)ceil(CELL_CAP * (double)pl->quota[l] / (double)cells) + 2;
        pl->K[l] = K;
        if (cells * K > pl->max_slots)
            pl->max_slots = cells * K;
        if (cells > pl->max_cells)
            pl->max_cells = cells;
    }
}

static void carve(sfmi_arena *a, const plan *pl, layout *ly)
{
    memset(ly, 0, sizeof *ly);
    if (pl->n_levels == 0)
        return;
    const size_t w0 = (size_t)pl->w[0], h0 = (size_t)pl->h[0];
    for (int l = 1; l < pl->n_levels; l++)
        ly->level[l] = SFM_ARENA_ARRAY(a, uint8_t, (size_t)pl->w[l] * (size_t)pl->h[l]);
    ly->smooth = SFM_ARENA_ARRAY(a, uint8_t, w0 * h0);
    ly->tmp = SFM_ARENA_ARRAY(a, uint8_t, w0);
    ly->xofs = SFM_ARENA_ARRAY(a, int32_t, w0);
    ly->xw = SFM_ARENA_ARRAY(a, uint16_t, w0);
    ly->row = SFM_ARENA_ARRAY(a, uint16_t, w0);
    ly->ring = SFM_ARENA_ARRAY(a, uint8_t, 3 * w0);
    ly->slots = SFM_ARENA_ARRAY(a, cand, pl->max_slots);
    ly->count = SFM_ARENA_ARRAY(a, int32_t, pl->max_cells);
    ly->rank = SFM_ARENA_ARRAY(a, int32_t, pl->max_slots);
    ly->steer = SFM_ARENA_ARRAY(a, int32_t, SFM_FEAT_STEER_TABLE_LEN);
}

size_t sfm_features_workspace_size(const sfm_features_params *p, int width, int height)
{
    if (!params_ok(p) || !dims_ok(width, height))
        return 0;
    plan pl;
    make_plan(p, width, height, &pl);
    sfmi_arena a;
    layout ly;
    sfmi_arena_measure(&a);
    carve(&a, &pl, &ly);
    return sfmi_arena_required(&a);
}

/* Strict total order: stronger Harris first, then raster order. */
static int before(const cand *a, const cand *b)
{
    if (a->harris != b->harris)
        return a->harris > b->harris;
    if (a->y != b->y)
        return a->y < b->y;
    return a->x < b->x;
}

/* Min-heap on (score, then raster order reversed) of at most K entries. */
static int heap_less(const cand *a, const cand *b)
{
    if (a->score != b->score)
        return a->score < b->score;
    if (a->y != b->y)
        return a->y > b->y;
    return a->x > b->x;
}

static void heap_push(cand *h, int32_t *n, int K, cand c)
{
    if (*n < K) {
        int i = (*n)++;
        while (i > 0) {
            int parent = (i - 1) / 2;
            if (!heap_less(&c, &h[parent]))
                break;
            h[i] = h[parent];
            i = parent;
        }
        h[i] = c;
        return;
    }
    if (!heap_less(&h[0], &c))
        return;
    int i = 0;
    for (;;) {
        int l = 2 * i + 1, r = l + 1, m = i;
        const cand *mv = &c;
        if (l < K && heap_less(&h[l], mv)) {
            m = l;
            mv = &h[l];
        }
        if (r < K && heap_less(&h[r], mv))
            m = r;
        if (m == i)
            break;
        h[i] = h[m];
        i = m;
    }
    h[i] = c;
}

static void sort_cands(cand *c, int n)
{
    for (int i = 1; i < n; i++) {
        cand v = c[i];
        int j = i - 1;
        while (j >= 0 && before(&v, &c[j])) {
            c[j + 1] = c[j];
            j--;
        }
        c[j + 1] = v;
    }
}

/* Heapsort of candidate indices into the order of before() (deterministic,
 * no recursion, O(n log n)). */
static void sift(const cand *c, int32_t *idx, int i, int n)
{
    int32_t v = idx[i];
    for (;;) {
        int ch = 2 * i + 1;
        if (ch >= n)
            break;
        /* max-heap on "later in the order" so the sorted array is ascending in it */
        if (ch + 1 < n && before(&c[idx[ch]], &c[idx[ch + 1]]))
            ch++;
        if (!before(&c[v], &c[idx[ch]]))
            break;
        idx[i] = idx[ch];
        i = ch;
    }
    idx[i] = v;
}

static void sort_by_harris(const cand *c, int32_t *idx, int n)
{
    /* heap whose root is the candidate that comes last in before() order */
    for (int i = n / 2 - 1; i >= 0; i--)
        sift(c, idx, i, n);
    for (int end = n - 1; end > 0; end--) {
        int32_t t = idx[0];
        idx[0] = idx[end];
        idx[end] = t;
        sift(c, idx, 0, end);
    }
}

/* FAST + NMS + cell heaps over one level. */
static void collect(const sfmi_feat_level *lv, int threshold, int cell, int gx, int K,
                    uint8_t *ring, cand *slots, int32_t *count, int cells)
{
    const int B = SFM_FEATURES_BORDER, w = lv->w, h = lv->h;
    for (int i = 0; i < cells; i++)
        count[i] = 0;
    memset(ring, 0, 3 * (size_t)w);
    for (int y = B - 1; y <= h - B; y++) {
        uint8_t *cur = ring + (size_t)(y % 3) * (size_t)w;
        sfmi_feat_fast_row(lv->data, lv->stride, y, B - 1, w - B + 1, threshold, cur);
        const int ym = y - 1;
        if (ym < B)
            continue;
        const uint8_t *up = ring + (size_t)((ym + 2) % 3) * (size_t)w; /* row ym - 1 */
        const uint8_t *mid = ring + (size_t)(ym % 3) * (size_t)w;
        const uint8_t *dn = cur;
        const int cy = (ym - B) / cell;
        for (int x = B; x < w - B; x++) {
            const int s = mid[x];
            if (s == 0) {
                /* skip runs of 8 empty scores in one read */
                uint64_t run;
                if (x + 9 <= w - B) {
                    memcpy(&run, mid + x + 1, 8);
                    if (run == 0)
                        x += 8;
                }
                continue;
            }
            /* strictly above earlier neighbours (raster order), at least later ones */
            if (!(s > up[x - 1] && s > up[x] && s > up[x + 1] && s > mid[x - 1] && s >= mid[x + 1] &&
                  s >= dn[x - 1] && s >= dn[x] && s >= dn[x + 1]))
                continue;
            const int ci = cy * gx + (x - B) / cell;
            cand c;
            c.x = x;
            c.y = ym;
            c.score = s;
            c.pad = 0;
            c.harris = 0.0;
            heap_push(slots + (size_t)ci * (size_t)K, &count[ci], K, c);
        }
    }
}

/* steered: bit b set once bin b of the level's steering table is written
 * (bins are filled on first use). */
static int emit(const sfmi_feat_level *lv, const uint8_t *smooth, int32_t *steer, uint64_t *steered,
                const uint8_t *disc, int level, const cand *c, sfm_keypoint *kp, uint8_t *desc)
{
    double rx, ry, co, si;
    /* gradient lines must meet within REFINE_RMS level-0 pixels (rms) */
    const double max_res = REFINE_RMS * REFINE_RMS / (lv->sx * lv->sy);
    (void)sfmi_feat_refine(lv->data, lv->stride, c->x, c->y, max_res, &rx, &ry);
    sfmi_feat_orientation(smooth, lv->w, c->x, c->y, disc, &co, &si);
    const int bin = sfmi_feat_angle_bin(co, si);
    if (!(*steered >> bin & 1u)) {
        sfmi_feat_steer_bin(lv->w, bin, steer);
        *steered |= (uint64_t)1 << bin;
    }
    sfmi_feat_describe(smooth, lv->w, c->x, c->y, steer + (size_t)bin * 512, desc);
    kp->x = (rx + 0.5) * lv->sx - 0.5;
    kp->y = (ry + 0.5) * lv->sy - 0.5;
    kp->angle = sfmi_atan2(si, co);
    kp->response = c->harris;
    kp->scale = 0.5 * (lv->sx + lv->sy);
    kp->level = level;
    kp->reserved = 0;
    return 1;
}

int sfm_features_detect(const sfm_image_u8 *image, const sfm_features_params *p, sfm_keypoint *kps, uint8_t *desc,
                        int capacity, void *ws, size_t ws_size)
{
    if (image == NULL || image->data == NULL || p == NULL || ws == NULL || kps == NULL || desc == NULL)
        return SFM_E_ARGUMENT;
    if (!dims_ok(image->width, image->height) || image->stride < image->width || !params_ok(p))
        return SFM_E_ARGUMENT;
    if (capacity < p->max_features)
        return SFM_E_CAPACITY;
    plan pl;
    make_plan(p, image->width, image->height, &pl);
    sfmi_arena a;
    layout ly;
    sfmi_arena_measure(&a);
    carve(&a, &pl, &ly);
    const size_t need = sfmi_arena_required(&a);
    if (need == 0 || ws_size < need)
        return SFM_E_WORKSPACE;
    sfmi_arena_init(&a, ws, ws_size);
    carve(&a, &pl, &ly);
    if (pl.n_levels > 0 && !sfmi_arena_ok(&a))
        return SFM_E_WORKSPACE;

    uint8_t disc[SFM_FEAT_DISC_MASK_LEN]; /* the only sizeable stack use: 992 bytes */
    sfmi_feat_disc_mask(disc);
    int n_out = 0, carry = 0;
    sfmi_feat_level prev = {image->data, image->width, image->height, image->stride, 1.0, 1.0};
    for (int l = 0; l < pl.n_levels; l++) {
        sfmi_feat_level lv;
        if (l == 0) {
            lv.data = image->data;
            lv.w = image->width;
            lv.h = image->height;
            lv.stride = image->stride;
            lv.sx = lv.sy = 1.0;
        } else {
            sfmi_feat_resize(prev.data, prev.w, prev.h, prev.stride, ly.level[l], pl.w[l], pl.h[l], ly.xofs, ly.xw, ly.row);
            lv.data = ly.level[l];
            lv.w = pl.w[l];
            lv.h = pl.h[l];
            lv.stride = pl.w[l];
            lv.sx = prev.sx * (double)prev.w / (double)lv.w;
            lv.sy = prev.sy * (double)prev.h / (double)lv.h;
        }
        prev = lv;
        int budget = pl.quota[l] + carry;
        if (budget > p->max_features - n_out)
            budget = p->max_features - n_out;
        if (budget <= 0)
            continue;
        const int cells = pl.gx[l] * pl.gy[l], K = pl.K[l];
        collect(&lv, p->fast_threshold, p->cell_size, pl.gx[l], K, ly.ring, ly.slots, ly.count, cells);
        for (int ci = 0; ci < cells; ci++) {
            cand *cc = ly.slots + (size_t)ci * (size_t)K;
            for (int k = 0; k < ly.count[ci]; k++)
                cc[k].harris = sfmi_feat_harris(lv.data, lv.stride, cc[k].x, cc[k].y);
            sort_cands(cc, ly.count[ci]);
        }
        sfmi_feat_smooth(lv.data, lv.w, lv.h, lv.stride, ly.smooth, ly.tmp);
        uint64_t steered = 0;
        /* every cell's kept candidates compete by Harris measure */
        int n = 0;
        for (int ci = 0; ci < cells; ci++)
            for (int k = 0; k < ly.count[ci]; k++)
                ly.rank[n++] = ci * K + k;
        sort_by_harris(ly.slots, ly.rank, n);
        const int take = n < budget ? n : budget;
        for (int i = 0; i < take; i++, n_out++)
            emit(&lv, ly.smooth, ly.steer, &steered, disc, l, &ly.slots[ly.rank[i]], &kps[n_out], desc + (size_t)n_out * SFM_FEATURES_DESC_BYTES);
        const int taken = take;
        carry = budget - taken;
    }
    return n_out;
}
