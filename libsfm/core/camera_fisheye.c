/*
 * Equidistant fisheye with Kannala-Brandt distortion, as OpenCV's fisheye
 * module (Kannala and Brandt, "A generic camera model and calibration method
 * for conventional, wide-angle, and fish-eye lenses", PAMI 2006):
 *   theta = angle between X and the optical axis = atan2(|(X, Y)|, Z),
 *   theta_d = theta (1 + k1 theta^2 + k2 theta^4 + k3 theta^6 + k4 theta^8),
 *   xd = theta_d (X, Y) / |(X, Y)|.
 * Unlike OpenCV's atan(r) form this takes theta from atan2, so directions
 * behind the camera plane (theta > pi/2) project too; only the negative
 * optical axis (theta = pi) has no image.
 *
 * Undistortion solves theta_d(theta) = |xd| on [0, theta_max] by Newton's
 * method safeguarded by bisection. theta_max is pi or, if sooner, the first
 * angle where theta_d stops increasing: the first positive root u = theta^2
 * of 1 + 3 k1 u + 5 k2 u^2 + 7 k3 u^3 + 9 k4 u^4. Beyond theta_d(theta_max)
 * there is no valid preimage: SFM_E_NO_CONVERGENCE.
 */
#include <math.h>

#include "core/camera_internal.h"
#include "sfm/sfm_poly.h"
#include "core/dmath.h"

#define PI 3.14159265358979323846

/* theta_d and d(theta_d)/d(theta) */
static double theta_d(const double *k, double th, double *dth)
{
    const double t2 = th * th;
    const double g = 1.0 + t2 * (k[0] + t2 * (k[1] + t2 * (k[2] + t2 * k[3])));
    if (dth)
        *dth = 1.0 + t2 * (3.0 * k[0] + t2 * (5.0 * k[1] + t2 * (7.0 * k[2] + t2 * 9.0 * k[3])));
    return th * g;
}

int sfmi_cam_fisheye_project(const double *k, const double X[3], double xd[2], double *D)
{
    /* m(X) = theta_d / rho is homogeneous of degree -1: work on X / s */
    const double s = fmax(fmax(fabs(X[0]), fabs(X[1])), fabs(X[2]));
    if (s == 0.0)
        return SFM_E_SINGULAR;
    const double x = X[0] / s, y = X[1] / s, z = X[2] / s;
    const double rho = sfmi_hypot(x, y);
    if (rho == 0.0 && !(z > 0.0))
        return SFM_E_SINGULAR; /* the negative optical axis */
    const double th = sfmi_atan2(rho, z);
    double dtd;
    const double td = theta_d(k, th, &dtd);
    /* small angles: theta / rho = (1/z)(1 - q^2/3 + q^4/5 - ...), q = rho/z */
    const int small = z > 0.0 && rho < 1e-4 * z;
    double m;
    if (small) {
        const double q2 = (rho / z) * (rho / z);
        m = (td / (th > 0.0 ? th : 1.0)) * (1.0 - q2 / 3.0 + q2 * q2 / 5.0) / z;
        if (th == 0.0)
            m = 1.0 / z;
    } else {
        m = td / rho;
    }
    xd[0] = m * x;
    xd[1] = m * y;
    if (D) {
        const double n2 = rho * rho + z * z;
        const double dmdz = -dtd / n2;
        /* dm/dX_j = X_j * qq for j = 0, 1; qq -> 2 (k1 - 1/3) / z^3 on axis */
        const double qq = small ? 2.0 * (k[0] - 1.0 / 3.0) / (z * z * z)
                                : (dtd * z / n2 - m) / (rho * rho);
        D[0] = (m + x * x * qq) / s;
        D[1] = x * y * qq / s;
        D[2] = x * dmdz / s;
        D[3] = x * y * qq / s;
        D[4] = (m + y * y * qq) / s;
        D[5] = y * dmdz / s;
    }
    return SFM_OK;
}

/* Largest angle up to which theta_d is increasing (at most pi). */
static double theta_max(const double *k)
{
    const double c[5] = {9.0 * k[3], 7.0 * k[2], 5.0 * k[1], 3.0 * k[0], 1.0};
    double u[4];
    int n = sfm_poly_roots4(c, u);
    for (int i = 0; i < n; i++)
        if (u[i] > 0.0)
            return fmin(sqrt(u[i]), PI);
    return PI;
}

int sfmi_cam_fisheye_unproject(const double *k, const double xd[2], double b[3])
{
    const double r = sfmi_hypot(xd[0], xd[1]);
    if (r == 0.0) {
        b[0] = 0.0;
        b[1] = 0.0;
        b[2] = 1.0;
        return SFM_OK;
    }
    const double tmax = theta_max(k);
    if (!(r < theta_d(k, tmax, NULL)))
        return SFM_E_NO_CONVERGENCE; /* no preimage in the invertible range */
    double lo = 0.0, hi = tmax, th = fmin(r, 0.5 * tmax), F = 0.0;
    for (int it = 0; it < 4 * SFM_CAM_MAX_ITERS; it++) {
        double dtd;
        F = theta_d(k, th, &dtd) - r;
        if (F == 0.0)
            break;
        if (F > 0.0)
            hi = th;
        else
            lo = th;
        double tn = dtd > 0.0 ? th - F / dtd : -1.0;
        if (!(tn > lo && tn < hi))
            tn = lo + 0.5 * (hi - lo);
        if (tn == th)
            break;
        th = tn;
    }
    F = theta_d(k, th, NULL) - r;
    if (!(fabs(F) <= SFM_CAM_UNDISTORT_TOL))
        return SFM_E_NO_CONVERGENCE;
    const double st = sfmi_sin(th);
    b[0] = st * xd[0] / r;
    b[1] = st * xd[1] / r;
    b[2] = sfmi_cos(th);
    return SFM_OK;
}
