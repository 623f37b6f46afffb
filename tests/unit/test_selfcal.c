/* Linear self-calibration by the absolute dual quadric: projective cameras
 * made from known metric ones by a random projective transform, the focal
 * length recovered, the metric cameras P_i H checked to be K [R | t], the
 * mirror resolved by cheirality, and critical motions refused. */
#include <math.h>
#include <string.h>

#include "sfm/sfm.h"
#include "sfm_test.h"

enum { MV = 5, NP = 40 };

static double Pm[MV][12], Pp[MV * 12], Xh[NP * 4];
static const double F = 800, W = 640, HH = 480;

/* motion: 0 general, 1 pure translation (parallel axes), 2 translation
 * along the optical axis */
static void scene(sfm_test_ctx *t, int m, int motion)
{
    const double K[9] = {F, 0, (W - 1) / 2, 0, F, (HH - 1) / 2, 0, 0, 1};
    for (int i = 0; i < m; i++) {
        double aa[3] = {0, 0, 0}, R[9], C[3];
        if (motion == 0) {
            aa[0] = sfm_test_normal(t, 0.15);
            aa[1] = sfm_test_normal(t, 0.3);
            aa[2] = sfm_test_normal(t, 0.15);
            C[0] = sfm_test_normal(t, 1);
            C[1] = sfm_test_normal(t, 1);
            C[2] = sfm_test_normal(t, 0.5);
        } else if (motion == 1) {
            C[0] = 0.8 * cos(2 * i);
            C[1] = 0.8 * sin(2 * i);
            C[2] = 0;
        } else {
            C[0] = C[1] = 0;
            C[2] = 0.7 * i;
        }
        if (i == 0)
            aa[0] = aa[1] = aa[2] = C[0] = C[1] = C[2] = 0;
        sfm_rot_from_axis_angle(aa, R);
        double Rt[12];
        for (int r = 0; r < 3; r++) {
            for (int c = 0; c < 3; c++)
                Rt[4 * r + c] = R[3 * r + c];
            Rt[4 * r + 3] = -(R[3 * r] * C[0] + R[3 * r + 1] * C[1] + R[3 * r + 2] * C[2]);
        }
        for (int r = 0; r < 3; r++)
            for (int c = 0; c < 4; c++)
                Pm[i][4 * r + c] = K[3 * r] * Rt[c] + K[3 * r + 1] * Rt[4 + c] + K[3 * r + 2] * Rt[8 + c];
    }
    /* a random projective frame: P = Pm G, X = G^{-1} Xm */
    double G[16], Gi[16];
    for (;;) {
        for (int k = 0; k < 16; k++)
            G[k] = (k % 5 == 0 ? 1.0 : 0.0) + sfm_test_normal(t, 0.4);
        double LU[16];
        int piv[4];
        memcpy(LU, G, sizeof LU);
        if (sfm_lu_factor(LU, 4, piv) < 0)
            continue;
        for (int k = 0; k < 16; k++)
            Gi[k] = k % 5 == 0;
        sfm_lu_solve(LU, piv, 4, Gi, 4);
        break;
    }
    for (int i = 0; i < m; i++)
        for (int r = 0; r < 3; r++)
            for (int c = 0; c < 4; c++) {
                double s = 0;
                for (int k = 0; k < 4; k++)
                    s += Pm[i][4 * r + k] * G[4 * k + c];
                Pp[12 * i + 4 * r + c] = s * (i % 2 ? -1.3 : 0.7);
            }
    for (int j = 0; j < NP; j++) {
        double Xm[4] = {sfm_test_uniform(t, -2, 2), sfm_test_uniform(t, -2, 2), sfm_test_uniform(t, 6, 10), 1};
        for (int r = 0; r < 4; r++) {
            double s = 0;
            for (int k = 0; k < 4; k++)
                s += Gi[4 * r + k] * Xm[k];
            Xh[4 * j + r] = s;
        }
    }
}

