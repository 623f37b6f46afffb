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
 * sin = 2t/(1+t^2)) leave one quartic in t: 4 complex solutions. Rotations
 * within about 1e-4 rad of pi about b (t very large) lose accuracy.
 * Degenerate (SFM_E_SINGULAR): alpha_1 = alpha_2 (then lambda drops out of
 * the difference), or a quartic that cancels to rounding (theta unobservable:
 * robot 2 still or moving along b only).
 * Stack under 1 KB; no workspace.
 */
#include <math.h>

#include "sfm/sfm_poly.h"
#include "solvers/r2r_axis.h"
#include "solvers/r2r_internal.h"

static int solve_b1b2_d_d(const sfm_r2r_step *steps, sfm_r2r_transform *out, double *ws)
{
    (void)ws;
    const double *b = steps[0].b1.v;
    double v[3], C0[9], n[3], e1[3], e2[3];
    for (int i = 0; i < 3; i++)
        v[i] = -b[i];
    if (!sfmi_r2r_align(steps[0].b2.v, v, C0) || !sfmi_r2r_frame(v, n, e1, e2))
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
    double da = al[0] - al[1], dr = rh[0] - rh[1], dc = a[0] - a[1], ds = bb[0] - bb[1];
    if (!(fabs(da) > 1e-12 * scale))
        return SFM_E_SINGULAR;
    /* lambda (1 + t^2) = L0 + L1 t + L2 t^2 */
    double L[3] = {-(dr + dc) / da, -2.0 * ds / da, -(dr - dc) / da};
    double U[3] = {1.0, 0.0, 1.0}, K[3] = {a[0], 2.0 * bb[0], -a[0]};
    double Q[5] = {0.0, 0.0, 0.0, 0.0, 0.0}, Qs[5] = {0.0, 0.0, 0.0, 0.0, 0.0}; /* ascending */
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
        qmax = fmax(qmax, fabs(Q[i]));
        smax = fmax(smax, Qs[i]);
    }
    if (!(qmax > 1e-10 * smax))
        return SFM_E_SINGULAR;
    double desc[5] = {Q[4], Q[3], Q[2], Q[1], Q[0]}, roots[4];
    int m = sfm_poly_roots4(desc, roots), cnt = 0;
    if (m < 0)
        return m;
    for (int j = 0; j < m; j++) {
        double t = roots[j], u = 1.0 + t * t, C[9], p[3];
        double lam = (L[0] + t * (L[1] + t * L[2])) / u;
        if (!(lam > 0.0))
            continue;
        sfmi_r2r_axis_rotate(n, (1.0 - t * t) / u, 2.0 * t / u, C0, C);
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
