/*
 * Internal projective helpers of the recon module (see projective.h).
 * Linear estimates use the normal equations of row-normalized DLT systems
 * in Hartley-normalized coordinates, where their conditioning is benign
 * (Hartley & Zisserman 4.4 and 7.1).
 */
#include <math.h>
#include <string.h>

#include "recon/projective.h"
#include "sfm/sfm_common.h"
#include "sfm/sfm_linalg.h"
#include "solvers/normalize.h"

void sfmi_normalize_vec(double *x, int n)
{
    double s = 0;
    for (int k = 0; k < n; k++)
        s += x[k] * x[k];
    s = sqrt(s);
    if (s > 0)
        for (int k = 0; k < n; k++)
            x[k] /= s;
}

void sfmi_normalize4(double X[4])
{
    sfmi_normalize_vec(X, 4);
}

int sfmi_hartley_view(const double *px, int n, double T[9], double *xn)
{
    /* centroid and mean distance over the observed points only */
    double cx = 0, cy = 0;
    int c = 0;
    for (int j = 0; j < n; j++)
        if (!isnan(px[2 * j]) && !isnan(px[2 * j + 1])) {
            cx += px[2 * j];
            cy += px[2 * j + 1];
            c++;
        }
    if (c < 2)
        return SFM_E_SINGULAR;
    cx /= c;
    cy /= c;
    double d = 0;
    for (int j = 0; j < n; j++)
        if (!isnan(px[2 * j]) && !isnan(px[2 * j + 1]))
            d += sqrt((px[2 * j] - cx) * (px[2 * j] - cx) + (px[2 * j + 1] - cy) * (px[2 * j + 1] - cy));
    d /= c;
    if (!(d > 0))
        return SFM_E_SINGULAR;
    double t[3] = {sqrt(2.0) / d, -sqrt(2.0) / d * cx, -sqrt(2.0) / d * cy};
    sfmi_hartley_matrix(t, T);
    for (int j = 0; j < n; j++) {
        if (isnan(px[2 * j]) || isnan(px[2 * j + 1])) {
            xn[2 * j] = xn[2 * j + 1] = (double)NAN;
            continue;
        }
        xn[2 * j] = t[0] * px[2 * j] + t[1];
        xn[2 * j + 1] = t[0] * px[2 * j + 1] + t[2];
    }
    return SFM_OK;
}

void sfmi_denormalize_camera(const double T[9], const double Pn[12], double P[12])
{
    /* T = [s 0 a; 0 s b; 0 0 1], T^{-1} = [1/s 0 -a/s; 0 1/s -b/s; 0 0 1] */
    double s = T[0], a = T[2], b = T[5];
    for (int c = 0; c < 4; c++) {
        P[c] = (Pn[c] - a * Pn[8 + c]) / s;
        P[4 + c] = (Pn[4 + c] - b * Pn[8 + c]) / s;
        P[8 + c] = Pn[8 + c];
    }
}

int sfmi_reproj_err2(const double P[12], const double X[4], const double x[2], double *e2)
{
    double y[3];
    for (int r = 0; r < 3; r++)
        y[r] = P[4 * r] * X[0] + P[4 * r + 1] * X[1] + P[4 * r + 2] * X[2] + P[4 * r + 3] * X[3];
    double sc = fabs(y[0]) + fabs(y[1]) + fabs(y[2]);
    if (!(fabs(y[2]) > 1e-14 * sc)) {
        *e2 = 0;
        return 0;
    }
    double du = y[0] / y[2] - x[0], dv = y[1] / y[2] - x[1];
    *e2 = du * du + dv * dv;
    return 1;
}

