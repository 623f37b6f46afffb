/*
 * LU factorization with partial pivoting (Doolittle, row-major, in place) and
 * the matching forward/back substitution.
 */
#include <math.h>

#include "core/linalg_util.h"

int sfm_lu_factor(double *A, int n, int *piv)
{
    if (A == NULL || piv == NULL || !sfmi_la_dim_ok(n))
        return SFM_E_ARGUMENT;
    if (!sfmi_la_all_finite(A, (size_t)n * (size_t)n))
        return SFM_E_NONFINITE;
    for (int k = 0; k < n; k++) {
        int p = k;
        double best = fabs(A[(size_t)k * n + k]);
        for (int i = k + 1; i < n; i++) {
            double v = fabs(A[(size_t)i * n + k]);
            if (v > best) {
                best = v;
                p = i;
            }
        }
        piv[k] = p;
        if (best == 0.0)
            return SFM_E_SINGULAR;
        if (p != k) {
            double *rk = A + (size_t)k * n, *rp = A + (size_t)p * n;
            for (int j = 0; j < n; j++) {
                double t = rk[j];
                rk[j] = rp[j];
                rp[j] = t;
            }
        }
        const double *rk = A + (size_t)k * n;
        double inv = 1.0 / rk[k];
        for (int i = k + 1; i < n; i++) {
            double *ri = A + (size_t)i * n;
            double l = ri[k] * inv;
            ri[k] = l;
            if (l != 0.0)
                for (int j = k + 1; j < n; j++)
                    ri[j] -= l * rk[j];
        }
    }
    return SFM_OK;
}

int sfm_lu_solve(const double *LU, const int *piv, int n, double *B, int nrhs)
{
    if (LU == NULL || piv == NULL || B == NULL || !sfmi_la_dim_ok(n) || !sfmi_la_dim_ok(nrhs))
        return SFM_E_ARGUMENT;
    for (int i = 0; i < n; i++)
        if (piv[i] < i || piv[i] >= n)
            return SFM_E_ARGUMENT;
    if (!sfmi_la_all_finite(LU, (size_t)n * (size_t)n) ||
        !sfmi_la_all_finite(B, (size_t)n * (size_t)nrhs))
        return SFM_E_NONFINITE;
    for (int i = 0; i < n; i++)
        if (LU[(size_t)i * n + i] == 0.0)
            return SFM_E_ARGUMENT; /* not a successful factorization */
    /* apply the row interchanges in the order they were made */
    for (int k = 0; k < n; k++) {
        int p = piv[k];
        if (p != k) {
            double *bk = B + (size_t)k * nrhs, *bp = B + (size_t)p * nrhs;
            for (int j = 0; j < nrhs; j++) {
                double t = bk[j];
                bk[j] = bp[j];
                bp[j] = t;
            }
        }
    }
    /* L y = P b (unit diagonal) */
    for (int i = 1; i < n; i++) {
        double *bi = B + (size_t)i * nrhs;
        for (int k = 0; k < i; k++) {
            double l = LU[(size_t)i * n + k];
            if (l != 0.0) {
                const double *bk = B + (size_t)k * nrhs;
                for (int j = 0; j < nrhs; j++)
                    bi[j] -= l * bk[j];
            }
        }
    }
    /* U x = y */
    for (int i = n - 1; i >= 0; i--) {
        double *bi = B + (size_t)i * nrhs;
        for (int k = i + 1; k < n; k++) {
            double u = LU[(size_t)i * n + k];
            if (u != 0.0) {
                const double *bk = B + (size_t)k * nrhs;
                for (int j = 0; j < nrhs; j++)
                    bi[j] -= u * bk[j];
            }
        }
        double inv = 1.0 / LU[(size_t)i * n + i];
        for (int j = 0; j < nrhs; j++)
            bi[j] *= inv;
    }
    return SFM_OK;
}
