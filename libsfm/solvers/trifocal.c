/*
 * Trifocal tensor algebra: from cameras, epipoles, fundamental matrices,
 * compatible cameras, point and line transfer. F32 comes from the cameras
 * through sfm_fundamental_from_projections.
 * Hartley & Zisserman, Multiple View Geometry, 2nd ed.: eq. 17.12 (tensor from
 * general cameras), alg. 15.1 (epipoles, fundamental matrices), sec. 15.1.4
 * (cameras), sec. 16.3 (point transfer via a line perpendicular to the
 * epipolar line). Storage T[i*9 + j*3 + k] = T_i^{jk}.
 */
#include <math.h>
#include <string.h>

#include "core/linalg_util.h"
#include "sfm/sfm_linalg.h"
#include "sfm/sfm_rotation.h"
#include "sfm/sfm_triangulate.h"
#include "sfm/sfm_trifocal.h"
#include "solvers/small_math.h"
#include "solvers/trifocal_internal.h"

/* det of the 4x4 matrix with rows r0..r3. */
static double det4(const double *r0, const double *r1, const double *r2, const double *r3)
{
    const double *m[4] = {r0, r1, r2, r3};
    /* Laplace expansion along the first two rows (2x2 minors). */
    double s0 = m[0][0] * m[1][1] - m[1][0] * m[0][1];
    double s1 = m[0][0] * m[1][2] - m[1][0] * m[0][2];
    double s2 = m[0][0] * m[1][3] - m[1][0] * m[0][3];
    double s3 = m[0][1] * m[1][2] - m[1][1] * m[0][2];
    double s4 = m[0][1] * m[1][3] - m[1][1] * m[0][3];
    double s5 = m[0][2] * m[1][3] - m[1][2] * m[0][3];
    double c5 = m[2][2] * m[3][3] - m[3][2] * m[2][3];
    double c4 = m[2][1] * m[3][3] - m[3][1] * m[2][3];
    double c3 = m[2][1] * m[3][2] - m[3][1] * m[2][2];
    double c2 = m[2][0] * m[3][3] - m[3][0] * m[2][3];
    double c1 = m[2][0] * m[3][2] - m[3][0] * m[2][2];
    double c0 = m[2][0] * m[3][1] - m[3][0] * m[2][1];
    return s0 * c5 - s1 * c4 + s2 * c3 + s3 * c2 - s4 * c1 + s5 * c0;
}

int sfmi_trifocal_normalize(double *v, int n)
{
    double s = 0;
    for (int i = 0; i < n; i++)
        s += v[i] * v[i];
    s = sqrt(s);
    if (!(s > 0) || !isfinite(s))
        return SFM_E_SINGULAR;
    for (int i = 0; i < n; i++)
        v[i] /= s;
    return SFM_OK;
}

/* det of the 3x3 matrix of columns a, b, c of the 3x4 P. */
static double det3_cols(const double *P, int a, int b, int c)
{
    return P[a] * (P[4 + b] * P[8 + c] - P[8 + b] * P[4 + c]) -
           P[b] * (P[4 + a] * P[8 + c] - P[8 + a] * P[4 + c]) +
           P[c] * (P[4 + a] * P[8 + b] - P[8 + a] * P[4 + b]);
}

/* Unit homogeneous centre of a camera (its null vector, by cofactors);
 * 0 when P has rank below 3. */
static int centre(const double *P, double C[4])
{
    C[0] = det3_cols(P, 1, 2, 3);
    C[1] = -det3_cols(P, 0, 2, 3);
    C[2] = det3_cols(P, 0, 1, 3);
    C[3] = -det3_cols(P, 0, 1, 2);
    return sfmi_trifocal_normalize(C, 4) == SFM_OK;
}

/* Two unit 4-vectors equal up to sign, to 1e-10 (coincident centres). */
static int same_point(const double *a, const double *b)
{
    double dp = 0, dm = 0;
    for (int k = 0; k < 4; k++) {
        dp += (a[k] - b[k]) * (a[k] - b[k]);
        dm += (a[k] + b[k]) * (a[k] + b[k]);
    }
    return (dp < dm ? dp : dm) < 1e-20;
}

