/*
 * FAST-9 corner test (Rosten and Drummond, "Machine learning for high-speed
 * corner detection", ECCV 2006): a pixel is a corner when 9 contiguous pixels
 * of the 16-pixel Bresenham circle of radius 3 are all brighter than
 * centre + t or all darker than centre - t. Any such arc contains one of the
 * opposite compass points 0/8 and two neighbouring compass points of
 * 0/4/8/12, which rejects most pixels after two or four reads. The score is
 * the largest t for which the pixel stays a corner: the maximum over the 16
 * arcs of the minimum absolute difference along the arc, taken in the arc's
 * direction.
 */
#include "features/fast.h"

#include <string.h>

/* Circle points in order, starting above the centre, clockwise in image
 * coordinates (y down). */
static const signed char circle_dx[16] = {0, 1, 2, 3, 3, 3, 2, 1, 0, -1, -2, -3, -3, -3, -2, -1};
static const signed char circle_dy[16] = {-3, -3, -2, -1, 0, 1, 2, 3, 3, 3, 2, 1, 0, -1, -2, -3};

/* Compass pre-test for 16 consecutive pixels: out[k] = 1 when two cyclically
 * neighbouring points of 0/4/8/12 are both brighter than c + t or both darker
 * than c - t (necessary for a 9-arc). Fixed trip count and byte types so that
 * compilers vectorise it without target flags. */
static void compass16(const uint8_t *restrict p, int stride, uint8_t t, uint8_t *restrict out)
{
    const uint8_t *n = p - 3 * stride, *e = p + 3, *s = p + 3 * stride, *w = p - 3;
    const uint8_t top = (uint8_t)(255 - t);
    for (int k = 0; k < 16; k++) {
        const uint8_t c = p[k];
        const uint8_t hi = (uint8_t)(c > top ? 255 : c + t);
        const uint8_t lo = (uint8_t)(c < t ? 0 : c - t);
        const uint8_t v0 = n[k], v4 = e[k], v8 = s[k], v12 = w[k];
        const uint8_t b0 = v0 > hi, b4 = v4 > hi, b8 = v8 > hi, b12 = v12 > hi;
        const uint8_t d0 = v0 < lo, d4 = v4 < lo, d8 = v8 < lo, d12 = v12 < lo;
        out[k] = (uint8_t)((b0 & b4) | (b4 & b8) | (b8 & b12) | (b12 & b0) | (d0 & d4) | (d4 & d8) |
                           (d8 & d12) | (d12 & d0));
    }
}

/* FAST score for 16 consecutive pixels in byte lanes: out[k] is the
 * maximum over both polarities and the 16 arcs of the minimum difference
 * along the arc, with differences saturated at 0. Pixel k is a corner at
 * threshold t exactly when out[k] > t, and then out[k] is its score (a
 * polarity without a 9-arc at t scores at most t, below one with an arc).
 * Sliding minima double the window (2, 4, 8; 9 as two overlapping 8s) on a
 * cyclic table whose first rows are repeated past row 15 before each step;
 * fixed trip counts and byte types so that compilers vectorise it without
 * target flags. */
static void score16(const uint8_t *restrict p, const int *restrict off, uint8_t *restrict out)
{
    uint8_t b[20][16], d[20][16], best[16];
    for (int j = 0; j < 16; j++) {
        const uint8_t *restrict q = p + off[j];
        for (int k = 0; k < 16; k++) {
            const uint8_t c = p[k], v = q[k];
            const uint8_t mx = v > c ? v : c, mn = v < c ? v : c;
            b[j][k] = (uint8_t)(mx - c);
            d[j][k] = (uint8_t)(c - mn);
        }
    }
    /* window minima of 2, 4, 8 in place: row j then holds the minimum of
     * circle points j .. j + len - 1 (cyclic: rows 16.. repeat rows 0..
     * before each step); the 9-window is two overlapping 8-windows */
    memcpy(b[16], b[0], 16);
    memcpy(d[16], d[0], 16);
    for (int j = 0; j < 16; j++)
        for (int k = 0; k < 16; k++) {
            b[j][k] = b[j][k] < b[j + 1][k] ? b[j][k] : b[j + 1][k];
            d[j][k] = d[j][k] < d[j + 1][k] ? d[j][k] : d[j + 1][k];
        }
    memcpy(b[16], b[0], 32);
    memcpy(d[16], d[0], 32);
    for (int j = 0; j < 16; j++)
        for (int k = 0; k < 16; k++) {
            b[j][k] = b[j][k] < b[j + 2][k] ? b[j][k] : b[j + 2][k];
            d[j][k] = d[j][k] < d[j + 2][k] ? d[j][k] : d[j + 2][k];
        }
    memcpy(b[16], b[0], 64);
    memcpy(d[16], d[0], 64);
    for (int j = 0; j < 16; j++)
        for (int k = 0; k < 16; k++) {
            b[j][k] = b[j][k] < b[j + 4][k] ? b[j][k] : b[j + 4][k];
            d[j][k] = d[j][k] < d[j + 4][k] ? d[j][k] : d[j + 4][k];
        }
    memcpy(b[16], b[0], 16);
    memcpy(d[16], d[0], 16);
    for (int k = 0; k < 16; k++)
        best[k] = 0;
    for (int j = 0; j < 16; j++)
        for (int k = 0; k < 16; k++) {
            const uint8_t mb = b[j][k] < b[j + 1][k] ? b[j][k] : b[j + 1][k];
            const uint8_t md = d[j][k] < d[j + 1][k] ? d[j][k] : d[j + 1][k];
            const uint8_t m = mb > md ? mb : md;
            best[k] = best[k] > m ? best[k] : m;
        }
    for (int k = 0; k < 16; k++)
        out[k] = best[k];
}

