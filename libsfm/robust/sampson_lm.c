/*
 * Levenberg-Marquardt on the Sampson error of an essential matrix
 * parametrised by (R, t) on SO(3) x S^2 (local rotation increment on the
 * left, translation increment in the tangent plane of t, then normalised).
 * Residual r = C / sqrt(D), C = b2^T E b1, D = |E b1|^2 + |E^T b2|^2 - 2 C^2
 * (see epipolar.h); its derivative along a direction dE of E is
 * dC / sqrt(D) - C dD / (2 D^1.5), dC = b2^T dE b1,
 * dD = 2 (E b1).(dE b1) + 2 (E^T b2).(dE^T b2) - 4 C dC.
 */
#include "robust/sampson_lm.h"

#include <math.h>
#include <string.h>

#include "core/lm.h"
#include "robust/epipolar.h"
#include "sfm/sfm_linalg.h"
#include "sfm/sfm_rotation.h"

/* The upright rotation: R <- exp([theta axis]x) R. */
static void upright_plus(const double *R, const double *d, double *out, const void *user)
{
    const double *axis = user;
    const double w[3] = {d[0] * axis[0], d[0] * axis[1], d[0] * axis[2]};
    double dR[9];
    if (sfm_rot_from_axis_angle(w, dR) != SFM_OK) {
        for (int k = 0; k < 9; k++)
            out[k] = (double)NAN;
        return;
    }
    sfmi_matmul3(dR, R, out);
}

/* Residual block j: the Sampson error of pair idx[j]; left out where D
 * vanishes (the pair at the epipoles). */
static int sampson_residual(const void *user, const double *const *x, int j, double *r, double *J)
{
    const sfmi_sampson_problem *dat = user;
    const double *R = x[0], *t = x[1];
    const double *x1 = dat->b1 + 3 * dat->idx[j], *x2 = dat->b2 + 3 * dat->idx[j];
    /* u = R b1, a = E b1 = t x u, v = b2 x t (so E^T b2 = R^T v and
     * |E^T b2| = |v|), C = u.v, D = |a|^2 + |v|^2 - 2 C^2. Under
     * u <- u + w x u: dC = w.(u x v), d|a|^2 = 2 w.(u x (a x t)).
     * Under t <- t + dt: dC = dt.(u x b2),
     * d|a|^2 + d|v|^2 = 2 dt.(u x a + v x b2). */
    double u[3], a[3], v[3];
    sfmi_matvec3(R, x1, u);
    sfmi_cross3(t, u, a);
    sfmi_cross3(x2, t, v);
    double C = sfmi_dot3(u, v);
    double D = sfmi_dot3(a, a) + sfmi_dot3(v, v) - 2.0 * C * C;
    if (!(D > 1e-300))
        return 0;
    double sD = sqrt(D);
    r[0] = C / sD;
    if (J == NULL)
        return 1;
    double gCw[3], axt[3], gDw[3], gCt[3], uxa[3], vxb[3], gDt[3];
    sfmi_cross3(u, v, gCw);
    sfmi_cross3(a, t, axt);
    sfmi_cross3(u, axt, gDw);
    sfmi_cross3(u, x2, gCt);
    sfmi_cross3(u, a, uxa);
    sfmi_cross3(v, x2, vxb);
    for (int k = 0; k < 3; k++) {
        gDw[k] = 2.0 * gDw[k] - 4.0 * C * gCw[k];
        gDt[k] = 2.0 * (uxa[k] + vxb[k]) - 4.0 * C * gCt[k];
    }
    const double ia = 1.0 / sD, ib = 0.5 * C / (D * sD);
    int nr;
    if (dat->axis) {
        J[0] = ia * sfmi_dot3(dat->axis, gCw) - ib * sfmi_dot3(dat->axis, gDw);
        nr = 1;
    } else {
        for (int k = 0; k < 3; k++)
            J[k] = ia * gCw[k] - ib * gDw[k];
        nr = 3;
    }
    if (dat->blocks[1].manifold == SFMI_LM_CONSTANT)
        return 1; /* t held: J has the rotation's columns only */
    /* t on the unit sphere, along the driver's tangent basis, kept for the
     * evaluation's other residuals. == suffices: t values equal up to the
     * sign of a zero give the same basis bits (0 - (+-0) = +0), a NaN never
     * matches */
    struct sfmi_sampson_basis *memo = dat->memo;
    if (!memo->valid || memo->t[0] != t[0] || memo->t[1] != t[1] || memo->t[2] != t[2]) {
        sfmi_lm_sphere_basis(t, 3, memo->B);
        memcpy(memo->t, t, sizeof memo->t);
        memo->valid = 1;
    }
    const double *B = memo->B;
    for (int c = 0; c < 2; c++) {
        const double e[3] = {B[c], B[2 + c], B[4 + c]};
        J[nr + c] = ia * sfmi_dot3(e, gCt) - ib * sfmi_dot3(e, gDt);
    }
    return 1;
}

void sfmi_sampson_lm_problem(const double *b1, const double *b2, const int *idx, int n,
                             const double *axis, double scale, double R[9], double t[3],
                             sfmi_sampson_problem *sp)
{
    sp->b1 = b1;
    sp->b2 = b2;
    sp->axis = axis;
    sp->idx = idx;
    sp->memo = &sp->memo_store;
    sp->memo->valid = 0;
    const sfmi_lm_block rb = {R, 9, SFMI_LM_SO3, 0, NULL, NULL};
    const sfmi_lm_block ub = {R, 9, SFMI_LM_CUSTOM, 1, upright_plus, axis};
    const sfmi_lm_block tb = {t, 3, SFMI_LM_SPHERE, 0, NULL, NULL};
    sp->blocks[0] = axis ? ub : rb;
    sp->blocks[1] = tb;
    const sfmi_lm_problem prob = {sp->blocks, 2, n, 1, sampson_residual, sp,
                                  scale > 0.0 ? SFMI_LM_LOSS_CAUCHY : SFMI_LM_LOSS_SQUARED, scale};
    sp->prob = prob;
}

int sfmi_robust_sampson_lm(const double *b1, const double *b2, const int *idx, int n,
                          const double *axis, double scale, int iters, double R[9], double t[3])
{
    sfmi_sampson_problem sp;
    sfmi_sampson_lm_problem(b1, b2, idx, n, axis, scale, R, t, &sp);
    double ws[SFMI_LM_DENSE_WS_DOUBLES(12, 5, 1)];
    /* iters linearisations of the previous loop, each with its rejected
     * retries: the driver counts every step tried, so twice as many (on a
     * dominant plane four steps could leave LO in the planar twin) */
    return sfmi_lm_refine(&sp.prob, 2 * iters, 1e-6, ws, sizeof ws);
}