int sfm_trifocal_from_cameras(const double P1[12], const double P2[12], const double P3[12],
                              double T[27])
{
    if (P1 == NULL || P2 == NULL || P3 == NULL || T == NULL)
        return SFM_E_ARGUMENT;
    if (!sfmi_la_all_finite(P1, 12) || !sfmi_la_all_finite(P2, 12) || !sfmi_la_all_finite(P3, 12))
        return SFM_E_NONFINITE;
    /* the tensor of cameras with coincident centres is not zero but
     * carries no three-view geometry (H&Z 15.1: the centres must differ) */
    double C1[4], C2[4], C3[4];
    if (!centre(P1, C1) || !centre(P2, C2) || !centre(P3, C3) || same_point(C1, C2) ||
        same_point(C1, C3) || same_point(C2, C3))
        return SFM_E_SINGULAR;
    double out[27];
    for (int i = 0; i < 3; i++) {
        /* ~a^i: P1 without row i; the sign (-1)^(i+1) in 1-based indexing. */
        const double *ra = &P1[((i + 1) % 3) * 4];
        const double *rb = &P1[((i + 2) % 3) * 4];
        /* Rows in cyclic order (i+1, i+2) absorb the sign: for i = 1 (0-based)
         * the pair (2, 0) is the swapped (0, 2) with the factor -1 built in. */
        for (int j = 0; j < 3; j++)
            for (int k = 0; k < 3; k++)
                out[i * 9 + j * 3 + k] = det4(ra, rb, &P2[j * 4], &P3[k * 4]);
    }
    if (sfmi_trifocal_normalize(out, 27) != SFM_OK)
        return SFM_E_SINGULAR;
    memcpy(T, out, sizeof out);
    return SFM_OK;
}

/* Unit null vector (right singular vector of the smallest singular value) of
 * a 3x3 matrix, or of its transpose when left != 0: the eigenvector of the
 * smallest eigenvalue l3 of the Gram matrix G (M^T M, or M M^T), l3 from
 * the characteristic cubic, the vector orthogonal to the rows of G - l3 I.
 * The error of that vector is about eps l1 / (l2 - l3); where the gap
 * l2 - l3 is below 1e-6 of the trace (the vector poorly determined to
 * start with), or G - l3 I is not of rank 2, the SVD of M gives it. */
static int null3_svd(const double *A, double v[3])
{
    double B[9], V[9], S[3];
    unsigned char ws[2048];
    if (sfm_svd_workspace_size(3, 3) > sizeof ws)
        return SFM_E_WORKSPACE;
    memcpy(B, A, sizeof B);
    int st = sfm_svd(B, 3, 3, NULL, S, V, ws, sizeof ws);
    if (st < 0)
        return st;
    for (int r = 0; r < 3; r++)
        v[r] = V[r * 3 + 2];
    return SFM_OK;
}

static int null3(const double M[9], int left, double v[3])
{
    double G[9], c[3], n[3];
    if (left)
        sfmi_matmul3_nt(M, M, G);
    else
        sfmi_matmul3_tn(M, M, G);
    /* det(x I + G) = x^3 + tr x^2 + c2 x + det: its largest root is -l3 */
    const double tr = G[0] + G[4] + G[8];
    const double c2 = (G[0] * G[4] - G[1] * G[1]) + (G[0] * G[8] - G[2] * G[2]) + (G[4] * G[8] - G[5] * G[5]);
    sfmi_cross3(&G[3], &G[6], c);
    const double l3 = -sfmi_cubic_largest_root(tr, c2, sfmi_dot3(G, c));
    /* l1 + l2 = tr - l3 = s, l1 l2 = c2 - l3 s: l2 the smaller root */
    const double sum = tr - l3, prod = c2 - l3 * sum;
    const double l2 = 0.5 * (sum - sqrt(fmax(sum * sum - 4.0 * prod, 0.0)));
    if (tr > 0.0 && l2 - l3 > 1e-6 * tr) {
        for (int k = 0; k < 9; k += 4)
            G[k] -= l3;
        const double m = sfmi_rank2_null3(G, G + 3, G + 6, 1e-6, n);
        if (m > 0.0 && isfinite(m)) {
            const double s = 1.0 / sqrt(m);
            for (int k = 0; k < 3; k++)
                v[k] = n[k] * s;
            return SFM_OK;
        }
    }
    double A[9];
    for (int k = 0; k < 9; k++)
        A[k] = left ? M[(k % 3) * 3 + k / 3] : M[k];
    return null3_svd(A, v);
}

