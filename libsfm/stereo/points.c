/*
 * Disparity to depth and to points. In rectified camera 1's frame a pixel
 * (u, v) of disparity d lies at Z = f B / (d - (cx1 - cx2)),
 * X = (u - cx1) Z / f, Y = (v - cy) Z / f (the Q matrix of
 * sfm_stereo_rectification); camera 1's original frame is R1^T of that.
 */
#include <math.h>

#include "sfm/sfm_stereo.h"

static int rect_ok(const sfm_stereo_rectification *r)
{
    /* R2 and Q are not read here, but a NaN anywhere means a corrupted
     * rectification: refused rather than half used. */
    for (int i = 0; i < 9; i++)
        if (!isfinite(r->R1[i]) || !isfinite(r->R2[i]) || !isfinite(r->K1[i]) ||
            !isfinite(r->K2[i]))
            return 0;
    for (int i = 0; i < 16; i++)
        if (!isfinite(r->Q[i]))
            return 0;
    return isfinite(r->baseline) && r->baseline > 0.0 && r->K1[0] > 0.0;
}

static double depth_of(const sfm_stereo_rectification *r, double d)
{
    double den = d - (r->K1[2] - r->K2[2]);
    if (!(den > 0.0))
        return (double)NAN;
    return r->K1[0] * r->baseline / den;
}

int sfm_stereo_depth(const float *disp, int width, int height,
                     const sfm_stereo_rectification *rect, float *depth)
{
    if (!disp || !rect || !depth || width < 1 || height < 1)
        return SFM_E_ARGUMENT;
    if (!rect_ok(rect))
        return SFM_E_NONFINITE;
    int valid = 0;
    for (size_t i = 0; i < (size_t)width * height; i++) {
        double z = isfinite(disp[i]) ? depth_of(rect, (double)disp[i]) : (double)NAN;
        depth[i] = (float)z;
        valid += isfinite(z) != 0;
    }
    return valid;
}

int sfm_stereo_points(const float *disp, int width, int height,
                      const sfm_stereo_rectification *rect, double max_depth, double *points,
                      int32_t *pixel_index, int capacity)
{
    if (!disp || !rect || width < 1 || height < 1 || capacity < 0 ||
        (size_t)width * height > 0x7fffffffu)
        return SFM_E_ARGUMENT;
    if (isnan(max_depth) || !rect_ok(rect))
        return SFM_E_NONFINITE;
    const double f = rect->K1[0], cx = rect->K1[2], cy = rect->K1[5];
    const double *R = rect->R1;
    int count = 0;
    for (int pass = 0; pass < (points ? 2 : 1); pass++) {
        if (pass == 1 && count > capacity)
            return SFM_E_CAPACITY;
        int k = 0;
        for (int v = 0; v < height; v++) {
            for (int u = 0; u < width; u++) {
                float d = disp[(size_t)v * width + u];
                if (!isfinite(d))
                    continue;
                double z = depth_of(rect, (double)d);
                if (!isfinite(z) || (max_depth > 0.0 && z > max_depth))
                    continue;
                if (pass == 0) {
                    count++;
                    continue;
                }
                double xr = (u - cx) * z / f, yr = (v - cy) * z / f;
                double *p = points + 3 * (size_t)k;
                /* x_cam1 = R1^T x_rect */
                p[0] = R[0] * xr + R[3] * yr + R[6] * z;
                p[1] = R[1] * xr + R[4] * yr + R[7] * z;
                p[2] = R[2] * xr + R[5] * yr + R[8] * z;
                if (pixel_index)
                    pixel_index[k] = (int32_t)((size_t)v * width + u);
                k++;
            }
        }
    }
    return count;
}
