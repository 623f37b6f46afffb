/*
 * Dense linear algebra against truth: reconstructions (A = U S V^T, QR = A,
 * LU solves), orthogonality, eigen-equations, matrices with known spectra,
 * rank-deficient and repeated-value cases, and the contract (NULL, sizes,
 * NaN, workspace one byte short: right status, outputs untouched).
 */
#include <float.h>
#include <math.h>
#include <string.h>

#include "sfm/sfm.h"
#include "sfm_test.h"

/* Scratch matrices (up to 100 x 100): inputs g_a..g_f, results g_u, g_v,
 * and g_q for random orthogonal matrices; about 800 KB of static memory in
 * all, within the Cortex-M target's budget. */
#define MAXE 10000
static double g_a[MAXE], g_b[MAXE], g_c[MAXE], g_d[MAXE], g_e[MAXE], g_f[MAXE];
static double g_u[MAXE], g_v[MAXE], g_q[MAXE];
static unsigned char g_ws[1 << 16];

static void rand_mat(sfm_test_ctx *t, double *A, int m, int n)
{
    for (int i = 0; i < m * n; i++)
        A[i] = sfm_test_uniform(t, -1.0, 1.0);
}

/* Random m x m orthogonal matrix (QR of a random matrix). */
static void rand_orth(sfm_test_ctx *t, double *Q, int m)
{
    double tau[64];
    rand_mat(t, g_q, m, m);
    sfm_qr_factor(g_q, m, m, tau);
    sfm_qr_form_q(g_q, tau, m, m, Q);
}

/* C = A (m x k) * B (k x n); tb: use B^T (B is n x k). */
static void matmul(const double *A, const double *B, double *C, int m, int k, int n, int tb)
{
    for (int i = 0; i < m; i++)
        for (int j = 0; j < n; j++) {
            double s = 0;
            for (int l = 0; l < k; l++)
                s += A[i * k + l] * (tb ? B[j * k + l] : B[l * n + j]);
            C[i * n + j] = s;
        }
}

static double fro(const double *A, int n)
{
    double s = 0;
    for (int i = 0; i < n; i++)
        s += A[i] * A[i];
    return sqrt(s);
}

/* max |Q^T Q - I| over the first k columns of Q (m rows, ld columns). */
static double orth_err(const double *Q, int m, int ld, int k)
{
    double e = 0;
    for (int a = 0; a < k; a++)
        for (int b = 0; b < k; b++) {
            double s = 0;
            for (int i = 0; i < m; i++)
                s += Q[i * ld + a] * Q[i * ld + b];
            e = fmax(e, fabs(s - (a == b ? 1.0 : 0.0)));
        }
    return e;
}

/* max |A - U diag(S) V^T| / max(|A|_F, tiny) */
static double svd_recon_err(const double *A, int m, int n, const double *U, const double *S,
                            const double *V)
{
    int p = m < n ? m : n;
    double e = 0;
    for (int i = 0; i < m; i++)
        for (int j = 0; j < n; j++) {
            double s = 0;
            for (int k = 0; k < p; k++)
                s += U[i * m + k] * S[k] * V[j * n + k];
            e = fmax(e, fabs(s - A[i * n + j]));
        }
    double nrm = fro(A, m * n);
    return nrm > 0 ? e / nrm : e;
}

/* ------------------------------------------------------------------ LU */

SFM_TEST(lu_solves_random_systems)
{
    static const int sizes[] = {1, 2, 3, 5, 9, 27, 60};
    for (int it = 0; it < SFM_TEST_ITERS(20); it++)
        for (size_t s = 0; s < sizeof sizes / sizeof sizes[0]; s++) {
            int n = sizes[s], piv[64];
            rand_mat(t, g_a, n, n);
            for (int i = 0; i < n; i++)
                g_a[i * n + i] += 3.0; /* comfortably nonsingular */
            rand_mat(t, g_b, n, 2);
            memcpy(g_c, g_a, sizeof(double) * n * n);
            matmul(g_a, g_b, g_d, n, n, 2, 0); /* d = A x */
            SFM_CHECK_EQ_INT(sfm_lu_factor(g_c, n, piv), SFM_OK);
            SFM_CHECK_EQ_INT(sfm_lu_solve(g_c, piv, n, g_d, 2), SFM_OK);
            for (int i = 0; i < 2 * n; i++)
                SFM_CHECK_NEAR(g_d[i], g_b[i], 1e-12);
        }
}

SFM_TEST(lu_permutation_and_singular)
{
    /* needs a pivot: [[0, 1], [1, 0]] */
    double A[4] = {0, 1, 1, 0}, b[2] = {2, 3};
    int piv[2];
    SFM_CHECK_EQ_INT(sfm_lu_factor(A, 2, piv), SFM_OK);
    SFM_CHECK_EQ_INT(piv[0], 1);
    SFM_CHECK_EQ_INT(sfm_lu_solve(A, piv, 2, b, 1), SFM_OK);
    SFM_CHECK_NEAR(b[0], 3, 0);
    SFM_CHECK_NEAR(b[1], 2, 0);
    double Z[9] = {1, 2, 3, 2, 4, 6, 0, 0, 0};
    int p3[3];
    SFM_CHECK_EQ_INT(sfm_lu_factor(Z, 3, p3), SFM_E_SINGULAR);
}

