/*
 * Robot-to-robot base system B1B2_D_D: {b1, b2} at the first step, one
 * distance at each of two more. Closed form through one quartic, 4
 * solutions. (Zhou & Roumeliotis, T-RO 2013; its number in their table is
 * not established here.)
 *
 * Step 0 (identity ego-motion): p = lambda b, b = b1_0, lambda > 0, and
 * C b2_0 = -b puts C on the circle R_n(theta) C0 about n = -b. A rotation
 * about b keeps the b-component, so b^T C t2_k = b^T C0 t2_k = beta_k is
 * known, and the distance at step k (k = 1, 2) reads
 *   lambda^2 + alpha_k lambda + rho_k - 2 A_k cos - 2 B_k sin = 0,
 *   alpha_k = 2 (beta_k - b.t1_k), rho_k = |t1_k|^2 + |t2_k|^2 - d_k^2 - 2 E_k,
 * with t1_k^T C t2_k = A_k cos + B_k sin + E_k on the circle. The
 * difference of the two is linear in lambda; lambda substituted into the
 * first, and the half-angle tangent t (cos = (1-t^2)/(1+t^2),
 * sin = 2t/(1+t^2)) leave one quartic in t: 4 complex solutions. The
 * tangent's pole is put at whichever quarter-turn the quartic is largest at
 * (as in relpose_upright_3pt.c), so no rotation about b is singular.
 * Degenerate (SFM_E_SINGULAR): alpha_1 = alpha_2 (then lambda drops out of
 * the difference), or a quartic that cancels to rounding (theta unobservable:
 * robot 2 still or moving along b only).
 * Stack under 2 KB (976 bytes of its own, gcc -O2 x86-64, and the quartic
 * solver's); no workspace.
 */
#include <math.h>

#include "sfm/sfm_poly.h"
#include "solvers/r2r_align.h"
#include "solvers/r2r_internal.h"

static int solve_b1b2_d_d(const sfm_r2r_step *steps, sfm_r2r_transform *out, double *ws)
{
    (void)ws;
    const double *b = steps[0].b1.v;
    double v[3], C0[9], n[3], e1[3], e2[3];
    for (int i = 0; i < 3; i++)
        v[i] = -b[i];
    if (!sfmi_r2r_align(steps[0].b2.v, v, C0) || !sfmi_r2r_unit_frame(v, n, e1, e2))
        return SFM_E_SINGULAR;
    double al[2], rh[2], a[2], bb[2], scale = 0.0;
    for (int k = 0; k < 2; k++) {
        const double *t1 = steps[k + 1].t1.v, *t2 = steps[k + 1].t2.v;
        double z[3], nz[3];
        sfmi_matvec3(C0, t2, z);
        sfmi_cross3(n, z, nz);
        double zn = sfmi_dot3(n, z), yn = sfmi_dot3(n, t1);
        double A = sfmi_dot3(z, t1) - zn * yn, B = sfmi_dot3(nz, t1), E = zn * yn;
        al[k] = 2.0 * (sfmi_dot3(b, z) - sfmi_dot3(b, t1));
        rh[k] = sfmi_dot3(t1, t1) + sfmi_dot3(t2, t2) - steps[k + 1].d * steps[k + 1].d - 2.0 * E;
        a[k] = -2.0 * A;
        bb[k] = -2.0 * B;
        scale += fabs(al[k]);
    }
    double da = al[0] - al[1];
    if (!(fabs(da) > 1e-12 * scale))
        return SFM_E_SINGULAR;
    /* The half-angle tangent has its pole at theta = pi, where the quartic's
     * leading coefficient vanishes with the trigonometric form's value. Of
     * the four quarter-turns of the origin, take the one whose pole sees the
     * largest value (relative to the coefficients' size): no angle is lost. */
    double L[3], Q[5], best = -1.0, bc = 1.0, bs = 0.0, BL[3] = {0.0, 0.0, 0.0}, BQ[5] = {0.0};
    for (int q = 0; q < 4; q++) {
        double cf = q == 0 ? 1.0 : q == 2 ? -1.0 : 0.0, sf = q == 1 ? 1.0 : q == 3 ? -1.0 : 0.0;
        double qa[2], qb[2];
        for (int k = 0; k < 2; k++) {
            qa[k] = a[k] * cf + bb[k] * sf;
            qb[k] = -a[k] * sf + bb[k] * cf;
        }
        double dr = rh[0] - rh[1], dc = qa[0] - qa[1], ds = qb[0] - qb[1];
        /* lambda (1 + t^2) = L0 + L1 t + L2 t^2 */
        L[0] = -(dr + dc) / da;
        L[1] = -2.0 * ds / da;
        L[2] = -(dr - dc) / da;
        double U[3] = {1.0, 0.0, 1.0}, K[3] = {qa[0], 2.0 * qb[0], -qa[0]};
        double Qs[5] = {0.0, 0.0, 0.0, 0.0, 0.0}; /* ascending */
        for (int i = 0; i < 5; i++)
            Q[i] = 0.0;
        for (int i = 0; i < 3; i++)
            for (int j = 0; j < 3; j++) {
                double t0 = L[i] * L[j], t1 = al[0] * L[i] * U[j], t2 = rh[0] * U[i] * U[j];
                double t3 = K[i] * U[j];
                Q[i + j] += t0 + t1 + t2 + t3;
                Qs[i + j] += fabs(t0) + fabs(t1) + fabs(t2) + fabs(t3);
            }
        /* A quartic that cancels to rounding is the identity 0 = 0: theta is
         * unobservable (robot 2 still, or moving only along b). */
        double qmax = 0.0, smax = 0.0;
        for (int i = 0; i < 5; i++) {
            qmax = fabs(Q[i]) > qmax ? fabs(Q[i]) : qmax;
            smax = Qs[i] > smax ? Qs[i] : smax;
        }
        if (!(qmax > 1e-10 * smax))
            return SFM_E_SINGULAR;
        if (fabs(Q[4]) / qmax > best) {
            best = fabs(Q[4]) / qmax;
            bc = cf;
            bs = sf;
            for (int i = 0; i < 3; i++)
                BL[i] = L[i];
            for (int i = 0; i < 5; i++)
                BQ[i] = Q[i];
        }
    }
    double desc[5] = {BQ[4], BQ[3], BQ[2], BQ[1], BQ[0]}, roots[4];
    int m = sfm_poly_roots4(desc, roots), cnt = 0;
    if (m < 0)
        return m;
    for (int j = 0; j < m; j++) {
        double t = roots[j], u = 1.0 + t * t, C[9], p[3];
        double lam = (BL[0] + t * (BL[1] + t * BL[2])) / u;
        if (!(lam > 0.0))
            continue;
        /* theta = the root's angle plus the chosen quarter-turn */
        double co = (1.0 - t * t) / u, si = 2.0 * t / u;
        sfmi_r2r_axis_rotate(n, co * bc - si * bs, si * bc + co * bs, C0, C);
        for (int i = 0; i < 3; i++)
            p[i] = lam * b[i];
        sfmi_r2r_emit(steps, 3, C, p, out, &cnt);
    }
    return cnt;
}

const sfmi_r2r_system_desc sfmi_r2r_b1b2_d_d = {
    SFM_R2R_SYS_B1B2_D_D,
    3,
    {SFM_R2R_B1 | SFM_R2R_B2, SFM_R2R_D, SFM_R2R_D, 0, 0, 0},
    4,
    0,
    solve_b1b2_d_d,
    "b1b2_d_d",
};
