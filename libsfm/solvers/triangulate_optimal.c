/*
 * Optimal two-view triangulation: P. Lindstrom, "Triangulation made easy",
 * CVPR 2010, algorithm niter2 (two iterations, which the paper shows agree
 * with the exact optimum of Hartley & Sturm to machine precision in practice).
 * Lindstrom writes the constraint x^T E x' = 0; with ours, x2^T F x1 = 0,
 * x = x2, x' = x1 and E = F. The corrected pair is triangulated linearly.
 * Stack: about 3 KiB (the 4x4 SVD workspace of the linear step; gcc 12 -O2
 * x86-64: 720 + 1680 + 440 bytes).
 */
#include <math.h>

#include "core/linalg_util.h"
#include "solvers/triangulate_internal.h"
#include "sfm/sfm_triangulate.h"

/* det of the 4x4 whose rows are a0, a1 (from P1) and b0, b1 (from P2). */
static double det4_rows(const double *a0, const double *a1, const double *b0, const double *b1)
{
    /* Laplace expansion along the first two rows (2x2 minors). */
    double s = 0.0;
    static const int pairs[6][2] = {{0, 1}, {0, 2}, {0, 3}, {1, 2}, {1, 3}, {2, 3}};
    static const int sign[6] = {1, -1, 1, 1, -1, 1};
    for (int p = 0; p < 6; p++) {
        int i = pairs[p][0], j = pairs[p][1];
        int k = pairs[5 - p][0], l = pairs[5 - p][1];
        double m1 = a0[i] * a1[j] - a0[j] * a1[i];
        double m2 = b0[k] * b1[l] - b0[l] * b1[k];
        s += sign[p] * m1 * m2;
    }
    return s;
}

int sfm_fundamental_from_projections(const double P1[12], const double P2[12], sfm_mat3 *F_out)
{
    double *F = F_out ? F_out->m : NULL;
    if (!P1 || !P2 || !F)
        return SFM_E_ARGUMENT;
    if (!sfmi_la_all_finite(P1, 12) || !sfmi_la_all_finite(P2, 12))
        return SFM_E_NONFINITE;
    double G[9], n = 0.0;
    /* F[j][i] = (-1)^(i+j) det[P1 without row i; P2 without row j] */
    for (int i = 0; i < 3; i++) {
        const double *a0 = P1 + 4 * (i == 0 ? 1 : 0), *a1 = P1 + 4 * (i == 2 ? 1 : 2);
        for (int j = 0; j < 3; j++) {
            const double *b0 = P2 + 4 * (j == 0 ? 1 : 0), *b1 = P2 + 4 * (j == 2 ? 1 : 2);
            double d = det4_rows(a0, a1, b0, b1);
            G[3 * j + i] = ((i + j) % 2 ? -d : d);
            n += d * d;
        }
    }
    /* F is of degree 2 in each of P1, P2: compare with their norms */
    double s1 = 0.0, s2 = 0.0;
    for (int k = 0; k < 12; k++) {
        s1 += P1[k] * P1[k];
        s2 += P2[k] * P2[k];
    }
    if (!(n > 1e-24 * (s1 * s2) * (s1 * s2)) || !isfinite(n))
        return SFM_E_ARGUMENT;
    n = 1.0 / sqrt(n);
    for (int k = 0; k < 9; k++)
        F[k] = G[k] * n;
    return SFM_OK;
}

int sfm_triangulate_optimal2(const double P1[12], const double P2[12], int npoints,
                             const double *x1, const double *x2, double *X, int *flags)
{
    if (!P1 || !P2 || !X || npoints < 0 || (npoints > 0 && (!x1 || !x2)))
        return SFM_E_ARGUMENT;
    if (!sfmi_la_all_finite(P1, 12) || !sfmi_la_all_finite(P2, 12) || !sfmi_la_all_finite(x1, 2L * npoints) ||
        !sfmi_la_all_finite(x2, 2L * npoints))
        return SFM_E_NONFINITE;
    sfm_mat3 Fm;
    int st = sfm_fundamental_from_projections(P1, P2, &Fm);
    const double *F = Fm.m;
    if (st < 0)
        return st;
    double P[24];
    for (int k = 0; k < 12; k++) {
        P[k] = P1[k];
        P[12 + k] = P2[k];
    }
    int good = 0;
    for (int j = 0; j < npoints; j++) {
        /* x = x2, x' = x1 (homogeneous, third coordinate 1) */
        double x[3] = {x2[2 * j], x2[2 * j + 1], 1.0}, xp[3] = {x1[2 * j], x1[2 * j + 1], 1.0};
        double Fxp[3], Ftx[2];
        for (int r = 0; r < 3; r++)
            Fxp[r] = F[3 * r] * xp[0] + F[3 * r + 1] * xp[1] + F[3 * r + 2];
        for (int c = 0; c < 2; c++)
            Ftx[c] = F[c] * x[0] + F[3 + c] * x[1] + F[6 + c];
        double n[2] = {Fxp[0], Fxp[1]}, np[2] = {Ftx[0], Ftx[1]};
        /* E~ = upper-left 2x2 of F */
        double a = n[0] * (F[0] * np[0] + F[1] * np[1]) + n[1] * (F[3] * np[0] + F[4] * np[1]);
        double b = 0.5 * (n[0] * n[0] + n[1] * n[1] + np[0] * np[0] + np[1] * np[1]);
        double c = x[0] * Fxp[0] + x[1] * Fxp[1] + Fxp[2];
        double disc = b * b - a * c;
        double d = disc > 0.0 ? sqrt(disc) : 0.0;
        double xc[2] = {x[0], x[1]}, xpc[2] = {xp[0], xp[1]};
        if (b + d > 0.0) {
            double lam = c / (b + d);
            double dx[2] = {lam * n[0], lam * n[1]}, dxp[2] = {lam * np[0], lam * np[1]};
            /* n -= E~ dx', n' -= E~^T dx */
            n[0] -= F[0] * dxp[0] + F[1] * dxp[1];
            n[1] -= F[3] * dxp[0] + F[4] * dxp[1];
            np[0] -= F[0] * dx[0] + F[3] * dx[1];
            np[1] -= F[1] * dx[0] + F[4] * dx[1];
            double nn = n[0] * n[0] + n[1] * n[1] + np[0] * np[0] + np[1] * np[1];
            if (nn > 0.0) {
                lam *= 2.0 * d / nn;
                xc[0] -= lam * n[0];
                xc[1] -= lam * n[1];
                xpc[0] -= lam * np[0];
                xpc[1] -= lam * np[1];
            }
        }
        sfmi_tri_acc acc;
        sfmi_tri_acc_init(&acc);
        sfmi_tri_acc_add_obs(&acc, P1, xpc[0], xpc[1]);
        sfmi_tri_acc_add_obs(&acc, P2, xc[0], xc[1]);
        double Xh[4];
        st = sfmi_tri_acc_solve(&acc, Xh);
        if (st < 0)
            return st;
        int fl = sfmi_tri_finish_h(Xh, 2, P, X + 3 * j);
        if (flags)
            flags[j] = fl;
        good += fl == 0;
    }
    return good;
}
