/*
 * Homography from n >= 4 point pairs: the normalized direct linear transform
 * (Hartley & Zisserman, "Multiple View Geometry", 2nd ed., alg. 4.2). Both
 * point sets are Hartley-normalized; each pair gives two rows of A h = 0;
 * h minimizes |A h| with |h| = 1 (exactly 8 rows: the exact null vector).
 */
#include <math.h>

#include "sfm/sfm_solvers.h"
#include "solvers/linear9.h"
#include "solvers/normalize.h"
#include "solvers/small_math.h"

static void dlt_rows(const double *p1, const double *p2, int i, const double t1[3],
                     const double t2[3], double r0[9], double r1[9])
{
    double x = t1[0] * p1[2 * i] + t1[1], y = t1[0] * p1[2 * i + 1] + t1[2];
    double u = t2[0] * p2[2 * i] + t2[1], v = t2[0] * p2[2 * i + 1] + t2[2];
    r0[0] = 0.0; r0[1] = 0.0; r0[2] = 0.0;
    r0[3] = -x;  r0[4] = -y;  r0[5] = -1.0;
    r0[6] = v * x; r0[7] = v * y; r0[8] = v;
    r1[0] = x;   r1[1] = y;   r1[2] = 1.0;
    r1[3] = 0.0; r1[4] = 0.0; r1[5] = 0.0;
    r1[6] = -u * x; r1[7] = -u * y; r1[8] = -u;
}

int sfm_homography_dlt(const double *p1, const double *p2, int n, sfm_mat3 *H)
{
    if (!p1 || !p2 || !H || n < 4)
        return SFM_E_ARGUMENT;
    double t1[3], t2[3];
    int norm = sfmi_hartley_pairs(p1, p2, n, t1, t2);
    if (norm != 0)
        return norm < 0 ? norm : 0; /* non-finite, or no scale: no model */
    double h[9];
    if (n == 4) {
        double A[72], N[9];
        for (int i = 0; i < 4; i++)
            dlt_rows(p1, p2, i, t1, t2, A + 18 * i, A + 18 * i + 9);
        if (sfmi_null9_exact(A, 8, N))
            return 0;
        for (int k = 0; k < 9; k++)
            h[k] = N[k];
    } else {
        sfmi_ls9 ls;
        sfmi_ls9_init(&ls);
        for (int i = 0; i < n; i++) {
            double r0[9], r1[9];
            dlt_rows(p1, p2, i, t1, t2, r0, r1);
            sfmi_ls9_add_row(&ls, r0);
            sfmi_ls9_add_row(&ls, r1);
        }
        int st = sfmi_ls9_solve(&ls, h);
        if (st == -1)
            return 0;
        if (st < 0)
            return st;
    }
    /* H = T2^-1 Hn T1 with T = [s 0 a; 0 s b; 0 0 1], T^-1 = [1/s 0 -a/s; ...]. */
    double T1[9], Ti[9], M[9], G[9];
    sfmi_hartley_matrix(t1, T1);
    double is = 1.0 / t2[0];
    Ti[0] = is; Ti[1] = 0.0; Ti[2] = -t2[1] * is;
    Ti[3] = 0.0; Ti[4] = is; Ti[5] = -t2[2] * is;
    Ti[6] = 0.0; Ti[7] = 0.0; Ti[8] = 1.0;
    sfmi_matmul3(h, T1, M);
    sfmi_matmul3(Ti, M, G);
    double det = G[0] * (G[4] * G[8] - G[5] * G[7]) - G[1] * (G[3] * G[8] - G[5] * G[6]) +
                 G[2] * (G[3] * G[7] - G[4] * G[6]);
    if (sfmi_normalize9(G) || det == 0.0)
        return 0;
    for (int k = 0; k < 9; k++)
        H->m[k] = det < 0.0 ? -G[k] : G[k];
    return 1;
}
