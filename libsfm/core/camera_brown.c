/*
 * Pinhole with radial-tangential (Brown-Conrady) distortion, in OpenCV's
 * parameterisation (Brown, "Decentering distortion of lenses", 1966; the
 * OpenCV calib3d documentation): with (x, y) = (X/Z, Y/Z), r2 = x^2 + y^2,
 *   xd = x (1 + k1 r2 + k2 r2^2 + k3 r2^3) + 2 p1 x y + p2 (r2 + 2 x^2)
 *   yd = y (1 + k1 r2 + k2 r2^2 + k3 r2^3) + p1 (r2 + 2 y^2) + 2 p2 x y.
 * k = {k1, k2, p1, p2, k3}; all zero is the plain pinhole.
 *
 * Undistortion is Newton's method on the 2x2 map with backtracking, started
 * at the distorted point. The map stops being invertible where the radial
 * profile r (1 + k1 r2 + k2 r2^2 + k3 r2^3) turns back, at the first positive
 * root u of 1 + 3 k1 u + 5 k2 u^2 + 7 k3 u^3 (u = r2): the iteration is kept
 * inside that disc, and an answer is accepted only where the map's Jacobian
 * determinant is positive and the residual is below SFM_CAM_UNDISTORT_TOL.
 * Pixels beyond the image of the fold have no valid preimage and are
 * SFM_E_NO_CONVERGENCE.
 */
#include <math.h>

#include "core/camera_internal.h"
#include "sfm/sfm_poly.h"
#include "core/dmath.h"

/* Distortion of normalised (x, y); Dd (2x2, may be NULL) its Jacobian. */
static void distort(const double *k, double x, double y, double out[2], double *Dd)
{
    const double k1 = k[0], k2 = k[1], p1 = k[2], p2 = k[3], k3 = k[4];
    const double r2 = x * x + y * y;
    const double R = 1.0 + r2 * (k1 + r2 * (k2 + r2 * k3));
    out[0] = x * R + 2.0 * p1 * x * y + p2 * (r2 + 2.0 * x * x);
    out[1] = y * R + p1 * (r2 + 2.0 * y * y) + 2.0 * p2 * x * y;
    if (Dd) {
        const double dR = k1 + r2 * (2.0 * k2 + 3.0 * k3 * r2); /* dR/dr2 */
        Dd[0] = R + 2.0 * x * x * dR + 2.0 * p1 * y + 6.0 * p2 * x;
        Dd[1] = 2.0 * x * y * dR + 2.0 * p1 * x + 2.0 * p2 * y;
        Dd[2] = Dd[1];
        Dd[3] = R + 2.0 * y * y * dR + 6.0 * p1 * y + 2.0 * p2 * x;
    }
}

int sfmi_cam_brown_project(const double *k, const double X[3], double xd[2], double *D)
{
    const double Z = X[2];
    if (!(Z > 0.0))
        return SFM_E_SINGULAR;
    const double x = X[0] / Z, y = X[1] / Z;
    double Dd[4];
    distort(k, x, y, xd, D ? Dd : NULL);
    if (D) {
        /* d(x, y)/dX = [1/Z 0 -x/Z; 0 1/Z -y/Z] */
        const double iz = 1.0 / Z;
        D[0] = Dd[0] * iz;
        D[1] = Dd[1] * iz;
        D[2] = -(Dd[0] * x + Dd[1] * y) * iz;
        D[3] = Dd[2] * iz;
        D[4] = Dd[3] * iz;
        D[5] = -(Dd[2] * x + Dd[3] * y) * iz;
    }
    return SFM_OK;
}

/* Squared radius where the radial profile folds; HUGE_VAL if it never does. */
static double fold_r2(const double *k)
{
    const double c[4] = {7.0 * k[4], 5.0 * k[1], 3.0 * k[0], 1.0};
    double u[3];
    int n = sfm_poly_roots3(c, u);
    for (int i = 0; i < n; i++)
        if (u[i] > 0.0)
            return u[i];
    return HUGE_VAL;
}

int sfmi_cam_brown_unproject(const double *k, const double xd[2], double b[3])
{
    double x = xd[0], y = xd[1];
    if (k[0] != 0.0 || k[1] != 0.0 || k[2] != 0.0 || k[3] != 0.0 || k[4] != 0.0) {
        const double umax = fold_r2(k);
        if (x * x + y * y >= umax) { /* start inside the invertible disc */
            const double s = sqrt(0.5 * umax / (x * x + y * y));
            x *= s;
            y *= s;
        }
        double f[2], Dd[4];
        distort(k, x, y, f, Dd);
        double rx = f[0] - xd[0], ry = f[1] - xd[1];
        double nr = sfmi_hypot(rx, ry);
        for (int it = 0; it < SFM_CAM_MAX_ITERS && nr > 0.0; it++) {
            const double det = Dd[0] * Dd[3] - Dd[1] * Dd[2];
            if (!(det > 0.0))
                break; /* on or past a fold */
            const double sx = (Dd[3] * rx - Dd[1] * ry) / det;
            const double sy = (Dd[0] * ry - Dd[2] * rx) / det;
            double t = 1.0;
            int moved = 0;
            for (int h = 0; h < 40; h++, t *= 0.5) {
                const double nx = x - t * sx, ny = y - t * sy;
                if (!(nx * nx + ny * ny < umax))
                    continue;
                double fn[2], Dn[4];
                distort(k, nx, ny, fn, Dn);
                const double qx = fn[0] - xd[0], qy = fn[1] - xd[1], nq = sfmi_hypot(qx, qy);
                if (nq < nr) {
                    x = nx;
                    y = ny;
                    rx = qx;
                    ry = qy;
                    nr = nq;
                    Dd[0] = Dn[0];
                    Dd[1] = Dn[1];
                    Dd[2] = Dn[2];
                    Dd[3] = Dn[3];
                    moved = 1;
                    break;
                }
            }
            if (!moved)
                break; /* at the rounding floor, or stuck */
        }
        const double det = Dd[0] * Dd[3] - Dd[1] * Dd[2];
        if (!(nr <= SFM_CAM_UNDISTORT_TOL) || !(det > 0.0) || !isfinite(x) || !isfinite(y))
            return SFM_E_NO_CONVERGENCE;
    }
    const double n = sfmi_hypot(sfmi_hypot(x, y), 1.0);
    b[0] = x / n;
    b[1] = y / n;
    b[2] = 1.0 / n;
    return SFM_OK;
}
