/*
 * Leader-follower motion (sfm_r2r_motion.h): the EKF propagation against
 * finite differences of the motion model written here from the header's
 * conventions, the KKT optimum against a polar grid over the admissible
 * disk (nothing on the grid better; the grid within its resolution of the
 * optimum), and the contract (every bad input its status, nothing written).
 * The dense grid and the Monte-Carlo claim are in tests/python/test_formation.py.
 */
#include <math.h>
#include <string.h>

#include "sfm/sfm.h"
#include "sfm_test.h"
#include "r2r_motion_scene.h"

static const double PI_T = 3.14159265358979323846;

/* the header's step, with the noise inputs n = (ld2, lw, fw, fd2) */
static void motion(const double x[3], const double n[6], double out[3])
{
    const double cp = cos(x[2]), sp = sin(x[2]), cw = cos(n[3]), sw = sin(n[3]);
    const double ax = x[0] + cp * n[0] - sp * n[1], ay = x[1] + sp * n[0] + cp * n[1];
    out[0] = cw * ax + sw * ay - n[4];
    out[1] = -sw * ax + cw * ay - n[5];
    out[2] = x[2] + n[2] - n[3];
}

static void random_spd(sfm_test_ctx *t, double P[9])
{
    r2r_random_spd(t, 0.05, 0.5, 1e-3, P);
}

static sfm_r2r_motion_noise test_noise(int sensor)
{
    sfm_r2r_motion_noise n = {0.02, 0.01, 0.015, 0.008,
                              sensor == SFM_R2R_MOTION_RANGE ? 0.05 : 0.02};
    return n;
}

SFM_TEST(r2r_motion_propagate_matches_finite_differences)
{
    const int iters = SFM_TEST_ITERS(200);
    double worst = 0.0;
    for (int it = 0; it < iters; it++) {
        double x[3] = {sfm_test_uniform(t, -4, 4), sfm_test_uniform(t, -4, 4),
                       sfm_test_uniform(t, -3, 3)};
        double P[9];
        random_spd(t, P);
        const double n[6] = {sfm_test_uniform(t, -0.4, 0.4), sfm_test_uniform(t, -0.4, 0.4),
                             sfm_test_uniform(t, -0.3, 0.3), sfm_test_uniform(t, -0.3, 0.3),
                             sfm_test_uniform(t, -0.5, 0.5), sfm_test_uniform(t, -0.5, 0.5)};
        const sfm_r2r_motion_noise nz = test_noise(SFM_R2R_MOTION_RANGE);
        const double sig[6] = {nz.sigma_leader_d, nz.sigma_leader_d, nz.sigma_leader_w,
                               nz.sigma_follower_w, nz.sigma_follower_d, nz.sigma_follower_d};
        sfm_r2r_motion_step u = {{{n[0], n[1]}}, n[2], n[3], {{n[4], n[5]}}};
        double xo[3], Po[9];
        SFM_CHECK_EQ_INT(sfm_r2r_motion_propagate(x, P, &u, &nz, xo, Po), SFM_OK);
        /* oracle: F P F^T + G Q G^T from central differences */
        double F[9], G[18];
        const double h = 1e-6;
        for (int j = 0; j < 3; j++) {
            double xp[3], xm[3], fp[3], fm[3];
            memcpy(xp, x, sizeof xp);
            memcpy(xm, x, sizeof xm);
            xp[j] += h;
            xm[j] -= h;
            motion(xp, n, fp);
            motion(xm, n, fm);
            for (int i = 0; i < 3; i++)
                F[3 * i + j] = (fp[i] - fm[i]) / (2 * h);
        }
        for (int j = 0; j < 6; j++) {
            double np_[6], nm[6], fp[3], fm[3];
            memcpy(np_, n, sizeof np_);
            memcpy(nm, n, sizeof nm);
            np_[j] += h;
            nm[j] -= h;
            motion(x, np_, fp);
            motion(x, nm, fm);
            for (int i = 0; i < 3; i++)
                G[6 * i + j] = (fp[i] - fm[i]) / (2 * h);
        }
        double xr[3];
        motion(x, n, xr);
        double d = fabs(xr[2] - xo[2]);
        d = fmin(d, fabs(d - 2 * PI_T));
        SFM_CHECK(fabs(xr[0] - xo[0]) < 1e-12 && fabs(xr[1] - xo[1]) < 1e-12 && d < 1e-12);
        for (int i = 0; i < 3; i++)
            for (int j = 0; j < 3; j++) {
                double v = 0.0;
                for (int a = 0; a < 3; a++)
                    for (int b = 0; b < 3; b++)
                        v += F[3 * i + a] * P[3 * a + b] * F[3 * j + b];
                for (int k = 0; k < 6; k++)
                    v += G[6 * i + k] * sig[k] * sig[k] * G[6 * j + k];
                const double e = fabs(v - Po[3 * i + j]) / (1e-3 + fabs(v));
                worst = e > worst ? e : worst;
            }
    }
    SFM_TEST_LOG("propagated covariance vs finite differences: worst relative error %.2e", worst);
    SFM_CHECK(worst < 1e-7);
}

