/*
 * Robot-to-robot base system B1_B1_B2: robot 1 sees robot 2 at two steps
 * (b1), robot 2 sees robot 1 at a third (b2) (Zhou & Roumeliotis, IEEE
 * T-RO 2013, the system of two bearings from one robot and one from the
 * other; 8 complex solutions).
 *
 * Canonical form: steps[0] has the identity ego-motion. With u_k = R1_k b1_k
 * (in {1}) and w = R2_2 b2_2 (in {2}) the bearings say
 *   p = l u0,   C t2_1 + p - t1_1 = m u1,   C^T (t1_2 - p) - t2_2 = n w
 * (l, m, n the distances at steps 0, 1, 2). So a = t1_1 - l u0 + m u1 is
 * C t2_1 and b = t1_2 - l u0 is C (t2_2 + n w): C drops out through
 * |a| = |t2_1|, |b| = |t2_2 + n w| and a.b = t2_1.(t2_2 + n w), three
 * quadratics in (l, m, n), Bezout number 8, attained by the generic template
 * (generated/r2r_tmpl_b1_b1_b2.c, 27x35, action matrix 8x8). Real roots with
 * l, m, n > 0 are polished by two Newton steps and dropped unless the
 * equations then confirm them; C is the rotation taking (t2_1, t2_2 + n w)
 * to (a, b).
 *
 * Degenerate motion: robot 2 must have moved by step 1 (t2_1 != 0), else a
 * rotation about one axis stays free: SFM_E_DEGENERATE. A root whose pair
 * (t2_1, t2_2 + n w) is parallel is dropped. The template's matrices live
 * in ws (the descriptor's ws_doubles).
 */
#include <math.h>

#include "solvers/generated/r2r_tmpl.h"
#include "solvers/r2r_align.h"
#include "solvers/r2r_internal.h"

/* The three quadratics in (l, m, n) and their Jacobian; in = (a, b, c). */
static void equations(const double *in, const double *x, double f[3], double J[9])
{
    const double *a = in, *b = in + 4, *c = in + 7;
    double l = x[0], m = x[1], n = x[2];
    f[0] = m * m + l * l + a[0] * l * m + a[1] * l + a[2] * m + a[3];
    f[1] = l * l - n * n + b[0] * l + b[1] * n + b[2];
    f[2] = l * l + c[0] * l * m + c[1] * l + c[2] * m + c[3] * n + c[4];
    J[0] = 2 * l + a[0] * m + a[1];
    J[1] = 2 * m + a[0] * l + a[2];
    J[2] = 0.0;
    J[3] = 2 * l + b[0];
    J[4] = 0.0;
    J[5] = -2 * n + b[1];
    J[6] = 2 * l + c[0] * m + c[1];
    J[7] = c[0] * l + c[2];
    J[8] = c[3];
}

static int solve(const sfm_r2r_step *s, sfm_r2r_transform *out, double *ws)
{
    double u0[3], u1[3], w[3];
    sfmi_r2r_u(&s[0], u0);
    sfmi_r2r_u(&s[1], u1);
    sfmi_r2r_w(&s[2], w);
    const double *t11 = s[1].t1.v, *t12 = s[2].t1.v, *t21 = s[1].t2.v, *t22 = s[2].t2.v;
    double scale = 1.0 + sqrt(sfmi_dot3(t11, t11) + sfmi_dot3(t12, t12) +
                              sfmi_dot3(t22, t22));
    if (!(sqrt(sfmi_dot3(t21, t21)) > 1e-9 * scale))
        return SFM_E_DEGENERATE;
    double in[SFMI_TMPL_B1_B1_B2_NIN], *a = in, *b = in + 4, *c = in + 7;
    a[0] = -2.0 * sfmi_dot3(u0, u1);
    a[1] = -2.0 * sfmi_dot3(u0, t11);
    a[2] = 2.0 * sfmi_dot3(u1, t11);
    a[3] = sfmi_dot3(t11, t11) - sfmi_dot3(t21, t21);
    b[0] = -2.0 * sfmi_dot3(u0, t12);
    b[1] = -2.0 * sfmi_dot3(w, t22);
    b[2] = sfmi_dot3(t12, t12) - sfmi_dot3(t22, t22);
    c[0] = -sfmi_dot3(u0, u1);
    c[1] = -sfmi_dot3(u0, t11) - sfmi_dot3(u0, t12);
    c[2] = sfmi_dot3(u1, t12);
    c[3] = -sfmi_dot3(t21, w);
    c[4] = sfmi_dot3(t11, t12) - sfmi_dot3(t21, t22);
    double sol[SFMI_TMPL_B1_B1_B2_NSOL * 3];
    int ns = sfmi_tmpl_b1_b1_b2(in, sol, ws);
    if (ns < 0)
        return ns;
    int n_out = 0;
    for (int k = 0; k < ns; k++) {
        double *x = sol + 3 * k;
        if (!sfmi_r2r_polish3(equations, in, x))
            continue;
        if (!(x[0] > 0.0 && x[1] > 0.0 && x[2] > 0.0))
            continue;
        double va[3], vb[3], v2[3];
        for (int i = 0; i < 3; i++) {
            va[i] = t11[i] - x[0] * u0[i] + x[1] * u1[i];
            vb[i] = t12[i] - x[0] * u0[i];
            v2[i] = t22[i] + x[2] * w[i];
        }
        sfm_r2r_transform T;
        if (!sfmi_r2r_align2(t21, v2, va, vb, T.C.m))
            continue;
        for (int i = 0; i < 3; i++)
            T.p.v[i] = x[0] * u0[i];
        out[n_out++] = T;
    }
    return n_out;
}

const sfmi_r2r_system_desc sfmi_r2r_b1_b1_b2 = {
    SFM_R2R_SYS_B1_B1_B2, 3, {SFM_R2R_B1, SFM_R2R_B1, SFM_R2R_B2, 0, 0, 0},
    SFMI_TMPL_B1_B1_B2_NSOL, SFMI_TMPL_B1_B1_B2_WS, solve, "b1_b1_b2"};
