/* The focal search of the uncalibrated and self-calibrating pipelines (see
 * focal_search.h). */
#include <math.h>

#include "core/dmath.h"
#include "recon/focal_search.h"

int sfmi_focal_sweep(sfmi_focal_score_fn score, void *ctx, const double *f, int count, double *cost)
{
    int kb = -1;
    for (int k = 0; k < count; k++) {
        cost[k] = score(ctx, f[k]);
        if (cost[k] < HUGE_VAL && (kb < 0 || cost[k] < cost[kb]))
            kb = k;
    }
    return kb;
}

void sfmi_focal_golden(sfmi_focal_score_fn score, void *ctx, double lo, double hi, int steps, int ties_low,
                       double u[2], double s[2])
{
    const double g = 0.5 * (sqrt(5.0) - 1);
    double x1 = hi - g * (hi - lo), x2 = lo + g * (hi - lo);
    /* x1 scored first: score may change the caller's state */
    double f1 = score(ctx, sfmi_exp(x1));
    double f2 = score(ctx, sfmi_exp(x2));
    for (int it = 0; it < steps; it++) {
        if (f1 < f2 || (ties_low && f1 == f2)) {
            hi = x2, x2 = x1, f2 = f1;
            x1 = hi - g * (hi - lo);
            f1 = score(ctx, sfmi_exp(x1));
        } else {
            lo = x1, x1 = x2, f1 = f2;
            x2 = lo + g * (hi - lo);
            f2 = score(ctx, sfmi_exp(x2));
        }
    }
    u[0] = x1, u[1] = x2;
    s[0] = f1, s[1] = f2;
}
