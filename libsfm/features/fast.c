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

/* Circle points in order, starting above the centre, clockwise in image
 * coordinates (y down). */
static const signed char circle_dx[16] = {0, 1, 2, 3, 3, 3, 2, 1, 0, -1, -2, -3, -3, -3, -2, -1};
static const signed char circle_dy[16] = {-3, -3, -2, -1, 0, 1, 2, 3, 3, 3, 2, 1, 0, -1, -2, -3};

/* Largest m such that some cyclic arc of 9 values of d[] is >= m everywhere. */
static int best_arc_min(const int *d)
{
    int best = -256;
    /* minima of windows of 8, then extend by one */
    for (int k = 0; k < 16; k++) {
        int m = d[k];
        for (int j = 1; j < 9; j++) {
            int v = d[(k + j) & 15];
            m = v < m ? v : m;
        }
        best = m > best ? m : best;
    }
    return best;
}

static int fast_score(const uint8_t *p, const int *off)
{
    const int c = p[0];
    int up[16], dn[16];
    for (int k = 0; k < 16; k++) {
        int v = p[off[k]];
        up[k] = v - c;
        dn[k] = c - v;
    }
    int a = best_arc_min(up), b = best_arc_min(dn);
    int s = a > b ? a : b;
    return s > 255 ? 255 : s;
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

void sfm_feat_fast_row(const uint8_t *img, int stride, int y, int x0, int x1, int t, uint8_t *score)
{
    int off[16];
    for (int k = 0; k < 16; k++)
        off[k] = circle_dy[k] * stride + circle_dx[k];
    const uint8_t *row = img + (long)y * stride;
    for (int x = x0; x < x1; x++) {
        const uint8_t *p = row + x;
        const int c = p[0];
        const int hi = c + t, lo = c - t;
        score[x] = 0;
        const int v0 = p[off[0]], v8 = p[off[8]];
        if (!(v0 > hi || v0 < lo || v8 > hi || v8 < lo))
            continue;
        const int v4 = p[off[4]], v12 = p[off[12]];
        unsigned b = (unsigned)(v0 > hi) | (unsigned)(v4 > hi) << 1 | (unsigned)(v8 > hi) << 2 | (unsigned)(v12 > hi) << 3;
        unsigned d = (unsigned)(v0 < lo) | (unsigned)(v4 < lo) << 1 | (unsigned)(v8 < lo) << 2 | (unsigned)(v12 < lo) << 3;
        /* two cyclically neighbouring compass points of the same kind */
        unsigned bb = b & ((b >> 1) | (b << 3)), dd = d & ((d >> 1) | (d << 3));
        if (((bb | dd) & 15u) == 0)
            continue;
        unsigned mb = 0, md = 0;
        for (int k = 0; k < 16; k++) {
            int v = p[off[k]];
            mb |= (unsigned)(v > hi) << k;
            md |= (unsigned)(v < lo) << k;
        }
        if (!has_arc9(mb) && !has_arc9(md))
            continue;
        int s = fast_score(p, off);
        score[x] = (uint8_t)(s < 1 ? 1 : s);
    }
}
