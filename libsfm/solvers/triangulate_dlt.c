/*
 * Linear (DLT) triangulation from n views (Hartley & Zisserman, section
 * 12.2), with a streaming QR so that any number of views fits a fixed stack,
 * and the shared pieces used by the optimal two-view method. The null vector
 * of the 4x4 factor comes from inverse iteration, the SVD only when that is
 * slow to converge.
 * Stack: the 4x4 factor plus the SVD workspace of a 4x4: about 2.5 KiB with
 * the SVD (gcc 12 -O2 x86-64: 288 + 1680 + 440 bytes).
 */
#include <math.h>
#include <string.h>

#include "core/linalg_util.h"
#include "solvers/triangulate_internal.h"
#include "sfm/sfm_linalg.h"
#include "sfm/sfm_triangulate.h"

void sfmi_tri_acc_init(sfmi_tri_acc *acc)
{
    memset(acc->R, 0, sizeof acc->R);
}

void sfmi_tri_acc_add(sfmi_tri_acc *acc, const double a_in[4])
{
    double n = sqrt(a_in[0] * a_in[0] + a_in[1] * a_in[1] + a_in[2] * a_in[2] + a_in[3] * a_in[3]);
    if (!(n > 0.0))
        return;
    double a[4] = {a_in[0] / n, a_in[1] / n, a_in[2] / n, a_in[3] / n};
    double *R = acc->R;
    for (int k = 0; k < 4; k++) {
        if (a[k] == 0.0)
            continue;
        /* rows are unit and the factor's entries bounded: no overflow */
        double r = sqrt(R[5 * k] * R[5 * k] + a[k] * a[k]);
        double c = R[5 * k] / r, s = a[k] / r;
        for (int j = k; j < 4; j++) {
            double rj = R[4 * k + j], aj = a[j];
            R[4 * k + j] = c * rj + s * aj;
            a[j] = -s * rj + c * aj;
        }
    }
}

void sfmi_tri_acc_add_obs(sfmi_tri_acc *acc, const double P[12], double u, double v)
{
    double a[4], b[4];
    for (int k = 0; k < 4; k++) {
        a[k] = u * P[8 + k] - P[k];
        b[k] = v * P[8 + k] - P[4 + k];
    }
    sfmi_tri_acc_add(acc, a);
    sfmi_tri_acc_add(acc, b);
}

static void unit4(double v[4])
{
    double n = 1.0 / sqrt(v[0] * v[0] + v[1] * v[1] + v[2] * v[2] + v[3] * v[3]);
    v[0] *= n;
    v[1] *= n;
    v[2] *= n;
    v[3] *= n;
}

int sfmi_tri_acc_solve(const sfmi_tri_acc *acc, double Xh[4])
{
    const double *R = acc->R;
    /* Inverse iteration on R^T R from e4 (the first step is the exact null
     * vector when R33 = 0): each step divides the error by (s4/s3)^2, so a
     * well-posed point converges in two or three steps. A vanishing R33 is
     * replaced by a tiny pivot (this moves the vector by far less than a
     * rounding error). Hard cases (slow convergence, a small leading
     * pivot) go to the SVD. */
    double dmax = fmax(fmax(fabs(R[0]), fabs(R[5])), fmax(fabs(R[10]), fabs(R[15])));
    if (dmax > 0.0 && fabs(R[0]) > 1e-8 * dmax && fabs(R[5]) > 1e-8 * dmax &&
        fabs(R[10]) > 1e-8 * dmax) {
        double r33 = R[15];
        double tiny = 1e-140 * dmax;
        if (fabs(r33) < tiny)
            r33 = r33 < 0.0 ? -tiny : tiny;
        double i0 = 1.0 / R[0], i1 = 1.0 / R[5], i2 = 1.0 / R[10], i3 = 1.0 / r33;
        double x[4] = {0.0, 0.0, 0.0, 1.0};
        for (int it = 0; it < 8; it++) {
            double y[4], z[4];
            /* R^T y = x (forward) */
            y[0] = x[0] * i0;
            y[1] = (x[1] - R[1] * y[0]) * i1;
            y[2] = (x[2] - R[2] * y[0] - R[6] * y[1]) * i2;
            y[3] = (x[3] - R[3] * y[0] - R[7] * y[1] - R[11] * y[2]) * i3;
            unit4(y);
            /* R z = y (back) */
            z[3] = y[3] * i3;
            z[2] = (y[2] - R[11] * z[3]) * i2;
            z[1] = (y[1] - R[6] * z[2] - R[7] * z[3]) * i1;
            z[0] = (y[0] - R[1] * z[1] - R[2] * z[2] - R[3] * z[3]) * i0;
            unit4(z);
            if (z[3] * x[3] + z[0] * x[0] + z[1] * x[1] + z[2] * x[2] < 0.0) {
                z[0] = -z[0];
                z[1] = -z[1];
                z[2] = -z[2];
                z[3] = -z[3];
            }
            double d = fmax(fmax(fabs(z[0] - x[0]), fabs(z[1] - x[1])),
                            fmax(fabs(z[2] - x[2]), fabs(z[3] - x[3])));
            memcpy(x, z, sizeof x);
            if (it > 0 && d < 1e-14) {
                if ((x[0] + x[1] + x[2] + x[3]) * 0.0 != 0.0)
                    break;
                memcpy(Xh, x, sizeof x);
                return SFM_OK;
            }
        }
    }
    double ws[160]; /* 1280 bytes; sfm_svd_workspace_size(4, 4) is checked */
    double S[4], V[16];
    size_t need = sfm_svd_workspace_size(4, 4);
    if (need > sizeof ws)
        return SFM_E_UNSUPPORTED;
    int st = sfm_svd(acc->R, 4, 4, NULL, S, V, ws, sizeof ws);
    if (st < 0)
        return st;
    for (int k = 0; k < 4; k++)
        Xh[k] = V[4 * k + 3];
    return SFM_OK;
}