SFM_TEST(lu_contract)
{
    double A[4] = {1, 2, 3, 4}, B[2] = {1, 1};
    int piv[2];
    SFM_CHECK_EQ_INT(sfm_lu_factor(NULL, 2, piv), SFM_E_ARGUMENT);
    SFM_CHECK_EQ_INT(sfm_lu_factor(A, 2, NULL), SFM_E_ARGUMENT);
    SFM_CHECK_EQ_INT(sfm_lu_factor(A, 0, piv), SFM_E_ARGUMENT);
    SFM_CHECK_EQ_INT(sfm_lu_factor(A, -1, piv), SFM_E_ARGUMENT);
    SFM_CHECK_EQ_INT(sfm_lu_factor(A, SFM_LINALG_MAX_DIM + 1, piv), SFM_E_ARGUMENT);
    double N[4] = {1, (double)NAN, 3, 4};
    sfm_test_fill_canary(piv, sizeof piv);
    SFM_CHECK_EQ_INT(sfm_lu_factor(N, 2, piv), SFM_E_NONFINITE);
    SFM_CHECK(sfm_test_canary_intact(piv, sizeof piv));
    SFM_CHECK(isnan(N[1]) && N[0] == 1 && N[3] == 4);
    SFM_CHECK_EQ_INT(sfm_lu_factor(A, 2, piv), SFM_OK);
    double Bc[2];
    sfm_test_fill_canary(Bc, sizeof Bc);
    SFM_CHECK_EQ_INT(sfm_lu_solve(NULL, piv, 2, Bc, 1), SFM_E_ARGUMENT);
    SFM_CHECK_EQ_INT(sfm_lu_solve(A, NULL, 2, Bc, 1), SFM_E_ARGUMENT);
    SFM_CHECK_EQ_INT(sfm_lu_solve(A, piv, 2, NULL, 1), SFM_E_ARGUMENT);
    SFM_CHECK_EQ_INT(sfm_lu_solve(A, piv, 2, Bc, 0), SFM_E_ARGUMENT);
    SFM_CHECK(sfm_test_canary_intact(Bc, sizeof Bc));
    double Bn[2] = {HUGE_VAL, 1};
    SFM_CHECK_EQ_INT(sfm_lu_solve(A, piv, 2, Bn, 1), SFM_E_NONFINITE);
    SFM_CHECK(isinf(Bn[0]) && Bn[1] == 1);
    int badpiv[2] = {5, 1};
    SFM_CHECK_EQ_INT(sfm_lu_solve(A, badpiv, 2, B, 1), SFM_E_ARGUMENT);
    SFM_CHECK(B[0] == 1 && B[1] == 1);
}

/* ------------------------------------------------------------ Cholesky */

SFM_TEST(cholesky_reconstructs_and_solves)
{
    static const int sizes[] = {1, 3, 6, 9, 27};
    for (int it = 0; it < SFM_TEST_ITERS(20); it++)
        for (size_t s = 0; s < sizeof sizes / sizeof sizes[0]; s++) {
            int n = sizes[s];
            rand_mat(t, g_a, n, n);
            matmul(g_a, g_a, g_b, n, n, n, 1); /* B = A A^T */
            for (int i = 0; i < n; i++)
                g_b[i * n + i] += 0.5;
            memcpy(g_c, g_b, sizeof(double) * n * n);
            for (int i = 0; i < n; i++)
                for (int j = i + 1; j < n; j++)
                    g_c[i * n + j] = (double)NAN; /* the upper triangle is never read */
            SFM_CHECK_EQ_INT(sfm_cholesky_factor(g_c, n), SFM_OK);
            matmul(g_c, g_c, g_d, n, n, n, 1);
            for (int i = 0; i < n * n; i++)
                SFM_CHECK_NEAR(g_d[i], g_b[i], 1e-12 * (1 + fabs(g_b[i])));
            for (int i = 0; i < n; i++)
                for (int j = i + 1; j < n; j++)
                    SFM_CHECK(g_c[i * n + j] == 0.0);
            rand_mat(t, g_e, n, 3);
            matmul(g_b, g_e, g_f, n, n, 3, 0);
            SFM_CHECK_EQ_INT(sfm_cholesky_solve(g_c, n, g_f, 3), SFM_OK);
            for (int i = 0; i < 3 * n; i++)
                SFM_CHECK_NEAR(g_f[i], g_e[i], 1e-9);
        }
}

SFM_TEST(cholesky_contract)
{
    double A[4] = {4, 0, 2, 3}, N[4] = {4, 0, (double)NAN, 3}, I[4] = {1, 0, 2, -1};
    SFM_CHECK_EQ_INT(sfm_cholesky_factor(NULL, 2), SFM_E_ARGUMENT);
    SFM_CHECK_EQ_INT(sfm_cholesky_factor(A, 0), SFM_E_ARGUMENT);
    SFM_CHECK_EQ_INT(sfm_cholesky_factor(N, 2), SFM_E_NONFINITE);
    SFM_CHECK(N[0] == 4 && N[3] == 3);
    SFM_CHECK_EQ_INT(sfm_cholesky_factor(I, 2), SFM_E_SINGULAR); /* indefinite */
    SFM_CHECK_EQ_INT(sfm_cholesky_factor(A, 2), SFM_OK);
    SFM_CHECK_NEAR(A[0], 2, 0);
    SFM_CHECK_NEAR(A[2], 1, 0);
    SFM_CHECK_NEAR(A[3], sqrt(2.0), 1e-15);
    double B[2];
    sfm_test_fill_canary(B, sizeof B);
    SFM_CHECK_EQ_INT(sfm_cholesky_solve(NULL, 2, B, 1), SFM_E_ARGUMENT);
    SFM_CHECK_EQ_INT(sfm_cholesky_solve(A, 2, NULL, 1), SFM_E_ARGUMENT);
    SFM_CHECK_EQ_INT(sfm_cholesky_solve(A, 2, B, -1), SFM_E_ARGUMENT);
    SFM_CHECK(sfm_test_canary_intact(B, sizeof B));
}

/* ------------------------------------------------------------------ QR */

SFM_TEST(qr_reconstructs_and_solves_least_squares)
{
    static const int shapes[][2] = {{1, 1}, {3, 3}, {5, 3}, {9, 9}, {27, 27}, {100, 9}, {40, 1}};
    for (int it = 0; it < SFM_TEST_ITERS(10); it++)
        for (size_t s = 0; s < sizeof shapes / sizeof shapes[0]; s++) {
            int m = shapes[s][0], n = shapes[s][1];
            double tau[32];
            rand_mat(t, g_a, m, n);
            memcpy(g_b, g_a, sizeof(double) * m * n);
            SFM_CHECK_EQ_INT(sfm_qr_factor(g_b, m, n, tau), SFM_OK);
            SFM_CHECK_EQ_INT(sfm_qr_form_q(g_b, tau, m, n, g_c), SFM_OK);
            SFM_CHECK(orth_err(g_c, m, m, m) < 1e-14 * m);
            /* Q R = A with R the upper triangle */
            for (int i = 0; i < m; i++)
                for (int j = 0; j < n; j++) {
                    double v = 0;
                    for (int k = 0; k <= j && k < m; k++)
                        v += g_c[i * m + k] * g_b[k * n + j];
                    SFM_CHECK_NEAR(v, g_a[i * n + j], 1e-14 * m);
                }
            /* least squares: normal equations hold at the solution */
            rand_mat(t, g_d, m, 1);
            memcpy(g_e, g_d, sizeof(double) * m);
            SFM_CHECK_EQ_INT(sfm_qr_solve(g_b, tau, m, n, g_e), SFM_OK);
            for (int j = 0; j < n; j++) {
                double g = 0;
                for (int i = 0; i < m; i++) {
                    double r = -g_d[i];
                    for (int k = 0; k < n; k++)
                        r += g_a[i * n + k] * g_e[k];
                    g += g_a[i * n + j] * r;
                }
                SFM_CHECK_NEAR(g, 0.0, 1e-10);
            }
        }
}

