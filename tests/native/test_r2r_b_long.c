/*
 * The long runs of the bearing/distance-only robot-to-robot base systems
 * (tests/unit/test_r2r_b.c runs fewer instances so it also fits the
 * emulated targets): the truth among the solutions in at least 99.9 % of
 * many random noise-free scenes; the log line gives the rate.
 */
#include "../unit/r2r_sim.h"

static double sys_ws[4096]; /* the solvers' work memory */

static void long_run(sfm_test_ctx *t, const sfmi_r2r_system_desc *desc, int trials)
{
    SFM_CHECK(desc->ws_doubles <= sizeof sys_ws / sizeof sys_ws[0]);
    r2r_sim_stats st = r2r_sim_run(t, desc, trials, 1e-6, sys_ws);
    SFM_TEST_LOG("%s: truth in %d of %d (%.3f %%), status failures %d, most solutions %d, "
                 "bad solutions %d",
                 desc->name, st.found, st.trials, 100.0 * st.found / st.trials, st.failed_status,
                 st.most, st.spurious);
    SFM_CHECK_MSG(st.found * 1000 >= st.trials * 999, "%s: truth in %d of %d", desc->name,
                  st.found, st.trials);
    SFM_CHECK_EQ_INT(st.spurious, 0);
}

SFM_TEST(r2r_b_long_b1_b1_b1) { long_run(t, &sfmi_r2r_b1_b1_b1, 30000); }
SFM_TEST(r2r_b_long_b1_b1_b2) { long_run(t, &sfmi_r2r_b1_b1_b2, 30000); }
SFM_TEST(r2r_b_long_b1_b1_d_d) { long_run(t, &sfmi_r2r_b1_b1_d_d, 30000); }
SFM_TEST(r2r_b_long_b1_b2_d_d) { long_run(t, &sfmi_r2r_b1_b2_d_d, 30000); }
SFM_TEST(r2r_b_long_b1_d_d_d_d) { long_run(t, &sfmi_r2r_b1_d_d_d_d, 3000); }
