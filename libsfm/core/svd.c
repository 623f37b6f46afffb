/*
 * Singular value decomposition by one-sided Jacobi (Hestenes 1958; the
 * convergence test and rotation follow Demmel & Veselic, "Jacobi's method is
 * more accurate than QR", SIAM J. Matrix Anal. Appl. 13(4), 1992).
 *
 * The routine works on a tall matrix M (rows >= cols): M = A when m >= n,
 * M = A^T otherwise (then A = V_M S U_M^T). Columns of M are rotated pairwise
 * until every pair is orthogonal to sqrt(rows) * eps relative to the product
 * of their norms; the rotations accumulate into V_M; the final column norms
 * are the singular values and the normalized columns the left vectors. A full
 * left basis is completed with the Householder QR of the computed columns:
 * the trailing columns of its Q span their orthogonal complement.
 *
 * Input is first scaled by an exact power of two so that the largest entry
 * lies in [0.5, 1): squares and dot products of finite inputs cannot overflow.
 */
#include <float.h>
#include <math.h>
#include <string.h>

#include "core/arena.h"
#include "core/linalg_util.h"
#include "core/svd_internal.h"
#include "core/dmath.h"

/* Sweeps before SFM_E_NO_CONVERGENCE; convergence takes 5 to 12 in practice. */
#define SVD_MAX_SWEEPS 80
/* A column shorter than this times |A|_F is numerically zero: it takes part in
 * no rotation (noise confined to the span of one other column would otherwise
 * keep rotating against it) and its direction in U comes from the orthogonal
 * completion. Such singular values are below eps |A|_F, noise in any case. */
#define SVD_ZERO_COL (1e-3 * DBL_EPSILON)

typedef struct svd_ws {
    double *W;   /* rows x cols, column-major copy of M */
    double *Vm;  /* cols x cols, column-major accumulated rotations */
    double *nrm; /* cols */
    int *perm;   /* cols: descending order of nrm */
    double *qr;  /* rows x cols, column-major, for the completion */
    double *tau; /* cols */
    double *tmp; /* rows */
} svd_ws;

static void svd_layout(sfmi_arena *a, int R, int C, svd_ws *w)
{
    w->W = SFM_ARENA_ARRAY(a, double, (size_t)R * C);
    w->Vm = SFM_ARENA_ARRAY(a, double, (size_t)C * C);
    w->nrm = SFM_ARENA_ARRAY(a, double, C);
    w->perm = SFM_ARENA_ARRAY(a, int, C);
    w->qr = SFM_ARENA_ARRAY(a, double, (size_t)R * C);
    w->tau = SFM_ARENA_ARRAY(a, double, C);
    w->tmp = SFM_ARENA_ARRAY(a, double, R);
}

size_t sfm_svd_workspace_size(int m, int n)
{
    if (!sfmi_la_dim_ok(m) || !sfmi_la_dim_ok(n))
        return 0;
    sfmi_arena a;
    svd_ws w;
    sfmi_arena_measure(&a);
    svd_layout(&a, m >= n ? m : n, m >= n ? n : m, &w);
    return sfmi_arena_required(&a);
}

static double dot(const double *x, const double *y, int n)
{
    double s = 0.0;
    for (int i = 0; i < n; i++)
        s += x[i] * y[i];
    return s;
}

/* One-sided Jacobi on the columns of W (R x C, column-major). Vm, when not
 * NULL, receives the accumulated rotations (C x C, column-major). Columns of
 * squared norm <= zero2 are left alone. */
static int jacobi_sweeps(double *W, int R, int C, double *Vm, double zero2)
{
    const double tol = sqrt((double)R) * DBL_EPSILON;
    if (Vm != NULL) {
        memset(Vm, 0, sizeof(double) * (size_t)C * (size_t)C);
        for (int i = 0; i < C; i++)
            Vm[(size_t)i * C + i] = 1.0;
    }
    if (C == 1)
        return SFM_OK;
    for (int sweep = 0; sweep < SVD_MAX_SWEEPS; sweep++) {
        int rotated = 0;
        for (int i = 0; i < C - 1; i++) {
            double *ci = W + (size_t)i * R;
            for (int j = i + 1; j < C; j++) {
                double *cj = W + (size_t)j * R;
                double alpha = 0.0, beta = 0.0, gamma = 0.0;
                for (int k = 0; k < R; k++) {
                    alpha += ci[k] * ci[k];
                    beta += cj[k] * cj[k];
                    gamma += ci[k] * cj[k];
                }
                if (!(fabs(gamma) > tol * sqrt(alpha) * sqrt(beta)) || alpha <= zero2 ||
                    beta <= zero2)
                    continue;
                rotated = 1;
                /* rotation that zeroes gamma: tan of the smaller angle */
                double c, s;
                sfmi_la_jacobi_angle((beta - alpha) / (2.0 * gamma), &c, &s);
                sfmi_la_rotate(ci, cj, R, 1, c, s);
                if (Vm != NULL)
                    sfmi_la_rotate(Vm + (size_t)i * C, Vm + (size_t)j * C, C, 1, c, s);
            }
        }
        if (!rotated)
            return SFM_OK;
    }
    return SFM_E_NO_CONVERGENCE;
}

/* Writes the full orthonormal R x R basis whose first r columns are the
 * normalized columns W[:, perm[0..r)] (the others complete it) into out
 * (row-major). */