SFM_TEST(qr_contract)
{
    double A[6] = {1, 2, 3, 4, 5, 6}, tau[2], Q[9], b[3] = {1, 2, 3};
    SFM_CHECK_EQ_INT(sfm_qr_factor(NULL, 3, 2, tau), SFM_E_ARGUMENT);
    SFM_CHECK_EQ_INT(sfm_qr_factor(A, 3, 2, NULL), SFM_E_ARGUMENT);
    SFM_CHECK_EQ_INT(sfm_qr_factor(A, 2, 3, tau), SFM_E_ARGUMENT); /* m < n */
    SFM_CHECK_EQ_INT(sfm_qr_factor(A, 3, 0, tau), SFM_E_ARGUMENT);
    double N[6] = {1, 2, 3, (double)NAN, 5, 6};
    sfm_test_fill_canary(tau, sizeof tau);
    SFM_CHECK_EQ_INT(sfm_qr_factor(N, 3, 2, tau), SFM_E_NONFINITE);
    SFM_CHECK(sfm_test_canary_intact(tau, sizeof tau));
    SFM_CHECK(N[0] == 1 && N[5] == 6);
    SFM_CHECK_EQ_INT(sfm_qr_factor(A, 3, 2, tau), SFM_OK);
    sfm_test_fill_canary(Q, sizeof Q);
    SFM_CHECK_EQ_INT(sfm_qr_form_q(A, tau, 3, 2, NULL), SFM_E_ARGUMENT);
    SFM_CHECK_EQ_INT(sfm_qr_form_q(A, NULL, 3, 2, Q), SFM_E_ARGUMENT);
    SFM_CHECK_EQ_INT(sfm_qr_form_q(A, tau, 1, 2, Q), SFM_E_ARGUMENT);
    SFM_CHECK(sfm_test_canary_intact(Q, sizeof Q));
    SFM_CHECK_EQ_INT(sfm_qr_solve(A, tau, 3, 2, NULL), SFM_E_ARGUMENT);
    double S[6] = {1, 2, 0, 0, 0, 0}, ts[2];
    SFM_CHECK_EQ_INT(sfm_qr_factor(S, 3, 2, ts), SFM_OK); /* rank one: R[1][1] = 0 */
    SFM_CHECK_EQ_INT(sfm_qr_solve(S, ts, 3, 2, b), SFM_E_SINGULAR);
    SFM_CHECK(b[0] == 1 && b[1] == 2 && b[2] == 3);
}

/* ----------------------------------------------------------------- SVD */

static void check_svd(sfm_test_ctx *t, const double *A, int m, int n, double recon_tol)
{
    double *U = g_u, *V = g_v;
    static double S[128];
    size_t ws = sfm_svd_workspace_size(m, n);
    SFM_CHECK(ws > 0 && ws <= sizeof g_ws);
    int st = sfm_svd(A, m, n, U, S, V, g_ws, ws);
    SFM_CHECK_EQ_INT(st, SFM_OK);
    if (st != SFM_OK)
        return;
    int p = m < n ? m : n;
    for (int k = 0; k < p; k++) {
        SFM_CHECK(S[k] >= 0 && isfinite(S[k]));
        if (k > 0)
            SFM_CHECK(S[k] <= S[k - 1]);
    }
    double re = svd_recon_err(A, m, n, U, S, V);
    SFM_CHECK_MSG(re <= recon_tol, "%dx%d recon %g", m, n, re);
    double ou = orth_err(U, m, m, m), ov = orth_err(V, n, n, n);
    SFM_CHECK_MSG(ou <= 1e-13 && ov <= 1e-13, "%dx%d orth U %g V %g", m, n, ou, ov);
    /* the NULL-U / NULL-V paths give the same singular values */
    static double S2[128];
    SFM_CHECK_EQ_INT(sfm_svd(A, m, n, NULL, S2, NULL, g_ws, ws), SFM_OK);
    for (int k = 0; k < p; k++)
        SFM_CHECK_NEAR(S2[k], S[k], 1e-14 * (S[0] + 1e-300));
}

SFM_TEST(svd_random_shapes)
{
    static const int shapes[][2] = {{1, 1}, {1, 5}, {5, 1}, {2, 2}, {3, 3}, {4, 3}, {3, 4},
                                    {2, 7}, {8, 9}, {9, 9}, {12, 9}, {27, 27}, {100, 9},
                                    {9, 100}, {30, 20}};
    for (int it = 0; it < SFM_TEST_ITERS(5); it++)
        for (size_t s = 0; s < sizeof shapes / sizeof shapes[0]; s++) {
            int m = shapes[s][0], n = shapes[s][1];
            rand_mat(t, g_a, m, n);
            check_svd(t, g_a, m, n, 1e-14);
        }
}

SFM_TEST(svd_known_values)
{
    /* [[3, 0], [4, 5]]: A^T A = [[25, 20], [20, 25]], singular values sqrt(45), sqrt(5) */
    double A[4] = {3, 0, 4, 5}, S[2], U[4], V[4];
    size_t ws = sfm_svd_workspace_size(2, 2);
    SFM_CHECK_EQ_INT(sfm_svd(A, 2, 2, U, S, V, g_ws, ws), SFM_OK);
    SFM_CHECK_NEAR(S[0], sqrt(45.0), 1e-14);
    SFM_CHECK_NEAR(S[1], sqrt(5.0), 1e-14);
    /* diagonal with unsorted entries and a sign */
    double D[9] = {1, 0, 0, 0, -7, 0, 0, 0, 3}, S3[3];
    SFM_CHECK_EQ_INT(sfm_svd(D, 3, 3, NULL, S3, NULL, g_ws, sfm_svd_workspace_size(3, 3)), SFM_OK);
    SFM_CHECK_NEAR(S3[0], 7, 0);
    SFM_CHECK_NEAR(S3[1], 3, 0);
    SFM_CHECK_NEAR(S3[2], 1, 0);
    check_svd(t, D, 3, 3, 1e-15);
    /* zero matrix: S = 0, U and V still orthogonal */
    memset(g_a, 0, sizeof(double) * 20);
    check_svd(t, g_a, 4, 5, 0);
    check_svd(t, g_a, 5, 4, 0);
}

