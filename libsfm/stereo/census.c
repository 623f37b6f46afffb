/*
 * Centre-symmetric census transform over a 9x7 window: one bit per pair of
 * pixels placed symmetrically about the centre, set when the pixel of the
 * pair below or right of the centre is brighter (Spangenberg, Langner,
 * Rojas, "Weighted semi-global matching and center-symmetric census
 * transform for robust driver assistance", CAIP 2013). 31 bits, kept as
 * two 16-bit planes (pairs 0-15 and 16-30) so that costs are computed in
 * 16-bit lanes. Borders replicate the edge pixels.
 */
#include "stereo/stereo_census.h"
#include "stereo/stereo_internal.h"

#define RX 4
#define RY 3

typedef uint8_t v8u8 __attribute__((vector_size(8)));

static int clampi(int v, int lo, int hi)
{
    return v < lo ? lo : (v > hi ? hi : v);
}

static inline sfmi_v16 load8(const uint8_t *p)
{
    v8u8 b;
    memcpy(&b, p, sizeof b);
    return __builtin_convertvector(b, sfmi_v16);
}

static void census_pixel(const uint8_t *img, int w, int h, int stride, int x, int y, uint16_t *lo,
                         uint16_t *hi)
{
    uint32_t bits = 0;
    int k = 0;
    uint32_t l = 0;
    for (int dy = 0; dy <= RY; dy++) {
        for (int dx = dy == 0 ? 1 : -RX; dx <= RX; dx++) {
            int a = img[(size_t)clampi(y + dy, 0, h - 1) * stride + clampi(x + dx, 0, w - 1)];
            int b = img[(size_t)clampi(y - dy, 0, h - 1) * stride + clampi(x - dx, 0, w - 1)];
            bits = (bits << 1) | (uint32_t)(a > b);
            if (++k == 16) {
                l = bits;
                bits = 0;
            }
        }
    }
    *lo = (uint16_t)l;
    *hi = (uint16_t)bits;
}

typedef uint8_t v16u8 __attribute__((vector_size(16)));

static inline v16u8 load16(const uint8_t *p)
{
    v16u8 b;
    memcpy(&b, p, sizeof b);
    return b;
}

/* Sixteen interior pixels: the comparisons in 8-bit lanes, four bytes of
 * bits per pixel (pairs 0-7, 8-15, 16-23, 24-30, first pair highest), then
 * lo = A << 8 | B and hi = C << 7 | E in 16-bit lanes. acc + acc - m
 * shifts a bit in: m is all ones where the comparison holds. */
static void census16(const uint8_t *c, int stride, uint16_t *lo, uint16_t *hi)
{
    v16u8 acc[4] = {{0}, {0}, {0}, {0}};
    int k = 0;
    for (int dy = 0; dy <= RY; dy++) {
        for (int dx = dy == 0 ? 1 : -RX; dx <= RX; dx++, k++) {
            v16u8 a = load16(c + (ptrdiff_t)dy * stride + dx);
            v16u8 b = load16(c - (ptrdiff_t)dy * stride - dx);
            v16u8 m = (v16u8)(a > b);
            acc[k >> 3] = acc[k >> 3] + acc[k >> 3] - m;
        }
    }
    uint8_t A[16], B[16], C[16], E[16];
    memcpy(A, &acc[0], 16);
    memcpy(B, &acc[1], 16);
    memcpy(C, &acc[2], 16);
    memcpy(E, &acc[3], 16);
    for (int i = 0; i < 16; i += 8) {
        sfmi_v16 a = load8(A + i), b = load8(B + i), cc = load8(C + i), e = load8(E + i);
        sfmi_v16 l = (sfmi_v16)(((sfmi_u16)a << 8) | (sfmi_u16)b);
        sfmi_v16 u = (sfmi_v16)(((sfmi_u16)cc << 7) | (sfmi_u16)e);
        memcpy(lo + i, &l, sizeof l);
        memcpy(hi + i, &u, sizeof u);
    }
}

void sfmi_stereo_census_row(const uint8_t *img, int w, int h, int stride, int y, uint16_t *lo,
                            uint16_t *hi)
{
    const sfmi_v16 one = sfmi_v16_splat(1);
    int x = 0;
    if (y >= RY && y < h - RY) {
        for (; x < RX; x++)
            census_pixel(img, w, h, stride, x, y, lo + x, hi + x);
        /* Interior: sixteen pixels at a time, then eight. */
        for (; x + 16 <= w - RX; x += 16)
            census16(img + (size_t)y * stride + x, stride, lo + x, hi + x);
        for (; x + 8 <= w - RX; x += 8) {
            const uint8_t *c = img + (size_t)y * stride + x;
            sfmi_v16 bits = sfmi_v16_splat(0), first = bits;
            int k = 0;
            for (int dy = 0; dy <= RY; dy++) {
                for (int dx = dy == 0 ? 1 : -RX; dx <= RX; dx++) {
                    sfmi_v16 a = load8(c + (ptrdiff_t)dy * stride + dx);
                    sfmi_v16 b = load8(c - (ptrdiff_t)dy * stride - dx);
                    bits = (sfmi_v16)(((sfmi_u16)bits << 1) | (sfmi_u16)((a > b) & one));
                    if (++k == 16) {
                        first = bits;
                        bits = sfmi_v16_splat(0);
                    }
                }
            }
            memcpy(lo + x, &first, sizeof first);
            memcpy(hi + x, &bits, sizeof bits);
        }
    }
    for (; x < w; x++)
        census_pixel(img, w, h, stride, x, y, lo + x, hi + x);
}