void sfmi_trifocal_fix_sign(double *v, int n)
{
    int m = 0;
    for (int i = 1; i < n; i++)
        if (fabs(v[i]) > fabs(v[m]))
            m = i;
    if (v[m] < 0)
        for (int i = 0; i < n; i++)
            v[i] = -v[i];
}

int sfm_trifocal_epipoles(const double T[27], double e2[3], double e3[3])
{
    if (T == NULL || e2 == NULL || e3 == NULL)
        return SFM_E_ARGUMENT;
    if (!sfmi_la_all_finite(T, 27))
        return SFM_E_NONFINITE;
    double tn = 0;
    for (int k = 0; k < 27; k++)
        tn += T[k] * T[k];
    if (!(tn > 1e-300)) /* the zero tensor has no epipoles */
        return SFM_E_SINGULAR;
    double U[9], V[9], a[3], b[3];
    for (int i = 0; i < 3; i++) {
        /* u_i^T T_i = 0 and T_i v_i = 0; e' is orthogonal to every u_i, e''
         * to every v_i. Rows of U and V hold u_i and v_i. */
        int st = null3(&T[i * 9], 1, &U[i * 3]);
        if (st < 0)
            return st;
        st = null3(&T[i * 9], 0, &V[i * 3]);
        if (st < 0)
            return st;
    }
    int st = null3(U, 0, a);
    if (st < 0)
        return st;
    st = null3(V, 0, b);
    if (st < 0)
        return st;
    if (sfmi_trifocal_normalize(a, 3) != SFM_OK || sfmi_trifocal_normalize(b, 3) != SFM_OK)
        return SFM_E_SINGULAR;
    sfmi_trifocal_fix_sign(a, 3);
    sfmi_trifocal_fix_sign(b, 3);
    memcpy(e2, a, sizeof a);
    memcpy(e3, b, sizeof b);
    return SFM_OK;
}

/* Cameras from T and its epipoles (both unit norm). */
void sfmi_trifocal_cameras_from(const double T[27], const double e2[3], const double e3[3],
                                double P2[12], double P3[12])
{
    for (int i = 0; i < 3; i++) {
        const double *Ti = &T[i * 9];
        double c2[3], tte[3];
        for (int r = 0; r < 3; r++) {
            c2[r] = Ti[r * 3] * e3[0] + Ti[r * 3 + 1] * e3[1] + Ti[r * 3 + 2] * e3[2];
            tte[r] = Ti[r] * e2[0] + Ti[3 + r] * e2[1] + Ti[6 + r] * e2[2]; /* T_i^T e' */
        }
        double d = e3[0] * tte[0] + e3[1] * tte[1] + e3[2] * tte[2];
        for (int r = 0; r < 3; r++) {
            P2[r * 4 + i] = c2[r];
            P3[r * 4 + i] = e3[r] * d - tte[r]; /* (e'' e''^T - I) T_i^T e' */
        }
    }
    for (int r = 0; r < 3; r++) {
        P2[r * 4 + 3] = e2[r];
        P3[r * 4 + 3] = e3[r];
    }
}

int sfm_trifocal_cameras(const double T[27], double P2[12], double P3[12])
{
    if (T == NULL || P2 == NULL || P3 == NULL)
        return SFM_E_ARGUMENT;
    double e2[3], e3[3], A[12], B[12];
    int st = sfm_trifocal_epipoles(T, e2, e3);
    if (st < 0)
        return st;
    sfmi_trifocal_cameras_from(T, e2, e3, A, B);
    memcpy(P2, A, sizeof A);
    memcpy(P3, B, sizeof B);
    return SFM_OK;
}

