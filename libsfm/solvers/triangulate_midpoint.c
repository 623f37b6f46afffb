/*
 * Midpoint triangulation from n calibrated views: the point closest, in the
 * least-squares sense, to all the rays (centre c_i = -R_i^T t_i, direction
 * d_i = R_i^T f_i / |f_i|): sum_i (I - d_i d_i^T) (X - c_i) = 0, a 3x3
 * symmetric system solved by Cramer's rule.
 * Stack: under 400 bytes (gcc 12 -O2 x86-64: 336).
 */
#include <math.h>

#include "core/linalg_util.h"
#include "sfm/sfm_triangulate.h"
#include "solvers/small_math.h"

int sfm_triangulate_midpoint(int nviews, const sfm_pose *poses, int npoints, const double *f,
                             double *X, int *flags)
{
    if (!poses || !X || nviews < 2 || npoints < 0 || (npoints > 0 && !f))
        return SFM_E_ARGUMENT;
    for (int v = 0; v < nviews; v++)
        if (!sfmi_la_all_finite(poses[v].R, 9) || !sfmi_la_all_finite(poses[v].t, 3))
            return SFM_E_NONFINITE;
    if (!sfmi_la_all_finite(f, 3L * nviews * npoints))
        return SFM_E_NONFINITE;
    for (long i = 0; i < (long)nviews * npoints; i++) {
        const double *b = f + 3 * i;
        if (!(b[0] * b[0] + b[1] * b[1] + b[2] * b[2] > 0.0))
            return SFM_E_ARGUMENT;
    }
    int good = 0;
    for (int j = 0; j < npoints; j++) {
        double A[6] = {0, 0, 0, 0, 0, 0}; /* 00 01 02 11 12 22 */
        double bsum[3] = {0, 0, 0}, dsum[3] = {0, 0, 0};
        for (int v = 0; v < nviews; v++) {
            const double *R = poses[v].R, *t = poses[v].t;
            const double *b = f + 3 * ((long)v * npoints + j);
            double d[3], c[3];
            sfmi_matvec3_t(R, b, d);
            sfmi_matvec3_t(R, t, c);
            for (int k = 0; k < 3; k++)
                c[k] = -c[k];
            double dn = 1.0 / sqrt(d[0] * d[0] + d[1] * d[1] + d[2] * d[2]);
            for (int k = 0; k < 3; k++) {
                d[k] *= dn;
                dsum[k] += d[k];
            }
            double dc = d[0] * c[0] + d[1] * c[1] + d[2] * c[2];
            A[0] += 1.0 - d[0] * d[0];
            A[1] -= d[0] * d[1];
            A[2] -= d[0] * d[2];
            A[3] += 1.0 - d[1] * d[1];
            A[4] -= d[1] * d[2];
            A[5] += 1.0 - d[2] * d[2];
            for (int k = 0; k < 3; k++)
                bsum[k] += c[k] - dc * d[k];
        }
        double c00 = A[3] * A[5] - A[4] * A[4];
        double c01 = A[2] * A[4] - A[1] * A[5];
        double c02 = A[1] * A[4] - A[2] * A[3];
        double c11 = A[0] * A[5] - A[2] * A[2];
        double c12 = A[1] * A[2] - A[0] * A[4];
        double c22 = A[0] * A[3] - A[1] * A[1];
        double det = A[0] * c00 + A[1] * c01 + A[2] * c02;
        double tr3 = (A[0] + A[3] + A[5]) / 3.0;
        int fl = 0;
        double *Xj = X + 3 * j;
        if (!(det > 1e-20 * tr3 * tr3 * tr3)) {
            /* parallel rays: the point is at infinity along them */
            double n = sqrt(dsum[0] * dsum[0] + dsum[1] * dsum[1] + dsum[2] * dsum[2]);
            fl = SFM_TRI_INFINITY;
            if (n > 0.0) {
                for (int k = 0; k < 3; k++)
                    Xj[k] = dsum[k] / n;
            } else {
                /* opposite rays: no direction in front of all; use view 0 */
                sfmi_matvec3_t(poses[0].R, f + 3 * (long)j, Xj);
                double m = sqrt(Xj[0] * Xj[0] + Xj[1] * Xj[1] + Xj[2] * Xj[2]);
                for (int k = 0; k < 3; k++)
                    Xj[k] /= m;
            }
            for (int v = 0; v < nviews; v++) {
                double d[3];
                sfmi_matvec3_t(poses[v].R, f + 3 * ((long)v * npoints + j), d);
                double dd = 0.0;
                for (int k = 0; k < 3; k++)
                    dd += d[k] * Xj[k];
                if (!(dd > 0.0))
                    fl |= SFM_TRI_BEHIND;
            }
        } else {
            double id = 1.0 / det;
            Xj[0] = (c00 * bsum[0] + c01 * bsum[1] + c02 * bsum[2]) * id;
            Xj[1] = (c01 * bsum[0] + c11 * bsum[1] + c12 * bsum[2]) * id;
            Xj[2] = (c02 * bsum[0] + c12 * bsum[1] + c22 * bsum[2]) * id;
            for (int v = 0; v < nviews; v++) {
                const double *R = poses[v].R, *t = poses[v].t;
                const double *b = f + 3 * ((long)v * npoints + j);
                /* depth along the bearing: (R X + t) . f */
                double z = 0.0;
                for (int k = 0; k < 3; k++)
                    z += (R[3 * k] * Xj[0] + R[3 * k + 1] * Xj[1] + R[3 * k + 2] * Xj[2] + t[k]) *
                         b[k];
                if (!(z > 0.0))
                    fl |= SFM_TRI_BEHIND;
            }
        }
        if (flags)
            flags[j] = fl;
        good += fl == 0;
    }
    return good;
}
