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
            SFM_CHECK_MSG(st == SFM_OK, "m %d trial %d status %d flags %d null ratio %g weak ratio %g", m, trial, st, r.flags, r.null_ratio, r.weak_ratio);
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

/* Orbital motion from noisy tracks: 8 views on a circle about the vertical
 * axis through a cloud, optical axes through its centre (Sturm 1997; Kahl,
 * Triggs, Astrom 2000: critical for a focal length per view), and general
 * motion about the same cloud; 0.5 px noise, projective cameras by
 * factorization. The turntable was answered with f = 556-560 px for 800
 * (the weak prior's (w + h) / 2 = 560); it must be refused as ambiguous. */
enum { MO = 8, NO = 60 };
static double mo_x[MO * NO * 2], mo_P[MO * 12], mo_X[NO * 4];
static unsigned char mo_ws[288 << 10];

static int orbit_scene(sfm_test_ctx *t, int turntable, double sigma)
{
    const double K[9] = {F, 0, (W - 1) / 2, 0, F, (HH - 1) / 2, 0, 0, 1};
    double Xw[NO * 3];
    for (int j = 0; j < NO; j++) {
        Xw[3 * j] = sfm_test_uniform(t, -1.5, 1.5);
        Xw[3 * j + 1] = sfm_test_uniform(t, -1.2, 1.2);
        Xw[3 * j + 2] = sfm_test_uniform(t, -1.5, 1.5);
    }
    for (int i = 0; i < MO; i++) {
        /* x_cam = R X + t: the cloud's centre on every optical axis when
         * t = (0, 0, 6) and R turns about the vertical axis */
        double aa[3] = {0, 0, 0}, R[9], tr[3] = {0, 0, 6};
        if (turntable) {
            aa[1] = 1.2 * i / (MO - 1); /* 69 deg in all */
        } else {
            for (int k = 0; k < 3; k++) {
                aa[k] = sfm_test_normal(t, 0.25);
                tr[k] += sfm_test_normal(t, 0.5);
            }
        }
        sfm_rot_from_axis_angle(aa, R);
        for (int j = 0; j < NO; j++) {
            double y[3];
            for (int r = 0; r < 3; r++) {
                double c = tr[r];
                for (int k = 0; k < 3; k++)
                    c += R[3 * r + k] * Xw[3 * j + k];
                y[r] = c;
            }
            double u = K[0] * y[0] / y[2] + K[2], v = K[4] * y[1] / y[2] + K[5];
            mo_x[(i * NO + j) * 2] = u + sfm_test_normal(t, sigma);
            mo_x[(i * NO + j) * 2 + 1] = v + sfm_test_normal(t, sigma);
        }
    }
    if (sfm_factorize_workspace_size(MO, NO) > sizeof mo_ws)
        return SFM_E_WORKSPACE;
    return sfm_factorize_projective(MO, NO, mo_x, NULL, mo_P, mo_X, NULL, mo_ws, sizeof mo_ws);
}