int sfmi_triangulate_homog(int m, int n, const double *x, const double *P, const int *view_ok, int j,
                           double X[4], void *ws, size_t ws_size)
{
    double A[16] = {0};
    int c = 0;
    for (int i = 0; i < m; i++) {
        const double *q = &x[((size_t)i * n + j) * 2];
        if (!view_ok[i] || isnan(q[0]) || isnan(q[1]))
            continue;
        const double *Pi = &P[12 * i];
        for (int e = 0; e < 2; e++) {
            double r[4], s = 0;
            for (int k = 0; k < 4; k++) {
                r[k] = q[e] * Pi[8 + k] - Pi[4 * e + k];
                s += r[k] * r[k];
            }
            if (!(s > 0))
                continue;
            s = 1 / sqrt(s);
            for (int a = 0; a < 4; a++)
                for (int b = 0; b < 4; b++)
                    A[a * 4 + b] += r[a] * r[b] * s * s;
        }
        c++;
    }
    if (c < 2)
        return SFM_E_SINGULAR;
    double w[4], V[16], v[4];
    int st = sfm_sym_eig(A, 4, w, V, ws, ws_size);
    if (st < 0)
        return st;
    /* a second vanishing eigenvalue: the point is not determined */
    if (!(w[1] > 1e-12 * w[3]))
        return SFM_E_SINGULAR;
    for (int k = 0; k < 4; k++)
        v[k] = V[k * 4];
    sfmi_normalize4(v);
    memcpy(X, v, sizeof v);
    return SFM_OK;
}

int sfmi_resection_dlt(const double *xv, int n, const double *X, const int *pt_ok, double P[12],
                       void *ws, size_t ws_size)
{
    double A[144] = {0};
    int c = 0;
    for (int j = 0; j < n; j++) {
        if (!pt_ok[j] || isnan(xv[2 * j]) || isnan(xv[2 * j + 1]))
            continue;
        const double *Xj = &X[4 * (size_t)j];
        for (int e = 0; e < 2; e++) {
            /* row: X^T in block e, -x_e X^T in block 2 */
            double r[12] = {0};
            for (int k = 0; k < 4; k++) {
                r[4 * e + k] = Xj[k];
                r[8 + k] = -xv[2 * j + e] * Xj[k];
            }
            double s = 0;
            for (int k = 0; k < 12; k++)
                s += r[k] * r[k];
            if (!(s > 0))
                continue;
            for (int a = 0; a < 12; a++)
                for (int b = 0; b <= a; b++)
                    A[a * 12 + b] += r[a] * r[b] / s;
        }
        c++;
    }
    if (c < 6)
        return SFM_E_SINGULAR;
    double w[12], V[144];
    int st = sfm_sym_eig(A, 12, w, V, ws, ws_size);
    if (st < 0)
        return st;
    if (!(w[1] > 1e-12 * w[11]))
        return SFM_E_SINGULAR;
    for (int k = 0; k < 12; k++)
        P[k] = V[k * 12];
    return SFM_OK;
}

double sfmi_third_view_scale(const sfm_pose *p3, int m, const double *X, const int *flags,
                             const double *b3)
{
    double num = 0, den = 0;
    const double *R3 = p3->R, *t3 = p3->t;
    for (int j = 0; j < m; j++) {
        if (flags[j] != 0)
            continue;
        const double *Xj = &X[3 * j], *b = &b3[3 * j];
        double y[3], ca[3], cc[3];
        for (int r = 0; r < 3; r++)
            y[r] = R3[r * 3] * Xj[0] + R3[r * 3 + 1] * Xj[1] + R3[r * 3 + 2] * Xj[2];
        ca[0] = b[1] * t3[2] - b[2] * t3[1];
        ca[1] = b[2] * t3[0] - b[0] * t3[2];
        ca[2] = b[0] * t3[1] - b[1] * t3[0];
        cc[0] = b[1] * y[2] - b[2] * y[1];
        cc[1] = b[2] * y[0] - b[0] * y[2];
        cc[2] = b[0] * y[1] - b[1] * y[0];
        num -= ca[0] * cc[0] + ca[1] * cc[1] + ca[2] * cc[2];
        den += ca[0] * ca[0] + ca[1] * ca[1] + ca[2] * ca[2];
    }
    double s = num / den;
    if (!(den > 0) || !isfinite(s))
        return (double)NAN;
    return s;
}
