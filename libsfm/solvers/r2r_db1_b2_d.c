/*
 * Robot-to-robot base system DB1_B2_D: {d, b1} at the first step, b2 at a
 * second, d at a third. Closed form, 4 solutions (2 x 2). (Zhou &
 * Roumeliotis, T-RO 2013, solve it in closed form; its number in their table
 * is not established here.)
 *
 * Step 0 (identity ego-motion): p = d_0 b1_0. Step 1: b2_1 says robot 1's
 * position in robot 2's first frame, C^T (t1_1 - p), lies on robot 2's ray
 * t2_1 + mu g (g = R2_1 b2_1, mu = d_1 > 0) at |t1_1 - p| from the origin:
 *   mu^2 + 2 mu g.t2_1 + |t2_1|^2 - |t1_1 - p|^2 = 0,
 * two mu, each a correspondence C (t2_1 + mu g) = t1_1 - p. C is then on a
 * circle about t1_1 - p, where the distance at step 2 is linear in
 * (cos, sin): two rotations per mu. No generated template needed.
 * Stack under 1 KB; no workspace.
 */
#include <math.h>

#include "solvers/r2r_align.h"
#include "solvers/r2r_internal.h"

static int solve_db1_b2_d(const sfm_r2r_step *steps, sfm_r2r_transform *out, double *ws)
{
    (void)ws;
    double p[3], h[3], g[3], y[3];
    for (int i = 0; i < 3; i++) {
        p[i] = steps[0].d * steps[0].b1.v[i];
        h[i] = steps[1].t1.v[i] - p[i];
        y[i] = p[i] - steps[2].t1.v[i];
    }
    sfmi_matvec3(steps[1].R2.m, steps[1].b2.v, g);
    const double *t2 = steps[1].t2.v, *x = steps[2].t2.v;
    double gt = sfmi_dot3(g, t2), tt = sfmi_dot3(t2, t2), hh = sfmi_dot3(h, h), mus[2];
    int nr = sfmi_r2r_quadratic_roots(-gt, gt * gt - tt + hh, hh + tt, mus), cnt = 0;
    double c = 0.5 * (steps[2].d * steps[2].d - sfmi_dot3(x, x) - sfmi_dot3(y, y));
    for (int r = 0; r < nr; r++) {
        double mu = mus[r], u[3];
        if (!(mu > 0.0))
            continue;
        for (int i = 0; i < 3; i++)
            u[i] = t2[i] + mu * g[i];
        sfmi_r2r_circle_emit(steps, 3, u, h, x, y, c, p, out, &cnt);
    }
    return cnt;
}

const sfmi_r2r_system_desc sfmi_r2r_db1_b2_d = {
    SFM_R2R_SYS_DB1_B2_D,
    3,
    {SFM_R2R_D | SFM_R2R_B1, SFM_R2R_B2, SFM_R2R_D, 0, 0, 0},
    4,
    0,
    solve_db1_b2_d,
    "db1_b2_d",
};
