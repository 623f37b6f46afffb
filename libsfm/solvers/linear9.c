/*
 * Null vectors of systems in 9 unknowns: Householder QR of A^T for exact
 * minimal samples, streaming Givens QR plus a 9x9 SVD for least squares.
 */
#include <math.h>
#include <string.h>

#include "sfm/sfm_linalg.h"
#include "solvers/linear9.h"

/* Null basis: Q e_j for j = m..8, Q = H_0 H_1 ... H_{m-1}, the nn = 9 - m
 * vectors as the columns of X (9 x nn, row-major) while the reflectors are
 * applied, so that the inner loops run across the columns; each dot product
 * and update adds its terms in the same order as one vector at a time
 * (below), so both give the same bits. Measured (callgrind, x86-64): 0.5k
 * fewer instructions for the 5-point's four vectors, more for the one or
 * two of the 7- and 8-point. */
static inline void null_basis(const double *A, const double *beta, int m, int nn, double *N)
{
    double X[9 * 8];
    for (int i = 0; i < 9; i++)
        for (int c = 0; c < nn; c++)
            X[nn * i + c] = i == m + c ? 1.0 : 0.0;
    for (int k = m - 1; k >= 0; k--) {
        const double *a = A + 9 * k;
        double w[8];
        for (int c = 0; c < nn; c++)
            w[c] = 0.0;
        for (int i = k; i < 9; i++)
            for (int c = 0; c < nn; c++)
                w[c] += a[i] * X[nn * i + c];
        for (int c = 0; c < nn; c++)
            w[c] *= beta[k];
        for (int i = k; i < 9; i++)
            for (int c = 0; c < nn; c++)
                X[nn * i + c] -= w[c] * a[i];
    }
    for (int c = 0; c < nn; c++)
        for (int i = 0; i < 9; i++)
            N[9 * c + i] = X[nn * i + c];
}

/* sum over i = k..8, ascending, of a[i] b[i]; b[i] -= f a[i] for i = k..8.
 * Built for speed, entered at the term of k with no loop counter (the same
 * operations in the same order as the loops of a build for size, so the
 * same bits): 13 % fewer instructions for the 7- and 8-point, 2 % for the
 * 5-point (callgrind, x86-64). */
static inline double dot_from(const double *a, const double *b, int k)
{
    double s = 0.0;
#if defined(__OPTIMIZE_SIZE__)
    for (int i = k; i < 9; i++)
        s += a[i] * b[i];
#else
    switch (k) {
    case 0: s += a[0] * b[0]; /* fall through */
    case 1: s += a[1] * b[1]; /* fall through */
    case 2: s += a[2] * b[2]; /* fall through */
    case 3: s += a[3] * b[3]; /* fall through */
    case 4: s += a[4] * b[4]; /* fall through */
    case 5: s += a[5] * b[5]; /* fall through */
    case 6: s += a[6] * b[6]; /* fall through */
    case 7: s += a[7] * b[7]; /* fall through */
    default: s += a[8] * b[8];
    }
#endif
    return s;
}

static inline void axpy_from(double *b, const double *a, double f, int k)
{
#if defined(__OPTIMIZE_SIZE__)
    for (int i = k; i < 9; i++)
        b[i] -= f * a[i];
#else
    switch (k) {
    case 0: b[0] -= f * a[0]; /* fall through */
    case 1: b[1] -= f * a[1]; /* fall through */
    case 2: b[2] -= f * a[2]; /* fall through */
    case 3: b[3] -= f * a[3]; /* fall through */
    case 4: b[4] -= f * a[4]; /* fall through */
    case 5: b[5] -= f * a[5]; /* fall through */
    case 6: b[6] -= f * a[6]; /* fall through */
    case 7: b[7] -= f * a[7]; /* fall through */
    default: b[8] -= f * a[8];
    }
#endif
}

