/*
 * Image pyramid for the feature detector: fixed scale step, each level
 * resampled bilinearly from the one above (as ORB's pyramid), and the 5-tap
 * Gaussian used before sampling binary descriptors (BRIEF smooths the patch
 * before its intensity tests; see the kernel below for the chosen sigma).
 */
#include "features/pyramid.h"

#include "sfm/sfm_features.h"

int sfmi_feat_level_sizes(int w0, int h0, int n_levels, double scale_factor, int *w, int *h)
{
    const int min_side = 2 * SFM_FEATURES_BORDER + 1;
    double s = 1.0;
    int n = 0;
    for (int l = 0; l < n_levels; l++) {
        int wl = l == 0 ? w0 : (int)((double)w0 / s + 0.5);
        int hl = l == 0 ? h0 : (int)((double)h0 / s + 0.5);
        if (wl < min_side || hl < min_side)
            break;
        w[l] = wl;
        h[l] = hl;
        n++;
        s *= scale_factor;
    }
    return n;
}

/* Vertical blend of two rows for 16 columns in 16-bit lanes (fixed trip
 * count: vectorised without target flags). */
static void vblend16(const uint8_t *restrict r0, const uint8_t *restrict r1, uint16_t wy, uint16_t *restrict out)
{
    const uint16_t w0 = (uint16_t)(256u - wy);
    for (int k = 0; k < 16; k++)
        out[k] = (uint16_t)(r0[k] * w0 + r1[k] * wy);
}

/* The source taps of output coordinate i at scale r, pixel centres aligned:
 * returns the left index, clamped to [0, size - 2], and *w the weight of the
 * right one, clamped to [0, 1]. */
static int tap(int i, double r, int size, double *w)
{
    double f = ((double)i + 0.5) * r - 0.5;
    if (f < 0.0)
        f = 0.0;
    int i0 = (int)f;
    if (i0 > size - 2)
        i0 = size - 2;
    double a = f - (double)i0;
    if (a > 1.0)
        a = 1.0;
    *w = a;
    return i0;
}

void sfmi_feat_resize(const uint8_t *src, int sw, int sh, int sstride,
                     uint8_t *dst, int dw, int dh, int32_t *xofs, uint16_t *xw, uint16_t *row)
{
    const double rx = (double)sw / (double)dw, ry = (double)sh / (double)dh;
    for (int x = 0; x < dw; x++) {
        double a;
        xofs[x] = tap(x, rx, sw, &a);
        xw[x] = (uint16_t)(a * 256.0 + 0.5);
    }
    for (int y = 0; y < dh; y++) {
        double b;
        const int y0 = tap(y, ry, sh, &b);
        const uint32_t wy = (uint32_t)(b * 256.0 + 0.5);
        const uint8_t *r0 = src + (size_t)y0 * (size_t)sstride;
        const uint8_t *r1 = r0 + sstride;
        /* vertical pass over the source columns, then horizontal taps */
        int x = 0;
        for (; x + 16 <= sw; x += 16)
            vblend16(r0 + x, r1 + x, (uint16_t)wy, row + x);
        for (; x < sw; x++)
            row[x] = (uint16_t)(r0[x] * (256u - wy) + r1[x] * wy);
        uint8_t *d = dst + (size_t)y * (size_t)dw;
        /* a (256 - w) + b w = 256 a + (b - a) w, exactly, in one product */
        for (x = 0; x < dw; x++) {
            const int o = xofs[x];
            const int32_t p0 = row[o], p1 = row[o + 1];
            d[x] = (uint8_t)((p0 * 256 + (p1 - p0) * (int32_t)xw[x] + 32768) >> 16);
        }
    }
}

/* exp(-k^2 / 4.5) for k = -2..2 (sigma 1.5), scaled to sum 256. Measured on
 * Herz-Jesu-P8: sigma 1.5 gave a higher share of epipolar-consistent matches
 * than sigma 2 (7 taps) or sigma 1, at fewer operations than sigma 2. */
#define G0 76u
#define G1 60u
#define G2 30u

/* Vertical taps for 16 columns; each sum is at most 256 * 255 + 128, so
 * 16-bit lanes suffice (fixed trip count: vectorised without target flags). */
static void vpass16(const uint8_t *restrict const *r, int x, uint8_t *restrict tmp)
{
    const uint8_t *restrict a = r[0] + x, *restrict b = r[1] + x, *restrict c = r[2] + x, *restrict d = r[3] + x,
                            *restrict e = r[4] + x;
    for (int k = 0; k < 16; k++) {
        uint16_t s = (uint16_t)(G2 * (uint16_t)(a[k] + e[k]) + G1 * (uint16_t)(b[k] + d[k]) + G0 * (uint16_t)c[k] + 128u);
        tmp[x + k] = (uint8_t)(s >> 8);
    }
}

static void hpass16(const uint8_t *restrict p, uint8_t *restrict d)
{
    for (int k = 0; k < 16; k++) {
        uint16_t s = (uint16_t)(G2 * (uint16_t)(p[k] + p[k + 4]) + G1 * (uint16_t)(p[k + 1] + p[k + 3]) +
                                G0 * (uint16_t)p[k + 2] + 128u);
        d[k] = (uint8_t)(s >> 8);
    }
}

static uint8_t vtap(const uint8_t *const *r, int x)
{
    uint32_t s = G2 * ((uint32_t)r[0][x] + r[4][x]) + G1 * ((uint32_t)r[1][x] + r[3][x]) + G0 * (uint32_t)r[2][x];
    return (uint8_t)((s + 128u) >> 8);
}

void sfmi_feat_smooth(const uint8_t *src, int w, int h, int sstride, uint8_t *dst, uint8_t *tmp)
{
    static const uint32_t g[5] = {G2, G1, G0, G1, G2};
    for (int y = 0; y < h; y++) {
        const uint8_t *r[5];
        for (int k = -2; k <= 2; k++) {
            int yy = y + k;
            yy = yy < 0 ? 0 : (yy >= h ? h - 1 : yy);
            r[k + 2] = src + (size_t)yy * (size_t)sstride;
        }
        int x = 0;
        for (; x + 16 <= w; x += 16)
            vpass16(r, x, tmp);
        for (; x < w; x++)
            tmp[x] = vtap(r, x);
        uint8_t *d = dst + (size_t)y * (size_t)w;
        /* interior: columns [2, w - 2) read tmp[x - 2 .. x + 2] */
        x = 2;
        for (; x + 16 <= w - 2; x += 16)
            hpass16(tmp + x - 2, d + x);
        for (; x < w - 2; x++) {
            uint32_t s = 0;
            for (int k = -2; k <= 2; k++)
                s += g[k + 2] * tmp[x + k];
            d[x] = (uint8_t)((s + 128u) >> 8);
        }
        for (x = 0; x < w; x++) {
            if (x == 2 && w - 2 > 2)
                x = w - 2; /* interior done above */
            uint32_t s = 0;
            for (int k = -2; k <= 2; k++) {
                int xx = x + k;
                xx = xx < 0 ? 0 : (xx >= w ? w - 1 : xx);
                s += g[k + 2] * tmp[xx];
            }
            d[x] = (uint8_t)((s + 128u) >> 8);
        }
    }
}