SFM_TEST(svd_rank_deficient_and_repeated)
{
    static const int shapes[][3] = {{9, 9, 8}, {9, 9, 5}, {27, 27, 20}, {100, 9, 3},
                                    {6, 9, 2}, {3, 3, 2}, {3, 3, 1}};
    for (int it = 0; it < SFM_TEST_ITERS(5); it++)
        for (size_t s = 0; s < sizeof shapes / sizeof shapes[0]; s++) {
            int m = shapes[s][0], n = shapes[s][1], r = shapes[s][2];
            rand_mat(t, g_b, m, r);
            rand_mat(t, g_c, r, n);
            matmul(g_b, g_c, g_a, m, r, n, 0);
            check_svd(t, g_a, m, n, 1e-14);
            static double S[128];
            SFM_CHECK_EQ_INT(sfm_svd(g_a, m, n, NULL, S, NULL, g_ws,
                                     sfm_svd_workspace_size(m, n)), SFM_OK);
            int p = m < n ? m : n;
            for (int k = r; k < p; k++)
                SFM_CHECK_MSG(S[k] <= 1e-14 * S[0] * m, "%dx%d rank %d: S[%d]/S[0] = %g", m,
                              n, r, k, S[k] / S[0]);
        }
    /* repeated singular values: Q1 diag(2, 2, 2, 1, 1, 0.5, 0) Q2^T */
    const int n = 7;
    static const double sv[7] = {2, 2, 2, 1, 1, 0.5, 0};
    for (int it = 0; it < SFM_TEST_ITERS(10); it++) {
        rand_orth(t, g_b, n);
        rand_orth(t, g_c, n);
        for (int i = 0; i < n; i++)
            for (int j = 0; j < n; j++)
                g_b[i * n + j] *= sv[j];
        matmul(g_b, g_c, g_a, n, n, n, 1);
        check_svd(t, g_a, n, n, 1e-14);
        double S[7];
        SFM_CHECK_EQ_INT(sfm_svd(g_a, n, n, NULL, S, NULL, g_ws, sfm_svd_workspace_size(n, n)),
                         SFM_OK);
        for (int k = 0; k < n; k++)
            SFM_CHECK_NEAR(S[k], sv[k], 1e-14);
    }
}

SFM_TEST(svd_extreme_scales_and_conditioning)
{
    const int n = 6;
    static const double scales[] = {1e-300, 1e-150, 1e150, 1e300};
    for (size_t s = 0; s < sizeof scales / sizeof scales[0]; s++) {
        rand_mat(t, g_a, n, n);
        double S1[6], S2[6];
        SFM_CHECK_EQ_INT(sfm_svd(g_a, n, n, NULL, S1, NULL, g_ws, sfm_svd_workspace_size(n, n)),
                         SFM_OK);
        for (int i = 0; i < n * n; i++)
            g_b[i] = g_a[i] * scales[s];
        check_svd(t, g_b, n, n, 1e-14);
        SFM_CHECK_EQ_INT(sfm_svd(g_b, n, n, NULL, S2, NULL, g_ws, sfm_svd_workspace_size(n, n)),
                         SFM_OK);
        for (int k = 0; k < n; k++)
            SFM_CHECK_NEAR(S2[k] / scales[s], S1[k], 1e-13 * S1[0]);
    }
    /* condition 1e10: U diag(1 .. 1e-10) V^T, every value to 1e-14 absolute */
    for (int it = 0; it < SFM_TEST_ITERS(10); it++) {
        const int m = 9;
        double sv[9];
        for (int k = 0; k < m; k++)
            sv[k] = pow(10.0, -10.0 * k / (m - 1));
        rand_orth(t, g_b, m);
        rand_orth(t, g_c, m);
        for (int i = 0; i < m; i++)
            for (int j = 0; j < m; j++)
                g_b[i * m + j] *= sv[j];
        matmul(g_b, g_c, g_a, m, m, m, 1);
        check_svd(t, g_a, m, m, 1e-14);
        double S[9];
        SFM_CHECK_EQ_INT(sfm_svd(g_a, m, m, NULL, S, NULL, g_ws, sfm_svd_workspace_size(m, m)),
                         SFM_OK);
        for (int k = 0; k < m; k++)
            SFM_CHECK_NEAR(S[k], sv[k], 1e-14);
    }
}

SFM_TEST(svd_is_deterministic_across_workspace_alignment)
{
    const int m = 12, n = 9;
    rand_mat(t, g_a, m, n);
    static double U1[144], V1[81], S1[9], U2[144], V2[81], S2[9];
    size_t ws = sfm_svd_workspace_size(m, n);
    SFM_CHECK_EQ_INT(sfm_svd(g_a, m, n, U1, S1, V1, g_ws, ws), SFM_OK);
    SFM_CHECK_EQ_INT(sfm_svd(g_a, m, n, U2, S2, V2, g_ws + 7, ws), SFM_OK);
    SFM_CHECK(memcmp(U1, U2, sizeof U1) == 0);
    SFM_CHECK(memcmp(S1, S2, sizeof S1) == 0);
    SFM_CHECK(memcmp(V1, V2, sizeof V1) == 0);
}