int sfmi_null9_exact(double *A, int m, double *N)
{
    /* Column j of A^T is row j of A: A[j*9 + i] = (A^T)(i, j). Reflector k
     * (v_k in row k of A from entry k on, beta_k) zeroes entries k+1..8 of
     * column k. */
    double beta[8];
    double dmax = 0.0, dmin = HUGE_VAL;
    for (int k = 0; k < m; k++) {
        double *a = A + 9 * k;
        double s = dot_from(a, a, k);
        double nrm = sqrt(s);
        double alpha = a[k] >= 0.0 ? -nrm : nrm;
        double d = fabs(alpha);
        if (d > dmax)
            dmax = d;
        if (d < dmin)
            dmin = d;
        if (nrm == 0.0) {
            beta[k] = 0.0;
            continue;
        }
        /* v = a(k:) - alpha e_k, beta = 2 / v^T v; v^T v = 2 nrm (nrm + |a_k|). */
        a[k] -= alpha;
        beta[k] = 1.0 / (nrm * (nrm + fabs(a[k] + alpha)));
        for (int j = k + 1; j < m; j++) {
            double *b = A + 9 * j;
            double dot = dot_from(a, b, k) * beta[k];
            axpy_from(b, a, dot, k);
        }
    }
    if (!(dmin > 1e-12 * dmax))
        return -1;
    if (m == 5) {
        null_basis(A, beta, 5, 4, N); /* the 5-point's: four vectors at a time */
        return 0;
    }
    /* Null basis: Q e_j for j = m..8, Q = H_0 H_1 ... H_{m-1}, one vector at
     * a time (for one or two vectors this is the cheaper order). */
    for (int j = m; j < 9; j++) {
        double *q = N + 9 * (j - m);
        memset(q, 0, 9 * sizeof(double));
        q[j] = 1.0;
        for (int k = m - 1; k >= 0; k--) {
            const double *a = A + 9 * k;
            axpy_from(q, a, dot_from(a, q, k) * beta[k], k);
        }
    }
    return 0;
}

void sfmi_ls9_init(sfmi_ls9 *ls)
{
    memset(ls->R, 0, sizeof ls->R);
    ls->rows = 0;
}

void sfmi_ls9_add_row(sfmi_ls9 *ls, const double row[9])
{
    double r[9];
    memcpy(r, row, sizeof r);
    for (int k = 0; k < 9; k++) {
        double b = r[k];
        if (b == 0.0)
            continue;
        double *Rk = ls->R + 10 * k; /* R(k, k..8) */
        double a = Rk[0];
        double h = sqrt(a * a + b * b);
        double c = a / h, s = b / h;
        Rk[0] = h;
        r[k] = 0.0;
        for (int j = 1; j < 9 - k; j++) {
            double u = Rk[j], w = r[k + j];
            Rk[j] = c * u + s * w;
            r[k + j] = c * w - s * u;
        }
    }
    ls->rows++;
}

int sfmi_ls9_solve(sfmi_ls9 *ls, double h[9])
{
    if (ls->rows < 8)
        return -1;
    double S[9], V[81];
    double ws[512];
    size_t need = sfm_svd_workspace_size(9, 9);
    if (need > sizeof ws)
        return SFM_E_CAPACITY; /* the core SVD needs more than budgeted */
    int st = sfm_svd(ls->R, 9, 9, NULL, S, V, ws, sizeof ws);
    if (st < 0)
        return st;
    if (!(S[7] > 1e-10 * S[0]))
        return -1;
    for (int i = 0; i < 9; i++)
        h[i] = V[9 * i + 8];
    return 0;
}

int sfmi_svd3(const double M[9], double U[9], double S[3], double V[9])
{
    double ws[64];
    if (sfm_svd_workspace_size(3, 3) > sizeof ws)
        return SFM_E_CAPACITY;
    return sfm_svd(M, 3, 3, U, S, V, ws, sizeof ws);
}
