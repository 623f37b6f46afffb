/*
 * Fundamental matrix from n >= 8 pixel pairs: the normalized eight-point
 * algorithm (Hartley 1997, "In defense of the eight-point algorithm").
 * Both point sets are Hartley-normalized, f minimizes |A f| with |f| = 1
 * (p2h^T F p1h = 0 per row), rank 2 is enforced by zeroing the smallest
 * singular value (the nearest rank-2 matrix in Frobenius norm), then F is
 * denormalized: F = T2^T Fn T1.
 */
#include <math.h>

#include "sfm/sfm_solvers.h"
#include "solvers/linear9.h"
#include "solvers/normalize.h"
#include "solvers/small_math.h"

static void epi_row(const double a[3], const double b[3], double r[9])
{
    /* b^T F a = sum_rc b_r F_rc a_c */
    for (int i = 0; i < 3; i++)
        for (int j = 0; j < 3; j++)
            r[3 * i + j] = b[i] * a[j];
}

int sfm_fundamental_8pt(const double *p1, const double *p2, int n, sfm_mat3 *F)
{
    if (!p1 || !p2 || !F || n < 8)
        return SFM_E_ARGUMENT;
    double t1[3], t2[3];
    int norm = sfmi_hartley_pairs(p1, p2, n, t1, t2);
    if (norm != 0)
        return norm < 0 ? norm : 0; /* non-finite, or no scale: no model */
    double f[9];
    if (n == 8) {
        double A[72];
        for (int i = 0; i < 8; i++) {
            double a[3] = {t1[0] * p1[2 * i] + t1[1], t1[0] * p1[2 * i + 1] + t1[2], 1.0};
            double b[3] = {t2[0] * p2[2 * i] + t2[1], t2[0] * p2[2 * i + 1] + t2[2], 1.0};
            epi_row(a, b, A + 9 * i);
        }
        if (sfmi_null9_exact(A, 8, f))
            return 0;
    } else {
        sfmi_ls9 ls;
        sfmi_ls9_init(&ls);
        for (int i = 0; i < n; i++) {
            double a[3] = {t1[0] * p1[2 * i] + t1[1], t1[0] * p1[2 * i + 1] + t1[2], 1.0};
            double b[3] = {t2[0] * p2[2 * i] + t2[1], t2[0] * p2[2 * i + 1] + t2[2], 1.0};
            double r[9];
            epi_row(a, b, r);
            sfmi_ls9_add_row(&ls, r);
        }
        int st = sfmi_ls9_solve(&ls, f);
        if (st == -1)
            return 0;
        if (st < 0)
            return st;
    }
    double U[9], S[3], V[9];
    int st = sfmi_svd3(f, U, S, V);
    if (st < 0)
        return st;
    if (!(S[1] > 1e-12 * S[0]))
        return 0; /* rank 1 or less: no epipolar geometry */
    /* Fn = U diag(S0, S1, 0) V^T, then F = T2^T Fn T1. */
    double Fn[9], M[9], G[9], T1[9], T2[9];
    for (int r = 0; r < 3; r++)
        for (int c = 0; c < 3; c++)
            Fn[3 * r + c] = U[3 * r] * S[0] * V[3 * c] + U[3 * r + 1] * S[1] * V[3 * c + 1];
    sfmi_hartley_matrix(t1, T1);
    sfmi_hartley_matrix(t2, T2);
    sfmi_matmul3(Fn, T1, M);
    for (int r = 0; r < 3; r++)
        for (int c = 0; c < 3; c++)
            G[3 * r + c] = T2[r] * M[c] + T2[3 + r] * M[3 + c] + T2[6 + r] * M[6 + c];
    if (sfmi_normalize9(G))
        return 0;
    for (int k = 0; k < 9; k++)
        F->m[k] = G[k];
    return 1;
}
