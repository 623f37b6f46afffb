/* Trifocal RANSAC on synthetic scenes with known cameras and outliers. */
#include <math.h>
#include <stdlib.h>
#include <string.h>

#include "sfm/sfm.h"
#include "sfm_test.h"

enum { N = 300 };

static void camera(sfm_test_ctx *t, double P[12])
{
    double R[9], C[3], K[9] = {600, 0, 320, 0, 600, 240, 0, 0, 1};
    /* small rotations and baselines: a robot's camera moving through a scene */
    double aa[3] = {sfm_test_normal(t, 0.1), sfm_test_normal(t, 0.1), sfm_test_normal(t, 0.1)};
    /* rotation from the unit quaternion (1, aa/2) / norm */
    double w = 1, x = aa[0] / 2, y = aa[1] / 2, z = aa[2] / 2, qn = sqrt(w * w + x * x + y * y + z * z);
    w /= qn; x /= qn; y /= qn; z /= qn;
    R[0] = 1 - 2 * (y * y + z * z); R[1] = 2 * (x * y - w * z);     R[2] = 2 * (x * z + w * y);
    R[3] = 2 * (x * y + w * z);     R[4] = 1 - 2 * (x * x + z * z); R[5] = 2 * (y * z - w * x);
    R[6] = 2 * (x * z - w * y);     R[7] = 2 * (y * z + w * x);     R[8] = 1 - 2 * (x * x + y * y);
    for (int k = 0; k < 3; k++)
        C[k] = sfm_test_normal(t, 0.5);
    for (int r = 0; r < 3; r++)
        for (int c = 0; c < 4; c++) {
            double s = 0;
            for (int k = 0; k < 3; k++) {
                double rt = c < 3 ? R[k * 3 + c] : -(R[k * 3] * C[0] + R[k * 3 + 1] * C[1] + R[k * 3 + 2] * C[2]);
                s += K[r * 3 + k] * rt;
            }
            P[r * 4 + c] = s;
        }
}

static int project(const double P[12], const double X[3], double x[2])
{
    double p[3];
    for (int r = 0; r < 3; r++)
        p[r] = P[r * 4] * X[0] + P[r * 4 + 1] * X[1] + P[r * 4 + 2] * X[2] + P[r * 4 + 3];
    if (!(p[2] > 1e-6))
        return 0;
    x[0] = p[0] / p[2];
    x[1] = p[1] / p[2];
    return x[0] > 0 && x[0] < 640 && x[1] > 0 && x[1] < 480;
}

typedef struct scene {
    double P[3][12];
    double x[3][2 * N];
    double clean[3][2 * N];
    int inlier[N];
} scene;

static void make_scene(sfm_test_ctx *t, scene *s, double outlier_ratio, double sigma)
{
    /* distinct centres (at least 0.3 apart at depths 5 to 10): two nearly
     * coincident ones leave the tensor undetermined, which the estimator
     * rightly reports as SFM_E_DEGENERATE; this test is about outliers */
    for (int again = 1; again;) {
        double C[3][3];
        for (int v = 0; v < 3; v++) {
            camera(t, s->P[v]);
            /* K^-1 P = [R | t], C = -R^T t (K = [600 0 320; 0 600 240; 0 0 1]) */
            double Rt[12];
            for (int c = 0; c < 4; c++) {
                Rt[8 + c] = s->P[v][8 + c];
                Rt[c] = (s->P[v][c] - 320 * Rt[8 + c]) / 600;
                Rt[4 + c] = (s->P[v][4 + c] - 240 * Rt[8 + c]) / 600;
            }
            for (int k = 0; k < 3; k++)
                C[v][k] = -(Rt[k] * Rt[3] + Rt[4 + k] * Rt[7] + Rt[8 + k] * Rt[11]);
        }
        again = 0;
        for (int a = 0; a < 3; a++)
            for (int b = a + 1; b < 3; b++)
                again |= hypot(hypot(C[a][0] - C[b][0], C[a][1] - C[b][1]), C[a][2] - C[b][2]) < 0.3;
    }
    int got = 0;
    while (got < N) {
        double X[3] = {sfm_test_uniform(t, -3, 3), sfm_test_uniform(t, -2, 2), sfm_test_uniform(t, 5, 10)};
        double y[3][2];
        if (!project(s->P[0], X, y[0]) || !project(s->P[1], X, y[1]) || !project(s->P[2], X, y[2]))
            continue;
        int out = sfm_test_uniform(t, 0, 1) < outlier_ratio;
        s->inlier[got] = !out;
        for (int v = 0; v < 3; v++) {
            s->clean[v][2 * got] = y[v][0];
            s->clean[v][2 * got + 1] = y[v][1];
            if (out && v == 2) { /* a wrong match in the third view */
                s->x[v][2 * got] = sfm_test_uniform(t, 0, 640);
                s->x[v][2 * got + 1] = sfm_test_uniform(t, 0, 480);
            } else {
                s->x[v][2 * got] = y[v][0] + sfm_test_normal(t, sigma);
                s->x[v][2 * got + 1] = y[v][1] + sfm_test_normal(t, sigma);
            }
        }
        got++;
    }
}

static unsigned char ws[4 << 20];
static scene sc;

