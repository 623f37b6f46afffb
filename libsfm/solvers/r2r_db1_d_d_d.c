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
 * Rotations by exactly pi have no Cayley vector; near pi the vector is
 * large and the template's roots lose digits, as they do when two roots
 * nearly meet. Each root is therefore polished by two Gauss-Newton steps
 * on the three equations over a rotation increment, C <- cay(delta/2) C,
 * whose Jacobian rows are (C v_k) x u_k.
 * Work memory: the template's matrices, SFMI_TMPL_SYS10_WS doubles of ws;
 * stack under 3 KB (gcc -O2 x86-64: 1152 bytes here, 704 in the template
 * function, 848 in its back end and the eigensolver).
 */
#include <math.h>

#include "solvers/generated/r2r_tmpl.h"
#include "solvers/r2r_align.h"
#include "solvers/r2r_internal.h"

/* Cayley rotation (1 + s's) C = (1 - s's) I + 2 [s]x + 2 s s^T. */
static void cayley(const double s[3], double C[9])
{
    double ss = sfmi_dot3(s, s);
    double S[9] = {0.0, -s[2], s[1], s[2], 0.0, -s[0], -s[1], s[0], 0.0};
    for (int r = 0; r < 3; r++)
        for (int c = 0; c < 3; c++)
            C[3 * r + c] = ((r == c ? 1.0 - ss : 0.0) + 2.0 * S[3 * r + c] + 2.0 * s[r] * s[c]) /
                           (1.0 + ss);
}

/* Gauss-Newton on u_k^T C v_k = c_k (inputs as packed for the template). */
static void polish(const double *in, double C[9])
{
    for (int iter = 0; iter < 2; iter++) {
        double J[3][3], f[3];
        for (int k = 0; k < 3; k++) {
            const double *u = in + 7 * k, *v = u + 3;
            double w[3];
            sfmi_matvec3(C, v, w);
            f[k] = sfmi_dot3(u, w) - u[6];
            sfmi_cross3(w, u, J[k]);
        }
        double a[3], b[3], c[3];
        sfmi_cross3(J[1], J[2], a);
        sfmi_cross3(J[2], J[0], b);
        sfmi_cross3(J[0], J[1], c);
        double det = sfmi_dot3(J[0], a);
        double jn = sfmi_dot3(J[0], J[0]) + sfmi_dot3(J[1], J[1]) + sfmi_dot3(J[2], J[2]);
        if (!(fabs(det) > 1e-9 * jn * sqrt(jn)))
            return;
        double h[3], R[9], Cn[9];
        for (int i = 0; i < 3; i++)
            h[i] = -0.5 * (f[0] * a[i] + f[1] * b[i] + f[2] * c[i]) / det;
        cayley(h, R);
        sfmi_matmul3(R, C, Cn);
        for (int i = 0; i < 9; i++)
            C[i] = Cn[i];
    }
}

static int solve_db1_d_d_d(const sfm_r2r_step *steps, sfm_r2r_transform *out, double *ws)
{
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
    int m = sfmi_tmpl_sys10(in, sol, ws);
    if (m < 0)
        return m;
    int n = 0;
    for (int j = 0; j < m; j++) {
        double C[9];
        cayley(sol + 3 * j, C);
        polish(in, C);
        sfmi_r2r_emit(steps, 4, C, p, out, &n);
    }
    return n;
}

const sfmi_r2r_system_desc sfmi_r2r_db1_d_d_d = {
    SFM_R2R_SYS_DB1_D_D_D,
    4,
    {SFM_R2R_D | SFM_R2R_B1, SFM_R2R_D, SFM_R2R_D, SFM_R2R_D, 0, 0},
    8,
    SFMI_TMPL_SYS10_WS,
    solve_db1_d_d_d,
    "db1_d_d_d",
};
