/* Inverse iteration for the smallest right singular vector of a triangular
 * factor (core/tri_null.h), against matrices built with a known SVD. */
#include <float.h>
#include <math.h>
#include <string.h>

#include "core/tri_null.h"
#include "sfm/sfm.h"
#include "sfm_test.h"

enum { TN_MAX = 32 };

/* A random orthogonal m x m matrix: Q of the QR of a Gaussian matrix. */
static void tn_orth(sfm_test_ctx *t, double *Q, int m)
{
    static double A[TN_MAX * TN_MAX];
    double tau[TN_MAX];
    for (int i = 0; i < m * m; i++)
        A[i] = sfm_rng_normal(&t->rng);
    SFM_CHECK_EQ_INT(sfm_qr_factor(A, m, m, tau), SFM_OK);
    SFM_CHECK_EQ_INT(sfm_qr_form_q(A, tau, m, m, Q), SFM_OK);
}

/* R (n x n upper triangular) of A = U diag(s) V^T with random U (m x m,
 * m >= n) and V (n x n); V returned. */
static void tn_build(sfm_test_ctx *t, const double *s, int m, int n, double *R, double *V)
{
    static double U[TN_MAX * TN_MAX], A[TN_MAX * TN_MAX];
    double tau[TN_MAX];
    tn_orth(t, U, m);
    tn_orth(t, V, n);
    for (int i = 0; i < m; i++)
        for (int j = 0; j < n; j++) {
            double acc = 0.0;
            for (int k = 0; k < n; k++)
                acc += U[i * m + k] * s[k] * V[j * n + k];
            A[i * n + j] = acc;
        }
    SFM_CHECK_EQ_INT(sfm_qr_factor(A, m, n, tau), SFM_OK);
    for (int i = 0; i < n; i++)
        for (int j = 0; j < n; j++)
            R[i * n + j] = j >= i ? A[i * n + j] : 1e300; /* below: never read */
}

/* min over the sign of |v - V[:, n-1]|. */
static double tn_err(const double *v, const double *V, int n)
{
    double dp = 0.0, dm = 0.0;
    for (int i = 0; i < n; i++) {
        double w = V[i * n + n - 1];
        dp += (v[i] - w) * (v[i] - w);
        dm += (v[i] + w) * (v[i] + w);
    }
    return sqrt(dp < dm ? dp : dm);
}

SFM_TEST(tri_null_recovers_known_vector)
{
    static double R[TN_MAX * TN_MAX], V[TN_MAX * TN_MAX];
    static const int dims[][2] = {{1, 1}, {3, 2}, {9, 9}, {28, 27}, {27, 15}, {30, 27}};
    double s[TN_MAX], v[TN_MAX], scratch[5 * TN_MAX], worst = 0.0;
    for (int it = 0; it < SFM_TEST_ITERS(20); it++)
        for (size_t d = 0; d < sizeof dims / sizeof dims[0]; d++) {
            int m = dims[d][0], n = dims[d][1];
            /* singular values from 1 down to 1e-3, the smallest 1e-3 times
             * the next (or exactly zero every other time) */
            for (int k = 0; k < n; k++)
                s[k] = pow(10.0, -3.0 * k / (n > 1 ? n - 1 : 1));
            if (n > 1)
                s[n - 1] = (it % 2) ? 0.0 : 1e-3 * s[n - 2];
            tn_build(t, s, m, n, R, V);
            SFM_CHECK_EQ_INT(sfmi_la_tri_smallest_right(R, n, 1e-13, v, scratch), 1);
            double nrm = 0.0;
            for (int i = 0; i < n; i++)
                nrm += v[i] * v[i];
            SFM_CHECK_NEAR(sqrt(nrm), 1.0, 1e-14);
            double e = tn_err(v, V, n);
            SFM_CHECK_MSG(e < 1e-11, "n = %d, error %g", n, e);
            if (e > worst)
                worst = e;
        }
    SFM_TEST_LOG("worst |v - v_true| %.2e", worst);
}

