/*
 * Robot-to-robot base system DB1_DB1: {d, b1} at two steps. The six scalar
 * equations have rank 5, so the system has no finite solution set: every
 * call is SFM_E_DEGENERATE.
 *
 * Why: with the identity ego-motion at step 0, p = d_0 b1_0. At step 1,
 * d_1 and b1_1 give robot 2's position there in {1} outright,
 * C t2_1 + p = t1_1 + d_1 R1_1 b1_1, i.e. the single correspondence
 * C t2_1 = w. Since |C t2_1| = |t2_1| for every rotation, one of its three
 * equations is |w| = |t2_1|, a condition on the data that holds whenever
 * the data are exact and constrains nothing; the other two leave C free to
 * turn about w (x_{1} = R_w(theta) C0 x_{2} + p fits all six measurements
 * for every theta; tests/unit/test_r2r_a.c checks this on random instances).
 * One more scalar measurement from any later step makes it finite: the
 * dispatcher must take a seventh equation (e.g. {d,b1} {d,b1} {d} has two
 * solutions on that circle) or report the sequence degenerate.
 * Zhou & Roumeliotis (T-RO 2013) count base systems as sequences of six
 * equations too; this one's place in their table is not established here.
 */
#include "solvers/r2r_internal.h"

const sfmi_r2r_system_desc sfmi_r2r_db1_db1 = {
    SFM_R2R_SYS_DB1_DB1,
    2,
    {SFM_R2R_D | SFM_R2R_B1, SFM_R2R_D | SFM_R2R_B1, 0, 0, 0, 0},
    0, /* a one-parameter family, not a finite set */
    0,
    sfmi_r2r_solve_rank5,
    "db1_db1",
};
