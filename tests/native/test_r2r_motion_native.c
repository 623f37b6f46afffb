/*
 * Leader-follower next motion on thousands of random states (host only: the
 * portable test in tests/unit runs a few dozen, also on Cortex-M7): the KKT
 * optimum is never beaten by any point of a 31 x 120 polar grid of the
 * admissible disk, nor by the best of 64 random admissible points, for both
 * sensors, with and without a nominal motion d0 and a minimum distance.
 */
#include <math.h>

#include "sfm/sfm.h"
#include "sfm_test.h"
#include "../unit/r2r_motion_scene.h"

static void many_states(sfm_test_ctx *t, int sensor)
{
    const int n = 3000, nr = 31, nt = 120;
    int done = 0, singular = 0, beaten = 0, boundary = 0, distance_active = 0;
    while (done < n) {
        double x[3] = {sfm_test_uniform(t, -5, 5), sfm_test_uniform(t, -5, 5),
                       sfm_test_uniform(t, -3.1, 3.1)};
        double P[9];
        r2r_random_spd(t, 0.02, 0.7, 1e-4, P);
        sfm_r2r_motion_step u = {{{sfm_test_uniform(t, -0.5, 0.5), sfm_test_uniform(t, -0.5, 0.5)}},
                                 sfm_test_uniform(t, -0.4, 0.4), sfm_test_uniform(t, -0.4, 0.4),
                                 {{0.0, 0.0}}};
        const int use_d0 = done % 2;
        const double d0[2] = {use_d0 ? sfm_test_uniform(t, -0.6, 0.6) : 0.0,
                              use_d0 ? sfm_test_uniform(t, -0.6, 0.6) : 0.0};
        const double r = sfm_test_uniform(t, 0.05, 1.5);
        const sfm_r2r_motion_noise nz = {sfm_test_uniform(t, 0, 0.05), sfm_test_uniform(t, 0, 0.02),
                                         sfm_test_uniform(t, 0, 0.05), sfm_test_uniform(t, 0, 0.02),
                                         sfm_test_uniform(t, 0.005, 0.2)};
        /* a third of the states keep a minimum distance */
        const double dmin = done % 3 == 2 ? sfm_test_uniform(t, 0.2, 6.0) : 0.0;
        sfm_r2r_motion_plan plan;
        const int st = sfm_r2r_motion_next(x, P, &u, use_d0 ? d0 : NULL, r, dmin, &nz, sensor, &plan);
        if (st == SFM_E_SINGULAR) {
            singular++;
            continue;
        }
        SFM_CHECK_EQ_INT(st, SFM_OK);
        if (st != SFM_OK)
            return;
        done++;
        boundary += plan.on_boundary != 0;
        distance_active += plan.on_boundary >= 2;
        const double fc = plan.trace;
        double xc[3], Pc[9];
        SFM_CHECK_EQ_INT(sfm_r2r_motion_propagate(x, P, &u, &nz, xc, Pc), SFM_OK);
        SFM_CHECK(plan.q.v[0] * plan.q.v[0] + plan.q.v[1] * plan.q.v[1] >= dmin * dmin * (1 - 1e-9));
        double best = HUGE_VAL;
        for (int i = 0; i < nr; i++)
            for (int j = 0; j < nt; j++) {
                const double rho = r * i / (nr - 1), th = 6.283185307179586 * j / nt;
                const double fx = d0[0] + rho * cos(th), fy = d0[1] + rho * sin(th);
                const double qx = xc[0] - fx, qy = xc[1] - fy;
                if (qx * qx + qy * qy < dmin * dmin)
                    continue;
                const double f = r2r_cost_at(x, P, &u, &nz, sensor, fx, fy);
                best = f < best ? f : best;
            }
        for (int k = 0; k < 64; k++) {
            const double rho = r * sqrt(sfm_test_uniform(t, 0, 1));
            const double th = sfm_test_uniform(t, -3.14159, 3.14159);
            const double fx = d0[0] + rho * cos(th), fy = d0[1] + rho * sin(th);
            const double qx = xc[0] - fx, qy = xc[1] - fy;
            if (qx * qx + qy * qy < dmin * dmin)
                continue;
            const double f = r2r_cost_at(x, P, &u, &nz, sensor, fx, fy);
            best = f < best ? f : best;
        }
        if (!(fc <= best + 1e-9 * fabs(best))) {
            beaten++;
            if (beaten <= 3)
                SFM_TEST_LOG("beaten: KKT %.15g, sample %.15g", fc, best);
        }
    }
    SFM_TEST_LOG("%d states (%d with a constraint active, %d of them the distance; %d redrawn: "
                 "disk reaching the leader or no admissible point): KKT optimum beaten by a grid "
                 "or random point in %d",
                 done, boundary, distance_active, singular, beaten);
    SFM_CHECK_EQ_INT(beaten, 0);
}

SFM_TEST(r2r_motion_native_range_thousands)
{
    many_states(t, SFM_R2R_MOTION_RANGE);
}

SFM_TEST(r2r_motion_native_bearing_thousands)
{
    many_states(t, SFM_R2R_MOTION_BEARING);
}