/* |M M^T / (M M^T)_22 - K K^T / (K K^T)_22| for M = (P H)[:, :3] */
static double metric_defect(const double P[12], const double H[16], const double K[9])
{
    double M[9], A[9], B[9];
    for (int r = 0; r < 3; r++)
        for (int c = 0; c < 3; c++) {
            double s = 0;
            for (int k = 0; k < 4; k++)
                s += P[4 * r + k] * H[4 * k + c];
            M[3 * r + c] = s;
        }
    for (int r = 0; r < 3; r++)
        for (int c = 0; c < 3; c++) {
            A[3 * r + c] = M[3 * r] * M[3 * c] + M[3 * r + 1] * M[3 * c + 1] + M[3 * r + 2] * M[3 * c + 2];
            B[3 * r + c] = K[3 * r] * K[3 * c] + K[3 * r + 1] * K[3 * c + 1] + K[3 * r + 2] * K[3 * c + 2];
        }
    double e = 0;
    for (int k = 0; k < 9; k++)
        e = fmax(e, fabs(A[k] / A[8] - B[k] / B[8]) / B[0] * B[8]);
    return e;
}

SFM_TEST(selfcal_linear_noise_free_focal_within_1_percent)
{
    const double wh[2 * MV] = {W, HH, W, HH, W, HH, W, HH, W, HH};
    for (int m = 3; m <= MV; m++)
        for (int trial = 0; trial < SFM_TEST_ITERS(20); trial++) {
            scene(t, m, 0);
            double K[9 * MV], H[16];
            sfm_selfcal_result r;
            int st = sfm_selfcal_linear(m, Pp, wh, NP, Xh, K, H, &r);
            SFM_CHECK_MSG(st == SFM_OK, "m %d trial %d status %d flags %d ratio %g", m, trial, st, r.flags, r.null_ratio);
            if (st != SFM_OK)
                continue;
            for (int i = 0; i < m; i++) {
                SFM_CHECK_MSG(fabs(K[9 * i] / F - 1) < 0.01, "m %d trial %d view %d f %g", m, trial, i, K[9 * i]);
                SFM_CHECK(metric_defect(&Pp[12 * i], H, &K[9 * i]) < 0.02);
            }
            SFM_CHECK(r.front_fraction > 0.999);
        }
}

SFM_TEST(selfcal_linear_refuses_critical_motions)
{
    const double wh[2 * MV] = {W, HH, W, HH, W, HH, W, HH, W, HH};
    for (int motion = 1; motion <= 2; motion++) {
        scene(t, MV, motion);
        double K[9 * MV], H[16];
        for (int k = 0; k < 16; k++)
            H[k] = 5;
        sfm_selfcal_result r;
        int st = sfm_selfcal_linear(MV, Pp, wh, NP, Xh, K, H, &r);
        SFM_TEST_LOG("motion %d: status %d flags %d null ratio %.3g", motion, st, r.flags, r.null_ratio);
        SFM_CHECK_EQ_INT(st, SFM_E_SINGULAR);
        SFM_CHECK(H[7] == 5);
    }
}

SFM_TEST(selfcal_linear_contract)
{
    const double wh[2 * MV] = {W, HH, W, HH, W, HH, W, HH, W, HH};
    scene(t, 3, 0);
    double K[9 * MV], H[16];
    SFM_CHECK_EQ_INT(sfm_selfcal_linear(2, Pp, wh, 0, NULL, K, H, NULL), SFM_E_ARGUMENT);
    SFM_CHECK_EQ_INT(sfm_selfcal_linear(3, NULL, wh, 0, NULL, K, H, NULL), SFM_E_ARGUMENT);
    SFM_CHECK_EQ_INT(sfm_selfcal_linear(3, Pp, wh, 5, NULL, K, H, NULL), SFM_E_ARGUMENT);
    double bad[6] = {W, HH, 0, HH, W, HH};
    SFM_CHECK_EQ_INT(sfm_selfcal_linear(3, Pp, bad, 0, NULL, K, H, NULL), SFM_E_ARGUMENT);
    Pp[3] = (double)NAN;
    SFM_CHECK_EQ_INT(sfm_selfcal_linear(3, Pp, wh, 0, NULL, K, H, NULL), SFM_E_NONFINITE);
}
