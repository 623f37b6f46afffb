/*
 * Robot-to-robot base system B1_B1_B1: robot 1 sees robot 2 (bearing b1) at
 * three steps, nothing else (Zhou & Roumeliotis, IEEE T-RO 2013, the system
 * of three bearings from one robot; 8 complex solutions).
 *
 * Canonical form (libsfm/solvers/r2r_internal.h): steps[0] has the identity
 * ego-motion. With u_k = R1_k b1_k (unit, in {1}), the three bearings say
 *   p = l u0,   C t2_k + p - t1_k = m_k u_k   (k = 1, 2; l, m_k the distances).
 * C drops out through the rotation's invariants: a_k = t1_k - l u0 + m_k u_k
 * is C t2_k, so |a_1| = |t2_1|, |a_2| = |t2_2| and a_1.a_2 = t2_1.t2_2, three
 * quadratics in (l, m1, m2) with Bezout number 8, which the generic
 * elimination template attains (generated/r2r_tmpl_b1_b1_b1.c, 27x35,
 * action matrix 8x8). Each real root with l, m1, m2 > 0 (the bearings point
 * at the robot) is polished by two Newton steps, dropped unless the
 * equations then confirm it, and gives C as the one rotation taking
 * (t2_1, t2_2) to (a_1, a_2).
 *
 * Degenerate motion: robot 2's positions t2_1, t2_2 must span a plane (else
 * C is not determined): SFM_E_DEGENERATE. The template's matrices live in
 * ws (the descriptor's ws_doubles).
 */
#include <math.h>

#include "solvers/generated/r2r_tmpl.h"
#include "solvers/r2r_align.h"
#include "solvers/r2r_internal.h"

/* The three quadratics in (l, m1, m2) and their Jacobian; in = (a, b, c). */
static void equations(const double *in, const double *x, double f[3], double J[9])
{
    const double *a = in, *b = in + 4, *c = in + 8;
    double l = x[0], m1 = x[1], m2 = x[2];
    f[0] = m1 * m1 + l * l + a[0] * l * m1 + a[1] * l + a[2] * m1 + a[3];
    f[1] = m2 * m2 + l * l + b[0] * l * m2 + b[1] * l + b[2] * m2 + b[3];
    f[2] = l * l + c[0] * l * m1 + c[1] * l * m2 + c[2] * m1 * m2 + c[3] * l + c[4] * m1 +
           c[5] * m2 + c[6];
    J[0] = 2 * l + a[0] * m1 + a[1];
    J[1] = 2 * m1 + a[0] * l + a[2];
    J[2] = 0.0;
    J[3] = 2 * l + b[0] * m2 + b[1];
    J[4] = 0.0;
    J[5] = 2 * m2 + b[0] * l + b[2];
    J[6] = 2 * l + c[0] * m1 + c[1] * m2 + c[3];
    J[7] = c[0] * l + c[2] * m2 + c[4];
    J[8] = c[1] * l + c[2] * m1 + c[5];
}

static int solve(const sfm_r2r_step *s, sfm_r2r_transform *out, double *ws)
{
    double u0[3], u1[3], u2[3];
    sfmi_r2r_u(&s[0], u0);
    sfmi_r2r_u(&s[1], u1);
    sfmi_r2r_u(&s[2], u2);
    const double *t11 = s[1].t1.v, *t12 = s[2].t1.v, *t21 = s[1].t2.v, *t22 = s[2].t2.v;
    double n[3];
    sfmi_cross3(t21, t22, n);
    if (!(sqrt(sfmi_dot3(n, n)) > 1e-9 * sqrt(sfmi_dot3(t21, t21) * sfmi_dot3(t22, t22))))
        return SFM_E_DEGENERATE;
    double in[SFMI_TMPL_B1_B1_B1_NIN], *a = in, *b = in + 4, *c = in + 8;
    a[0] = -2.0 * sfmi_dot3(u0, u1);
    a[1] = -2.0 * sfmi_dot3(u0, t11);
    a[2] = 2.0 * sfmi_dot3(u1, t11);
    a[3] = sfmi_dot3(t11, t11) - sfmi_dot3(t21, t21);
    b[0] = -2.0 * sfmi_dot3(u0, u2);
    b[1] = -2.0 * sfmi_dot3(u0, t12);
    b[2] = 2.0 * sfmi_dot3(u2, t12);
    b[3] = sfmi_dot3(t12, t12) - sfmi_dot3(t22, t22);
    c[0] = -sfmi_dot3(u0, u1);
    c[1] = -sfmi_dot3(u0, u2);
    c[2] = sfmi_dot3(u1, u2);
    c[3] = -sfmi_dot3(u0, t11) - sfmi_dot3(u0, t12);
    c[4] = sfmi_dot3(u1, t12);
    c[5] = sfmi_dot3(u2, t11);
    c[6] = sfmi_dot3(t11, t12) - sfmi_dot3(t21, t22);
    double sol[SFMI_TMPL_B1_B1_B1_NSOL * 3];
    int ns = sfmi_tmpl_b1_b1_b1(in, sol, ws);
    if (ns < 0)
        return ns;
    int n_out = 0;
    for (int k = 0; k < ns; k++) {
        double *x = sol + 3 * k;
        if (!sfmi_r2r_polish3(equations, in, x))
            continue;
        if (!(x[0] > 0.0 && x[1] > 0.0 && x[2] > 0.0))
            continue;
        double a1[3], a2[3];
        for (int i = 0; i < 3; i++) {
            a1[i] = t11[i] - x[0] * u0[i] + x[1] * u1[i];
            a2[i] = t12[i] - x[0] * u0[i] + x[2] * u2[i];
        }
        sfm_r2r_transform T;
        if (!sfmi_r2r_align2(t21, t22, a1, a2, T.C.m))
            continue;
        for (int i = 0; i < 3; i++)
            T.p.v[i] = x[0] * u0[i];
        out[n_out++] = T;
    }
    return n_out;
}

const sfmi_r2r_system_desc sfmi_r2r_b1_b1_b1 = {
    SFM_R2R_SYS_B1_B1_B1, 3, {SFM_R2R_B1, SFM_R2R_B1, SFM_R2R_B1, 0, 0, 0},
    SFMI_TMPL_B1_B1_B1_NSOL, SFMI_TMPL_B1_B1_B1_WS, solve, "b1_b1_b1"};
