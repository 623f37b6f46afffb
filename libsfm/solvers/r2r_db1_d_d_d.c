/*
 * Robot-to-robot base system DB1_D_D_D: {d, b1} at the first step, one
 * distance at each of three more steps. Zhou & Roumeliotis (T-RO 2013)
 * call it System 10 and report 8 solutions.
 *
 * The first step gives p outright: with the identity ego-motion,
 * p = d_0 b1_0. Each later distance then reads
 *   |C t2_k + u_k|^2 = d_k^2,  u_k = p - t1_k
 *   <=>  u_k^T C t2_k = (d_k^2 - |t2_k|^2 - |u_k|^2) / 2,
 * three bilinear equations in C alone. On the Cayley form of C they are
 * three quadrics with 8 common roots (the Bezout bound, reached for generic
 * data): the generated action-matrix solver sfmi_tmpl_sys10 returns them.
 * Rotations by exactly pi have no Cayley vector; one that close to pi is
 * recovered with a correspondingly large vector (and lost only within about
 * 1e-6 rad of pi).
 * Stack: the template's, about 10.5 KB; no workspace.
 */
#include <math.h>

#include "solvers/generated/r2r_tmpl.h"
#include "solvers/r2r_axis.h"
#include "solvers/r2r_internal.h"

static int solve_db1_d_d_d(const sfm_r2r_step *steps, sfm_r2r_transform *out, double *ws)
{
    (void)ws;
    double p[3], in[SFMI_TMPL_SYS10_NIN], sol[SFMI_TMPL_SYS10_NSOL * SFMI_TMPL_SYS10_NX];
    for (int i = 0; i < 3; i++)
        p[i] = steps[0].d * steps[0].b1.v[i];
    for (int k = 0; k < 3; k++) {
        const sfm_r2r_step *s = &steps[k + 1];
        double *u = in + 7 * k, *v = u + 3;
        for (int i = 0; i < 3; i++) {
            u[i] = p[i] - s->t1.v[i];
            v[i] = s->t2.v[i];
        }
        u[6] = 0.5 * (s->d * s->d - sfmi_dot3(v, v) - sfmi_dot3(u, u));
    }
    int m = sfmi_tmpl_sys10(in, sol);
    if (m < 0)
        return m;
    int n = 0;
    for (int j = 0; j < m; j++) {
        const double *sv = sol + 3 * j;
        double ss = sfmi_dot3(sv, sv), C[9];
        double S[9] = {0.0, -sv[2], sv[1], sv[2], 0.0, -sv[0], -sv[1], sv[0], 0.0};
        for (int r = 0; r < 3; r++)
            for (int c = 0; c < 3; c++)
                C[3 * r + c] = ((r == c ? 1.0 - ss : 0.0) + 2.0 * S[3 * r + c] +
                                2.0 * sv[r] * sv[c]) / (1.0 + ss);
        sfmi_r2r_emit(steps, 4, C, p, out, &n);
    }
    return n;
}

const sfmi_r2r_system_desc sfmi_r2r_db1_d_d_d = {
    SFM_R2R_SYS_DB1_D_D_D,
    4,
    {SFM_R2R_D | SFM_R2R_B1, SFM_R2R_D, SFM_R2R_D, SFM_R2R_D, 0, 0},
    8,
    0,
    solve_db1_d_d_d,
    "db1_d_d_d",
};
