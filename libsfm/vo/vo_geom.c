/* Small rigid-transform helpers of the VO pipeline. Poses are world-to-camera,
 * x_cam = R X + t, R row-major. */
#include <math.h>

#include "core/dmath.h"
#include "solvers/small_math.h"
#include "vo/vo_internal.h"

void sfmi_vo_compose(const double Ra[9], const double ta[3], const double Rb[9],
                     const double tb[3], double R[9], double t[3])
{
    double Rt[9], tt[3];
    sfmi_matmul3(Ra, Rb, Rt);
    for (int r = 0; r < 3; r++)
        tt[r] = Ra[3 * r] * tb[0] + Ra[3 * r + 1] * tb[1] + Ra[3 * r + 2] * tb[2] + ta[r];
    for (int k = 0; k < 9; k++)
        R[k] = Rt[k];
    for (int k = 0; k < 3; k++)
        t[k] = tt[k];
}

void sfmi_vo_inverse(const double R[9], const double t[3], double Ri[9], double ti[3])
{
    double Rt[9];
    for (int r = 0; r < 3; r++)
        for (int c = 0; c < 3; c++)
            Rt[3 * r + c] = R[3 * c + r];
    for (int r = 0; r < 3; r++)
        ti[r] = -(Rt[3 * r] * t[0] + Rt[3 * r + 1] * t[1] + Rt[3 * r + 2] * t[2]);
    for (int k = 0; k < 9; k++)
        Ri[k] = Rt[k];
}

void sfmi_vo_transform(const double R[9], const double t[3], const double X[3], double x[3])
{
    for (int r = 0; r < 3; r++)
        x[r] = R[3 * r] * X[0] + R[3 * r + 1] * X[1] + R[3 * r + 2] * X[2] + t[r];
}

int sfmi_vo_project(const double K[4], const double R[9], const double t[3], const double X[3],
                    double uv[2])
{
    double x[3];
    sfmi_vo_transform(R, t, X, x);
    if (!(x[2] > 1e-9 * (fabs(x[0]) + fabs(x[1]) + 1e-12)))
        return 0;
    uv[0] = K[0] * x[0] / x[2] + K[2];
    uv[1] = K[1] * x[1] / x[2] + K[3];
    return 1;
}

void sfmi_vo_centre(const double R[9], const double t[3], double c[3])
{
    for (int k = 0; k < 3; k++)
        c[k] = -(R[k] * t[0] + R[3 + k] * t[1] + R[6 + k] * t[2]);
}

double sfmi_vo_ray_angle(const double c1[3], const double c2[3], const double X[3])
{
    double a[3], b[3];
    for (int k = 0; k < 3; k++) {
        a[k] = X[k] - c1[k];
        b[k] = X[k] - c2[k];
    }
    double cr[3] = {a[1] * b[2] - a[2] * b[1], a[2] * b[0] - a[0] * b[2], a[0] * b[1] - a[1] * b[0]};
    double s = sqrt(cr[0] * cr[0] + cr[1] * cr[1] + cr[2] * cr[2]);
    double c = a[0] * b[0] + a[1] * b[1] + a[2] * b[2];
    return sfmi_atan2(s, c);
}

/* Quickselect (Hoare partition) for the lower median. */
double sfmi_vo_median(double *v, int n)
{
    int k = (n - 1) / 2, lo = 0, hi = n - 1;
    while (lo < hi) {
        double pivot = v[(lo + hi) / 2];
        int i = lo, j = hi;
        while (i <= j) {
            while (v[i] < pivot)
                i++;
            while (v[j] > pivot)
                j--;
            if (i <= j) {
                double tmp = v[i];
                v[i] = v[j];
                v[j] = tmp;
                i++;
                j--;
            }
        }
        if (k <= j)
            hi = j;
        else if (k >= i)
            lo = i;
        else
            break;
    }
    return v[k];
}
