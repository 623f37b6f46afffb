/*
 * Fundamental matrices from seven pixel pairs (Hartley & Zisserman, "Multiple
 * View Geometry", 2nd ed., sec. 11.1.2). After Hartley normalization the 7x9
 * system has a two-dimensional null space {F1, F2}; det(F1 + l F2) = 0 is a
 * cubic in l whose real roots give up to three rank-2 solutions. The base of
 * the pencil is the member with the smaller determinant so the cubic's leading
 * coefficient is the larger one (the member whose own determinant is ~0 is
 * then still found at l ~ 0, not lost at infinity).
 */
#include <math.h>

#include "sfm/sfm_poly.h"
#include "sfm/sfm_solvers.h"
#include "solvers/linear9.h"
#include "solvers/normalize.h"

static void cofactors(const double *A, double C[9])
{
    C[0] = A[4] * A[8] - A[5] * A[7];
    C[1] = A[5] * A[6] - A[3] * A[8];
    C[2] = A[3] * A[7] - A[4] * A[6];
    C[3] = A[2] * A[7] - A[1] * A[8];
    C[4] = A[0] * A[8] - A[2] * A[6];
    C[5] = A[1] * A[6] - A[0] * A[7];
    C[6] = A[1] * A[5] - A[2] * A[4];
    C[7] = A[2] * A[3] - A[0] * A[5];
    C[8] = A[0] * A[4] - A[1] * A[3];
}

int sfm_fundamental_7pt(const double *p1, const double *p2, sfm_mat3 *F)
{
    if (!p1 || !p2 || !F)
        return SFM_E_ARGUMENT;
    double t1[3], t2[3];
    int norm = sfmi_hartley_pairs(p1, p2, 7, t1, t2);
    if (norm != 0)
        return norm < 0 ? norm : 0; /* non-finite, or no scale: no model */
    double A[63], N[18];
    for (int i = 0; i < 7; i++) {
        double a0 = t1[0] * p1[2 * i] + t1[1], a1 = t1[0] * p1[2 * i + 1] + t1[2];
        double b0 = t2[0] * p2[2 * i] + t2[1], b1 = t2[0] * p2[2 * i + 1] + t2[2];
        double *r = A + 9 * i;
        r[0] = b0 * a0; r[1] = b0 * a1; r[2] = b0;
        r[3] = b1 * a0; r[4] = b1 * a1; r[5] = b1;
        r[6] = a0;      r[7] = a1;      r[8] = 1.0;
    }
    if (sfmi_null9_exact(A, 7, N))
        return 0;
    double C1[9], C2[9];
    cofactors(N, C1);
    cofactors(N + 9, C2);
    double d1 = 0.0, d2 = 0.0, m12 = 0.0, m21 = 0.0;
    for (int k = 0; k < 3; k++)
        d1 += N[k] * C1[k], d2 += N[9 + k] * C2[k];
    for (int k = 0; k < 9; k++)
        m12 += C1[k] * N[9 + k], m21 += N[k] * C2[k];
    /* det(P + l Q) = det P + l tr(adj(P) Q) + l^2 tr(P adj(Q)) + l^3 det Q. */
    const double *P = N, *Q = N + 9;
    double c[4] = {d2, m21, m12, d1};
    if (fabs(d1) > fabs(d2)) {
        P = N + 9;
        Q = N;
        c[0] = d1; c[1] = m12; c[2] = m21; c[3] = d2;
    }
    double l[3];
    int nr = sfm_poly_roots3(c, l);
    if (nr < 0)
        return 0;
    double T1[9], T2[9];
    sfmi_hartley_matrix(t1, T1);
    sfmi_hartley_matrix(t2, T2);
    int ns = 0;
    double out[3][9];
    for (int k = 0; k < nr; k++) {
        double Fn[9], M[9], G[9];
        for (int i = 0; i < 9; i++)
            Fn[i] = P[i] + l[k] * Q[i];
        /* F = T2^T Fn T1 */
        for (int r = 0; r < 3; r++)
            for (int cc = 0; cc < 3; cc++)
                M[3 * r + cc] = Fn[3 * r] * T1[cc] + Fn[3 * r + 1] * T1[3 + cc] + Fn[3 * r + 2] * T1[6 + cc];
        for (int r = 0; r < 3; r++)
            for (int cc = 0; cc < 3; cc++)
                G[3 * r + cc] = T2[r] * M[cc] + T2[3 + r] * M[3 + cc] + T2[6 + r] * M[6 + cc];
        if (sfmi_normalize9(G))
            continue;
        for (int i = 0; i < 9; i++)
            out[ns][i] = G[i];
        ns++;
    }
    for (int k = 0; k < ns; k++)
        for (int i = 0; i < 9; i++)
            F[k].m[i] = out[k][i];
    return ns;
}
