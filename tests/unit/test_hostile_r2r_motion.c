/* Leader-follower filter against hostile finite inputs: angles of any size
 * must wrap in bounded time to (-pi, pi], and finite inputs whose result
 * overflows (a sigma of 1e200 squared) must give a status, never an
 * infinite or NaN estimate reported as SFM_OK. Outputs are pre-filled with
 * a canary: nothing may be written on failure. */
#include <math.h>
#include <string.h>

#include "sfm/sfm_r2r_motion.h"
#include "sfm_test.h"

#define PI_ 3.14159265358979323846

static const double g_x[3] = {2.0, 0.5, 0.1};
static const double g_P[9] = {0.1, 0, 0, 0, 0.1, 0, 0, 0, 0.01};
static const sfm_r2r_motion_noise g_noise = {0.01, 0.01, 0.01, 0.01, 0.05};

static int wrapped(double a) { return a > -PI_ && a <= PI_; }

SFM_TEST(r2r_motion_huge_angles_wrap_in_bounded_time)
{
    sfm_r2r_motion_step u;
    memset(&u, 0, sizeof u);
    u.leader_d.v[0] = 0.1;
    u.follower_d.v[0] = 0.1;
    /* headings and turns far beyond a few turns: the subtraction loop took
     * |a| / 2 pi steps (1e154: forever, 2 pi is below an ulp) */
    const double big[] = {1e154, -1e154, 1e300, 2.0 * PI_ * 1e6 + 0.3, -7.5e15, 1e18};
    int n = 0;
    for (int k = 0; k < (int)(sizeof big / sizeof big[0]); k++) {
        double x[3] = {g_x[0], g_x[1], big[k]}, xo[3], Po[9];
        SFM_CHECK_EQ_INT(sfm_r2r_motion_propagate(x, g_P, &u, &g_noise, xo, Po), SFM_OK);
        SFM_CHECK(wrapped(xo[2]));
        sfm_r2r_motion_step v = u;
        v.leader_w = big[k];
        SFM_CHECK_EQ_INT(sfm_r2r_motion_propagate(g_x, g_P, &v, &g_noise, xo, Po), SFM_OK);
        SFM_CHECK(wrapped(xo[2]));
        v = u;
        v.follower_w = big[k];
        double tr;
        SFM_CHECK_EQ_INT(sfm_r2r_motion_cost(g_x, g_P, &v, &g_noise, SFM_R2R_MOTION_BEARING, &tr), SFM_OK);
        SFM_CHECK(isfinite(tr) && tr > 0);
        /* a bearing measurement of any finite size: the innovation wraps */
        SFM_CHECK_EQ_INT(sfm_r2r_motion_update(g_x, g_P, SFM_R2R_MOTION_BEARING, big[k], &g_noise, xo, Po),
                         SFM_OK);
        SFM_CHECK(wrapped(xo[2]) && isfinite(xo[0]) && isfinite(xo[1]));
        n++;
    }
    SFM_CHECK_EQ_INT(n, 6);
    /* 2 pi * 1e6 + 0.3 is 0.3 up to the rounding of the sum (about 1e-9):
     * the reduction keeps it */
    double x[3] = {g_x[0], g_x[1], 2.0 * PI_ * 1e6 + 0.3}, xo[3], Po[9];
    u.leader_w = u.follower_w = 0;
    SFM_CHECK_EQ_INT(sfm_r2r_motion_propagate(x, g_P, &u, &g_noise, xo, Po), SFM_OK);
    SFM_CHECK_NEAR(xo[2], 0.3, 1e-8);
    /* the wrap of an angle a few turns off is unchanged: 0.1 + 2 pi + 0.2 */
    u.leader_w = 2.0 * PI_ + 0.2;
    SFM_CHECK_EQ_INT(sfm_r2r_motion_propagate(g_x, g_P, &u, &g_noise, xo, Po), SFM_OK);
    SFM_CHECK_NEAR(xo[2], 0.3, 1e-12);
}