SFM_TEST(svd_contract)
{
    double A[6] = {1, 2, 3, 4, 5, 6}, U[4], S[2], V[9];
    size_t ws = sfm_svd_workspace_size(2, 3);
    SFM_CHECK(ws > 0);
    SFM_CHECK_EQ_INT(sfm_svd_workspace_size(0, 3), 0);
    SFM_CHECK_EQ_INT(sfm_svd_workspace_size(2, -1), 0);
    SFM_CHECK_EQ_INT(sfm_svd_workspace_size(SFM_LINALG_MAX_DIM + 1, 1), 0);
    sfm_test_fill_canary(U, sizeof U);
    sfm_test_fill_canary(S, sizeof S);
    sfm_test_fill_canary(V, sizeof V);
    SFM_CHECK_EQ_INT(sfm_svd(NULL, 2, 3, U, S, V, g_ws, ws), SFM_E_ARGUMENT);
    SFM_CHECK_EQ_INT(sfm_svd(A, 2, 3, U, NULL, V, g_ws, ws), SFM_E_ARGUMENT);
    SFM_CHECK_EQ_INT(sfm_svd(A, 2, 3, U, S, V, NULL, ws), SFM_E_ARGUMENT);
    SFM_CHECK_EQ_INT(sfm_svd(A, 0, 3, U, S, V, g_ws, ws), SFM_E_ARGUMENT);
    SFM_CHECK_EQ_INT(sfm_svd(A, 2, -3, U, S, V, g_ws, ws), SFM_E_ARGUMENT);
    SFM_CHECK_EQ_INT(sfm_svd(A, 2, 3, U, S, V, g_ws, ws - 1), SFM_E_WORKSPACE);
    SFM_CHECK_EQ_INT(sfm_svd(A, 2, 3, U, S, V, g_ws + 1, ws - 1), SFM_E_WORKSPACE);
    double N[6] = {1, 2, 3, 4, HUGE_VAL, 6};
    SFM_CHECK_EQ_INT(sfm_svd(N, 2, 3, U, S, V, g_ws, ws), SFM_E_NONFINITE);
    N[4] = (double)NAN;
    SFM_CHECK_EQ_INT(sfm_svd(N, 2, 3, U, S, V, g_ws, ws), SFM_E_NONFINITE);
    SFM_CHECK(sfm_test_canary_intact(U, sizeof U));
    SFM_CHECK(sfm_test_canary_intact(S, sizeof S));
    SFM_CHECK(sfm_test_canary_intact(V, sizeof V));
    /* exactly the reported size works at any alignment */
    for (int off = 0; off < 16; off++)
        SFM_CHECK_EQ_INT(sfm_svd(A, 2, 3, U, S, V, g_ws + off, ws), SFM_OK);
}

/* ------------------------------------------------------- symmetric eig */

static void check_sym_eig(sfm_test_ctx *t, const double *A, int n, double tol)
{
    static double w[128], w2[128];
    double *V = g_v;
    size_t ws = sfm_sym_eig_workspace_size(n);
    SFM_CHECK(ws > 0 && ws <= sizeof g_ws);
    SFM_CHECK_EQ_INT(sfm_sym_eig(A, n, w, V, g_ws, ws), SFM_OK);
    double nrm = 0;
    for (int i = 0; i < n; i++)
        for (int j = 0; j < n; j++)
            nrm = fmax(nrm, fabs(A[(i >= j ? i * n + j : j * n + i)]));
    for (int k = 1; k < n; k++)
        SFM_CHECK(w[k] >= w[k - 1]);
    SFM_CHECK(orth_err(V, n, n, n) <= 1e-13);
    for (int k = 0; k < n; k++)
        for (int i = 0; i < n; i++) {
            double s = 0;
            for (int j = 0; j < n; j++)
                s += A[(i >= j ? i * n + j : j * n + i)] * V[j * n + k];
            SFM_CHECK_NEAR(s, w[k] * V[i * n + k], tol * (nrm > 0 ? nrm : 1));
        }
    SFM_CHECK_EQ_INT(sfm_sym_eig(A, n, w2, NULL, g_ws, ws), SFM_OK);
    for (int k = 0; k < n; k++)
        SFM_CHECK_NEAR(w2[k], w[k], 1e-14 * (nrm > 0 ? nrm : 1));
}

SFM_TEST(sym_eig_random_and_known)
{
    static const int sizes[] = {1, 2, 3, 4, 9, 27, 50};
    for (int it = 0; it < SFM_TEST_ITERS(5); it++)
        for (size_t s = 0; s < sizeof sizes / sizeof sizes[0]; s++) {
            int n = sizes[s];
            rand_mat(t, g_a, n, n);
            for (int i = 0; i < n; i++)
                for (int j = i + 1; j < n; j++)
                    g_a[i * n + j] = (double)NAN; /* only the lower triangle is read */
            check_sym_eig(t, g_a, n, 1e-13);
        }
    double A[4] = {2, 0, 1, 2}, w[2], V[4];
    SFM_CHECK_EQ_INT(sfm_sym_eig(A, 2, w, V, g_ws, sfm_sym_eig_workspace_size(2)), SFM_OK);
    SFM_CHECK_NEAR(w[0], 1, 1e-15);
    SFM_CHECK_NEAR(w[1], 3, 1e-15);
    SFM_CHECK_NEAR(fabs(V[0]), sqrt(0.5), 1e-15);
    /* repeated eigenvalues: Q diag(-1, 2, 2, 2, 5) Q^T */
    static const double ev[5] = {-1, 2, 2, 2, 5};
    for (int it = 0; it < SFM_TEST_ITERS(10); it++) {
        rand_orth(t, g_b, 5);
        for (int i = 0; i < 5; i++)
            for (int j = 0; j < 5; j++)
                g_c[i * 5 + j] = g_b[i * 5 + j] * ev[j];
        matmul(g_c, g_b, g_a, 5, 5, 5, 1);
        check_sym_eig(t, g_a, 5, 1e-14);
        double ww[5];
        SFM_CHECK_EQ_INT(sfm_sym_eig(g_a, 5, ww, NULL, g_ws, sfm_sym_eig_workspace_size(5)),
                         SFM_OK);
        for (int k = 0; k < 5; k++)
            SFM_CHECK_NEAR(ww[k], ev[k], 1e-14);
    }
    memset(g_a, 0, sizeof(double) * 16);
    check_sym_eig(t, g_a, 4, 0);
    /* huge and tiny entries do not overflow */
    double B[4] = {1e300, 0, 5e299, -1e300}, wb[2];
    SFM_CHECK_EQ_INT(sfm_sym_eig(B, 2, wb, V, g_ws, sfm_sym_eig_workspace_size(2)), SFM_OK);
    SFM_CHECK_NEAR(wb[1] / 1e300, sqrt(1.25), 1e-15);
    SFM_CHECK_NEAR(wb[0] / 1e300, -sqrt(1.25), 1e-15);
}

SFM_TEST(sym_eig_contract)
{
    double A[4] = {1, 0, 2, 3}, w[2], V[4];
    size_t ws = sfm_sym_eig_workspace_size(2);
    SFM_CHECK_EQ_INT(sfm_sym_eig_workspace_size(0), 0);
    sfm_test_fill_canary(w, sizeof w);
    sfm_test_fill_canary(V, sizeof V);
    SFM_CHECK_EQ_INT(sfm_sym_eig(NULL, 2, w, V, g_ws, ws), SFM_E_ARGUMENT);
    SFM_CHECK_EQ_INT(sfm_sym_eig(A, 2, NULL, V, g_ws, ws), SFM_E_ARGUMENT);
    SFM_CHECK_EQ_INT(sfm_sym_eig(A, 2, w, V, NULL, ws), SFM_E_ARGUMENT);
    SFM_CHECK_EQ_INT(sfm_sym_eig(A, 0, w, V, g_ws, ws), SFM_E_ARGUMENT);
    SFM_CHECK_EQ_INT(sfm_sym_eig(A, 2, w, V, g_ws, ws - 1), SFM_E_WORKSPACE);
    double N[4] = {1, 0, (double)NAN, 3};
    SFM_CHECK_EQ_INT(sfm_sym_eig(N, 2, w, V, g_ws, ws), SFM_E_NONFINITE);
    SFM_CHECK(sfm_test_canary_intact(w, sizeof w));
    SFM_CHECK(sfm_test_canary_intact(V, sizeof V));
}