static void kkt_against_grid(sfm_test_ctx *t, int sensor)
{
    const int iters = SFM_TEST_ITERS(60);
    const int nr = 41, nt = 240;
    int done = 0, interior = 0, distance = 0;
    double worst_gap = 0.0;
    while (done < iters) {
        double x[3] = {sfm_test_uniform(t, -4, 4), sfm_test_uniform(t, -4, 4),
                       sfm_test_uniform(t, -3, 3)};
        double P[9];
        random_spd(t, P);
        sfm_r2r_motion_step u = {{{sfm_test_uniform(t, -0.4, 0.4), sfm_test_uniform(t, -0.4, 0.4)}},
                                 sfm_test_uniform(t, -0.3, 0.3), sfm_test_uniform(t, -0.3, 0.3),
                                 {{0.0, 0.0}}};
        const double d0[2] = {sfm_test_uniform(t, -0.5, 0.5), sfm_test_uniform(t, -0.5, 0.5)};
        const double r = sfm_test_uniform(t, 0.1, 1.0);
        const sfm_r2r_motion_noise nz = test_noise(sensor);
        /* every other state keeps a minimum distance that may bind */
        const double dmin = done % 2 ? sfm_test_uniform(t, 0.3, 5.0) : 0.0;
        sfm_r2r_motion_plan plan;
        int st = sfm_r2r_motion_next(x, P, &u, d0, r, dmin, &nz, sensor, &plan);
        if (st == SFM_E_SINGULAR)
            continue; /* the disk reaches the leader, or no point keeps dmin: drawn again */
        SFM_CHECK_EQ_INT(st, SFM_OK);
        if (st != SFM_OK)
            return;
        done++;
        interior += !plan.on_boundary;
        distance += plan.on_boundary >= 2;
        double c[3], Pc[9];
        SFM_CHECK_EQ_INT(sfm_r2r_motion_propagate(x, P, &u, &nz, c, Pc), SFM_OK);
        SFM_CHECK(plan.q.v[0] * plan.q.v[0] + plan.q.v[1] * plan.q.v[1] >= dmin * dmin * (1 - 1e-9));
        const double dx = plan.follower_d.v[0] - d0[0], dy = plan.follower_d.v[1] - d0[1];
        SFM_CHECK(sqrt(dx * dx + dy * dy) <= r * (1.0 + 1e-9));
        SFM_CHECK(plan.multiplier >= 0.0);
        const double fc = r2r_cost_at(x, P, &u, &nz, sensor, plan.follower_d.v[0], plan.follower_d.v[1]);
        SFM_CHECK_NEAR(fc, plan.trace, 1e-12 * fabs(fc));
        /* the grid's admissible points; the variation between admissible
         * neighbours bounds what the grid can miss */
        double fmin_g = HUGE_VAL, var = 0.0, prev_ring[240];
        for (int i = 0; i < nr; i++) {
            const double rho = r * i / (nr - 1);
            double prev = HUGE_VAL;
            for (int j = 0; j < nt; j++) {
                const double th = -PI_T + 2 * PI_T * j / nt;
                const double fx = d0[0] + rho * cos(th), fy = d0[1] + rho * sin(th);
                const double qx = c[0] - fx, qy = c[1] - fy;
                const double f = qx * qx + qy * qy >= dmin * dmin
                                     ? r2r_cost_at(x, P, &u, &nz, sensor, fx, fy)
                                     : HUGE_VAL;
                fmin_g = f < fmin_g ? f : fmin_g;
                if (f < HUGE_VAL && prev < HUGE_VAL && fabs(f - prev) > var)
                    var = fabs(f - prev);
                if (i > 0 && f < HUGE_VAL && prev_ring[j] < HUGE_VAL && fabs(f - prev_ring[j]) > var)
                    var = fabs(f - prev_ring[j]);
                prev_ring[j] = f;
                prev = f;
            }
        }
        /* nothing on the grid better than the optimum; the grid within one
         * cell's variation of it */
        SFM_CHECK_MSG(fc <= fmin_g + 1e-9 * fabs(fmin_g), "KKT %.12g worse than grid %.12g", fc,
                      fmin_g);
        SFM_CHECK_MSG(fmin_g - fc <= 2.0 * var + 1e-12, "grid %.12g far above KKT %.12g (cell %.3g)",
                      fmin_g, fc, var);
        if (var > 0.0 && (fmin_g - fc) / var > worst_gap)
            worst_gap = (fmin_g - fc) / var;
    }
    SFM_TEST_LOG("%d states (%d optima inside the disk, %d on the distance circle): grid "
                 "shortfall at most %.4f of a cell's variation", done, interior, distance, worst_gap);
}

