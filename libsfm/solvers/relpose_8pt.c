/*
 * Essential matrix from n >= 8 bearing pairs: the linear eight-point
 * algorithm (Longuet-Higgins 1981; Hartley & Zisserman, sec. 11.7.3).
 * e minimizes |A e| with |e| = 1 over the rows kron(x2_i, x1_i) of
 * x2^T E x1 = 0, then E is projected to the essential manifold: with
 * E = U diag(s1, s2, s3) V^T, the nearest essential matrix in Frobenius
 * norm is U diag(1, 1, 0) V^T (times (s1 + s2) / 2; we return unit norm).
 * Bearings are used as given (unit vectors are already well scaled).
 */
#include <math.h>

#include "core/linalg_util.h"
#include "sfm/sfm_solvers.h"
#include "solvers/linear9.h"
#include "solvers/normalize.h"

int sfm_relpose_8pt(const double *x1, const double *x2, int n, sfm_mat3 *E)
{
    if (!x1 || !x2 || !E || n < 8)
        return SFM_E_ARGUMENT;
    if (!sfmi_la_all_finite(x1, 3 * n) || !sfmi_la_all_finite(x2, 3 * n))
        return SFM_E_NONFINITE;
    double e[9];
    if (n == 8) {
        double A[72];
        for (int i = 0; i < 8; i++)
            for (int r = 0; r < 3; r++)
                for (int c = 0; c < 3; c++)
                    A[9 * i + 3 * r + c] = x2[3 * i + r] * x1[3 * i + c];
        if (sfmi_null9_exact(A, 8, e))
            return 0;
    } else {
        sfmi_ls9 ls;
        sfmi_ls9_init(&ls);
        for (int i = 0; i < n; i++) {
            double row[9];
            for (int r = 0; r < 3; r++)
                for (int c = 0; c < 3; c++)
                    row[3 * r + c] = x2[3 * i + r] * x1[3 * i + c];
            sfmi_ls9_add_row(&ls, row);
        }
        int st = sfmi_ls9_solve(&ls, e);
        if (st == -1)
            return 0;
        if (st < 0)
            return st;
    }
    double U[9], S[3], V[9];
    int st = sfmi_svd3(e, U, S, V);
    if (st < 0)
        return st;
    if (!(S[1] > 1e-12 * S[0]))
        return 0;
    const double k = 1.0 / sqrt(2.0);
    for (int r = 0; r < 3; r++)
        for (int c = 0; c < 3; c++)
            E->m[3 * r + c] = k * (U[3 * r] * V[3 * c] + U[3 * r + 1] * V[3 * c + 1]);
    return 1;
}
