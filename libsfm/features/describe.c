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

void sfm_feat_describe(const uint8_t *img, int stride, int x, int y, double c, double s, uint8_t *out)
{
    const uint8_t *ctr = img + (long)y * stride + x;
    /* |rotated coordinate| <= 15, so (int)(v + 16.5) - 16 rounds half up. */
    for (int byte = 0; byte < 32; byte++) {
        unsigned bits = 0;
        for (int k = 0; k < 8; k++) {
            const signed char *pr = sfm_brief_pattern[byte * 8 + k];
            double x1 = pr[0], y1 = pr[1], x2 = pr[2], y2 = pr[3];
            int u1 = (int)(c * x1 - s * y1 + 16.5) - 16, v1 = (int)(s * x1 + c * y1 + 16.5) - 16;
            int u2 = (int)(c * x2 - s * y2 + 16.5) - 16, v2 = (int)(s * x2 + c * y2 + 16.5) - 16;
            int a = ctr[(long)v1 * stride + u1], b = ctr[(long)v2 * stride + u2];
            bits |= (unsigned)(a < b) << k;
        }
        out[byte] = (uint8_t)bits;
    }
}