SFM_TEST(r2r_motion_overflow_is_a_status_and_writes_nothing)
{
    sfm_r2r_motion_step u;
    memset(&u, 0, sizeof u);
    u.leader_d.v[0] = 0.1;
    u.follower_d.v[0] = 0.1;
    int tried = 0;
    const double huge[] = {1e154, 1e200, 1e308};
    for (int k = 0; k < 3; k++) {
        double canary[12];
        for (int i = 0; i < 12; i++)
            canary[i] = -12345.0;
        double xo[3], Po[9];
        /* each noise sigma squared overflows; so does a leader step */
        for (int f = 0; f < 5; f++) {
            sfm_r2r_motion_noise n = g_noise;
            double *s[5] = {&n.sigma_leader_d, &n.sigma_leader_w, &n.sigma_follower_d,
                            &n.sigma_follower_w, &n.sigma_meas};
            *s[f] = huge[k];
            memcpy(xo, canary, sizeof xo);
            memcpy(Po, canary, sizeof Po);
            int st = sfm_r2r_motion_propagate(g_x, g_P, &u, &n, xo, Po);
            tried++;
            if (st == SFM_OK) {
                int fin = 1;
                for (int i = 0; i < 9; i++)
                    fin &= isfinite(Po[i]) != 0;
                SFM_CHECK_MSG(fin && isfinite(xo[0]) && isfinite(xo[2]), "propagate sigma %d = %g", f, huge[k]);
            } else {
                SFM_CHECK_EQ_INT(st, SFM_E_NONFINITE);
                SFM_CHECK(memcmp(xo, canary, sizeof xo) == 0 && memcmp(Po, canary, sizeof Po) == 0);
            }
            double tr = -12345.0;
            st = sfm_r2r_motion_cost(g_x, g_P, &u, &n, SFM_R2R_MOTION_RANGE, &tr);
            tried++;
            if (st == SFM_OK)
                SFM_CHECK_MSG(isfinite(tr), "cost sigma %d = %g", f, huge[k]);
            else
                SFM_CHECK(tr == -12345.0);
            sfm_r2r_motion_plan pl, pc;
            memset(&pl, 0x5a, sizeof pl);
            pc = pl;
            st = sfm_r2r_motion_next(g_x, g_P, &u, NULL, 1e-12, 1e-12, &n, SFM_R2R_MOTION_BEARING, &pl);
            tried++;
            if (st == SFM_OK)
                SFM_CHECK_MSG(isfinite(pl.trace) && isfinite(pl.follower_d.v[0]), "next sigma %d = %g", f,
                              huge[k]);
            else
                SFM_CHECK(memcmp(&pl, &pc, sizeof pl) == 0);
        }
        /* a position of 1e308: the range update's innovation overflows */
        double x[3] = {huge[k], g_x[1], g_x[2]};
        memcpy(xo, canary, sizeof xo);
        memcpy(Po, canary, sizeof Po);
        int st = sfm_r2r_motion_update(x, g_P, SFM_R2R_MOTION_RANGE, 1e308, &g_noise, xo, Po);
        tried++;
        if (st == SFM_OK)
            SFM_CHECK(isfinite(xo[0]) && isfinite(xo[1]) && isfinite(Po[0]));
        else
            SFM_CHECK(memcmp(xo, canary, sizeof xo) == 0);
        /* a covariance entry of 1e308 overflows the gain */
        double P[9];
        memcpy(P, g_P, sizeof P);
        P[8] = huge[k];
        memcpy(xo, canary, sizeof xo);
        st = sfm_r2r_motion_update(g_x, P, SFM_R2R_MOTION_RANGE, 1.0, &g_noise, xo, Po);
        tried++;
        if (st == SFM_OK)
            SFM_CHECK(isfinite(xo[0]) && isfinite(xo[2]) && isfinite(Po[8]));
        else
            SFM_CHECK(memcmp(xo, canary, sizeof xo) == 0);
    }
    SFM_CHECK_EQ_INT(tried, 51);
}
