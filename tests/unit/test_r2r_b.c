/*
 * The bearing/distance-only robot-to-robot base systems (B1_B1_B1,
 * B1_B1_B2, B1_B1_D_D, B1_B2_D_D, B1_D_D_D_D) on random noise-free scenes:
 * the true (C, p) must be among the returned solutions in at least 99.9 %
 * of the instances, every returned solution must be a rotation that
 * reproduces the measurements, and no more solutions than the complex count.
 */
#include "r2r_sim.h"

/* the solvers' work memory, as the descriptors size it */
static double sys_ws[4096];

static void check_system(sfm_test_ctx *t, const sfmi_r2r_system_desc *desc, int trials,
                         double *ws)
{
    SFM_CHECK(desc->ws_doubles <= sizeof sys_ws / sizeof sys_ws[0]);
    if (!ws)
        ws = sys_ws;
    r2r_sim_stats st = r2r_sim_run(t, desc, trials, 1e-6, ws);
    SFM_TEST_LOG("%s: truth in %d of %d (%.3f %%), status failures %d, most solutions %d, "
                 "bad solutions %d, worst error %.2g",
                 desc->name, st.found, st.trials, 100.0 * st.found / st.trials, st.failed_status,
                 st.most, st.spurious, st.worst_found);
    SFM_CHECK_MSG(st.found * 1000 >= st.trials * 999, "%s: truth in %d of %d", desc->name,
                  st.found, st.trials);
    SFM_CHECK(st.most <= desc->max_solutions);
    SFM_CHECK_EQ_INT(st.spurious, 0);
}

SFM_TEST(r2r_b1_b1_b1_truth_among_solutions)
{
    check_system(t, &sfmi_r2r_b1_b1_b1, SFM_TEST_ITERS(3000), NULL);
}

SFM_TEST(r2r_b1_b1_b2_truth_among_solutions)
{
    check_system(t, &sfmi_r2r_b1_b1_b2, SFM_TEST_ITERS(3000), NULL);
}

SFM_TEST(r2r_b1_b1_d_d_truth_among_solutions)
{
    check_system(t, &sfmi_r2r_b1_b1_d_d, SFM_TEST_ITERS(3000), NULL);
}

SFM_TEST(r2r_b1_b2_d_d_truth_among_solutions)
{
    check_system(t, &sfmi_r2r_b1_b2_d_d, SFM_TEST_ITERS(3000), NULL);
}

SFM_TEST(r2r_b1_d_d_d_d_truth_among_solutions)
{
    /* the slowest of the six (a scan of about 1500 resultants): fewer
     * instances here, the long run is in tests/native/test_r2r_b_long.c */
    check_system(t, &sfmi_r2r_b1_d_d_d_d, SFM_TEST_ITERS(1000), NULL);
}

/* Both robots standing still (they may turn on the spot): no base system
 * determines (C, p); every solver says so and writes nothing. */
SFM_TEST(r2r_b_standing_still_is_degenerate)
{
    const sfmi_r2r_system_desc *sys[] = {&sfmi_r2r_b1_b1_b1, &sfmi_r2r_b1_b1_b2,
                                         &sfmi_r2r_b1_b1_d_d, &sfmi_r2r_b1_b2_d_d,
                                         &sfmi_r2r_b1_d_d_d_d};
    for (unsigned i = 0; i < sizeof sys / sizeof sys[0]; i++) {
        sfm_r2r_step steps[6];
        sfm_r2r_transform truth, out[SFM_R2R_MAX_SOLUTIONS];
        r2r_sim_scene(t, sys[i], 3.0, steps, &truth);
        for (int k = 1; k < sys[i]->n_steps; k++) {
            for (int j = 0; j < 3; j++)
                steps[k].t1.v[j] = steps[k].t2.v[j] = 0.0;
            r2r_sim_measure(&steps[k], &truth);
        }
        sfm_test_fill_canary(out, sizeof out);
        int n = sys[i]->solve(steps, out, sys_ws);
        SFM_CHECK_MSG(n == SFM_E_DEGENERATE, "%s: %d", sys[i]->name, n);
        SFM_CHECK(sfm_test_canary_intact(out, sizeof out));
    }
}

/* Robot 2 standing still while robot 1 moves: robot 2's rotation about
 * its own position is unobservable from its position alone; the systems
 * that see it only through its positions say so. */
SFM_TEST(r2r_b_robot2_still_is_degenerate)
{
    const sfmi_r2r_system_desc *sys[] = {&sfmi_r2r_b1_b1_b1, &sfmi_r2r_b1_b1_d_d,
                                         &sfmi_r2r_b1_d_d_d_d};
    for (unsigned i = 0; i < sizeof sys / sizeof sys[0]; i++) {
        sfm_r2r_step steps[6];
        sfm_r2r_transform truth, out[SFM_R2R_MAX_SOLUTIONS];
        r2r_sim_scene(t, sys[i], 3.0, steps, &truth);
        for (int k = 1; k < sys[i]->n_steps; k++) {
            for (int j = 0; j < 3; j++)
                steps[k].t2.v[j] = 0.0;
            r2r_sim_measure(&steps[k], &truth);
        }
        sfm_test_fill_canary(out, sizeof out);
        int n = sys[i]->solve(steps, out, sys_ws);
        SFM_CHECK_MSG(n == SFM_E_DEGENERATE, "%s: %d", sys[i]->name, n);
        SFM_CHECK(sfm_test_canary_intact(out, sizeof out));
    }
}
