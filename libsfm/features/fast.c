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

/* Largest m such that some cyclic arc of 9 values of d[] is >= m everywhere:
 * window minima of 2, 4, 8, then 9 by doubling. */
static int best_arc_min(const int *d)
{
    int m2[16], m4[16], best = -256;
    for (int k = 0; k < 16; k++)
        m2[k] = d[k] < d[(k + 1) & 15] ? d[k] : d[(k + 1) & 15];
    for (int k = 0; k < 16; k++)
        m4[k] = m2[k] < m2[(k + 2) & 15] ? m2[k] : m2[(k + 2) & 15];
    for (int k = 0; k < 16; k++) {
        int m8 = m4[k] < m4[(k + 4) & 15] ? m4[k] : m4[(k + 4) & 15];
        int v = d[(k + 8) & 15];
        int m9 = m8 < v ? m8 : v;
        best = m9 > best ? m9 : best;
    }
    return best;
}

/* flags: bit 0 brighter arc present, bit 1 darker arc present. */
static int fast_score(const uint8_t *p, const int *off, unsigned flags)
{
    const int c = p[0];
    int d[16];
    int s = 0;
    if (flags & 1u) {
        for (int k = 0; k < 16; k++)
            d[k] = p[off[k]] - c;
        s = best_arc_min(d);
    }
    if (flags & 2u) {
        for (int k = 0; k < 16; k++)
            d[k] = c - p[off[k]];
        int b = best_arc_min(d);
        s = b > s ? b : s;
    }
    s = s > 255 ? 255 : s;
    return s < 1 ? 1 : s;
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

static uint8_t full_test(const uint8_t *p, const int *off, int t)
{
    const int c = p[0], hi = c + t, lo = c - t;
    unsigned mb = 0, md = 0;
    for (int k = 0; k < 16; k++) {
        int v = p[off[k]];
        mb |= (unsigned)(v > hi) << k;
        md |= (unsigned)(v < lo) << k;
    }
    unsigned flags = (unsigned)has_arc9(mb) | (unsigned)has_arc9(md) << 1;
    return flags ? (uint8_t)fast_score(p, off, flags) : 0;
}

/* FAST score for 16 consecutive pixels in byte lanes: out[k] is the largest
 * t' such that pixel k has a 9-arc brighter than c + t' or darker than
 * c - t' (saturating differences: a polarity without an arc scores at most
 * the threshold, below any polarity with one, so the maximum over both is
 * the score of fast_score whenever the pixel is a corner, and at most t
 * otherwise). The circle is unrolled to 24 rows so that arcs need no wrap;
 * fixed trip counts and byte types so that compilers vectorise it. */
static void score16(const uint8_t *restrict p, const int *restrict off, uint8_t *restrict out)
{
    uint8_t b[24][16], d[24][16], best[16];
    for (int j = 0; j < 24; j++) {
        const uint8_t *restrict q = p + off[j & 15];
        for (int k = 0; k < 16; k++) {
            const uint8_t c = p[k], v = q[k];
            b[j][k] = (uint8_t)(v > c ? v - c : 0);
            d[j][k] = (uint8_t)(c > v ? c - v : 0);
        }
    }
    for (int k = 0; k < 16; k++)
        best[k] = 0;
    /* window minima of 2, 4, 8 then 9, in place: row j holds the minimum of
     * rows j .. j + len - 1 of the input */
    for (int j = 0; j < 23; j++)
        for (int k = 0; k < 16; k++) {
            b[j][k] = b[j][k] < b[j + 1][k] ? b[j][k] : b[j + 1][k];
            d[j][k] = d[j][k] < d[j + 1][k] ? d[j][k] : d[j + 1][k];
        }
    for (int j = 0; j < 21; j++)
        for (int k = 0; k < 16; k++) {
            b[j][k] = b[j][k] < b[j + 2][k] ? b[j][k] : b[j + 2][k];
            d[j][k] = d[j][k] < d[j + 2][k] ? d[j][k] : d[j + 2][k];
        }
    for (int j = 0; j < 16; j++)
        for (int k = 0; k < 16; k++) {
            uint8_t mb = b[j][k] < b[j + 4][k] ? b[j][k] : b[j + 4][k];
            uint8_t md = d[j][k] < d[j + 4][k] ? d[j][k] : d[j + 4][k];
            /* the ninth point of the arc starting at j is j + 8 */
            const uint8_t c = p[k], v = p[off[(j + 8) & 15] + k];
            const uint8_t eb = (uint8_t)(v > c ? v - c : 0), ed = (uint8_t)(c > v ? c - v : 0);
            mb = mb < eb ? mb : eb;
            md = md < ed ? md : ed;
            const uint8_t m = mb > md ? mb : md;
            best[k] = best[k] > m ? best[k] : m;
        }
    for (int k = 0; k < 16; k++)
        out[k] = best[k];
}

/* Blocks with at most this many compass candidates test them one by one
 * (measured on Herz-Jesu-P8: 1 and 6 cost more instructions than 3). */
#define CANDS_SCALAR 3

void sfm_feat_fast_row(const uint8_t *img, int stride, int y, int x0, int x1, int t, uint8_t *score)
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