/* ----------------------------------------------------- nonsymmetric eig */

/* Checks A V = V Lambda column by column (pairs as real/imaginary parts),
 * the order, the pair layout and the normalization. */
static void check_eig(sfm_test_ctx *t, const double *A, int n, double tol)
{
    static double wr[128], wi[128], wr2[128], wi2[128];
    double *V = g_v;
    size_t ws = sfm_eig_workspace_size(n);
    SFM_CHECK(ws > 0 && ws <= sizeof g_ws);
    int st = sfm_eig(A, n, wr, wi, V, g_ws, ws);
    SFM_CHECK_EQ_INT(st, SFM_OK);
    if (st != SFM_OK)
        return;
    double nrm = fmax(fro(A, n * n), 1e-300);
    for (int k = 0; k < n; k++) {
        SFM_CHECK(isfinite(wr[k]) && isfinite(wi[k]));
        if (wi[k] > 0) {
            SFM_CHECK_MSG(k + 1 < n && wi[k + 1] == -wi[k] && wr[k + 1] == wr[k],
                          "pair at %d not adjacent", k);
            if (k > 0)
                SFM_CHECK(wr[k] <= wr[k - 1]);
            if (k + 2 < n)
                SFM_CHECK(wr[k + 2] <= wr[k + 1]);
            double s = 0, big = 0;
            for (int i = 0; i < n; i++) {
                double re = V[i * n + k], im = V[i * n + k + 1];
                s += re * re + im * im;
                big = fmax(big, re * re + im * im);
            }
            SFM_CHECK_NEAR(s, 1.0, 1e-13);
            /* a component of largest modulus (to rounding) is real positive */
            int found = 0;
            for (int i = 0; i < n; i++) {
                double re = V[i * n + k], im = V[i * n + k + 1];
                if (re * re + im * im >= big * (1 - 1e-12) && im == 0.0 && re > 0)
                    found = 1;
            }
            SFM_CHECK(found);
            for (int i = 0; i < n; i++) {
                double ar = 0, ai = 0;
                for (int j = 0; j < n; j++) {
                    ar += A[i * n + j] * V[j * n + k];
                    ai += A[i * n + j] * V[j * n + k + 1];
                }
                double er = wr[k] * V[i * n + k] - wi[k] * V[i * n + k + 1];
                double ei = wi[k] * V[i * n + k] + wr[k] * V[i * n + k + 1];
                SFM_CHECK_NEAR(ar, er, tol * nrm);
                SFM_CHECK_NEAR(ai, ei, tol * nrm);
            }
            k++;
        } else {
            SFM_CHECK(wi[k] == 0.0);
            if (k > 0)
                SFM_CHECK(wr[k] <= wr[k - 1]);
            double s = 0, big = 0;
            for (int i = 0; i < n; i++) {
                s += V[i * n + k] * V[i * n + k];
                big = fmax(big, fabs(V[i * n + k]));
            }
            SFM_CHECK_NEAR(s, 1.0, 1e-13);
            int found = 0;
            for (int i = 0; i < n; i++)
                if (V[i * n + k] >= big * (1 - 1e-12))
                    found = 1;
            SFM_CHECK(found);
            for (int i = 0; i < n; i++) {
                double a = 0;
                for (int j = 0; j < n; j++)
                    a += A[i * n + j] * V[j * n + k];
                SFM_CHECK_NEAR(a, wr[k] * V[i * n + k], tol * nrm);
            }
        }
    }
    SFM_CHECK_EQ_INT(sfm_eig(A, n, wr2, wi2, NULL, g_ws, ws), SFM_OK);
    for (int k = 0; k < n; k++) {
        SFM_CHECK_NEAR(wr2[k], wr[k], 1e-12 * nrm);
        SFM_CHECK_NEAR(wi2[k], wi[k], 1e-12 * nrm);
    }
}

SFM_TEST(eig_random_matrices)
{
    static const int sizes[] = {1, 2, 3, 4, 5, 8, 10, 20, 27};
    for (int it = 0; it < SFM_TEST_ITERS(20); it++)
        for (size_t s = 0; s < sizeof sizes / sizeof sizes[0]; s++) {
            int n = sizes[s];
            rand_mat(t, g_a, n, n);
            check_eig(t, g_a, n, 1e-13);
        }
}