static void run_case(sfm_test_ctx *t, double ratio)
{
    size_t need = sfm_ransac_trifocal_workspace_size(N);
    SFM_CHECK(need > 0 && need <= sizeof ws);
    make_scene(t, &sc, ratio, 0.5);
    sfm_ransac_options opt;
    sfm_ransac_default_options(&opt);
    opt.threshold = 2.0;
    double T[27], P[36];
    sfm_mat3 F21;
    uint8_t mask[N];
    sfm_ransac_stats st;
    int cnt = sfm_ransac_trifocal(sc.x[0], sc.x[1], sc.x[2], N, &opt, T, P, mask, &st, ws, need);
    SFM_CHECK(cnt >= 7);
    if (cnt < 7)
        return;
    int tp = 0, fp = 0, truth = 0;
    for (int i = 0; i < N; i++) {
        truth += sc.inlier[i];
        tp += mask[i] && sc.inlier[i];
        fp += mask[i] && !sc.inlier[i];
    }
    /* transfer of noise-free points through the estimated tensor */
    SFM_CHECK_EQ_INT(sfm_trifocal_fundamentals(T, &F21, NULL, NULL), SFM_OK);
    double err = 0;
    int m = 0;
    for (int i = 0; i < N; i++) {
        double y[2];
        if (sfm_trifocal_transfer(T, &F21, &sc.clean[0][2 * i], &sc.clean[1][2 * i], y) != SFM_OK)
            continue;
        err += hypot(y[0] - sc.clean[2][2 * i], y[1] - sc.clean[2][2 * i + 1]);
        m++;
    }
    err /= m;
    SFM_TEST_LOG("%.0f%% outliers: %d iterations, %d inliers (%d of %d true found, %d false), mean transfer error %.3f px",
                 ratio * 100, st.iterations, cnt, tp, truth, fp, err);
    SFM_CHECK(tp >= truth * 95 / 100);
    SFM_CHECK(fp <= (N - truth) / 20 + 2);
    /* 0.5 px of noise on 117 inliers at 60 % outliers: the maximum-likelihood
     * tensor transfers the noise-free points with a mean error of about that
     * (0.54 px measured with the camera centres at least 0.3 apart; the test
     * above proves the estimate reaches the likelihood of the true cameras) */
    SFM_CHECK(err < (ratio > 0.5 ? 0.65 : 0.5));

    /* the same seed gives the same mask, bit for bit */
    uint8_t mask2[N];
    double T2[27];
    SFM_CHECK_EQ_INT(sfm_ransac_trifocal(sc.x[0], sc.x[1], sc.x[2], N, &opt, T2, NULL, mask2, NULL, ws, need), cnt);
    SFM_CHECK(memcmp(mask, mask2, N) == 0 && memcmp(T, T2, sizeof T) == 0);
}

SFM_TEST(trifocal_ransac_30_percent_outliers)
{
    run_case(t, 0.3);
}

SFM_TEST(trifocal_ransac_60_percent_outliers)
{
    run_case(t, 0.6);
}

SFM_TEST(trifocal_ransac_contracts)
{
    double x[14] = {0}, T[27];
    SFM_CHECK_EQ_INT(sfm_ransac_trifocal(NULL, x, x, 7, NULL, T, NULL, NULL, NULL, ws, sizeof ws), SFM_E_ARGUMENT);
    SFM_CHECK_EQ_INT(sfm_ransac_trifocal(x, x, x, 6, NULL, T, NULL, NULL, NULL, ws, sizeof ws), SFM_E_ARGUMENT);
    SFM_CHECK_EQ_INT(sfm_ransac_trifocal_workspace_size(6), 0);
    make_scene(t, &sc, 0.0, 0.5);
    sfm_test_fill_canary(T, sizeof T);
    size_t need = sfm_ransac_trifocal_workspace_size(N);
    SFM_CHECK_EQ_INT(sfm_ransac_trifocal(sc.x[0], sc.x[1], sc.x[2], N, NULL, T, NULL, NULL, NULL, ws, need - 1),
                     SFM_E_WORKSPACE);
    SFM_CHECK(sfm_test_canary_intact(T, sizeof T));
    sc.x[1][7] = NAN;
    SFM_CHECK_EQ_INT(sfm_ransac_trifocal(sc.x[0], sc.x[1], sc.x[2], N, NULL, T, NULL, NULL, NULL, ws, need),
                     SFM_E_NONFINITE);
    SFM_CHECK(sfm_test_canary_intact(T, sizeof T));
}

/* With no outliers the gold-standard step reaches the maximum-likelihood
 * cameras: their reprojection cost is at most that of the true cameras. */
SFM_TEST(trifocal_ransac_reaches_maximum_likelihood)
{
    make_scene(t, &sc, 0.0, 0.5);
    size_t need = sfm_ransac_trifocal_workspace_size(N);
    double T[27], P[36];
    sfm_ransac_options opt;
    sfm_ransac_default_options(&opt);
    opt.threshold = 3.0;
    int cnt = sfm_ransac_trifocal(sc.x[0], sc.x[1], sc.x[2], N, &opt, T, P, NULL, NULL, ws, need);
    SFM_CHECK_EQ_INT(cnt, N);
    double ce = 0, cg = 0;
    for (int i = 0; i < N; i++) {
        double e, g;
        SFM_CHECK_EQ_INT(sfm_trifocal_point_error(P, &P[12], &P[24], &sc.x[0][2 * i], &sc.x[1][2 * i],
                                                  &sc.x[2][2 * i], &e, NULL), SFM_OK);
        SFM_CHECK_EQ_INT(sfm_trifocal_point_error(sc.P[0], sc.P[1], sc.P[2], &sc.x[0][2 * i], &sc.x[1][2 * i],
                                                  &sc.x[2][2 * i], &g, NULL), SFM_OK);
        ce += e;
        cg += g;
    }
    SFM_TEST_LOG("reprojection cost: estimated cameras %.4f, true cameras %.4f (%d points, 0.5 px noise)", ce, cg, N);
    SFM_CHECK(ce <= cg * 1.0001);
}