SFM_TEST(tri_null_slow_contraction_still_converges)
{
    /* s_n / s_{n-1} = 0.7: about 50 steps for 1e-13 */
    static double R[TN_MAX * TN_MAX], V[TN_MAX * TN_MAX];
    double s[27], v[27], scratch[135];
    for (int k = 0; k < 27; k++)
        s[k] = 1.0 - 0.02 * k;
    s[26] = 0.7 * s[25];
    tn_build(t, s, 28, 27, R, V);
    SFM_CHECK_EQ_INT(sfmi_la_tri_smallest_right(R, 27, 1e-13, v, scratch), 1);
    SFM_CHECK(tn_err(v, V, 27) < 1e-11);
}

SFM_TEST(tri_null_two_vector_phase)
{
    /* s_n / s_{n-1} = 0.97: one vector would need hundreds of steps; the
     * pair converges at (s_n / s_{n-2})^2 = 0.25 a step */
    static double R[TN_MAX * TN_MAX], V[TN_MAX * TN_MAX];
    double s[27], v[27], scratch[135];
    for (int it = 0; it < SFM_TEST_ITERS(10); it++) {
        for (int k = 0; k < 27; k++)
            s[k] = 1.0 - 0.02 * k;
        s[26] = 0.5 * s[24];
        s[25] = s[26] / 0.97;
        tn_build(t, s, 28, 27, R, V);
        SFM_CHECK_EQ_INT(sfmi_la_tri_smallest_right(R, 27, 1e-13, v, scratch), 1);
        double e = tn_err(v, V, 27);
        SFM_CHECK_MSG(e < 1e-11, "error %g", e);
    }
}

SFM_TEST(tri_null_exact_zero_pivots)
{
    /* singular triangular matrices: zero last pivot, zero interior pivot */
    static double R[27 * 27];
    double v[27], scratch[135];
    for (int zero = 26; zero >= 10; zero -= 16) {
        for (int i = 0; i < 27; i++)
            for (int j = 0; j < 27; j++)
                R[i * 27 + j] = j < i ? 0.0 : sfm_test_uniform(t, -1, 1);
        for (int i = 0; i < 27; i++)
            R[i * 27 + i] = (i == zero) ? 0.0 : 1.0 + sfm_test_uniform(t, 0, 1);
        SFM_CHECK_EQ_INT(sfmi_la_tri_smallest_right(R, 27, 1e-13, v, scratch), 1);
        double r2 = 0.0;
        for (int i = 0; i < 27; i++) {
            double acc = 0.0;
            for (int j = i; j < 27; j++)
                acc += R[i * 27 + j] * v[j];
            r2 += acc * acc;
        }
        SFM_CHECK_MSG(sqrt(r2) < 1e-13, "zero pivot %d: |R v| = %g", zero, sqrt(r2));
    }
}

SFM_TEST(tri_null_declines_without_a_gap)
{
    /* two equal smallest singular values, a zero and a NaN matrix: 0 and v
     * untouched, so the caller falls back to the SVD */
    static double R[TN_MAX * TN_MAX], V[TN_MAX * TN_MAX];
    double s[27], v[27], scratch[135];
    for (int k = 0; k < 27; k++)
        s[k] = 1.0 - 0.02 * k;
    s[26] = s[25];
    tn_build(t, s, 28, 27, R, V);
    for (int i = 0; i < 27; i++)
        v[i] = 42.0;
    int got = sfmi_la_tri_smallest_right(R, 27, 1e-13, v, scratch);
    SFM_CHECK_EQ_INT(got, 0);
    for (int i = 0; i < 27; i++)
        SFM_CHECK(v[i] == 42.0);
    memset(R, 0, sizeof(double) * 27 * 27);
    SFM_CHECK_EQ_INT(sfmi_la_tri_smallest_right(R, 27, 1e-13, v, scratch), 0);
    R[5] = (double)NAN;
    R[0] = 1.0;
    SFM_CHECK_EQ_INT(sfmi_la_tri_smallest_right(R, 27, 1e-13, v, scratch), 0);
    for (int i = 0; i < 27; i++)
        SFM_CHECK(v[i] == 42.0);
}