static double det3_of_P(const double P[12])
{
    return P[0] * (P[5] * P[10] - P[6] * P[9]) - P[1] * (P[4] * P[10] - P[6] * P[8]) +
           P[2] * (P[4] * P[9] - P[5] * P[8]);
}

int sfmi_tri_finish_h(const double Xh_in[4], int nviews, const double *P, double X[3])
{
    double Xh[4] = {Xh_in[0], Xh_in[1], Xh_in[2], Xh_in[3]};
    double d3 = sqrt(Xh[0] * Xh[0] + Xh[1] * Xh[1] + Xh[2] * Xh[2]);
    int flags = 0;
    if (fabs(Xh[3]) <= 1e-12 * d3) {
        /* at infinity: orient the direction to the majority of the cameras */
        int vote = 0;
        for (int v = 0; v < nviews; v++) {
            const double *Pv = P + 12 * v;
            double z = (Pv[8] * Xh[0] + Pv[9] * Xh[1] + Pv[10] * Xh[2]) * det3_of_P(Pv);
            vote += (z > 0.0) - (z < 0.0);
        }
        double s = (vote < 0 ? -1.0 : 1.0) / (d3 > 0.0 ? d3 : 1.0);
        for (int k = 0; k < 3; k++)
            X[k] = Xh[k] * s;
        for (int v = 0; v < nviews; v++) {
            const double *Pv = P + 12 * v;
            double z = (Pv[8] * X[0] + Pv[9] * X[1] + Pv[10] * X[2]) * det3_of_P(Pv);
            if (!(z > 0.0))
                flags |= SFM_TRI_BEHIND;
        }
        return flags | SFM_TRI_INFINITY;
    }
    for (int k = 0; k < 3; k++)
        X[k] = Xh[k] / Xh[3];
    for (int v = 0; v < nviews; v++) {
        const double *Pv = P + 12 * v;
        double z = (Pv[8] * X[0] + Pv[9] * X[1] + Pv[10] * X[2] + Pv[11]) * det3_of_P(Pv);
        if (!(z > 0.0))
            flags |= SFM_TRI_BEHIND;
    }
    return flags;
}

int sfm_triangulate_dlt(int nviews, const double *P, int npoints, const double *x, double *X,
                        int *flags)
{
    if (!P || !X || nviews < 2 || npoints < 0 || (npoints > 0 && !x))
        return SFM_E_ARGUMENT;
    if (!sfmi_la_all_finite(P, 12L * nviews) || !sfmi_la_all_finite(x, 2L * nviews * npoints))
        return SFM_E_NONFINITE;
    int good = 0;
    for (int j = 0; j < npoints; j++) {
        sfmi_tri_acc acc;
        sfmi_tri_acc_init(&acc);
        for (int v = 0; v < nviews; v++) {
            const double *o = x + 2 * ((long)v * npoints + j);
            sfmi_tri_acc_add_obs(&acc, P + 12 * v, o[0], o[1]);
        }
        double Xh[4];
        int st = sfmi_tri_acc_solve(&acc, Xh);
        if (st < 0)
            return st;
        int fl = sfmi_tri_finish_h(Xh, nviews, P, X + 3 * j);
        if (flags)
            flags[j] = fl;
        good += fl == 0;
    }
    return good;
}
