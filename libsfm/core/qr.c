/*
 * Householder QR (LAPACK's storage: reflectors H_k = I - tau_k v_k v_k^T with
 * v_k[k] = 1 implicit, v_k below the diagonal of column k; Q = H_0 ... H_{n-1}).
 */
#include <math.h>

#include "core/linalg_util.h"
#include "core/dmath.h"

/* 2-norm of A[r0..m) of column c, safe against overflow/underflow. */
static double col_norm(const double *A, int m, int n, int r0, int c)
{
    double scale = 0.0;
    for (int i = r0; i < m; i++) {
        double v = fabs(A[(size_t)i * n + c]);
        if (v > scale)
            scale = v;
    }
    if (scale == 0.0)
        return 0.0;
    double inv = 1.0 / scale, s = 0.0;
    for (int i = r0; i < m; i++) {
        double v = A[(size_t)i * n + c] * inv;
        s += v * v;
    }
    return scale * sqrt(s);
}

int sfm_qr_factor(double *A, int m, int n, double *tau)
{
    if (A == NULL || tau == NULL || !sfmi_la_dim_ok(m) || !sfmi_la_dim_ok(n) || m < n)
        return SFM_E_ARGUMENT;
    if (!sfmi_la_all_finite(A, (size_t)m * (size_t)n))
        return SFM_E_NONFINITE;
    for (int k = 0; k < n; k++) {
        double alpha = A[(size_t)k * n + k];
        double xnorm = k + 1 < m ? col_norm(A, m, n, k + 1, k) : 0.0;
        if (xnorm == 0.0) {
            tau[k] = 0.0;
            continue;
        }
        double beta = -copysign(sfmi_hypot(alpha, xnorm), alpha);
        tau[k] = (beta - alpha) / beta;
        double inv = 1.0 / (alpha - beta);
        for (int i = k + 1; i < m; i++)
            A[(size_t)i * n + k] *= inv;
        A[(size_t)k * n + k] = beta;
        /* apply H_k to the trailing columns, row by row so the inner loops
         * run along rows; each column's sums keep the order i = k+1, k+2,
         * ..., so the result is the same as column by column. The
         * products v^T A_j gather in tau[k+1..n), not yet in use. */
        double *w = tau;
        const double *ak = A + (size_t)k * n;
        for (int j = k + 1; j < n; j++)
            w[j] = ak[j];
        for (int i = k + 1; i < m; i++) {
            const double *ai = A + (size_t)i * n;
            double vi = ai[k];
            for (int j = k + 1; j < n; j++)
                w[j] += vi * ai[j];
        }
        for (int j = k + 1; j < n; j++) {
            w[j] *= tau[k];
            A[(size_t)k * n + j] -= w[j];
        }
        for (int i = k + 1; i < m; i++) {
            double *ai = A + (size_t)i * n;
            double vi = ai[k];
            for (int j = k + 1; j < n; j++)
                ai[j] -= w[j] * vi;
        }
    }
    return SFM_OK;
}

int sfm_qr_form_q(const double *QR, const double *tau, int m, int n, double *Q)
{
    if (QR == NULL || tau == NULL || Q == NULL || !sfmi_la_dim_ok(m) || !sfmi_la_dim_ok(n) ||
        m < n)
        return SFM_E_ARGUMENT;
    for (int i = 0; i < m; i++)
        for (int j = 0; j < m; j++)
            Q[(size_t)i * m + j] = i == j ? 1.0 : 0.0;
    /* backward accumulation: Q = H_k (H_{k+1} ... H_{n-1}) touches only
     * rows and columns k..m-1 */
    for (int k = n - 1; k >= 0; k--) {
        double tk = tau[k];
        if (tk == 0.0)
            continue;
        for (int j = k; j < m; j++) {
            double s = Q[(size_t)k * m + j];
            for (int i = k + 1; i < m; i++)
                s += QR[(size_t)i * n + k] * Q[(size_t)i * m + j];
            s *= tk;
            Q[(size_t)k * m + j] -= s;
            for (int i = k + 1; i < m; i++)
                Q[(size_t)i * m + j] -= s * QR[(size_t)i * n + k];
        }
    }
    return SFM_OK;
}

int sfm_qr_solve(const double *QR, const double *tau, int m, int n, double *b)
{
    if (QR == NULL || tau == NULL || b == NULL || !sfmi_la_dim_ok(m) || !sfmi_la_dim_ok(n) ||
        m < n)
        return SFM_E_ARGUMENT;
    for (int k = 0; k < n; k++)
        if (QR[(size_t)k * n + k] == 0.0)
            return SFM_E_SINGULAR;
    /* b = Q^T b = H_{n-1} ... H_0 b */
    for (int k = 0; k < n; k++) {
        double tk = tau[k];
        if (tk == 0.0)
            continue;
        double s = b[k];
        for (int i = k + 1; i < m; i++)
            s += QR[(size_t)i * n + k] * b[i];
        s *= tk;
        b[k] -= s;
        for (int i = k + 1; i < m; i++)
            b[i] -= s * QR[(size_t)i * n + k];
    }
    for (int i = n - 1; i >= 0; i--) {
        double s = b[i];
        for (int j = i + 1; j < n; j++)
            s -= QR[(size_t)i * n + j] * b[j];
        b[i] = s / QR[(size_t)i * n + i];
    }
    return SFM_OK;
}
