/* Projective factorization: synthetic scenes with known cameras, with and
 * without missing observations, checked against the noise-free projections
 * (a projective reconstruction reproduces them up to the noise), and the
 * contract of sfm_factorize_projective. */
#include <math.h>
#include <string.h>

#include "sfm/sfm.h"
#include "sfm/sfm_factorize.h"
#include "sfm_test.h"

enum { M = 6, N = 120 };

static unsigned char ws[1 << 20];
static double clean[M * N * 2], obs[M * N * 2];

/* cameras on an arc looking at a cloud around (0, 0, 6), f = 800, 640x480 */
static void scene(sfm_test_ctx *t, double sigma, double missing)
{
    double Ps[M][12];
    for (int i = 0; i < M; i++) {
        double aa[3] = {sfm_test_normal(t, 0.05), 0.08 * (i - 2.5) + sfm_test_normal(t, 0.02),
                        sfm_test_normal(t, 0.05)};
        double R[9];
        sfm_rot_from_axis_angle(aa, R);
        double C[3] = {0.5 * (i - 2.5), sfm_test_normal(t, 0.2), sfm_test_normal(t, 0.3)};
        const double K[9] = {800, 0, 320, 0, 800, 240, 0, 0, 1};
        double Rt[12];
        for (int r = 0; r < 3; r++) {
            for (int c = 0; c < 3; c++)
                Rt[r * 4 + c] = R[r * 3 + c];
            Rt[r * 4 + 3] = -(R[r * 3] * C[0] + R[r * 3 + 1] * C[1] + R[r * 3 + 2] * C[2]);
        }
        for (int r = 0; r < 3; r++)
            for (int c = 0; c < 4; c++)
                Ps[i][r * 4 + c] = K[r * 3] * Rt[c] + K[r * 3 + 1] * Rt[4 + c] + K[r * 3 + 2] * Rt[8 + c];
    }
    for (int j = 0; j < N; j++) {
        double X[4] = {sfm_test_uniform(t, -2, 2), sfm_test_uniform(t, -1.5, 1.5), sfm_test_uniform(t, 4, 8), 1};
        for (int i = 0; i < M; i++) {
            double y[3];
            for (int r = 0; r < 3; r++)
                y[r] = Ps[i][4 * r] * X[0] + Ps[i][4 * r + 1] * X[1] + Ps[i][4 * r + 2] * X[2] + Ps[i][4 * r + 3];
            double *c = &clean[(i * N + j) * 2], *o = &obs[(i * N + j) * 2];
            c[0] = y[0] / y[2];
            c[1] = y[1] / y[2];
            o[0] = c[0] + sfm_test_normal(t, sigma);
            o[1] = c[1] + sfm_test_normal(t, sigma);
        }
        /* missing: each observation dropped with this probability, keeping
         * tracks of at least 2 views */
        int kept = M;
        for (int i = 0; i < M && missing > 0; i++)
            if (kept > 2 && sfm_test_uniform(t, 0, 1) < missing) {
                obs[(i * N + j) * 2] = obs[(i * N + j) * 2 + 1] = (double)NAN;
                kept--;
            }
    }
}

/* rms over observed entries of |proj(P, X) - clean| */
static double rms_to_clean(const double *P, const double *X)
{
    double s = 0;
    int c = 0;
    for (int i = 0; i < M; i++)
        for (int j = 0; j < N; j++) {
            if (isnan(obs[(i * N + j) * 2]))
                continue;
            const double *Pi = &P[12 * i], *Xj = &X[4 * j];
            double y[3];
            for (int r = 0; r < 3; r++)
                y[r] = Pi[4 * r] * Xj[0] + Pi[4 * r + 1] * Xj[1] + Pi[4 * r + 2] * Xj[2] + Pi[4 * r + 3] * Xj[3];
            double du = y[0] / y[2] - clean[(i * N + j) * 2], dv = y[1] / y[2] - clean[(i * N + j) * 2 + 1];
            s += du * du + dv * dv;
            c++;
        }
    return sqrt(s / c);
}

