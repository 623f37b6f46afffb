/*
 * Levenberg-Marquardt for absolute pose on the reprojection error measured in
 * the tangent plane of each observed bearing (equal to the normalised image
 * plane error at the image centre of a pinhole camera, and defined for any
 * central camera, fisheye included). d r_k / d Xc = (e_k - r_k b) / (b . Xc);
 * d Xc / d w = -[R X]x; d Xc / d t = I.
 */
#include "robust/reproj_lm.h"

#include <math.h>
#include <string.h>

#include "robust/epipolar.h"
#include "robust/lm_small.h"
#include "sfm/sfm_linalg.h"
#include "sfm/sfm_rotation.h"

double sfm_robust_reproj2(const double R[9], const double t[3], const double *b,
                          const double *X)
{
    double Xc0 = R[0] * X[0] + R[1] * X[1] + R[2] * X[2] + t[0];
    double Xc1 = R[3] * X[0] + R[4] * X[1] + R[5] * X[2] + t[1];
    double Xc2 = R[6] * X[0] + R[7] * X[1] + R[8] * X[2] + t[2];
    double d = b[0] * Xc0 + b[1] * Xc1 + b[2] * Xc2;
    if (!(d > 0.0))
        return SFM_ROBUST_HUGE;
    /* |Xc/d - b|^2 = |Xc|^2/d^2 - 1, computed without the cancellation */
    double u0 = Xc0 / d - b[0], u1 = Xc1 / d - b[1], u2 = Xc2 / d - b[2];
    return u0 * u0 + u1 * u1 + u2 * u2;
}

static double cost(const double *b, const double *X, const int *idx, int n, const double *R,
                   const double *t, double s2)
{
    double c = 0.0;
    for (int j = 0; j < n; j++) {
        double r2 = sfm_robust_reproj2(R, t, b + 3 * idx[j], X + 3 * idx[j]);
        if (r2 < SFM_ROBUST_HUGE)
            c += sfm_lm_cauchy_loss(r2, s2);
    }
    return c;
}

int sfm_robust_reproj_lm(const double *b, const double *X, const int *idx, int n, double scale,
                         int iters, double R[9], double t[3])
{
    const double s2 = scale > 0.0 ? scale * scale : 0.0;
    double cur = cost(b, X, idx, n, R, t, s2);
    double lambda = 1e-4;
    int improved = 0;
    for (int it = 0; it < iters; it++) {
        double H[36], g[6];
        memset(H, 0, sizeof H);
        memset(g, 0, sizeof g);
        for (int j = 0; j < n; j++) {
            const double *bb = b + 3 * idx[j], *XX = X + 3 * idx[j];
            double RX[3], Xc[3], e[2][3];
            sfm_matvec3(R, XX, RX);
            Xc[0] = RX[0] + t[0];
            Xc[1] = RX[1] + t[1];
            Xc[2] = RX[2] + t[2];
            double d = sfm_dot3(bb, Xc);
            if (!(d > 0.0))
                continue;
            sfm_tangent_basis(bb, e[0], e[1]);
            double rr[2] = {sfm_dot3(e[0], Xc) / d, sfm_dot3(e[1], Xc) / d};
            double w = sfm_lm_cauchy_weight(rr[0] * rr[0] + rr[1] * rr[1], s2);
            for (int k = 0; k < 2; k++) {
                double r = rr[k];
                double a[3]; /* d r / d Xc */
                for (int c = 0; c < 3; c++)
                    a[c] = (e[k][c] - r * bb[c]) / d;
                /* d r / d w = a . (-[RX]x) = (RX x a) */
                double J[6];
                sfm_cross3(RX, a, J);
                J[3] = a[0];
                J[4] = a[1];
                J[5] = a[2];
                for (int p = 0; p < 6; p++) {
                    g[p] += w * J[p] * r;
                    for (int q = 0; q <= p; q++)
                        H[p * 6 + q] += w * J[p] * J[q];
                }
            }
        }
        int accepted = 0;
        for (int tries = 0; tries < 6 && !accepted; tries++) {
            double x[6];
            if (sfm_lm_small_step(H, g, 6, lambda, x) < 0) {
                lambda *= 10.0;
                continue;
            }
            double dR[9], Rn[9], tn[3];
            if (sfm_rot_from_axis_angle(x, dR) != SFM_OK)
                return -1;
            sfm_matmul3(dR, R, Rn);
            tn[0] = t[0] + x[3];
            tn[1] = t[1] + x[4];
            tn[2] = t[2] + x[5];
            double cn = cost(b, X, idx, n, Rn, tn, s2);
            if (cn < cur) {
                double rel = (cur - cn) / (cur > 0 ? cur : 1.0);
                memcpy(R, Rn, sizeof Rn);
                memcpy(t, tn, sizeof tn);
                cur = cn;
                accepted = 1;
                improved = 1;
                lambda = sfm_lm_small_relax(lambda);
                if (rel < 1e-10)
                    return 0;
            } else {
                lambda *= 10.0;
            }
        }
        if (!accepted)
            break;
    }
    return improved ? 0 : 1;
}
