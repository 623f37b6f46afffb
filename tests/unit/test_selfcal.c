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

/* Hostile inputs of sfm_selfcal_solve. Each call gets outputs filled with
 * canaries: on an argument, non-finite or workspace status nothing at all
 * is written (report included); on SFM_E_SINGULAR or SFM_E_NO_CONVERGENCE
 * only the report; on SFM_OK the focal lengths are positive and finite. */
static double hk_K[9 * SFM_SELFCAL_MAX_VIEWS], hk_H[16], hk_Xm[3 * NP];
static sfm_pose hk_poses[SFM_SELFCAL_MAX_VIEWS];
static sfm_selfcal_report hk_rep;

static int hostile_call(sfm_test_ctx *t, const char *what, int m, const double *P, const double *wh, int n,
                        const double *X, int no, const int *oc, const int *op, const double *oxy,
                        const sfm_selfcal_options *o, void *ws, size_t ws_size)
{
    sfm_test_fill_canary(hk_K, sizeof hk_K);
    sfm_test_fill_canary(hk_H, sizeof hk_H);
    sfm_test_fill_canary(hk_Xm, sizeof hk_Xm);
    sfm_test_fill_canary(hk_poses, sizeof hk_poses);
    sfm_test_fill_canary(&hk_rep, sizeof hk_rep);
    int st = sfm_selfcal_solve(m, P, wh, n, X, no, oc, op, oxy, o, hk_K, hk_H, hk_poses, hk_Xm, &hk_rep, ws,
                               ws_size);
    int outs = sfm_test_canary_intact(hk_K, sizeof hk_K) && sfm_test_canary_intact(hk_H, sizeof hk_H) &&
               sfm_test_canary_intact(hk_Xm, sizeof hk_Xm) && sfm_test_canary_intact(hk_poses, sizeof hk_poses);
    int rep = sfm_test_canary_intact(&hk_rep, sizeof hk_rep);
    if (st == SFM_OK) {
        int good = !outs && !rep;
        for (int i = 0; i < m; i++)
            good = good && isfinite(hk_K[9 * i]) && hk_K[9 * i] > 0 && hk_K[9 * i + 8] == 1;
        for (int k = 0; k < 16; k++)
            good = good && isfinite(hk_H[k]);
        SFM_CHECK_MSG(good, "%s: SFM_OK with an output unwritten or not finite", what);
    } else if (st == SFM_E_SINGULAR || st == SFM_E_NO_CONVERGENCE) {
        SFM_CHECK_MSG(outs && !rep, "%s: status %d wrote an output or no report", what, st);
    } else {
        SFM_CHECK_MSG(st == SFM_E_ARGUMENT || st == SFM_E_NONFINITE || st == SFM_E_WORKSPACE,
                      "%s: unlisted status %d", what, st);
        SFM_CHECK_MSG(outs && rep, "%s: status %d wrote an output", what, st);
    }
    return st;
}

