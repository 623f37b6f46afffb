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

/* Exact segment test for 16 consecutive pixels: out[k] bit 0 when pixel k
 * has a brighter 9-arc, bit 1 a darker one. Each circle point is read for
 * the 16 pixels at once (contiguous bytes), building 16-bit cyclic masks;
 * the 9-run test doubles runs on 32-bit copies (m | m << 16). */
static void segment16(const uint8_t *restrict p, const int *restrict off, uint8_t t, uint8_t *restrict out)
{
    uint8_t hi[16], lo[16];
    uint16_t mb[16], md[16];
    const uint8_t top = (uint8_t)(255 - t);
    for (int k = 0; k < 16; k++) {
        const uint8_t c = p[k];
        hi[k] = (uint8_t)(c > top ? 255 : c + t);
        lo[k] = (uint8_t)(c < t ? 0 : c - t);
        mb[k] = 0;
        md[k] = 0;
    }
    for (int j = 0; j < 16; j++) {
        const uint8_t *restrict q = p + off[j];
        const uint16_t bit = (uint16_t)(1u << j);
        for (int k = 0; k < 16; k++) {
            mb[k] |= q[k] > hi[k] ? bit : 0;
            md[k] |= q[k] < lo[k] ? bit : 0;
        }
    }
    for (int k = 0; k < 16; k++) {
        uint32_t x = (uint32_t)mb[k] | ((uint32_t)mb[k] << 16);
        uint32_t y = (uint32_t)md[k] | ((uint32_t)md[k] << 16);
        uint32_t r = x & (x >> 1), q = y & (y >> 1);
        r &= r >> 2;
        q &= q >> 2;
        r &= r >> 4;
        q &= q >> 4;
        r &= x >> 8;
        q &= y >> 8;
        out[k] = (uint8_t)((unsigned)((r & 0xFFFFu) != 0) | (unsigned)((q & 0xFFFFu) != 0) << 1);
    }
}

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
        /* few candidates: test them one by one; many: all 16 at once */
        const uint64_t ones = 0x0101010101010101ULL;
        const int cands = (int)(((lo8 + hi8) * ones) >> 56);
        if (cands <= 3) {
            for (int k = 0; k < 16; k++)
                if (m[k])
                    score[x + k] = full_test(row + x + k, off, t);
            continue;
        }
        segment16(row + x, off, (uint8_t)t, m);
        for (int k = 0; k < 16; k++)
            if (m[k])
                score[x + k] = (uint8_t)fast_score(row + x + k, off, m[k]);
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