SFM_TEST(eig_known_spectra)
{
    double wr[4], wi[4], V[16];
    /* rotation by 90 degrees: +-i */
    double R[4] = {0, -1, 1, 0};
    SFM_CHECK_EQ_INT(sfm_eig(R, 2, wr, wi, V, g_ws, sfm_eig_workspace_size(2)), SFM_OK);
    SFM_CHECK_NEAR(wr[0], 0, 1e-15);
    SFM_CHECK_NEAR(wi[0], 1, 1e-15);
    SFM_CHECK_NEAR(wi[1], -1, 1e-15);
    check_eig(t, R, 2, 1e-15);
    /* companion matrix of (x-1)(x-2)(x-3) = x^3 - 6x^2 + 11x - 6 */
    double C[9] = {6, -11, 6, 1, 0, 0, 0, 1, 0};
    SFM_CHECK_EQ_INT(sfm_eig(C, 3, wr, wi, V, g_ws, sfm_eig_workspace_size(3)), SFM_OK);
    for (int k = 0; k < 3; k++) {
        SFM_CHECK_NEAR(wr[k], 3 - k, 1e-13);
        SFM_CHECK(wi[k] == 0);
    }
    check_eig(t, C, 3, 1e-14);
    /* block diag(rotation-scaling with real part 1, real 1, real 2): the
     * pair and the real eigenvalue 1 tie on the real part; the pair first */
    double B[16] = {1, -2, 0, 0, 2, 1, 0, 0, 0, 0, 1, 0, 0, 0, 0, 2};
    SFM_CHECK_EQ_INT(sfm_eig(B, 4, wr, wi, V, g_ws, sfm_eig_workspace_size(4)), SFM_OK);
    SFM_CHECK_NEAR(wr[0], 2, 1e-15);
    SFM_CHECK_NEAR(wr[1], 1, 1e-15);
    SFM_CHECK_NEAR(wi[1], 2, 1e-15);
    SFM_CHECK_NEAR(wi[2], -2, 1e-15);
    SFM_CHECK_NEAR(wr[3], 1, 1e-15);
    SFM_CHECK(wi[3] == 0);
    check_eig(t, B, 4, 1e-14);
    /* triangular: eigenvalues are the diagonal */
    double T[9] = {1, 5, -3, 0, 4, 2, 0, 0, -2};
    SFM_CHECK_EQ_INT(sfm_eig(T, 3, wr, wi, V, g_ws, sfm_eig_workspace_size(3)), SFM_OK);
    SFM_CHECK_NEAR(wr[0], 4, 1e-14);
    SFM_CHECK_NEAR(wr[1], 1, 1e-14);
    SFM_CHECK_NEAR(wr[2], -2, 1e-14);
    check_eig(t, T, 3, 1e-14);
    /* zero and defective matrices: finite output, no hang */
    double Z[9] = {0};
    check_eig(t, Z, 3, 0);
    double J[4] = {1, 1, 0, 1};
    SFM_CHECK_EQ_INT(sfm_eig(J, 2, wr, wi, V, g_ws, sfm_eig_workspace_size(2)), SFM_OK);
    for (int i = 0; i < 4; i++)
        SFM_CHECK(isfinite(V[i]));
    SFM_CHECK_NEAR(wr[0], 1, 0);
    SFM_CHECK_NEAR(wr[1], 1, 0);
    /* a similarity transform of a known spectrum with a complex pair */
    const int n = 6;
    static const double d[6] = {3, 0.5, -1, -1, 2, 0.5};
    for (int it = 0; it < SFM_TEST_ITERS(20); it++) {
        rand_mat(t, g_b, n, n);
        for (int i = 0; i < n; i++)
            g_b[i * n + i] += 3.0;
        memset(g_c, 0, sizeof(double) * n * n);
        for (int i = 0; i < n; i++)
            g_c[i * n + i] = d[i];
        g_c[1 * n + 5] = 1.5; /* 0.5 +- 1.5 i */
        g_c[5 * n + 1] = -1.5;
        /* A = B C B^-1 */
        int piv[6];
        memcpy(g_d, g_b, sizeof(double) * n * n);
        SFM_CHECK_EQ_INT(sfm_lu_factor(g_d, n, piv), SFM_OK);
        matmul(g_b, g_c, g_e, n, n, n, 0);
        /* X = E B^-1  <=>  B^T X^T = E^T */
        for (int i = 0; i < n; i++)
            for (int j = 0; j < n; j++) {
                g_f[i * n + j] = g_e[j * n + i];
                g_a[i * n + j] = g_b[j * n + i];
            }
        SFM_CHECK_EQ_INT(sfm_lu_factor(g_a, n, piv), SFM_OK);
        SFM_CHECK_EQ_INT(sfm_lu_solve(g_a, piv, n, g_f, n), SFM_OK);
        for (int i = 0; i < n; i++)
            for (int j = 0; j < n; j++)
                g_a[i * n + j] = g_f[j * n + i];
        double w_r[6], w_i[6];
        SFM_CHECK_EQ_INT(sfm_eig(g_a, n, w_r, w_i, NULL, g_ws, sfm_eig_workspace_size(n)),
                         SFM_OK);
        static const double er[6] = {3, 2, 0.5, 0.5, -1, -1};
        static const double ei[6] = {0, 0, 1.5, -1.5, 0, 0};
        for (int k = 0; k < n; k++) {
            SFM_CHECK_NEAR(w_r[k], er[k], 1e-6); /* -1 is a double root */
            SFM_CHECK_NEAR(w_i[k], ei[k], 1e-6);
        }
    }
}

SFM_TEST(eig_defective_and_sparse_integer_matrices)
{
    /* eigenvalue 0 with a Jordan block: the pair of nearly equal eigenvalues
     * it splits into must not spoil the other vectors */
    static const double J[16] = {3, 0, 0, 0, 1, 0, 0, 0, 0, 0, 0, 0, -2, -3, 1, 0};
    check_eig(t, J, 4, 1e-13);
    for (int it = 0; it < SFM_TEST_ITERS(300); it++) {
        int n = 1 + (int)sfm_rng_bounded(&t->rng, 8);
        for (int i = 0; i < n * n; i++)
            g_a[i] = sfm_rng_bounded(&t->rng, 2) ? 0.0 : (double)sfm_rng_bounded(&t->rng, 5) - 2.0;
        check_eig(t, g_a, n, 1e-12);
    }
    /* cyclic permutations: all eigenvalues on the unit circle, a classic
     * stall for unshifted QR */
    for (int n = 2; n <= 12; n++) {
        memset(g_a, 0, sizeof(double) * n * n);
        for (int i = 0; i < n; i++)
            g_a[((i + 1) % n) * n + i] = 1.0;
        check_eig(t, g_a, n, 1e-13);
    }
}

SFM_TEST(eig_extreme_scales)
{
    const int n = 5;
    static const double scales[] = {1e-300, 1e300};
    for (size_t s = 0; s < 2; s++) {
        rand_mat(t, g_a, n, n);
        double wr1[5], wi1[5], wr2[5], wi2[5];
        SFM_CHECK_EQ_INT(sfm_eig(g_a, n, wr1, wi1, NULL, g_ws, sfm_eig_workspace_size(n)),
                         SFM_OK);
        for (int i = 0; i < n * n; i++)
            g_b[i] = g_a[i] * scales[s];
        SFM_CHECK_EQ_INT(sfm_eig(g_b, n, wr2, wi2, NULL, g_ws, sfm_eig_workspace_size(n)),
                         SFM_OK);
        for (int k = 0; k < n; k++) {
            SFM_CHECK_NEAR(wr2[k] / scales[s], wr1[k], 1e-13);
            SFM_CHECK_NEAR(wi2[k] / scales[s], wi1[k], 1e-13);
        }
        check_eig(t, g_b, n, 1e-13);
    }
}

