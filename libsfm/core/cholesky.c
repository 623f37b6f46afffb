/*
 * Cholesky factorization A = L L^T (row-major lower triangle, in place) and
 * the matching two triangular solves.
 */
#include <math.h>

#include "core/linalg_util.h"

int sfm_cholesky_factor(double *A, int n)
{
    if (A == NULL || !sfmi_la_dim_ok(n))
        return SFM_E_ARGUMENT;
    for (int i = 0; i < n; i++)
        for (int j = 0; j <= i; j++)
            if (!isfinite(A[(size_t)i * n + j]))
                return SFM_E_NONFINITE;
    for (int j = 0; j < n; j++) {
        double *rj = A + (size_t)j * n;
        double d = rj[j];
        for (int k = 0; k < j; k++)
            d -= rj[k] * rj[k];
        if (!(d > 0.0) || !isfinite(d))
            return SFM_E_SINGULAR;
        double ljj = sqrt(d);
        rj[j] = ljj;
        double inv = 1.0 / ljj;
        for (int i = j + 1; i < n; i++) {
            double *ri = A + (size_t)i * n;
            double s = ri[j];
            for (int k = 0; k < j; k++)
                s -= ri[k] * rj[k];
            ri[j] = s * inv;
        }
    }
    for (int i = 0; i < n; i++)
        for (int j = i + 1; j < n; j++)
            A[(size_t)i * n + j] = 0.0;
    return SFM_OK;
}

int sfm_cholesky_solve(const double *L, int n, double *B, int nrhs)
{
    if (L == NULL || B == NULL || !sfmi_la_dim_ok(n) || !sfmi_la_dim_ok(nrhs))
        return SFM_E_ARGUMENT;
    for (int i = 0; i < n; i++)
        if (!(L[(size_t)i * n + i] != 0.0))
            return SFM_E_ARGUMENT; /* not a successful factorization */
    /* L y = b */
    for (int i = 0; i < n; i++) {
        double *bi = B + (size_t)i * nrhs;
        const double *li = L + (size_t)i * n;
        for (int k = 0; k < i; k++) {
            const double *bk = B + (size_t)k * nrhs;
            for (int j = 0; j < nrhs; j++)
                bi[j] -= li[k] * bk[j];
        }
        double inv = 1.0 / li[i];
        for (int j = 0; j < nrhs; j++)
            bi[j] *= inv;
    }
    /* L^T x = y */
    for (int i = n - 1; i >= 0; i--) {
        double *bi = B + (size_t)i * nrhs;
        for (int k = i + 1; k < n; k++) {
            double lki = L[(size_t)k * n + i];
            const double *bk = B + (size_t)k * nrhs;
            for (int j = 0; j < nrhs; j++)
                bi[j] -= lki * bk[j];
        }
        double inv = 1.0 / L[(size_t)i * n + i];
        for (int j = 0; j < nrhs; j++)
            bi[j] *= inv;
    }
    return SFM_OK;
}