/* The same score for one pixel, circle points in byte lanes; 0 when the
 * pixel is no corner at threshold t. */
static uint8_t score1(const uint8_t *p, const int *off, int t)
{
    const uint8_t c = p[0];
    uint8_t b[20], d[20];
    for (int j = 0; j < 16; j++) {
        const uint8_t v = p[off[j]];
        b[j] = v;
        d[j] = v;
    }
    for (int j = 0; j < 16; j++) {
        const uint8_t mx = b[j] > c ? b[j] : c, mn = d[j] < c ? d[j] : c;
        b[j] = (uint8_t)(mx - c);
        d[j] = (uint8_t)(c - mn);
    }
    memcpy(b + 16, b, 1);
    memcpy(d + 16, d, 1);
    for (int j = 0; j < 16; j++) {
        b[j] = b[j] < b[j + 1] ? b[j] : b[j + 1];
        d[j] = d[j] < d[j + 1] ? d[j] : d[j + 1];
    }
    memcpy(b + 16, b, 2);
    memcpy(d + 16, d, 2);
    for (int j = 0; j < 16; j++) {
        b[j] = b[j] < b[j + 2] ? b[j] : b[j + 2];
        d[j] = d[j] < d[j + 2] ? d[j] : d[j + 2];
    }
    memcpy(b + 16, b, 4);
    memcpy(d + 16, d, 4);
    for (int j = 0; j < 16; j++) {
        b[j] = b[j] < b[j + 4] ? b[j] : b[j + 4];
        d[j] = d[j] < d[j + 4] ? d[j] : d[j + 4];
    }
    b[16] = b[0];
    d[16] = d[0];
    uint8_t best = 0;
    for (int j = 0; j < 16; j++) {
        const uint8_t mb = b[j] < b[j + 1] ? b[j] : b[j + 1];
        const uint8_t md = d[j] < d[j + 1] ? d[j] : d[j + 1];
        const uint8_t m = mb > md ? mb : md;
        best = best > m ? best : m;
    }
    return (uint8_t)(best > t ? best : 0);
}

/* 1 when the 16-bit cyclic mask holds 9 contiguous set bits. */
static int has_arc9(unsigned m)
{
    unsigned x = m | (m << 16);
    unsigned r2 = x & (x >> 1);
    unsigned r4 = r2 & (r2 >> 2);
    unsigned r8 = r4 & (r4 >> 4);
    unsigned r9 = r8 & (x >> 8);
    return (r9 & 0xFFFFu) != 0;
}

static uint8_t full_test(const uint8_t *p, const int *off, int t)
{
    const int c = p[0], hi = c + t, lo = c - t;
    unsigned mb = 0, md = 0;
    for (int k = 0; k < 16; k++) {
        int v = p[off[k]];
        mb |= (unsigned)(v > hi) << k;
        md |= (unsigned)(v < lo) << k;
    }
    return (has_arc9(mb) | has_arc9(md)) ? score1(p, off, t) : 0;
}

/* Blocks with at most this many compass candidates test them one by one:
 * the exact segment test on bit masks first, the byte-lane score only for
 * corners (its byte stores feeding wide loads cost more time than
 * instructions suggest). Measured on Herz-Jesu-P8 (thread CPU time): 2 was
 * at least as fast as 0, 1, 3 and 6. */
#define CANDS_SCALAR 2

void sfmi_feat_fast_row(const uint8_t *img, int stride, int y, int x0, int x1, int t, uint8_t *score)
{
    int off[16];
    for (int k = 0; k < 16; k++)
        off[k] = circle_dy[k] * stride + circle_dx[k];
    const uint8_t *row = img + (long)y * stride;
    int x = x0;
    for (; x + 16 <= x1; x += 16) {
        uint8_t m[16];
        compass16(row + x, stride, (uint8_t)t, m);
        uint64_t lo8, hi8;
        memcpy(&lo8, m, 8);
        memcpy(&hi8, m + 8, 8);
        memset(score + x, 0, 16);
        if ((lo8 | hi8) == 0)
            continue;
        /* few candidates: test them one by one; many: score all 16 at once */
        const uint64_t ones = 0x0101010101010101ULL;
        const int cands = (int)(((lo8 + hi8) * ones) >> 56);
        if (cands <= CANDS_SCALAR) {
            for (int k = 0; k < 16; k++)
                if (m[k])
                    score[x + k] = full_test(row + x + k, off, t);
            continue;
        }
        uint8_t s[16];
        score16(row + x, off, s);
        for (int k = 0; k < 16; k++)
            score[x + k] = (uint8_t)(s[k] > t ? s[k] : 0);
    }
    for (; x < x1; x++) {
        const uint8_t *p = row + x;
        const int c = p[0];
        const int hi = c + t, lo = c - t;
        score[x] = 0;
        const int v0 = p[off[0]], v8 = p[off[8]];
        if (!(v0 > hi || v0 < lo || v8 > hi || v8 < lo))
            continue;
        score[x] = full_test(p, off, t);
    }
}