SFM_TEST(eig_contract)
{
    double A[4] = {1, 2, 3, 4}, wr[2], wi[2], V[4];
    size_t ws = sfm_eig_workspace_size(2);
    SFM_CHECK_EQ_INT(sfm_eig_workspace_size(-2), 0);
    sfm_test_fill_canary(wr, sizeof wr);
    sfm_test_fill_canary(wi, sizeof wi);
    sfm_test_fill_canary(V, sizeof V);
    SFM_CHECK_EQ_INT(sfm_eig(NULL, 2, wr, wi, V, g_ws, ws), SFM_E_ARGUMENT);
    SFM_CHECK_EQ_INT(sfm_eig(A, 2, NULL, wi, V, g_ws, ws), SFM_E_ARGUMENT);
    SFM_CHECK_EQ_INT(sfm_eig(A, 2, wr, NULL, V, g_ws, ws), SFM_E_ARGUMENT);
    SFM_CHECK_EQ_INT(sfm_eig(A, 2, wr, wi, V, NULL, ws), SFM_E_ARGUMENT);
    SFM_CHECK_EQ_INT(sfm_eig(A, 0, wr, wi, V, g_ws, ws), SFM_E_ARGUMENT);
    SFM_CHECK_EQ_INT(sfm_eig(A, 2, wr, wi, V, g_ws, ws - 1), SFM_E_WORKSPACE);
    double N[4] = {1, 2, -HUGE_VAL, 4};
    SFM_CHECK_EQ_INT(sfm_eig(N, 2, wr, wi, V, g_ws, ws), SFM_E_NONFINITE);
    SFM_CHECK(sfm_test_canary_intact(wr, sizeof wr));
    SFM_CHECK(sfm_test_canary_intact(wi, sizeof wi));
    SFM_CHECK(sfm_test_canary_intact(V, sizeof V));
}

/* ----------------------------------------------------------- null space */

SFM_TEST(nullspace_of_rank_deficient_matrices)
{
    static const int cases[][4] = {{8, 9, 1, 8}, {9, 9, 3, 6}, {3, 9, 6, 3}, {2, 3, 1, 2},
                                   {100, 9, 1, 8}, {5, 9, 4, 5}};
    for (int it = 0; it < SFM_TEST_ITERS(10); it++)
        for (size_t c = 0; c < sizeof cases / sizeof cases[0]; c++) {
            int m = cases[c][0], n = cases[c][1], k = cases[c][2], r = cases[c][3];
            rand_mat(t, g_b, m, r);
            rand_mat(t, g_c, r, n);
            matmul(g_b, g_c, g_a, m, r, n, 0);
            double *N = g_u;
            static double S[64];
            size_t ws = sfm_nullspace_workspace_size(m, n);
            SFM_CHECK(ws > 0 && ws <= sizeof g_ws);
            SFM_CHECK_EQ_INT(sfm_nullspace(g_a, m, n, k, N, S, g_ws, ws), SFM_OK);
            SFM_CHECK(orth_err(N, n, k, k) < 1e-13);
            double an = fro(g_a, m * n);
            for (int j = 0; j < k; j++) {
                SFM_CHECK(S[j] <= 1e-13 * an);
                if (j > 0)
                    SFM_CHECK(S[j] >= S[j - 1]);
                for (int i = 0; i < m; i++) {
                    double s = 0;
                    for (int l = 0; l < n; l++)
                        s += g_a[i * n + l] * N[l * k + j];
                    SFM_CHECK_NEAR(s, 0.0, 1e-13 * an);
                }
            }
        }
    /* smallest singular vectors of a diagonal matrix, smallest first */
    double D[9] = {3, 0, 0, 0, 1, 0, 0, 0, 2}, N[6], S[2];
    SFM_CHECK_EQ_INT(sfm_nullspace(D, 3, 3, 2, N, S, g_ws, sfm_nullspace_workspace_size(3, 3)),
                     SFM_OK);
    SFM_CHECK_NEAR(S[0], 1, 0);
    SFM_CHECK_NEAR(S[1], 2, 0);
    SFM_CHECK_NEAR(fabs(N[1 * 2 + 0]), 1, 0);
    SFM_CHECK_NEAR(fabs(N[2 * 2 + 1]), 1, 0);
    SFM_CHECK_EQ_INT(sfm_nullspace(D, 3, 3, 1, N, NULL, g_ws, sfm_nullspace_workspace_size(3, 3)),
                     SFM_OK);
}

SFM_TEST(nullspace_contract)
{
    double A[6] = {1, 2, 3, 4, 5, 6}, N[3], S[1];
    size_t ws = sfm_nullspace_workspace_size(2, 3);
    SFM_CHECK_EQ_INT(sfm_nullspace_workspace_size(2, 0), 0);
    sfm_test_fill_canary(N, sizeof N);
    sfm_test_fill_canary(S, sizeof S);
    SFM_CHECK_EQ_INT(sfm_nullspace(NULL, 2, 3, 1, N, S, g_ws, ws), SFM_E_ARGUMENT);
    SFM_CHECK_EQ_INT(sfm_nullspace(A, 2, 3, 1, NULL, S, g_ws, ws), SFM_E_ARGUMENT);
    SFM_CHECK_EQ_INT(sfm_nullspace(A, 2, 3, 0, N, S, g_ws, ws), SFM_E_ARGUMENT);
    SFM_CHECK_EQ_INT(sfm_nullspace(A, 2, 3, 4, N, S, g_ws, ws), SFM_E_ARGUMENT);
    SFM_CHECK_EQ_INT(sfm_nullspace(A, 2, 3, 1, N, S, NULL, ws), SFM_E_ARGUMENT);
    SFM_CHECK_EQ_INT(sfm_nullspace(A, 2, 3, 1, N, S, g_ws, ws - 1), SFM_E_WORKSPACE);
    double B[6] = {1, 2, 3, 4, (double)NAN, 6};
    SFM_CHECK_EQ_INT(sfm_nullspace(B, 2, 3, 1, N, S, g_ws, ws), SFM_E_NONFINITE);
    SFM_CHECK(sfm_test_canary_intact(N, sizeof N));
    SFM_CHECK(sfm_test_canary_intact(S, sizeof S));
    SFM_CHECK_EQ_INT(sfm_nullspace(A, 2, 3, 1, N, S, g_ws, ws), SFM_OK);
    /* (1, -2, 1) spans the null space of [[1, 2, 3], [4, 5, 6]] */
    double sgn = N[0] > 0 ? 1 : -1;
    SFM_CHECK_NEAR(sgn * N[0], 1 / sqrt(6.0), 1e-15);
    SFM_CHECK_NEAR(sgn * N[1], -2 / sqrt(6.0), 1e-15);
    SFM_CHECK_NEAR(sgn * N[2], 1 / sqrt(6.0), 1e-15);
}