int sfm_trifocal_fundamentals(const double T[27], sfm_mat3 *F21_out, sfm_mat3 *F31_out, sfm_mat3 *F32_out)
{
    double *F21 = F21_out ? F21_out->m : NULL;
    double *F31 = F31_out ? F31_out->m : NULL;
    double *F32 = F32_out ? F32_out->m : NULL;
    if (T == NULL)
        return SFM_E_ARGUMENT;
    double e2[3], e3[3], a[9], b[9];
    sfm_mat3 c;
    int st = sfm_trifocal_epipoles(T, e2, e3);
    if (st < 0)
        return st;
    double M2[9], M3[9], Ex[9];
    for (int i = 0; i < 3; i++) {
        const double *Ti = &T[i * 9];
        for (int r = 0; r < 3; r++) {
            M2[r * 3 + i] = Ti[r * 3] * e3[0] + Ti[r * 3 + 1] * e3[1] + Ti[r * 3 + 2] * e3[2];
            M3[r * 3 + i] = Ti[r] * e2[0] + Ti[3 + r] * e2[1] + Ti[6 + r] * e2[2];
        }
    }
    sfm_skew(e2, Ex);
    sfmi_matmul3(Ex, M2, a);
    sfm_skew(e3, Ex);
    sfmi_matmul3(Ex, M3, b);
    if (sfmi_trifocal_normalize(a, 9) != SFM_OK || sfmi_trifocal_normalize(b, 9) != SFM_OK)
        return SFM_E_SINGULAR;
    if (F32 != NULL) {
        double P2[12], P3[12];
        sfmi_trifocal_cameras_from(T, e2, e3, P2, P3);
        st = sfm_fundamental_from_projections(P2, P3, &c);
        if (st < 0)
            return st;
    }
    if (F21 != NULL)
        memcpy(F21, a, sizeof a);
    if (F31 != NULL)
        memcpy(F31, b, sizeof b);
    if (F32 != NULL)
        memcpy(F32, c.m, sizeof c.m);
    return SFM_OK;
}

int sfm_trifocal_transfer(const double T[27], const sfm_mat3 *F21_in, const double x1[2],
                          const double x2[2], double x3[2])
{
    const double *F21 = F21_in ? F21_in->m : NULL;
    if (T == NULL || x1 == NULL || x2 == NULL || x3 == NULL)
        return SFM_E_ARGUMENT;
    if (!sfmi_la_all_finite(T, 27) || !sfmi_la_all_finite(x1, 2) || !sfmi_la_all_finite(x2, 2) ||
        (F21 != NULL && !sfmi_la_all_finite(F21, 9)))
        return SFM_E_NONFINITE;
    sfm_mat3 Fm;
    const double *F = Fm.m;
    if (F21 != NULL) {
        memcpy(Fm.m, F21, sizeof Fm.m);
    } else {
        int st = sfm_trifocal_fundamentals(T, &Fm, NULL, NULL);
        if (st < 0)
            return st;
    }
    const double p[3] = {x1[0], x1[1], 1.0};
    double le[3];
    for (int r = 0; r < 3; r++)
        le[r] = F[r * 3] * p[0] + F[r * 3 + 1] * p[1] + F[r * 3 + 2] * p[2];
    /* The line through x2 perpendicular to the epipolar line le. */
    double l2[3] = {le[1], -le[0], -x2[0] * le[1] + x2[1] * le[0]};
    if (!(l2[0] * l2[0] + l2[1] * l2[1] > 0))
        return SFM_E_SINGULAR;
    double y[3] = {0, 0, 0};
    for (int i = 0; i < 3; i++)
        for (int j = 0; j < 3; j++) {
            double w = p[i] * l2[j];
            for (int k = 0; k < 3; k++)
                y[k] += w * T[i * 9 + j * 3 + k];
        }
    double scale = fabs(y[0]) + fabs(y[1]) + fabs(y[2]);
    if (!(fabs(y[2]) > 1e-12 * scale))
        return SFM_E_SINGULAR;
    x3[0] = y[0] / y[2];
    x3[1] = y[1] / y[2];
    return SFM_OK;
}

int sfm_trifocal_transfer_line(const double T[27], const double l2[3], const double l3[3],
                               double l1[3])
{
    if (T == NULL || l2 == NULL || l3 == NULL || l1 == NULL)
        return SFM_E_ARGUMENT;
    if (!sfmi_la_all_finite(T, 27) || !sfmi_la_all_finite(l2, 3) || !sfmi_la_all_finite(l3, 3))
        return SFM_E_NONFINITE;
    double out[3];
    for (int i = 0; i < 3; i++) {
        double s = 0;
        for (int j = 0; j < 3; j++)
            for (int k = 0; k < 3; k++)
                s += l2[j] * l3[k] * T[i * 9 + j * 3 + k];
        out[i] = s;
    }
    memcpy(l1, out, sizeof out);
    return SFM_OK;
}
