/*
 * Robot-to-robot base system DB1_B1_D: {d, b1} at the first step, b1 at a
 * second, d at a third. Closed form, 4 solutions (2 x 2). (Zhou &
 * Roumeliotis, T-RO 2013, solve it in closed form; its number in their table
 * is not established here.)
 *
 * Step 0 (identity ego-motion): p = d_0 b1_0. Step 1: robot 2's position
 * C t2_1 + p lies on robot 1's ray t1_1 + mu f (f = R1_1 b1_1, mu > 0) and at
 * |t2_1| from p, so with h = p - t1_1
 *   mu^2 - 2 mu f.h + |h|^2 - |t2_1|^2 = 0,
 * two mu, each a correspondence C t2_1 = mu f - h. That leaves C on a circle
 * about (mu f - h); the distance at step 2 is linear in (cos, sin) on it:
 * two rotations per mu. No polynomial beyond a quadratic, so no generated
 * template. Stack under 1 KB; no workspace.
 */
#include <math.h>

#include "solvers/r2r_align.h"
#include "solvers/r2r_internal.h"

static int solve_db1_b1_d(const sfm_r2r_step *steps, sfm_r2r_transform *out, double *ws)
{
    (void)ws;
    double p[3], h[3], f[3], y[3];
    for (int i = 0; i < 3; i++) {
        p[i] = steps[0].d * steps[0].b1.v[i];
        h[i] = p[i] - steps[1].t1.v[i];
        y[i] = p[i] - steps[2].t1.v[i];
    }
    sfmi_matvec3(steps[1].R1.m, steps[1].b1.v, f);
    const double *u = steps[1].t2.v, *x = steps[2].t2.v;
    double fh = sfmi_dot3(f, h), hh = sfmi_dot3(h, h), uu = sfmi_dot3(u, u), mus[2];
    int nr = sfmi_r2r_quadratic_roots(fh, fh * fh - hh + uu, hh + uu, mus), cnt = 0;
    double c = 0.5 * (steps[2].d * steps[2].d - sfmi_dot3(x, x) - sfmi_dot3(y, y));
    for (int r = 0; r < nr; r++) {
        double mu = mus[r], v[3];
        if (!(mu > 0.0))
            continue;
        for (int i = 0; i < 3; i++)
            v[i] = mu * f[i] - h[i];
        sfmi_r2r_circle_emit(steps, 3, u, v, x, y, c, p, out, &cnt);
    }
    return cnt;
}

const sfmi_r2r_system_desc sfmi_r2r_db1_b1_d = {
    SFM_R2R_SYS_DB1_B1_D,
    3,
    {SFM_R2R_D | SFM_R2R_B1, SFM_R2R_B1, SFM_R2R_D, 0, 0, 0},
    4,
    0,
    solve_db1_b1_d,
    "db1_b1_d",
};