SFM_TEST(selfcal_linear_refuses_turntable_answers_general_motion)
{
    double wh[2 * MO];
    for (int i = 0; i < MO; i++)
        wh[2 * i] = W, wh[2 * i + 1] = HH;
    for (int trial = 0; trial < SFM_TEST_ITERS(10); trial++) {
        for (int turntable = 0; turntable < 2; turntable++) {
            int st = orbit_scene(t, turntable, 0.5);
            SFM_CHECK_EQ_INT(st, SFM_OK);
            if (st != SFM_OK)
                continue;
            double K[9 * MO], H[16];
            for (int k = 0; k < 16; k++)
                H[k] = 5;
            sfm_selfcal_result r;
            st = sfm_selfcal_linear(MO, mo_P, wh, NO, mo_X, K, H, &r);
            SFM_TEST_LOG("trial %d %s: status %d flags %d null ratio %.3g weak ratio %.3g f1 %.1f", trial,
                         turntable ? "turntable" : "general", st, r.flags, r.null_ratio, r.weak_ratio,
                         st == SFM_OK ? K[0] : r.focal[0]);
            if (turntable) {
                SFM_CHECK_EQ_INT(st, SFM_E_SINGULAR);
                SFM_CHECK(r.flags & SFM_SELFCAL_FLAG_AMBIGUOUS);
                SFM_CHECK(H[7] == 5);
            } else {
                SFM_CHECK_EQ_INT(st, SFM_OK);
                if (st != SFM_OK)
                    continue;
                /* 0.5 px, 60 points in 8 views: measured within 1.7 % */
                for (int i = 0; i < MO; i++)
                    SFM_CHECK_MSG(fabs(K[9 * i] / F - 1) < 0.03, "view %d f %g", i, K[9 * i]);
            }
        }
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

/* The focal search (sfm_selfcal_solve): observations of the scene's points
 * with noise sigma; the answer against the true focal length and poses. */
static int obs_cam[MV * NP], obs_pt[MV * NP];
static double obs_xy[2 * MV * NP];
static unsigned char sws[192 << 10];

static int observe(sfm_test_ctx *t, int m, double sigma)
{
    int k = 0;
    for (int i = 0; i < m; i++)
        for (int j = 0; j < NP; j++) {
            double y[3];
            for (int r = 0; r < 3; r++)
                y[r] = Pp[12 * i + 4 * r] * Xh[4 * j] + Pp[12 * i + 4 * r + 1] * Xh[4 * j + 1] +
                       Pp[12 * i + 4 * r + 2] * Xh[4 * j + 2] + Pp[12 * i + 4 * r + 3] * Xh[4 * j + 3];
            obs_cam[k] = i;
            obs_pt[k] = j;
            obs_xy[2 * k] = y[0] / y[2] + sfm_test_normal(t, sigma);
            obs_xy[2 * k + 1] = y[1] / y[2] + sfm_test_normal(t, sigma);
            k++;
        }
    return k;
}

SFM_TEST(selfcal_solve_focal_and_poses_against_truth)
{
    const double wh[2 * MV] = {W, HH, W, HH, W, HH, W, HH, W, HH};
    for (int trial = 0; trial < SFM_TEST_ITERS(4); trial++) {
        scene(t, MV, 0);
        int no = observe(t, MV, 0.3);
        double K[9 * MV], H[16];
        sfm_pose poses[MV];
        sfm_selfcal_report rep;
        SFM_CHECK(sfm_selfcal_workspace_size(MV, NP, no) <= sizeof sws);
        int st = sfm_selfcal_solve(MV, Pp, wh, NP, Xh, no, obs_cam, obs_pt, obs_xy, NULL, K, H, poses, NULL,
                                   &rep, sws, sizeof sws);
        SFM_CHECK_MSG(st == SFM_OK, "trial %d status %d path %d f %g rise %g", trial, st, rep.path, rep.focal,
                      rep.profile_rise);
        if (st != SFM_OK)
            continue;
        SFM_TEST_LOG("trial %d: path %d linear %d f %.2f (sweep %.2f) sigma %.4f rise %.0f rms %.3f", trial,
                     rep.path, rep.linear_status, rep.focal, rep.focal_sweep, rep.focal_sigma, rep.profile_rise,
                     rep.rms);
        /* 0.3 px on 40 points in 5 views: measured within 0.3 % */
        SFM_CHECK_MSG(fabs(K[0] / F - 1) < 0.01, "f %g", K[0]);
        SFM_CHECK(rep.path == SFM_SELFCAL_PATH_LINEAR || rep.path == SFM_SELFCAL_PATH_SWEEP);
        SFM_CHECK(rep.rms < 0.6 && rep.front_fraction == 1.0);
        /* relative rotations R_i R_1^T against the truth's (K^{-1} Pm_i) */
        double R1[9];
        for (int r = 0; r < 3; r++)
            for (int c = 0; c < 3; c++)
                R1[3 * r + c] = (Pm[0][4 * r + c] - (r < 2 ? ((r ? HH : W) - 1) / 2 * Pm[0][8 + c] : 0)) /
                                (r < 2 ? F : 1);
        for (int i = 1; i < MV; i++) {
            double Ri[9], A[9], B[9], ang;
            for (int r = 0; r < 3; r++)
                for (int c = 0; c < 3; c++)
                    Ri[3 * r + c] = (Pm[i][4 * r + c] - (r < 2 ? ((r ? HH : W) - 1) / 2 * Pm[i][8 + c] : 0)) /
                                    (r < 2 ? F : 1);
            for (int r = 0; r < 3; r++)
                for (int c = 0; c < 3; c++) {
                    A[3 * r + c] = Ri[3 * r] * R1[3 * c] + Ri[3 * r + 1] * R1[3 * c + 1] + Ri[3 * r + 2] * R1[3 * c + 2];
                    B[3 * r + c] = poses[i].R[3 * r + c];
                }
            sfm_rot_angle_between(A, B, &ang);
            SFM_CHECK_MSG(ang < 0.01, "view %d rotation error %g rad", i, ang);
        }
    }
}

SFM_TEST(selfcal_solve_refuses_pure_translation)
{
    const double wh[2 * MV] = {W, HH, W, HH, W, HH, W, HH, W, HH};
    scene(t, MV, 1);
    int no = observe(t, MV, 0.3);
    double K[9 * MV], H[16];
    for (int k = 0; k < 9 * MV; k++)
        K[k] = 5;
    sfm_selfcal_report rep;
    int st = sfm_selfcal_solve(MV, Pp, wh, NP, Xh, no, obs_cam, obs_pt, obs_xy, NULL, K, H, NULL, NULL, &rep, sws,
                               sizeof sws);
    SFM_TEST_LOG("pure translation: status %d, far rise %.3g noise variances, sigma f %.3g", st, rep.profile_rise,
                 rep.focal_sigma);
    SFM_CHECK_EQ_INT(st, SFM_E_SINGULAR);
    SFM_CHECK(K[0] == 5 && K[9 * MV - 1] == 5);
}

SFM_TEST(selfcal_solve_contract)
{
    const double wh[2 * MV] = {W, HH, W, HH, W, HH, W, HH, W, HH};
    scene(t, MV, 0);
    int no = observe(t, MV, 0.0);
    double K[9 * MV], H[16];
    for (int k = 0; k < 9 * MV; k++)
        K[k] = 5;
    sfm_selfcal_report rep;
    size_t need = sfm_selfcal_workspace_size(MV, NP, no);
    SFM_CHECK(need > 0 && need <= sizeof sws);
    SFM_CHECK(sfm_selfcal_workspace_size(2, NP, no) == 0 && sfm_selfcal_workspace_size(MV, 0, no) == 0);
    SFM_CHECK_EQ_INT(sfm_selfcal_solve(MV, NULL, wh, NP, Xh, no, obs_cam, obs_pt, obs_xy, NULL, K, H, NULL, NULL,
                                       &rep, sws, need), SFM_E_ARGUMENT);
    SFM_CHECK_EQ_INT(sfm_selfcal_solve(2, Pp, wh, NP, Xh, no, obs_cam, obs_pt, obs_xy, NULL, K, H, NULL, NULL, &rep,
                                       sws, need), SFM_E_ARGUMENT);
    sfm_selfcal_options o;
    sfm_selfcal_default_options(&o);
    o.sweep_steps = 2;
    SFM_CHECK_EQ_INT(sfm_selfcal_solve(MV, Pp, wh, NP, Xh, no, obs_cam, obs_pt, obs_xy, &o, K, H, NULL, NULL, &rep,
                                       sws, need), SFM_E_ARGUMENT);
    obs_pt[3] = NP;
    SFM_CHECK_EQ_INT(sfm_selfcal_solve(MV, Pp, wh, NP, Xh, no, obs_cam, obs_pt, obs_xy, NULL, K, H, NULL, NULL,
                                       &rep, sws, need), SFM_E_ARGUMENT);
    obs_pt[3] = 3;
    SFM_CHECK_EQ_INT(sfm_selfcal_solve(MV, Pp, wh, NP, Xh, no, obs_cam, obs_pt, obs_xy, NULL, K, H, NULL, NULL,
                                       &rep, sws, need - 1), SFM_E_WORKSPACE);
    obs_xy[5] = (double)NAN;
    SFM_CHECK_EQ_INT(sfm_selfcal_solve(MV, Pp, wh, NP, Xh, no, obs_cam, obs_pt, obs_xy, NULL, K, H, NULL, NULL,
                                       &rep, sws, need), SFM_E_NONFINITE);
    SFM_CHECK(K[0] == 5 && K[9 * MV - 1] == 5);
}