static void run(sfm_test_ctx *t, double sigma, double missing, double tol_clean)
{
    scene(t, sigma, missing);
    size_t need = sfm_factorize_workspace_size(M, N);
    SFM_CHECK(need > 0 && need <= sizeof ws);
    double P[12 * M], X[4 * N];
    sfm_factorize_result r;
    int st = sfm_factorize_projective(M, N, obs, NULL, P, X, &r, ws, need);
    SFM_CHECK_EQ_INT(st, SFM_OK);
    if (st != SFM_OK)
        return;
    double e = rms_to_clean(P, X);
    SFM_TEST_LOG("sigma %.2f missing %.0f%%: block %dx%d, %d iterations (converged %d, monotone %d), "
                 "residual %.3g -> %.3g, rms to observations %.4f px, to clean %.4f px",
                 sigma, 100 * missing, r.block_views, r.block_points, r.iterations, r.converged,
                 r.monotone, r.first_residual, r.last_residual, r.reproj_rms, e);
    SFM_CHECK_EQ_INT(r.points_recovered, N);
    SFM_CHECK(e <= tol_clean);
    SFM_CHECK(r.monotone);
}

SFM_TEST(factorize_complete_noise_free_is_exact)
{
    run(t, 0.0, 0.0, 1e-4);
}

SFM_TEST(factorize_complete_at_noise_floor)
{
    run(t, 0.5, 0.0, 0.5);
}

SFM_TEST(factorize_20_percent_missing_at_noise_floor)
{
    run(t, 0.5, 0.2, 0.6);
}

SFM_TEST(factorize_50_percent_missing_at_noise_floor)
{
    run(t, 0.5, 0.5, 0.7);
}

SFM_TEST(factorize_contract)
{
    scene(t, 0.3, 0.0);
    size_t need = sfm_factorize_workspace_size(M, N);
    double P[12 * M], X[4 * N];
    for (int k = 0; k < 12 * M; k++)
        P[k] = 7;
    SFM_CHECK_EQ_INT(sfm_factorize_workspace_size(1, N), 0);
    SFM_CHECK_EQ_INT(sfm_factorize_workspace_size(M, 7), 0);
    SFM_CHECK_EQ_INT(sfm_factorize_projective(M, N, NULL, NULL, P, X, NULL, ws, need), SFM_E_ARGUMENT);
    SFM_CHECK_EQ_INT(sfm_factorize_projective(1, N, obs, NULL, P, X, NULL, ws, need), SFM_E_ARGUMENT);
    SFM_CHECK_EQ_INT(sfm_factorize_projective(M, N, obs, NULL, P, X, NULL, ws, need - 1), SFM_E_WORKSPACE);
    sfm_factorize_options o;
    sfm_factorize_default_options(&o);
    o.tolerance = -1;
    SFM_CHECK_EQ_INT(sfm_factorize_projective(M, N, obs, &o, P, X, NULL, ws, need), SFM_E_ARGUMENT);
    obs[5] = HUGE_VAL;
    SFM_CHECK_EQ_INT(sfm_factorize_projective(M, N, obs, NULL, P, X, NULL, ws, need), SFM_E_NONFINITE);
    /* a view with every observation missing cannot be resectioned */
    scene(t, 0.3, 0.0);
    for (int j = 0; j < N; j++)
        obs[(3 * N + j) * 2] = obs[(3 * N + j) * 2 + 1] = (double)NAN;
    SFM_CHECK_EQ_INT(sfm_factorize_projective(M, N, obs, NULL, P, X, NULL, ws, need), SFM_E_SINGULAR);
    /* every track of view 4 at one pixel */
    scene(t, 0.3, 0.0);
    for (int j = 0; j < N; j++)
        obs[(4 * N + j) * 2] = 100, obs[(4 * N + j) * 2 + 1] = 50;
    SFM_CHECK(sfm_factorize_projective(M, N, obs, NULL, P, X, NULL, ws, need) == SFM_E_SINGULAR);
    for (int k = 0; k < 12 * M; k++)
        SFM_CHECK(P[k] == 7);
}
