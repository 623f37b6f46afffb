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
#include "sfm/sfm_linalg.h"
#include "sfm/sfm_rotation.h"

#define MAXP 5

/* Cauchy loss of a squared residual (plain square when s2 <= 0). */
static double loss(double r2, double s2)
{
    return s2 > 0.0 ? s2 * log1p(r2 / s2) : r2;
}

static double cost(const double *b1, const double *b2, const int *idx, int n, const double *E,
                   double s2)
{
    double c = 0.0;
    for (int j = 0; j < n; j++) {
        int i = idx[j];
        double r2 = sfm_sampson_bearing2(E, b1 + 3 * i, b2 + 3 * i);
        c += r2 < SFM_ROBUST_HUGE ? loss(r2, s2) : 0.0;
    }
    return c;
}

static void skew(const double *v, double *S)
{
    S[0] = 0.0;
    S[1] = -v[2];
    S[2] = v[1];
    S[3] = v[2];
    S[4] = 0.0;
    S[5] = -v[0];
    S[6] = -v[1];
    S[7] = v[0];
    S[8] = 0.0;
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
        /* directions of E for each parameter */
        double dE[MAXP][9], St[9], S[9], tmp[9], e1[3], e2[3];
        skew(t, St);
        for (int k = 0; k < nr; k++) {
            double w[3] = {0.0, 0.0, 0.0};
            if (axis) {
                w[0] = axis[0];
                w[1] = axis[1];
                w[2] = axis[2];
            } else {
                w[k] = 1.0;
            }
            skew(w, S);
            sfm_matmul3(St, S, tmp);
            sfm_matmul3(tmp, R, dE[k]);
        }
        sfm_tangent_basis(t, e1, e2);
        skew(e1, S);
        sfm_matmul3(S, R, dE[nr]);
        skew(e2, S);
        sfm_matmul3(S, R, dE[nr + 1]);

        double H[MAXP * MAXP], g[MAXP];
        memset(H, 0, sizeof H);
        memset(g, 0, sizeof g);
        for (int j = 0; j < n; j++) {
            const double *x1 = b1 + 3 * idx[j], *x2 = b2 + 3 * idx[j];
            double Eb1[3], Etb2[3];
            sfm_matvec3(E, x1, Eb1);
            Etb2[0] = E[0] * x2[0] + E[3] * x2[1] + E[6] * x2[2];
            Etb2[1] = E[1] * x2[0] + E[4] * x2[1] + E[7] * x2[2];
            Etb2[2] = E[2] * x2[0] + E[5] * x2[1] + E[8] * x2[2];
            double C = sfm_dot3(x2, Eb1);
            double D = sfm_dot3(Eb1, Eb1) + sfm_dot3(Etb2, Etb2) - 2.0 * C * C;
            if (!(D > 1e-300))
                continue;
            double sD = sqrt(D);
            double r = C / sD;
            double J[MAXP];
            for (int p = 0; p < np; p++) {
                const double *M = dE[p];
                double Mb1[3], Mtb2[3];
                sfm_matvec3(M, x1, Mb1);
                Mtb2[0] = M[0] * x2[0] + M[3] * x2[1] + M[6] * x2[2];
                Mtb2[1] = M[1] * x2[0] + M[4] * x2[1] + M[7] * x2[2];
                Mtb2[2] = M[2] * x2[0] + M[5] * x2[1] + M[8] * x2[2];
                double dC = sfm_dot3(x2, Mb1);
                double dD = 2.0 * sfm_dot3(Eb1, Mb1) + 2.0 * sfm_dot3(Etb2, Mtb2) - 4.0 * C * dC;
                J[p] = dC / sD - 0.5 * C * dD / (D * sD);
            }
            double w = s2 > 0.0 ? 1.0 / (1.0 + r * r / s2) : 1.0;
            for (int p = 0; p < np; p++) {
                g[p] += w * J[p] * r;
                for (int q = 0; q <= p; q++)
                    H[p * np + q] += w * J[p] * J[q];
            }
        }
        /* damped steps until one lowers the cost */
        int accepted = 0;
        for (int tries = 0; tries < 6 && !accepted; tries++) {
            double A[MAXP * MAXP], x[MAXP];
            for (int p = 0; p < np; p++) {
                for (int q = 0; q <= p; q++)
                    A[p * np + q] = H[p * np + q];
                A[p * np + p] += lambda * (H[p * np + p] > 1e-12 ? H[p * np + p] : 1e-12);
                x[p] = -g[p];
            }
            if (sfm_cholesky_factor(A, np) != SFM_OK || sfm_cholesky_solve(A, np, x, 1) != SFM_OK) {
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
                lambda = lambda * 0.1 > 1e-10 ? lambda * 0.1 : 1e-10;
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
