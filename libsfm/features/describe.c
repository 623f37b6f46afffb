/*
 * Oriented binary descriptor.
 *
 * Orientation: Rosin, "Measuring corner properties", CVIU 1999: the intensity
 * centroid of a disc, m10 = sum u I(u, v), m01 = sum v I(u, v); the angle is
 * atan2(m01, m10). Only the unit vector is needed to steer the pattern, so no
 * trigonometry runs per keypoint (the angle reported to callers is computed
 * once from it).
 *
 * Descriptor: BRIEF (Calonder et al., ECCV 2010) sampled on a smoothed image,
 * steered by the orientation as in ORB (Rublee et al., ICCV 2011): each point
 * of the pattern is rotated and rounded to the nearest pixel.
 */
#include "features/describe.h"

#include <math.h>
#include <stddef.h>

#include "features/brief_pattern.h"
#include "core/dmath.h"

/* floor(sqrt(15^2 - v^2)) for v = 0..15: the half-width of the disc rows. */
static const signed char disc_umax[16] = {15, 14, 14, 14, 14, 14, 13, 13, 12, 12, 11, 10, 9, 7, 5, 0};

void sfmi_feat_disc_mask(uint8_t *mask)
{
    for (int v = -15; v <= 15; v++) {
        const int um = disc_umax[v < 0 ? -v : v];
        for (int k = 0; k < 32; k++) {
            const int u = k - 16;
            mask[(v + 15) * 32 + k] = (uint8_t)(u >= -um && u <= um ? 0xFF : 0x00);
        }
    }
}

/* Sums over one 32-wide row (u = -16..15) under the mask: fixed trip counts
 * and a mask instead of a branch, so it vectorises without target flags, in
 * 16-bit lanes: the masked row has |u| <= 15, so each half-row moment is at
 * most 255 * (1 + ... + 15) = 30600 and each half-row sum 255 * 16. */
static void row_moments(const uint8_t *restrict r, const uint8_t *restrict m, int32_t *s_out, int32_t *su_out)
{
    uint16_t sl = 0, sr = 0, ml = 0, mr = 0;
    for (int k = 0; k < 16; k++) {
        const uint16_t p = (uint16_t)(r[k] & m[k]);
        sl = (uint16_t)(sl + p);
        ml = (uint16_t)(ml + (uint16_t)(16 - k) * p);
    }
    for (int k = 0; k < 16; k++) {
        const uint16_t p = (uint16_t)(r[16 + k] & m[16 + k]);
        sr = (uint16_t)(sr + p);
        mr = (uint16_t)(mr + (uint16_t)k * p);
    }
    *s_out = (int32_t)sl + (int32_t)sr;
    *su_out = (int32_t)mr - (int32_t)ml;
}

void sfmi_feat_orientation(const uint8_t *img, int stride, int x, int y, const uint8_t *mask, double *c, double *s)
{
    const uint8_t *ctr = img + (long)y * stride + x;
    int32_t m10 = 0, m01 = 0; /* |m10|, |m01| <= 255 * 15 * 709 */
    for (int v = -15; v <= 15; v++) {
        int32_t rs, ru;
        row_moments(ctr + (long)v * stride - 16, mask + (v + 15) * 32, &rs, &ru);
        m10 += ru;
        m01 += v * rs;
    }
    double fx = (double)m10, fy = (double)m01;
    double n = sqrt(fx * fx + fy * fy);
    if (n > 0.0) {
        *c = fx / n;
        *s = fy / n;
    } else {
        *c = 1.0;
        *s = 0.0;
    }
}

/* Steering in 12-bit fixed point: integer arithmetic gives the same bits on
 * every platform. |c x - s y| <= 15 for pattern points, so adding 16 before
 * the shift keeps the value positive and the shift is a floor. */
#define FIX 12
#define BIAS (16 << FIX)

/* Offsets (relative to the patch centre, for this stride) of the pattern
 * rotated by (c, s): o1[i], o2[i] for the two points of pair i. */
static void steer(int stride, double c, double s, int32_t *restrict o1, int32_t *restrict o2)
{
    const int32_t cs = (int32_t)floor(c * (double)(1 << FIX) + 0.5), sn = (int32_t)floor(s * (double)(1 << FIX) + 0.5);
    const int32_t half = 1 << (FIX - 1);
    const signed char *x1 = sfmi_brief_pattern[0], *y1 = sfmi_brief_pattern[1], *x2 = sfmi_brief_pattern[2],
                      *y2 = sfmi_brief_pattern[3];
    for (int k = 0; k < SFM_BRIEF_PAIRS; k++) {
        int32_t u1 = ((cs * x1[k] - sn * y1[k] + BIAS + half) >> FIX) - 16;
        int32_t v1 = ((sn * x1[k] + cs * y1[k] + BIAS + half) >> FIX) - 16;
        int32_t u2 = ((cs * x2[k] - sn * y2[k] + BIAS + half) >> FIX) - 16;
        int32_t v2 = ((sn * x2[k] + cs * y2[k] + BIAS + half) >> FIX) - 16;
        o1[k] = v1 * stride + u1;
        o2[k] = v2 * stride + u2;
    }
}

void sfmi_feat_steer_bin(int stride, int bin, int32_t *table)
{
    const double a = 6.283185307179586 * (double)bin / (double)SFM_FEAT_ANGLE_BINS;
    steer(stride, sfmi_cos(a), sfmi_sin(a), table + (size_t)bin * 2 * SFM_BRIEF_PAIRS,
          table + (size_t)bin * 2 * SFM_BRIEF_PAIRS + SFM_BRIEF_PAIRS);
}

void sfmi_feat_steer_table(int stride, int32_t *table)
{
    for (int b = 0; b < SFM_FEAT_ANGLE_BINS; b++)
        sfmi_feat_steer_bin(stride, b, table);
}

int sfmi_feat_angle_bin(double c, double s)
{
    const double a = sfmi_atan2(s, c); /* (-pi, pi] */
    int b = (int)floor(a * ((double)SFM_FEAT_ANGLE_BINS / 6.283185307179586) + 0.5);
    b %= SFM_FEAT_ANGLE_BINS;
    return b < 0 ? b + SFM_FEAT_ANGLE_BINS : b;
}

void sfmi_feat_describe(const uint8_t *img, int stride, int x, int y, const int32_t *offsets, uint8_t *out)
{
    const uint8_t *ctr = img + (long)y * stride + x;
    const int32_t *o1 = offsets, *o2 = offsets + SFM_BRIEF_PAIRS;
    for (int byte = 0; byte < 32; byte++) {
        unsigned bits = 0;
        for (int k = 0; k < 8; k++) {
            const int i = byte * 8 + k;
            bits |= (unsigned)(ctr[o1[i]] < ctr[o2[i]]) << k;
        }
        out[byte] = (uint8_t)bits;
    }
}
