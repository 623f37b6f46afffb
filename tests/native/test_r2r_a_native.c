/*
 * The robot-to-robot base systems with a step of three or more equations on
 * many more random noise-free instances than the portable unit tests run
 * (100000 per closed-form system, 20000 for the template-based DB1_D_D_D):
 * the same checks (tests/unit/r2r_a_scene.h), truth among the solutions in
 * at least 99.9 % and every returned solution reproducing the measurements.
 */
#include "../unit/r2r_a_scene.h"

SFM_TEST(r2r_a_native_closed_forms_100k)
{
    run_system(t, &sfmi_r2r_db1b2_d, 100000);
    run_system(t, &sfmi_r2r_b1b2_b1, 100000);
    run_system(t, &sfmi_r2r_b1b2_d_d, 100000);
    run_system(t, &sfmi_r2r_db1_b1_d, 100000);
    run_system(t, &sfmi_r2r_db1_b2_d, 100000);
}

SFM_TEST(r2r_a_native_db1_d_d_d_20k)
{
    run_system(t, &sfmi_r2r_db1_d_d_d, 20000);
}
