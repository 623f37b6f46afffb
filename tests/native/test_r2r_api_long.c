/*
 * The dispatcher through the base-system solvers of this build, at host
 * scale: ten random scenes per six-equation combination over six steps
 * (13,910 solves), the truth among the solutions per base system; every
 * system must be built (SFM_E_UNSUPPORTED fails). tests/unit/test_r2r_api.c
 * runs one scene per combination on every target.
 */
#include "../unit/r2r_api_scene.h"
#include "solvers/r2r_solve_internal.h"

SFM_TEST(r2r_solve_native_ten_scenes_per_combination)
{
    static scene sc;
    static sfm_r2r_transform out[SFM_R2R_MAX_SOLUTIONS];
    static double ws[8192];
    int total = n_combos();
    int runs[SFM_R2R_SYS_COUNT_] = {0}, found[SFM_R2R_SYS_COUNT_] = {0};
    int degen[SFM_R2R_SYS_COUNT_] = {0}, absent[SFM_R2R_SYS_COUNT_] = {0};
    size_t wsz = sfm_r2r_solve_workspace_size(6);
    SFM_CHECK(wsz <= sizeof ws);
    for (int rep = 0; rep < 10; rep++)
        for (int i = 0; i < total; i++) {
            unsigned m[6];
            combo(i, m);
            make_scene(t, &sc, 6, m);
            int sys = sfm_r2r_classify(sc.s, 6);
            SFM_CHECK(sys >= 1);
            if (sys < 1)
                continue;
            int n = sfm_r2r_solve(sc.s, 6, out, ws, wsz);
            if (n == SFM_E_UNSUPPORTED) {
                absent[sys] = 1;
                continue;
            }
            runs[sys]++;
            if (n == SFM_E_DEGENERATE)
                degen[sys]++;
            for (int j = 0; j < n; j++)
                if (terr(out + j, &sc.T) < 1e-6) {
                    found[sys]++;
                    break;
                }
        }
    for (int s = 1; s < SFM_R2R_SYS_COUNT_; s++) {
        if (absent[s]) { /* all 14 are built: a lost registry entry fails */
            SFM_TEST_LOG("%s not on this build", sys_names[s]);
            SFM_CHECK(!absent[s]);
            continue;
        }
        if (sfmi_r2r_table[s]->max_solutions == 0) {
            SFM_TEST_LOG("%s: rank-deficient, SFM_E_DEGENERATE in %d of %d", sys_names[s], degen[s], runs[s]);
            SFM_CHECK_EQ_INT(degen[s], runs[s]);
            continue;
        }
        SFM_TEST_LOG("%s: truth among the solutions in %d of %d (%.2f %%), %d degenerate", sys_names[s],
                     found[s], runs[s], 100.0 * found[s] / (runs[s] ? runs[s] : 1), degen[s]);
        SFM_CHECK_MSG(found[s] * 1000 >= runs[s] * 999, "%s: %d of %d", sys_names[s], found[s], runs[s]);
    }
}
