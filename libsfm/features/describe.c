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

/* floor(sqrt(15^2 - v^2)) for v = 0..15: the half-width of the disc rows. */
static const signed char disc_umax[16] = {15, 14, 14, 14, 14, 14, 13, 13, 12, 12, 11, 10, 9, 7, 5, 0};

void sfm_feat_orientation(const uint8_t *img, int stride, int x, int y, double *c, double *s)
{
    const uint8_t *ctr = img + (long)y * stride + x;
    long m10 = 0, m01 = 0;
    for (int u = -15; u <= 15; u++)
        m10 += (long)u * ctr[u];
    for (int v = 1; v <= 15; v++) {
        const uint8_t *rp = ctr + (long)v * stride, *rm = ctr - (long)v * stride;
        const int um = disc_umax[v];
        long dsum = 0;
        for (int u = -um; u <= um; u++) {
            int p = rp[u], m = rm[u];
            dsum += p - m;
            m10 += (long)u * (p + m);
        }
        m01 += (long)v * dsum;
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
    const signed char *x1 = sfm_brief_pattern[0], *y1 = sfm_brief_pattern[1], *x2 = sfm_brief_pattern[2],
                      *y2 = sfm_brief_pattern[3];
    for (int k = 0; k < SFM_BRIEF_PAIRS; k++) {
        int32_t u1 = ((cs * x1[k] - sn * y1[k] + BIAS + half) >> FIX) - 16;
        int32_t v1 = ((sn * x1[k] + cs * y1[k] + BIAS + half) >> FIX) - 16;
        int32_t u2 = ((cs * x2[k] - sn * y2[k] + BIAS + half) >> FIX) - 16;
        int32_t v2 = ((sn * x2[k] + cs * y2[k] + BIAS + half) >> FIX) - 16;
        o1[k] = v1 * stride + u1;
        o2[k] = v2 * stride + u2;
    }
}

void sfm_feat_steer_table(int stride, int32_t *table)
{
    for (int b = 0; b < SFM_FEAT_ANGLE_BINS; b++) {
        const double a = 6.283185307179586 * (double)b / (double)SFM_FEAT_ANGLE_BINS;
        steer(stride, cos(a), sin(a), table + (size_t)b * 2 * SFM_BRIEF_PAIRS,
              table + (size_t)b * 2 * SFM_BRIEF_PAIRS + SFM_BRIEF_PAIRS);
    }
}

int sfm_feat_angle_bin(double c, double s)
{
    const double a = atan2(s, c); /* (-pi, pi] */
    int b = (int)floor(a * ((double)SFM_FEAT_ANGLE_BINS / 6.283185307179586) + 0.5);
    b %= SFM_FEAT_ANGLE_BINS;
    return b < 0 ? b + SFM_FEAT_ANGLE_BINS : b;
}

void sfm_feat_describe(const uint8_t *img, int stride, int x, int y, const int32_t *offsets, uint8_t *out)
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