SFM_TEST(selfcal_solve_hostile_arguments)
{
    double wh[2 * MV];
    for (int i = 0; i < MV; i++)
        wh[2 * i] = W, wh[2 * i + 1] = HH;
    scene(t, MV, 0);
    const int no = observe(t, MV, 0.2);
    const size_t need = sfm_selfcal_workspace_size(MV, NP, no);
    SFM_CHECK(need > 0 && need <= sizeof sws);
    int tried = 0;
#define HOSTILE(expect, ...)                                                                                  \
    do {                                                                                                      \
        tried++;                                                                                              \
        SFM_CHECK_EQ_INT(hostile_call(t, #__VA_ARGS__, __VA_ARGS__), expect);                                 \
    } while (0)
    /* every required pointer; poses and Xm may be NULL (see below) */
    HOSTILE(SFM_E_ARGUMENT, MV, NULL, wh, NP, Xh, no, obs_cam, obs_pt, obs_xy, NULL, sws, need);
    HOSTILE(SFM_E_ARGUMENT, MV, Pp, NULL, NP, Xh, no, obs_cam, obs_pt, obs_xy, NULL, sws, need);
    HOSTILE(SFM_E_ARGUMENT, MV, Pp, wh, NP, NULL, no, obs_cam, obs_pt, obs_xy, NULL, sws, need);
    HOSTILE(SFM_E_ARGUMENT, MV, Pp, wh, NP, Xh, no, NULL, obs_pt, obs_xy, NULL, sws, need);
    HOSTILE(SFM_E_ARGUMENT, MV, Pp, wh, NP, Xh, no, obs_cam, NULL, obs_xy, NULL, sws, need);
    HOSTILE(SFM_E_ARGUMENT, MV, Pp, wh, NP, Xh, no, obs_cam, obs_pt, NULL, NULL, sws, need);
    HOSTILE(SFM_E_WORKSPACE, MV, Pp, wh, NP, Xh, no, obs_cam, obs_pt, obs_xy, NULL, NULL, need);
    HOSTILE(SFM_E_WORKSPACE, MV, Pp, wh, NP, Xh, no, obs_cam, obs_pt, obs_xy, NULL, sws, need - 1);
    HOSTILE(SFM_E_WORKSPACE, MV, Pp, wh, NP, Xh, no, obs_cam, obs_pt, obs_xy, NULL, sws, 0);
    {
        sfm_selfcal_report r;
        double K[9 * MV], H[16];
        SFM_CHECK_EQ_INT(sfm_selfcal_solve(MV, Pp, wh, NP, Xh, no, obs_cam, obs_pt, obs_xy, NULL, NULL, H, NULL,
                                           NULL, &r, sws, need), SFM_E_ARGUMENT);
        SFM_CHECK_EQ_INT(sfm_selfcal_solve(MV, Pp, wh, NP, Xh, no, obs_cam, obs_pt, obs_xy, NULL, K, NULL, NULL,
                                           NULL, &r, sws, need), SFM_E_ARGUMENT);
        SFM_CHECK_EQ_INT(sfm_selfcal_solve(MV, Pp, wh, NP, Xh, no, obs_cam, obs_pt, obs_xy, NULL, K, H, NULL,
                                           NULL, NULL, sws, need), SFM_E_ARGUMENT);
        tried += 3;
    }
    /* counts: views, points, observations */
    const int bad_m[] = {-1, 0, 1, 2, SFM_SELFCAL_MAX_VIEWS + 1, 1 << 30, -2147483647 - 1};
    for (size_t k = 0; k < sizeof bad_m / sizeof bad_m[0]; k++)
        HOSTILE(SFM_E_ARGUMENT, bad_m[k], Pp, wh, NP, Xh, no, obs_cam, obs_pt, obs_xy, NULL, sws, sizeof sws);
    const int bad_n[] = {-1, 0, -2147483647 - 1};
    for (size_t k = 0; k < sizeof bad_n / sizeof bad_n[0]; k++) {
        HOSTILE(SFM_E_ARGUMENT, MV, Pp, wh, bad_n[k], Xh, no, obs_cam, obs_pt, obs_xy, NULL, sws, sizeof sws);
        HOSTILE(SFM_E_ARGUMENT, MV, Pp, wh, NP, Xh, bad_n[k], obs_cam, obs_pt, obs_xy, NULL, sws, sizeof sws);
    }
    SFM_CHECK(sfm_selfcal_workspace_size(MV, NP, 0) == 0 && sfm_selfcal_workspace_size(MV, -1, no) == 0 &&
              sfm_selfcal_workspace_size(SFM_SELFCAL_MAX_VIEWS + 1, NP, no) == 0 &&
              sfm_selfcal_workspace_size(MV, 1 << 30, 1 << 30) == 0);
    /* fewer points than the observations reference */
    HOSTILE(SFM_E_ARGUMENT, MV, Pp, wh, NP - 1, Xh, no, obs_cam, obs_pt, obs_xy, NULL, sws, sizeof sws);
    /* fewer views than the observations reference */
    HOSTILE(SFM_E_ARGUMENT, MV - 1, Pp, wh, NP, Xh, no, obs_cam, obs_pt, obs_xy, NULL, sws, sizeof sws);
    /* indices out of range, either end */
    const int bad_idx[4] = {-1, MV, -2147483647 - 1, 2147483647};
    for (int k = 0; k < 4; k++) {
        int keep = obs_cam[7];
        obs_cam[7] = bad_idx[k];
        HOSTILE(SFM_E_ARGUMENT, MV, Pp, wh, NP, Xh, no, obs_cam, obs_pt, obs_xy, NULL, sws, need);
        obs_cam[7] = keep;
        keep = obs_pt[no - 1];
        obs_pt[no - 1] = k == 1 ? NP : bad_idx[k];
        HOSTILE(SFM_E_ARGUMENT, MV, Pp, wh, NP, Xh, no, obs_cam, obs_pt, obs_xy, NULL, sws, need);
        obs_pt[no - 1] = keep;
    }
    /* NaN and infinities in each array */
    const double bad_v[3] = {(double)NAN, (double)INFINITY, -(double)INFINITY};
    for (int k = 0; k < 3; k++) {
        double keep = Pp[12 * MV - 1];
        Pp[12 * MV - 1] = bad_v[k];
        HOSTILE(SFM_E_NONFINITE, MV, Pp, wh, NP, Xh, no, obs_cam, obs_pt, obs_xy, NULL, sws, need);
        Pp[12 * MV - 1] = keep;
        keep = Xh[4 * NP - 1];
        Xh[4 * NP - 1] = bad_v[k];
        HOSTILE(SFM_E_NONFINITE, MV, Pp, wh, NP, Xh, no, obs_cam, obs_pt, obs_xy, NULL, sws, need);
        Xh[4 * NP - 1] = keep;
        keep = obs_xy[2 * no - 1];
        obs_xy[2 * no - 1] = bad_v[k];
        HOSTILE(SFM_E_NONFINITE, MV, Pp, wh, NP, Xh, no, obs_cam, obs_pt, obs_xy, NULL, sws, need);
        obs_xy[2 * no - 1] = keep;
        keep = wh[2 * MV - 1];
        wh[2 * MV - 1] = bad_v[k];
        tried++;
        int st = hostile_call(t, "wh non-finite", MV, Pp, wh, NP, Xh, no, obs_cam, obs_pt, obs_xy, NULL, sws, need);
        SFM_CHECK_MSG(st == SFM_E_NONFINITE || st == SFM_E_ARGUMENT, "wh %g: status %d", wh[2 * MV - 1], st);
        wh[2 * MV - 1] = keep;
    }
    /* image sizes of zero, negative, below a pixel */
    const double bad_wh[3] = {0.0, -640.0, -0.0};
    for (int k = 0; k < 3; k++) {
        double keep = wh[2];
        wh[2] = bad_wh[k];
        HOSTILE(SFM_E_ARGUMENT, MV, Pp, wh, NP, Xh, no, obs_cam, obs_pt, obs_xy, NULL, sws, need);
        wh[2] = keep;
    }
    /* every option out of its range, NaN in each real one */
    for (int f = 0; f < 24; f++) {
        sfm_selfcal_options o;
        sfm_selfcal_default_options(&o);
        switch (f) {
        case 0: o.sweep = 2; break;
        case 1: o.sweep = -1; break;
        case 2: o.sweep_steps = 2; break;
        case 3: o.sweep_steps = SFM_SELFCAL_MAX_SWEEP + 1; break;
        case 4: o.focal_min = 0; break;
        case 5: o.focal_min = (double)NAN; break;
        case 6: o.focal_max = o.focal_min; break;
        case 7: o.focal_max = (double)INFINITY; break;
        case 8: o.focal_max = (double)NAN; break;
        case 9: o.per_view_focal = 2; break;
        case 10: o.principal = 3; break;
        case 11: o.principal = -1; break;
        case 12: o.loss_scale = 0; break;
        case 13: o.loss_scale = (double)NAN; break;
        case 14: o.max_rms = 0; break;
        case 15: o.max_rms = (double)NAN; break;
        case 16: o.min_front = 1.5; break;
        case 17: o.min_front = (double)NAN; break;
        case 18: o.min_profile = -1; break;
        case 19: o.min_profile = (double)NAN; break;
        case 20: o.max_focal_sigma = 0; break;
        case 21: o.max_focal_sigma = (double)NAN; break;
        case 22: o.max_iterations = 0; break;
        default: o.loss_scale = (double)INFINITY; break;
        }
        SFM_CHECK_MSG(hostile_call(t, "option", MV, Pp, wh, NP, Xh, no, obs_cam, obs_pt, obs_xy, &o, sws, need) ==
                          SFM_E_ARGUMENT, "option case %d accepted", f);
        tried++;
    }
    /* SHARED principal point with views of two sizes */
    {
        sfm_selfcal_options o;
        sfm_selfcal_default_options(&o);
        o.principal = SFM_SELFCAL_PRINCIPAL_SHARED;
        wh[4] = W + 2;
        HOSTILE(SFM_E_ARGUMENT, MV, Pp, wh, NP, Xh, no, obs_cam, obs_pt, obs_xy, &o, sws, need);
        wh[4] = W;
    }
    /* poses and Xm NULL: the same answer */
    {
        double K1[9 * MV], H1[16], K2[9 * MV], H2[16];
        sfm_selfcal_report r1, r2;
        int s1 = sfm_selfcal_solve(MV, Pp, wh, NP, Xh, no, obs_cam, obs_pt, obs_xy, NULL, K1, H1, NULL, NULL, &r1,
                                   sws, need);
        int s2 = sfm_selfcal_solve(MV, Pp, wh, NP, Xh, no, obs_cam, obs_pt, obs_xy, NULL, K2, H2, hk_poses, hk_Xm,
                                   &r2, sws, need);
        SFM_CHECK_EQ_INT(s1, SFM_OK);
        SFM_CHECK(s1 == s2 && memcmp(K1, K2, sizeof K1) == 0 && memcmp(H1, H2, sizeof H1) == 0);
        SFM_CHECK_MSG(fabs(K1[0] / F - 1) < 0.01, "f %g", K1[0]);
        tried += 2;
    }
#undef HOSTILE
    SFM_TEST_LOG("%d hostile argument sets", tried);
}

/* Degenerate geometry and odd but valid inputs of sfm_selfcal_solve: a
 * status the header lists, outputs only on SFM_OK, and an SFM_OK answer is
 * the truth's (no silent wrong focal length). */
SFM_TEST(selfcal_solve_hostile_geometry)
{
    static double P2[12 * MV], X2[4 * NP], xy2[4 * MV * NP];
    static unsigned char big[384 << 10];
    static int oc2[2 * MV * NP], op2[2 * MV * NP];
    double wh[2 * MV];
    for (int i = 0; i < MV; i++)
        wh[2 * i] = W, wh[2 * i + 1] = HH;
    scene(t, MV, 0);
    const int no = observe(t, MV, 0.2);
    int tried = 0, st;
#define GEOM(what, ...)                                                                                       \
    do {                                                                                                      \
        tried++;                                                                                              \
        st = hostile_call(t, what, __VA_ARGS__);                                                              \
        SFM_TEST_LOG("%s: status %d f %.6g sigma %.3g", what, st, st == SFM_OK ? hk_K[0] : 0.0,               \
                     st == SFM_OK ? hk_rep.focal_sigma : 0.0);                                                \
    } while (0)
#define TRUTH_OR_REFUSED(what)                                                                                \
    SFM_CHECK_MSG(st == SFM_E_SINGULAR || st == SFM_E_NO_CONVERGENCE ||                                       \
                      (st == SFM_OK && fabs(hk_K[0] / F - 1) < 4 * hk_rep.focal_sigma),                   \
                  "%s: status %d f %g", what, st, hk_K[0])
#define REFUSED(what)                                                                                         \
    SFM_CHECK_MSG(st == SFM_E_SINGULAR || st == SFM_E_NO_CONVERGENCE, "%s: status %d f %g", what, st,          \
                  st == SFM_OK ? hk_K[0] : 0.0)

    /* each camera and each point rescaled (negative included): projective
     * quantities, the same answer */
    memcpy(P2, Pp, sizeof(double) * 12 * MV);
    memcpy(X2, Xh, sizeof(double) * 4 * NP);
    const double sc[5] = {1e-200, -3e7, 0.5, -1, 1e250};
    for (int i = 0; i < MV; i++)
        for (int k = 0; k < 12; k++)
            P2[12 * i + k] *= sc[i];
    for (int j = 0; j < NP; j++)
        for (int k = 0; k < 4; k++)
            X2[4 * j + k] *= j % 3 == 0 ? -1.0 : (j % 3 == 1 ? 1e-12 : 1e12);
    GEOM("rescaled P and X", MV, P2, wh, NP, X2, no, obs_cam, obs_pt, obs_xy, NULL, sws, sizeof sws);
    SFM_CHECK_MSG(st == SFM_OK && fabs(hk_K[0] / F - 1) < 0.01, "rescaled: status %d f %g", st, hk_K[0]);

    /* one camera zero, or of rank 2 (its third row a copy of the first),
     * first or later; and every camera scaled by 1e150, 1e-150, 1e-15 and
     * 1e180 (1e-15 and below were refused, 1e180 SFM_E_NONFINITE from the
     * linear method: squared sums under- and overflowed) */
    const double big_small[5] = {1e150, 1e-150, 1e-15, 1e180, 1e-318 /* subnormal entries, below 2^-1024 */};
    for (int c = 0; c < 9; c++) {
        memcpy(P2, Pp, sizeof(double) * 12 * MV);
        const int v = c % 2 ? 2 : 0;
        if (c < 2)
            memset(&P2[12 * v], 0, 12 * sizeof(double));
        else if (c < 4)
            memcpy(&P2[12 * v + 8], &P2[12 * v], 4 * sizeof(double));
        else
            for (int k = 0; k < 12 * MV; k++)
                P2[k] *= big_small[c - 4];
        GEOM("degenerate or extreme camera", MV, P2, wh, NP, Xh, no, obs_cam, obs_pt, obs_xy, NULL, sws,
             sizeof sws);
        if (c < 4) {
            REFUSED("degenerate camera");
            continue;
        }
        if (c == 8) {
            /* about 30 significant bits left: the truth or refused, and no hang
             * (2^1046 was one factor: infinite, then halved forever) */
            TRUTH_OR_REFUSED("subnormal cameras");
            continue;
        }
        SFM_CHECK_MSG(st == SFM_OK && fabs(hk_K[0] / F - 1) < 4 * hk_rep.focal_sigma, "scale %g: status %d f %g",
                      big_small[c - 4], st, hk_K[0]);
        /* the linear method alone: the same focal lengths as unscaled */
        double K1[9 * MV], K2[9 * MV], H1[16], H2[16];
        int s1 = sfm_selfcal_linear(MV, Pp, wh, NP, Xh, K1, H1, NULL);
        int s2 = sfm_selfcal_linear(MV, P2, wh, NP, Xh, K2, H2, NULL);
        SFM_CHECK_MSG(s1 == SFM_OK && s2 == SFM_OK && fabs(K2[0] / K1[0] - 1) < 1e-9,
                      "linear at scale %g: status %d f %g (unscaled %d, %g)", big_small[c - 4], s2, K2[0], s1, K1[0]);
    }

    /* every point a zero row: nothing to adjust */
    memset(X2, 0, sizeof(double) * 4 * NP);
    GEOM("X all zero", MV, Pp, wh, NP, X2, no, obs_cam, obs_pt, obs_xy, NULL, sws, sizeof sws);
    REFUSED("X all zero");

    /* every point at infinity of the given frame (w = 0) */
    memcpy(X2, Xh, sizeof(double) * 4 * NP);
    for (int j = 0; j < NP; j++)
        X2[4 * j + 3] = 0;
    GEOM("X at infinity (frame)", MV, Pp, wh, NP, X2, no, obs_cam, obs_pt, obs_xy, NULL, sws, sizeof sws);
    TRUTH_OR_REFUSED("X at infinity (frame)");

    /* every camera the same: no baseline */
    for (int i = 0; i < MV; i++)
        memcpy(&P2[12 * i], Pp, 12 * sizeof(double));
    for (int k = 0; k < no; k++) {
        oc2[k] = obs_cam[k], op2[k] = obs_pt[k];
        xy2[2 * k] = obs_xy[2 * (obs_pt[k])], xy2[2 * k + 1] = obs_xy[2 * (obs_pt[k]) + 1];
    }
    GEOM("identical cameras", MV, P2, wh, NP, Xh, no, oc2, op2, xy2, NULL, sws, sizeof sws);
    REFUSED("identical cameras");

    /* two views duplicated (view 4 = view 2, view 5 = view 1) with their
     * observations: the same scene seen three times */
    memcpy(P2, Pp, sizeof(double) * 12 * MV);
    memcpy(&P2[36], &Pp[12], 12 * sizeof(double));
    memcpy(&P2[48], &Pp[0], 12 * sizeof(double));
    {
        int k2 = 0;
        for (int k = 0; k < no; k++) {
            int i = obs_cam[k];
            int src = i == 3 ? 1 : (i == 4 ? 0 : i);
            oc2[k2] = i, op2[k2] = obs_pt[k];
            xy2[2 * k2] = obs_xy[2 * (src * NP + obs_pt[k])];
            xy2[2 * k2 + 1] = obs_xy[2 * (src * NP + obs_pt[k]) + 1];
            k2++;
        }
        GEOM("duplicated views", MV, P2, wh, NP, Xh, k2, oc2, op2, xy2, NULL, sws, sizeof sws);
        TRUTH_OR_REFUSED("duplicated views");
    }

    /* every observation given twice: the same scene */
    for (int k = 0; k < no; k++) {
        oc2[2 * k] = oc2[2 * k + 1] = obs_cam[k];
        op2[2 * k] = op2[2 * k + 1] = obs_pt[k];
        xy2[4 * k] = xy2[4 * k + 2] = obs_xy[2 * k];
        xy2[4 * k + 1] = xy2[4 * k + 3] = obs_xy[2 * k + 1];
    }
    SFM_CHECK(sfm_selfcal_workspace_size(MV, NP, 2 * no) <= sizeof big);
    GEOM("observations twice", MV, Pp, wh, NP, Xh, 2 * no, oc2, op2, xy2, NULL, big, sizeof big);
    /* a camera sees a point once: a repeated pair would count as evidence
     * twice (focal_sigma 0.0011 for the 0.0018 of the same data once) */
    SFM_CHECK_EQ_INT(st, SFM_E_ARGUMENT);
    /* one repeated pair among the others, the last one */
    for (int k = 0; k < no; k++)
        oc2[k] = obs_cam[k], op2[k] = obs_pt[k], xy2[2 * k] = obs_xy[2 * k], xy2[2 * k + 1] = obs_xy[2 * k + 1];
    oc2[no] = obs_cam[0], op2[no] = obs_pt[0], xy2[2 * no] = obs_xy[0] + 0.5, xy2[2 * no + 1] = obs_xy[1];
    GEOM("one observation twice", MV, Pp, wh, NP, Xh, no + 1, oc2, op2, xy2, NULL, big, sizeof big);
    SFM_CHECK_EQ_INT(st, SFM_E_ARGUMENT);

    /* each point seen by one camera only, twice (no two views share a
     * point): the tracks say nothing of the geometry */
    for (int k = 0; k < 2 * NP; k++) {
        int j = k / 2, i = j % MV;
        oc2[k] = i, op2[k] = j;
        xy2[2 * k] = obs_xy[2 * (i * NP + j)];
        xy2[2 * k + 1] = obs_xy[2 * (i * NP + j) + 1];
    }
    GEOM("single-view tracks", MV, Pp, wh, NP, Xh, 2 * NP, oc2, op2, xy2, NULL, sws, sizeof sws);
    SFM_CHECK_EQ_INT(st, SFM_E_ARGUMENT);

    /* one view sees nothing */
    {
        int k2 = 0;
        for (int k = 0; k < no; k++)
            if (obs_cam[k] != 2)
                oc2[k2] = obs_cam[k], op2[k2] = obs_pt[k], xy2[2 * k2] = obs_xy[2 * k],
                xy2[2 * k2 + 1] = obs_xy[2 * k + 1], k2++;
        GEOM("a blind view", MV, Pp, wh, NP, Xh, k2, oc2, op2, xy2, NULL, sws, sizeof sws);
        REFUSED("a blind view");
    }

    /* observations unrelated to the cameras (uniform in the image) */
    for (int k = 0; k < no; k++) {
        xy2[2 * k] = sfm_test_uniform(t, 0, W);
        xy2[2 * k + 1] = sfm_test_uniform(t, 0, HH);
    }
    GEOM("random observations", MV, Pp, wh, NP, Xh, no, obs_cam, obs_pt, xy2, NULL, sws, sizeof sws);
    REFUSED("random observations");

    /* observations far outside the image (1e12 px) */
    for (int k = 0; k < no; k++)
        xy2[2 * k] = obs_xy[2 * k] + 1e12, xy2[2 * k + 1] = obs_xy[2 * k + 1] - 1e12;
    GEOM("observations off the image", MV, Pp, wh, NP, Xh, no, obs_cam, obs_pt, xy2, NULL, sws, sizeof sws);
    REFUSED("observations off the image");

    /* image sizes 1 x 1, huge and tiny: the priors are wrong, the answer
     * must not be a confident wrong focal length */
    const double sizes[4] = {1, 1e-300, 1e300, 1.7e308};
    for (int s = 0; s < 4; s++) {
        double w2[2 * MV];
        for (int i = 0; i < 2 * MV; i++)
            w2[i] = sizes[s];
        GEOM("odd image size", MV, Pp, w2, NP, Xh, no, obs_cam, obs_pt, obs_xy, NULL, sws, sizeof sws);
        REFUSED("odd image size");
    }

    /* the focal range at its extremes: the truth or refused */
    {
        sfm_selfcal_options o;
        sfm_selfcal_default_options(&o);
        o.focal_min = 1e-300;
        o.focal_max = 1e300;
        o.sweep_steps = SFM_SELFCAL_MAX_SWEEP;
        GEOM("focal range 1e-300..1e300", MV, Pp, wh, NP, Xh, no, obs_cam, obs_pt, obs_xy, &o, sws, sizeof sws);
        TRUTH_OR_REFUSED("focal range 1e-300..1e300");
        o.focal_min = 100, o.focal_max = 200; /* the truth is not inside */
        o.sweep = SFM_SELFCAL_SWEEP_ALWAYS;
        GEOM("focal range above the truth", MV, Pp, wh, NP, Xh, no, obs_cam, obs_pt, obs_xy, &o, sws, sizeof sws);
        TRUTH_OR_REFUSED("focal range above the truth");
        o.max_iterations = 2147483647;
        o.focal_min = 0.25, o.focal_max = 4;
        o.per_view_focal = 1, o.principal = SFM_SELFCAL_PRINCIPAL_PER_VIEW;
        GEOM("largest model, unbounded iterations", MV, Pp, wh, NP, Xh, no, obs_cam, obs_pt, obs_xy, &o, sws,
             sizeof sws);
        TRUTH_OR_REFUSED("largest model, unbounded iterations");
    }

    /* the smallest problem: 3 views, 8 points */
    GEOM("3 views, 8 points", 3, Pp, wh, 8, Xh, 0, obs_cam, obs_pt, obs_xy, NULL, sws, sizeof sws);
    {
        int k2 = 0;
        for (int k = 0; k < no; k++)
            if (obs_cam[k] < 3 && obs_pt[k] < 8)
                oc2[k2] = obs_cam[k], op2[k2] = obs_pt[k], xy2[2 * k2] = obs_xy[2 * k],
                xy2[2 * k2 + 1] = obs_xy[2 * k + 1], k2++;
        GEOM("3 views, 8 points", 3, Pp, wh, 8, Xh, k2, oc2, op2, xy2, NULL, sws, sizeof sws);
        TRUTH_OR_REFUSED("3 views, 8 points");
    }
#undef GEOM
#undef TRUTH_OR_REFUSED
#undef REFUSED
    SFM_TEST_LOG("%d degenerate or odd inputs", tried);
}
