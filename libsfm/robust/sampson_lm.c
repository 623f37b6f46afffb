/*
 * Levenberg-Marquardt on the Sampson error of an essential matrix
 * parametrised by (R, t) on SO(3) x S^2 (local rotation increment on the
 * left, translation increment in the tangent plane of t, then normalised).
 * Residual r = C / sqrt(D), C = b2^T E b1, D = |E b1|^2 + |E^T b2|^2 - 2 C^2
 * (see epipolar.h); its derivative along a direction dE of E is
 * dC / sqrt(D) - C dD / (2 D^1.5), dC = b2^T dE b1,
 * dD = 2 (E b1).(dE b1) + 2 (E^T b2).(dE^T b2) - 4 C dC.
 */
#include "robust/sampson_lm.h"

#include <math.h>
#include <string.h>

#include "robust/epipolar.h"
#include "robust/lm_small.h"
#include "sfm/sfm_linalg.h"
#include "sfm/sfm_rotation.h"

#define MAXP 5

static double cost(const double *b1, const double *b2, const int *idx, int n, const double *E,
                   double s2)
{
    double c = 0.0;
    for (int j = 0; j < n; j++) {
        int i = idx[j];
        double r2 = sfm_sampson_bearing2(E, b1 + 3 * i, b2 + 3 * i);
        if (r2 < SFM_ROBUST_HUGE)
            c += sfm_lm_cauchy_loss(r2, s2);
    }
    return c;
}

int sfm_robust_sampson_lm(const double *b1, const double *b2, const int *idx, int n,
                          const double *axis, double scale, int iters, double R[9], double t[3])
{
    const double s2 = scale > 0.0 ? scale * scale : 0.0;
    const int np = axis ? 3 : 5;
    const int nr = axis ? 1 : 3;
    double E[9];
    sfm_essential_from_pose(R, t, E);
    double cur = cost(b1, b2, idx, n, E, s2);
    double lambda = 1e-4;
    int improved = 0;
    for (int it = 0; it < iters; it++) {
        double e1[3], e2[3];
        sfm_tangent_basis(t, e1, e2);
        double H[MAXP * MAXP], g[MAXP];
        memset(H, 0, sizeof H);
        memset(g, 0, sizeof g);
        for (int j = 0; j < n; j++) {
            const double *x1 = b1 + 3 * idx[j], *x2 = b2 + 3 * idx[j];
            /* u = R b1, a = E b1 = t x u, v = b2 x t (so E^T b2 = R^T v and
             * |E^T b2| = |v|), C = u.v, D = |a|^2 + |v|^2 - 2 C^2. Under
             * u <- u + w x u: dC = w.(u x v), d|a|^2 = 2 w.(u x (a x t)).
             * Under t <- t + dt: dC = dt.(u x b2),
             * d|a|^2 + d|v|^2 = 2 dt.(u x a + v x b2). */
            double u[3], a[3], v[3];
            sfm_matvec3(R, x1, u);
            sfm_cross3(t, u, a);
            sfm_cross3(x2, t, v);
            double C = sfm_dot3(u, v);
            double D = sfm_dot3(a, a) + sfm_dot3(v, v) - 2.0 * C * C;
            if (!(D > 1e-300))
                continue;
            double gCw[3], axt[3], gDw[3], gCt[3], uxa[3], vxb[3], gDt[3];
            sfm_cross3(u, v, gCw);
            sfm_cross3(a, t, axt);
            sfm_cross3(u, axt, gDw);
            sfm_cross3(u, x2, gCt);
            sfm_cross3(u, a, uxa);
            sfm_cross3(v, x2, vxb);
            for (int k = 0; k < 3; k++) {
                gDw[k] = 2.0 * gDw[k] - 4.0 * C * gCw[k];
                gDt[k] = 2.0 * (uxa[k] + vxb[k]) - 4.0 * C * gCt[k];
            }
            double sD = sqrt(D);
            double r = C / sD;
            const double ia = 1.0 / sD, ib = 0.5 * C / (D * sD);
            double J[MAXP];
            if (axis) {
                J[0] = ia * sfm_dot3(axis, gCw) - ib * sfm_dot3(axis, gDw);
            } else {
                for (int k = 0; k < 3; k++)
                    J[k] = ia * gCw[k] - ib * gDw[k];
            }
            J[nr] = ia * sfm_dot3(e1, gCt) - ib * sfm_dot3(e1, gDt);
            J[nr + 1] = ia * sfm_dot3(e2, gCt) - ib * sfm_dot3(e2, gDt);
            double w = sfm_lm_cauchy_weight(r * r, s2);
            for (int p = 0; p < np; p++) {
                double wj = w * J[p];
                g[p] += wj * r;
                for (int q = 0; q <= p; q++)
                    H[p * np + q] += wj * J[q];
            }
        }
        /* damped steps until one lowers the cost */
        int accepted = 0;
        for (int tries = 0; tries < 6 && !accepted; tries++) {
            double x[MAXP];
            if (sfm_lm_small_step(H, g, np, lambda, x) < 0) {
                lambda *= 10.0;
                continue;
            }
            double w[3], dR[9], Rn[9], tn[3];
            if (axis) {
                w[0] = x[0] * axis[0];
                w[1] = x[0] * axis[1];
                w[2] = x[0] * axis[2];
            } else {
                w[0] = x[0];
                w[1] = x[1];
                w[2] = x[2];
            }
            if (sfm_rot_from_axis_angle(w, dR) != SFM_OK)
                return -1;
            sfm_matmul3(dR, R, Rn);
            for (int k = 0; k < 3; k++)
                tn[k] = t[k] + x[nr] * e1[k] + x[nr + 1] * e2[k];
            double l = sqrt(sfm_dot3(tn, tn));
            if (!(l > 0.0) || !isfinite(l))
                return -1;
            tn[0] /= l;
            tn[1] /= l;
            tn[2] /= l;
            double En[9];
            sfm_essential_from_pose(Rn, tn, En);
            double cn = cost(b1, b2, idx, n, En, s2);
            if (cn < cur) {
                memcpy(R, Rn, sizeof Rn);
                memcpy(t, tn, sizeof tn);
                memcpy(E, En, sizeof En);
                double rel = (cur - cn) / (cur > 0 ? cur : 1.0);
                cur = cn;
                accepted = 1;
                improved = 1;
                lambda = sfm_lm_small_relax(lambda);
                if (rel < 1e-6)
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
