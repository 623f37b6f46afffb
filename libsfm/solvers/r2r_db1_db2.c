/*
 * Robot-to-robot base system DB1_DB2: {d, b1} at one step, {d, b2} at
 * another. The six scalar equations have rank 5, so the system has no
 * finite solution set: every call is SFM_E_DEGENERATE.
 *
 * Why: with the identity ego-motion at step 0, p = d_0 b1_0. At step 1,
 * d_1 and b2_1 give robot 1's position there in robot 2's first frame,
 * C^T (t1_1 - p) = t2_1 + d_1 R2_1 b2_1 = u, i.e. the single correspondence
 * C u = t1_1 - p. Since |C u| = |u| for every rotation, one of its three
 * equations is |u| = |t1_1 - p|, a condition on the data that holds
 * whenever the data are exact and constrains nothing; the other two leave C
 * free to turn about t1_1 - p (tests/unit/test_r2r_a.c checks the family on
 * random instances). A seventh scalar equation from another step makes it
 * finite; the dispatcher must take one or report the sequence degenerate.
 * Zhou & Roumeliotis (T-RO 2013) count base systems as sequences of six
 * equations too; this one's place in their table is not established here.
 */
#include "solvers/r2r_internal.h"

const sfmi_r2r_system_desc sfmi_r2r_db1_db2 = {
    SFM_R2R_SYS_DB1_DB2,
    2,
    {SFM_R2R_D | SFM_R2R_B1, SFM_R2R_D | SFM_R2R_B2, 0, 0, 0, 0},
    0, /* a one-parameter family, not a finite set */
    0,
    sfmi_r2r_solve_rank5,
    "db1_db2",
};
