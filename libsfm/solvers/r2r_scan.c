/*
 * The sampled root scan of the robot-to-robot solvers whose eliminant is
 * evaluated directly rather than from coefficients (r2r_b1_b2_d_d.c,
 * r2r_b1_d_d_d_d.c): bisection of sign changes and a golden-section search
 * of sign-keeping dips, called by sfmi_r2r_scan_step (r2r_align.h).
 */
#include <math.h>

#include "solvers/r2r_align.h"

int sfmi_r2r_dip_cross(double (*fn)(const void *, double), const void *ctx, double a, double b,
                       double s, double *xm)
{
    const double gr = 0.38196601125010515;
    double x1 = a + gr * (b - a), x2 = b - gr * (b - a);
    double g1 = s * fn(ctx, x1), g2 = s * fn(ctx, x2);
    for (int it = 0; it < 40 && g1 > 0.0 && g2 > 0.0; it++) {
        if (g1 < g2) {
            b = x2;
            x2 = x1;
            g2 = g1;
            x1 = a + gr * (b - a);
            g1 = s * fn(ctx, x1);
        } else {
            a = x1;
            x1 = x2;
            g1 = g2;
            x2 = b - gr * (b - a);
            g2 = s * fn(ctx, x2);
        }
    }
    if (!(g1 <= 0.0) && !(g2 <= 0.0))
        return 0;
    *xm = g1 <= 0.0 ? x1 : x2;
    return 1;
}

double sfmi_r2r_bisect(double (*fn)(const void *, double), const void *ctx, double a, double b,
                       double fa, int iters, int stop_nonfinite)
{
    for (int it = 0; it < iters; it++) {
        double mid = 0.5 * (a + b), fm = fn(ctx, mid);
        if (stop_nonfinite && !isfinite(fm))
            break;
        if ((fm < 0.0) == (fa < 0.0)) {
            a = mid;
            fa = fm;
        } else {
            b = mid;
        }
    }
    return 0.5 * (a + b);
}