static void write_left_basis(const svd_ws *w, int R, int C, int r, double *out)
{
    for (int k = 0; k < r; k++) {
        const double *col = w->W + (size_t)w->perm[k] * R;
        double inv = 1.0 / w->nrm[w->perm[k]];
        for (int i = 0; i < R; i++)
            out[(size_t)i * R + k] = col[i] * inv;
    }
    if (r == R)
        return;
    /* Householder QR of the r computed columns (column-major copy) */
    double *q = w->qr;
    for (int k = 0; k < r; k++)
        for (int i = 0; i < R; i++)
            q[(size_t)k * R + i] = out[(size_t)i * R + k];
    for (int k = 0; k < r; k++) {
        double *v = q + (size_t)k * R;
        double alpha = v[k];
        double xn = 0.0;
        for (int i = k + 1; i < R; i++)
            xn += v[i] * v[i];
        xn = sqrt(xn);
        if (xn == 0.0) {
            w->tau[k] = 0.0;
            continue;
        }
        double beta = -copysign(sfmi_hypot(alpha, xn), alpha);
        w->tau[k] = (beta - alpha) / beta;
        double inv = 1.0 / (alpha - beta);
        for (int i = k + 1; i < R; i++)
            v[i] *= inv;
        v[k] = 1.0;
        for (int j = k + 1; j < r; j++) {
            double *cj = q + (size_t)j * R;
            double s = w->tau[k] * dot(v + k, cj + k, R - k);
            for (int i = k; i < R; i++)
                cj[i] -= s * v[i];
        }
    }
    (void)C;
    /* columns r..R-1 of Q = H_0 ... H_{r-1}: apply to e_j from the last
     * reflector to the first */
    double *x = w->tmp;
    for (int j = r; j < R; j++) {
        memset(x, 0, sizeof(double) * (size_t)R);
        x[j] = 1.0;
        for (int k = r - 1; k >= 0; k--) {
            if (w->tau[k] == 0.0)
                continue;
            const double *v = q + (size_t)k * R;
            double s = w->tau[k] * dot(v + k, x + k, R - k);
            for (int i = k; i < R; i++)
                x[i] -= s * v[i];
        }
        for (int i = 0; i < R; i++)
            out[(size_t)i * R + j] = x[i];
    }
}

int sfmi_svd_core(const double *A, int m, int n, double *U, double *S, double *V, void *ws,
                 size_t ws_size)
{
    const int tall = m >= n;
    const int R = tall ? m : n, C = tall ? n : m;
    sfmi_arena a;
    svd_ws w;
    /* the reported size is the contract, whatever the buffer's alignment */
    if (ws_size < sfm_svd_workspace_size(m, n))
        return SFM_E_WORKSPACE;
    sfmi_arena_init(&a, ws, ws_size);
    svd_layout(&a, R, C, &w);
    if (!sfmi_arena_ok(&a))
        return SFM_E_WORKSPACE;

    const size_t mn = (size_t)m * (size_t)n;
    const double f = sfmi_la_pow2_scale(sfmi_la_max_abs(A, mn));
    if (tall) {
        for (int i = 0; i < m; i++)
            for (int j = 0; j < n; j++)
                w.W[(size_t)j * m + i] = A[(size_t)i * n + j] * f;
    } else {
        for (size_t i = 0; i < mn; i++)
            w.W[i] = A[i] * f;
    }
    const int want_vm = tall ? V != NULL : U != NULL;
    const int want_um = tall ? U != NULL : V != NULL;
    const double fro = sqrt(dot(w.W, w.W, (int)mn)); /* invariant under the rotations */
    const double zero_norm = SVD_ZERO_COL * fro;
    int st = jacobi_sweeps(w.W, R, C, want_vm ? w.Vm : NULL, zero_norm * zero_norm);
    if (st != SFM_OK)
        return st;

    for (int k = 0; k < C; k++) {
        const double *ck = w.W + (size_t)k * R;
        w.nrm[k] = sqrt(dot(ck, ck, R));
        /* stable insertion into the descending order */
        int p = k;
        while (p > 0 && w.nrm[w.perm[p - 1]] < w.nrm[k]) {
            w.perm[p] = w.perm[p - 1];
            p--;
        }
        w.perm[p] = k;
    }
    int r = 0;
    while (r < C && w.nrm[w.perm[r]] > zero_norm)
        r++;

    const double finv = 1.0 / f;
    for (int k = 0; k < C; k++)
        S[k] = w.nrm[w.perm[k]] * finv;
    double *Vm_out = tall ? V : U;
    double *Um_out = tall ? U : V;
    if (want_vm)
        for (int k = 0; k < C; k++)
            for (int i = 0; i < C; i++)
                Vm_out[(size_t)i * C + k] = w.Vm[(size_t)w.perm[k] * C + i];
    if (want_um)
        write_left_basis(&w, R, C, r, Um_out);
    return SFM_OK;
}

int sfm_svd(const double *A, int m, int n, double *U, double *S, double *V, void *ws,
            size_t ws_size)
{
    if (A == NULL || S == NULL || ws == NULL || !sfmi_la_dim_ok(m) || !sfmi_la_dim_ok(n))
        return SFM_E_ARGUMENT;
    if (!sfmi_la_all_finite(A, (size_t)m * (size_t)n))
        return SFM_E_NONFINITE;
    return sfmi_svd_core(A, m, n, U, S, V, ws, ws_size);
}
