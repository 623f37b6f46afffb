/*
 * Robot-to-robot base system B1B2_B1: {b1, b2} at the first step, b1 at a
 * second. Closed form, 2 solutions. (Zhou & Roumeliotis, T-RO 2013, solve
 * it in closed form; its number in their table is not established here.)
 *
 * Step 0 (identity ego-motion): p = lambda b with b = b1_0, lambda > 0, and
 * C b2_0 = -b, so C = R_n(theta) C0 on the circle about n = -b. Step 1:
 * q = C t2_1 + lambda b - t1_1 is parallel to f = R1_1 b1_1, i.e. q lies in
 * the plane spanned by f and b, whose normal m = b x f does not see lambda:
 *   m^T C t2_1 = m^T t1_1,
 * linear in (cos theta, sin theta), two rotations. For each, lambda and
 * |q| = mu follow from lambda b - mu f = t1_1 - C t2_1 (two unknowns, the
 * plane's two equations). Solutions that put a bearing backwards (lambda or
 * mu negative: the algebra only sees lines) are dropped.
 * Degenerate: f parallel to b (the second bearing adds no plane).
 * Stack under 1 KB; no workspace.
 */
#include <math.h>

#include "solvers/r2r_align.h"
#include "solvers/r2r_internal.h"

static int solve_b1b2_b1(const sfm_r2r_step *steps, sfm_r2r_transform *out, double *ws)
{
    (void)ws;
    const double *b = steps[0].b1.v;
    double v[3], f[3], mvec[3], C0[9], n[3], e1[3], e2[3], C[2][9];
    for (int i = 0; i < 3; i++)
        v[i] = -b[i];
    if (!sfmi_r2r_align(steps[0].b2.v, v, C0) || !sfmi_r2r_unit_frame(v, n, e1, e2))
        return SFM_E_SINGULAR;
    sfmi_matvec3(steps[1].R1.m, steps[1].b1.v, f);
    sfmi_cross3(b, f, mvec);
    double g = sfmi_dot3(b, f);
    if (!(1.0 - g * g > 1e-12))
        return 0;
    const double *t1 = steps[1].t1.v, *t2 = steps[1].t2.v;
    int m = sfmi_r2r_circle_solve(C0, n, t2, mvec, sfmi_dot3(mvec, t1), C), cnt = 0;
    for (int j = 0; j < m; j++) {
        double w[3], r[3], p[3];
        sfmi_matvec3(C[j], t2, w);
        for (int i = 0; i < 3; i++)
            r[i] = t1[i] - w[i];
        /* lambda - g mu = r.b, g lambda - mu = r.f */
        double al = sfmi_dot3(r, b), be = sfmi_dot3(r, f);
        double mu = (g * al - be) / (1.0 - g * g), lam = al + g * mu;
        if (!(lam > 0.0) || !(mu > 0.0))
            continue;
        for (int i = 0; i < 3; i++)
            p[i] = lam * b[i];
        sfmi_r2r_emit(steps, 2, C[j], p, out, &cnt);
    }
    return cnt;
}

const sfmi_r2r_system_desc sfmi_r2r_b1b2_b1 = {
    SFM_R2R_SYS_B1B2_B1,
    2,
    {SFM_R2R_B1 | SFM_R2R_B2, SFM_R2R_B1, 0, 0, 0, 0},
    2,
    0,
    solve_b1b2_b1,
    "b1b2_b1",
};