SFM_TEST(r2r_motion_next_range_against_grid)
{
    kkt_against_grid(t, SFM_R2R_MOTION_RANGE);
}

SFM_TEST(r2r_motion_next_bearing_against_grid)
{
    kkt_against_grid(t, SFM_R2R_MOTION_BEARING);
}

SFM_TEST(r2r_motion_contract)
{
    const double x[3] = {3.0, 1.0, 0.2};
    const double P[9] = {0.1, 0, 0, 0, 0.1, 0, 0, 0, 0.05};
    const sfm_r2r_motion_step u = {{{0.2, 0.0}}, 0.0, 0.0, {{0.1, 0.0}}};
    const sfm_r2r_motion_noise nz = test_noise(SFM_R2R_MOTION_RANGE);
    sfm_r2r_motion_plan plan;
    double xo[3], Po[9], tr;
    SFM_CHECK_EQ_INT(sfm_r2r_motion_next(x, P, &u, NULL, 0.5, 0.0, &nz, SFM_R2R_MOTION_RANGE, &plan),
                     SFM_OK);
    SFM_CHECK(plan.n_critical >= 1);

    double dmin_ = 0.0;
#define EXPECT_NEXT(st, xx, PP, uu, dd, rr, nn, sens)                                       \
    do {                                                                                  \
        sfm_test_fill_canary(&plan, sizeof plan);                                         \
        SFM_CHECK_EQ_INT(sfm_r2r_motion_next(xx, PP, uu, dd, rr, dmin_, nn, sens, &plan), st); \
        SFM_CHECK(sfm_test_canary_intact(&plan, sizeof plan));                            \
    } while (0)

    EXPECT_NEXT(SFM_E_ARGUMENT, NULL, P, &u, NULL, 0.5, &nz, SFM_R2R_MOTION_RANGE);
    EXPECT_NEXT(SFM_E_ARGUMENT, x, NULL, &u, NULL, 0.5, &nz, SFM_R2R_MOTION_RANGE);
    EXPECT_NEXT(SFM_E_ARGUMENT, x, P, NULL, NULL, 0.5, &nz, SFM_R2R_MOTION_RANGE);
    EXPECT_NEXT(SFM_E_ARGUMENT, x, P, &u, NULL, 0.5, NULL, SFM_R2R_MOTION_RANGE);
    EXPECT_NEXT(SFM_E_ARGUMENT, x, P, &u, NULL, 0.5, &nz, 0);
    EXPECT_NEXT(SFM_E_ARGUMENT, x, P, &u, NULL, 0.5, &nz, 3);
    EXPECT_NEXT(SFM_E_ARGUMENT, x, P, &u, NULL, 0.0, &nz, SFM_R2R_MOTION_RANGE);
    EXPECT_NEXT(SFM_E_ARGUMENT, x, P, &u, NULL, -1.0, &nz, SFM_R2R_MOTION_RANGE);
    EXPECT_NEXT(SFM_E_NONFINITE, x, P, &u, NULL, (double)NAN, &nz, SFM_R2R_MOTION_RANGE);
    EXPECT_NEXT(SFM_E_NONFINITE, x, P, &u, NULL, HUGE_VAL, &nz, SFM_R2R_MOTION_RANGE);
    {
        double xb[3] = {3.0, (double)NAN, 0.0};
        EXPECT_NEXT(SFM_E_NONFINITE, xb, P, &u, NULL, 0.5, &nz, SFM_R2R_MOTION_RANGE);
        double Pb[9];
        memcpy(Pb, P, sizeof Pb);
        Pb[4] = HUGE_VAL;
        EXPECT_NEXT(SFM_E_NONFINITE, x, Pb, &u, NULL, 0.5, &nz, SFM_R2R_MOTION_RANGE);
        memcpy(Pb, P, sizeof Pb);
        Pb[4] = -0.1; /* not definite */
        EXPECT_NEXT(SFM_E_ARGUMENT, x, Pb, &u, NULL, 0.5, &nz, SFM_R2R_MOTION_RANGE);
        memcpy(Pb, P, sizeof Pb);
        Pb[1] = 0.05; /* not symmetric */
        EXPECT_NEXT(SFM_E_ARGUMENT, x, Pb, &u, NULL, 0.5, &nz, SFM_R2R_MOTION_RANGE);
        memcpy(Pb, P, sizeof Pb);
        Pb[1] = Pb[3] = 0.2; /* symmetric, indefinite */
        EXPECT_NEXT(SFM_E_ARGUMENT, x, Pb, &u, NULL, 0.5, &nz, SFM_R2R_MOTION_RANGE);
        sfm_r2r_motion_step ub = u;
        ub.leader_w = (double)NAN;
        EXPECT_NEXT(SFM_E_NONFINITE, x, P, &ub, NULL, 0.5, &nz, SFM_R2R_MOTION_RANGE);
        const double d0b[2] = {(double)NAN, 0.0};
        EXPECT_NEXT(SFM_E_NONFINITE, x, P, &u, d0b, 0.5, &nz, SFM_R2R_MOTION_RANGE);
        sfm_r2r_motion_noise nb = nz;
        nb.sigma_meas = 0.0;
        EXPECT_NEXT(SFM_E_ARGUMENT, x, P, &u, NULL, 0.5, &nb, SFM_R2R_MOTION_RANGE);
        nb = nz;
        nb.sigma_follower_w = -0.01;
        EXPECT_NEXT(SFM_E_ARGUMENT, x, P, &u, NULL, 0.5, &nb, SFM_R2R_MOTION_RANGE);
        nb = nz;
        nb.sigma_leader_d = (double)NAN;
        EXPECT_NEXT(SFM_E_NONFINITE, x, P, &u, NULL, 0.5, &nb, SFM_R2R_MOTION_BEARING);
        /* the disk reaches the leader's predicted position */
        EXPECT_NEXT(SFM_E_SINGULAR, x, P, &u, NULL, 4.0, &nz, SFM_R2R_MOTION_BEARING);
        const double d0c[2] = {3.2, 1.04};
        EXPECT_NEXT(SFM_E_SINGULAR, x, P, &u, d0c, 0.1, &nz, SFM_R2R_MOTION_RANGE);
        /* the minimum distance: negative, NaN, or out of reach of the disk */
        dmin_ = -0.1;
        EXPECT_NEXT(SFM_E_ARGUMENT, x, P, &u, NULL, 0.5, &nz, SFM_R2R_MOTION_RANGE);
        dmin_ = (double)NAN;
        EXPECT_NEXT(SFM_E_NONFINITE, x, P, &u, NULL, 0.5, &nz, SFM_R2R_MOTION_RANGE);
        dmin_ = 4.0; /* |c| + 0.5 is about 3.87 */
        EXPECT_NEXT(SFM_E_SINGULAR, x, P, &u, NULL, 0.5, &nz, SFM_R2R_MOTION_BEARING);
        /* with a minimum distance the disk may contain the leader */
        dmin_ = 1.0;
        SFM_CHECK_EQ_INT(sfm_r2r_motion_next(x, P, &u, NULL, 4.0, dmin_, &nz,
                                             SFM_R2R_MOTION_BEARING, &plan), SFM_OK);
        SFM_CHECK(plan.on_boundary >= 2);
        SFM_CHECK_NEAR(sqrt(plan.q.v[0] * plan.q.v[0] + plan.q.v[1] * plan.q.v[1]), 1.0, 1e-9);
        dmin_ = 0.0;
    }
#undef EXPECT_NEXT

    sfm_test_fill_canary(xo, sizeof xo);
    sfm_test_fill_canary(Po, sizeof Po);
    SFM_CHECK_EQ_INT(sfm_r2r_motion_propagate(x, P, &u, NULL, xo, Po), SFM_E_ARGUMENT);
    SFM_CHECK_EQ_INT(sfm_r2r_motion_propagate(x, P, &u, &nz, NULL, Po), SFM_E_ARGUMENT);
    {
        const double Pb[9] = {0.1, 0, 0, 0, 0.1, 0, 0, 0, 0.0};
        SFM_CHECK_EQ_INT(sfm_r2r_motion_propagate(x, Pb, &u, &nz, xo, Po), SFM_E_ARGUMENT);
        const double xb[3] = {0.0, 0.0, (double)NAN};
        SFM_CHECK_EQ_INT(sfm_r2r_motion_update(xb, P, SFM_R2R_MOTION_RANGE, 1.0, &nz, xo, Po),
                         SFM_E_NONFINITE);
        const double x0[3] = {0.0, 0.0, 0.0};
        SFM_CHECK_EQ_INT(sfm_r2r_motion_update(x0, P, SFM_R2R_MOTION_BEARING, 1.0, &nz, xo, Po),
                         SFM_E_SINGULAR);
    }
    SFM_CHECK_EQ_INT(sfm_r2r_motion_update(x, P, SFM_R2R_MOTION_RANGE, -1.0, &nz, xo, Po),
                     SFM_E_ARGUMENT);
    SFM_CHECK_EQ_INT(sfm_r2r_motion_update(x, P, 7, 1.0, &nz, xo, Po), SFM_E_ARGUMENT);
    SFM_CHECK_EQ_INT(sfm_r2r_motion_update(x, P, SFM_R2R_MOTION_BEARING, (double)NAN, &nz, xo, Po),
                     SFM_E_NONFINITE);
    SFM_CHECK(sfm_test_canary_intact(xo, sizeof xo) && sfm_test_canary_intact(Po, sizeof Po));
    SFM_CHECK_EQ_INT(sfm_r2r_motion_cost(x, P, &u, &nz, SFM_R2R_MOTION_RANGE, NULL), SFM_E_ARGUMENT);
    SFM_CHECK_EQ_INT(sfm_r2r_motion_cost(x, P, &u, &nz, 9, &tr), SFM_E_ARGUMENT);
    /* the leader exactly where the follower's translation puts it */
    {
        sfm_r2r_motion_step uc = u;
        uc.follower_d.v[0] = 3.0 + 0.2 * cos(0.2);
        uc.follower_d.v[1] = 1.0 + 0.2 * sin(0.2);
        SFM_CHECK_EQ_INT(sfm_r2r_motion_cost(x, P, &uc, &nz, SFM_R2R_MOTION_RANGE, &tr),
                         SFM_E_SINGULAR);
    }
}

