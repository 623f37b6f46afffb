/*
 * Corner measure and sub-pixel location from the image structure tensor.
 *
 * Harris and Stephens, "A combined corner and edge detector", 1988: ranks
 * FAST candidates (as ORB does), R = det M - k tr(M)^2, k = 0.04.
 *
 * Foerstner and Guelch, "A fast operator for detection and precise location
 * of distinct points, corners and centres of circular features", 1987: the
 * corner is the point p minimising sum_i (g_i . (p - x_i))^2 over a window,
 * i.e. the least-squares intersection of the lines through each pixel x_i
 * orthogonal to its gradient g_i: M p = sum_i g_i g_i^T x_i. For an ideal
 * L- or X-junction every such line through an edge pixel passes through the
 * corner, so the estimate is unbiased up to sampling of the window.
 * The estimate is accepted only when the lines do meet: their weighted mean
 * squared distance from it stays below a bound. On FAST responses to blobs
 * and texture the lines scatter and the estimate moves in ways that do not
 * repeat between views (measured on Herz-Jesu-P8: refining every corner
 * lowered the share of epipolar-consistent matches), so those keep their
 * integer position.
 */
#include "features/corner.h"

#include <math.h>

#define WIN 3

/* Structure tensor sums around (x, y); bx, by: sum of g g^T (u, v) with
 * (u, v) the offset from (x, y); e: sum of (g . (u, v))^2. Gradients are at
 * most 255 in magnitude per axis, so every sum over the 7x7 window fits in
 * 32 bits (|sxx| <= 49 * 255^2, |bx| <= 49 * 2 * 255^2 * 3, e <= 49 * 1530^2). */
static void tensor(const uint8_t *img, int stride, int x, int y, int32_t *sxx, int32_t *syy, int32_t *sxy,
                   int32_t *bx, int32_t *by, int32_t *ee)
{
    int32_t a = 0, b = 0, c = 0, px = 0, py = 0, e = 0;
    for (int v = -WIN; v <= WIN; v++) {
        const uint8_t *r = img + (long)(y + v) * stride + x;
        for (int u = -WIN; u <= WIN; u++) {
            const int32_t gx = (int32_t)r[u + 1] - (int32_t)r[u - 1];
            const int32_t gy = (int32_t)r[u + stride] - (int32_t)r[u - stride];
            const int32_t xx = gx * gx, yy = gy * gy, xy = gx * gy;
            a += xx;
            b += yy;
            c += xy;
            px += xx * u + xy * v;
            py += xy * u + yy * v;
            const int32_t gp = gx * u + gy * v;
            e += gp * gp;
        }
    }
    *sxx = a;
    *syy = b;
    *sxy = c;
    *bx = px;
    *by = py;
    *ee = e;
}

double sfmi_feat_harris(const uint8_t *img, int stride, int x, int y)
{
    int32_t a = 0, b = 0, c = 0;
    for (int v = -WIN; v <= WIN; v++) {
        const uint8_t *r = img + (long)(y + v) * stride + x;
        for (int u = -WIN; u <= WIN; u++) {
            const int32_t gx = (int32_t)r[u + 1] - (int32_t)r[u - 1];
            const int32_t gy = (int32_t)r[u + stride] - (int32_t)r[u - stride];
            a += gx * gx;
            b += gy * gy;
            c += gx * gy;
        }
    }
    const double da = (double)a, db = (double)b, dc = (double)c, tr = da + db;
    return da * db - dc * dc - 0.04 * tr * tr;
}

int sfmi_feat_refine(const uint8_t *img, int stride, int x, int y, double max_residual, double *rx, double *ry)
{
    int cx = x, cy = y;
    double fx = (double)x, fy = (double)y;
    int ok = 0;
    for (int it = 0; it < 3; it++) {
        int32_t a, b, c, px, py, e;
        tensor(img, stride, cx, cy, &a, &b, &c, &px, &py, &e);
        double da = (double)a, db = (double)b, dc = (double)c;
        double det = da * db - dc * dc, tr = da + db;
        if (!(tr > 0.0) || det <= 1e-3 * tr * tr)
            break;
        double ux = (db * (double)px - dc * (double)py) / det;
        double uy = (da * (double)py - dc * (double)px) / det;
        fx = (double)cx + ux;
        fy = (double)cy + uy;
        if (!(fabs(fx - (double)x) <= 3.0 && fabs(fy - (double)y) <= 3.0))
            break;
        /* weighted mean squared distance of the gradient lines from the
         * estimate: small only where the window really is a junction. A
         * window far off it is not re-centred (saves the iterations on
         * texture that would be rejected anyway). */
        const double res = (da * ux * ux + 2.0 * dc * ux * uy + db * uy * uy -
                            2.0 * (ux * (double)px + uy * (double)py) + (double)e) / tr;
        if (fabs(ux) <= 0.5 && fabs(uy) <= 0.5) {
            ok = res <= max_residual;
            break;
        }
        if (res > 4.0 * max_residual)
            break;
        cx = (int)floor(fx + 0.5);
        cy = (int)floor(fy + 0.5);
    }
    if (!ok) {
        *rx = (double)x;
        *ry = (double)y;
        return 0;
    }
    *rx = fx;
    *ry = fy;
    return 1;
}
