/*
 * Hartley normalization of 2D point sets and small helpers shared by the
 * solvers. See normalize.h.
 */
#define SFMI_INLINE_EXTERN /* this file emits sfmi_hartley_pairs (core/inline.h) */
#include <math.h>

#include "solvers/normalize.h"

int sfmi_hartley_2d(const double *p, int n, double t[3])
{
    double cx = 0.0, cy = 0.0, d = 0.0;
    for (int i = 0; i < n; i++) {
        cx += p[2 * i];
        cy += p[2 * i + 1];
    }
    cx /= n;
    cy /= n;
    for (int i = 0; i < n; i++) {
        double dx = p[2 * i] - cx, dy = p[2 * i + 1] - cy;
        d += sqrt(dx * dx + dy * dy);
    }
    d /= n;
    /* All points coincide, to rounding of the coordinates' size. */
    double size = fabs(cx) + fabs(cy);
    if (!(d > 1e-14 * size) || d == 0.0)
        return -1;
    double s = sqrt(2.0) / d;
    t[0] = s;
    t[1] = -s * cx;
    t[2] = -s * cy;
    return 0;
}

/* the one external copy of the header's inline definition (core/inline.h) */
extern inline int sfmi_hartley_pairs(const double *p1, const double *p2, int n, double t1[3],
                                     double t2[3]);

void sfmi_hartley_inverse(const double t[3], double ti[3])
{
    ti[0] = 1.0 / t[0];
    ti[1] = -t[1] / t[0];
    ti[2] = -t[2] / t[0];
}

void sfmi_hartley_matrix(const double t[3], double T[9])
{
    T[0] = t[0]; T[1] = 0.0;  T[2] = t[1];
    T[3] = 0.0;  T[4] = t[0]; T[5] = t[2];
    T[6] = 0.0;  T[7] = 0.0;  T[8] = 1.0;
}

int sfmi_normalize9(double M[9])
{
    double s = 0.0;
    for (int i = 0; i < 9; i++)
        s += M[i] * M[i];
    if (!(s > 0.0) || !isfinite(s))
        return -1;
    s = 1.0 / sqrt(s);
    for (int i = 0; i < 9; i++)
        M[i] *= s;
    return 0;
}
