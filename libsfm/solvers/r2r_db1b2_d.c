/*
 * Robot-to-robot base system DB1B2_D: {d, b1, b2} at the first step, one
 * distance at a second. Closed form, 2 solutions. (Zhou & Roumeliotis,
 * T-RO 2013, solve this base system in closed form too; its number in their
 * table is not established here.)
 *
 * With the identity ego-motion at step 0: p = d_0 b1_0, and
 * b2_0 = -C^T p / d_0 gives the correspondence C b2_0 = -b1_0, which leaves
 * C on the circle R_n(theta) C0, n = -b1_0. The distance at step 1,
 *   (p - t1_1)^T C t2_1 = (d_1^2 - |t2_1|^2 - |p - t1_1|^2) / 2,
 * is linear in (cos theta, sin theta): two rotations (one when tangent,
 * none when the data admit no rotation). No polynomial solve is needed, so
 * no generated template. Stack under 1 KB; no workspace.
 */
#include "solvers/r2r_align.h"
#include "solvers/r2r_internal.h"

static int solve_db1b2_d(const sfm_r2r_step *steps, sfm_r2r_transform *out, double *ws)
{
    (void)ws;
    double p[3], v[3], y[3];
    for (int i = 0; i < 3; i++) {
        p[i] = steps[0].d * steps[0].b1.v[i];
        v[i] = -steps[0].b1.v[i];
        y[i] = p[i] - steps[1].t1.v[i];
    }
    const double *x = steps[1].t2.v;
    double c = 0.5 * (steps[1].d * steps[1].d - sfmi_dot3(x, x) - sfmi_dot3(y, y));
    int cnt = 0;
    if (!sfmi_r2r_circle_emit(steps, 2, steps[0].b2.v, v, x, y, c, p, out, &cnt))
        return SFM_E_SINGULAR;
    return cnt;
}

const sfmi_r2r_system_desc sfmi_r2r_db1b2_d = {
    SFM_R2R_SYS_DB1B2_D,
    2,
    {SFM_R2R_D | SFM_R2R_B1 | SFM_R2R_B2, SFM_R2R_D, 0, 0, 0, 0},
    2,
    0,
    solve_db1b2_d,
    "db1b2_d",
};