/* An update with the measurement the state predicts leaves the state alone
 * and shrinks the covariance along the Jacobian only: a known answer. */
SFM_TEST(r2r_motion_update_known_answer)
{
    const double x[3] = {3.0, 4.0, 0.3};
    const double P[9] = {0.2, 0, 0, 0, 0.2, 0, 0, 0, 0.1};
    const sfm_r2r_motion_noise nz = test_noise(SFM_R2R_MOTION_RANGE);
    double xo[3], Po[9];
    SFM_CHECK_EQ_INT(sfm_r2r_motion_update(x, P, SFM_R2R_MOTION_RANGE, 5.0, &nz, xo, Po), SFM_OK);
    SFM_CHECK_NEAR(xo[0], 3.0, 1e-15);
    SFM_CHECK_NEAR(xo[1], 4.0, 1e-15);
    SFM_CHECK_NEAR(xo[2], 0.3, 1e-15);
    /* along u = (0.6, 0.8): 0.2 -> 0.2 s^2 / (0.2 + s^2); across: unchanged */
    const double s2 = 0.05 * 0.05, along = 0.2 * s2 / (0.2 + s2);
    const double uu[2] = {0.6, 0.8};
    for (int i = 0; i < 2; i++)
        for (int j = 0; j < 2; j++) {
            const double e = (i == j ? 0.2 : 0.0) + (along - 0.2) * uu[i] * uu[j];
            SFM_CHECK_NEAR(Po[3 * i + j], e, 1e-15);
        }
    SFM_CHECK_NEAR(Po[8], 0.1, 1e-15);
    /* bearing, a measurement 0.1 rad off: the innovation wraps across pi */
    const double xb[3] = {-2.0, 1e-3, 0.0};
    const sfm_r2r_motion_noise nb = test_noise(SFM_R2R_MOTION_BEARING);
    SFM_CHECK_EQ_INT(sfm_r2r_motion_update(xb, P, SFM_R2R_MOTION_BEARING, -PI_T + 0.05, &nb, xo, Po),
                     SFM_OK);
    /* bearing increases counter-clockwise: p moves by K * innovation with
     * innovation ~ +0.05 rad (not -2 pi + 0.05) */
    SFM_CHECK(fabs(xo[0] + 2.0) < 0.05 && xo[1] < 0.0 && xo[1] > -0.12);
}
