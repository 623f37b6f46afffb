/*
 * Image pyramid for the feature detector: fixed scale step, each level
 * resampled bilinearly from the one above (as ORB's pyramid), and the 7-tap
 * Gaussian used before sampling binary descriptors (BRIEF smooths with a
 * Gaussian of sigma about 2 over the 31x31 patch).
 */
#include "features/pyramid.h"

#include "sfm/sfm_features.h"

int sfm_feat_level_sizes(int w0, int h0, int n_levels, double scale_factor, int *w, int *h)
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

void sfm_feat_resize(const uint8_t *src, int sw, int sh, int sstride,
                     uint8_t *dst, int dw, int dh, int32_t *xofs, uint16_t *xw, uint16_t *row)
{
    const double rx = (double)sw / (double)dw, ry = (double)sh / (double)dh;
    for (int x = 0; x < dw; x++) {
        double fx = ((double)x + 0.5) * rx - 0.5;
        if (fx < 0.0)
            fx = 0.0;
        int x0 = (int)fx;
        if (x0 > sw - 2)
            x0 = sw - 2;
        double a = fx - (double)x0;
        if (a > 1.0)
            a = 1.0;
        xofs[x] = x0;
        xw[x] = (uint16_t)(a * 256.0 + 0.5);
    }
    for (int y = 0; y < dh; y++) {
        double fy = ((double)y + 0.5) * ry - 0.5;
        if (fy < 0.0)
            fy = 0.0;
        int y0 = (int)fy;
        if (y0 > sh - 2)
            y0 = sh - 2;
        double b = fy - (double)y0;
        if (b > 1.0)
            b = 1.0;
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
        for (x = 0; x < dw; x++) {
            const int o = xofs[x];
            const uint32_t wx = xw[x];
            d[x] = (uint8_t)(((uint32_t)row[o] * (256u - wx) + (uint32_t)row[o + 1] * wx + 32768u) >> 16);
        }
    }
}

/* exp(-k^2 / 8) for k = -3..3 (sigma 2), scaled to sum 256. */
#define G0 54u
#define G1 49u
#define G2 34u
#define G3 18u

/* Vertical taps for 16 columns; each sum is at most 256 * 255 + 128, so
 * 16-bit lanes suffice (fixed trip count: vectorised without target flags). */
static void vpass16(const uint8_t *restrict const *r, int x, uint8_t *restrict tmp)
{
    const uint8_t *restrict a = r[0] + x, *restrict b = r[1] + x, *restrict c = r[2] + x, *restrict d = r[3] + x,
                            *restrict e = r[4] + x, *restrict f = r[5] + x, *restrict g = r[6] + x;
    for (int k = 0; k < 16; k++) {
        uint16_t s = (uint16_t)(G3 * (uint16_t)(a[k] + g[k]) + G2 * (uint16_t)(b[k] + f[k]) +
                                G1 * (uint16_t)(c[k] + e[k]) + G0 * (uint16_t)d[k] + 128u);
        tmp[x + k] = (uint8_t)(s >> 8);
    }
}

static void hpass16(const uint8_t *restrict p, uint8_t *restrict d)
{
    for (int k = 0; k < 16; k++) {
        uint16_t s = (uint16_t)(G3 * (uint16_t)(p[k] + p[k + 6]) + G2 * (uint16_t)(p[k + 1] + p[k + 5]) +
                                G1 * (uint16_t)(p[k + 2] + p[k + 4]) + G0 * (uint16_t)p[k + 3] + 128u);
        d[k] = (uint8_t)(s >> 8);
    }
}

static uint8_t vtap(const uint8_t *const *r, int x)
{
    uint32_t s = G3 * ((uint32_t)r[0][x] + r[6][x]) + G2 * ((uint32_t)r[1][x] + r[5][x]) +
                 G1 * ((uint32_t)r[2][x] + r[4][x]) + G0 * (uint32_t)r[3][x];
    return (uint8_t)((s + 128u) >> 8);
}

void sfm_feat_smooth(const uint8_t *src, int w, int h, int sstride, uint8_t *dst, uint8_t *tmp)
{
    static const uint32_t g[7] = {G3, G2, G1, G0, G1, G2, G3};
    for (int y = 0; y < h; y++) {
        const uint8_t *r[7];
        for (int k = -3; k <= 3; k++) {
            int yy = y + k;
            yy = yy < 0 ? 0 : (yy >= h ? h - 1 : yy);
            r[k + 3] = src + (size_t)yy * (size_t)sstride;
        }
        int x = 0;
        for (; x + 16 <= w; x += 16)
            vpass16(r, x, tmp);
        for (; x < w; x++)
            tmp[x] = vtap(r, x);
        uint8_t *d = dst + (size_t)y * (size_t)w;
        /* interior: columns [3, w - 3) read tmp[x - 3 .. x + 3] */
        x = 3;
        for (; x + 16 <= w - 3; x += 16)
            hpass16(tmp + x - 3, d + x);
        for (; x < w - 3; x++) {
            uint32_t s = 0;
            for (int k = -3; k <= 3; k++)
                s += g[k + 3] * tmp[x + k];
            d[x] = (uint8_t)((s + 128u) >> 8);
        }
        for (x = 0; x < w; x++) {
            if (x == 3 && w - 3 > 3)
                x = w - 3; /* interior done above */
            uint32_t s = 0;
            for (int k = -3; k <= 3; k++) {
                int xx = x + k;
                xx = xx < 0 ? 0 : (xx >= w ? w - 1 : xx);
                s += g[k + 3] * tmp[xx];
            }
            d[x] = (uint8_t)((s + 128u) >> 8);
        }
    }
}
