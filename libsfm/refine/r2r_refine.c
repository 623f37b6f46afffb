/*
 * Maximum-likelihood refinement of the robot-to-robot transform (C, p) over
 * every distance and bearing of a sequence (the least-squares step after the
 * minimal solvers, Zhou & Roumeliotis, T-RO 2013, Sec. VII), by the core
 * Levenberg-Marquardt driver: C on SO(3) with the left update
 * C <- exp([w]x) C, p Euclidean.
 *
 * The measurement model is sfm_r2r_predict's, written out here because the
 * Jacobians need its intermediate vectors (a unit test holds the two costs
 * equal).
 *
 * Residual blocks: 3 per step, block 3k + j holding measurement j of step k
 * (0 distance, 1 bearing b1, 2 bearing b2); a block whose measurement the
 * step does not carry is left out (the driver's return 0), so a robust loss
 * acts on one measurement at a time and no index table is needed.
 *
 * Jacobians, with w = C t2 + p - t1 and a = C t2:
 *   dw/dw_rot = -[a]x, dw/dp = I;
 *   b1: v = R1^T w,  u = v / |v|;
 *   b2: v = R2^T (C^T (t1 - p) - t2) (|v| = |w|), and
 *       C'^T = C^T exp(-[w_rot]x) gives dv/dw_rot = R2^T C^T [t1 - p]x,
 *       dv/dp = -R2^T C^T;
 *   tangent residual r_k = e_k . u, dr_k/dv = e_k^T (I - u u^T) / |v|.
 */
#include <math.h>
#include <string.h>

#include "core/linalg_util.h"
#include "core/lm.h"
#include "robust/epipolar.h"
#include "sfm/sfm_r2r.h"
#include "solvers/small_math.h"

/* Below this |w| (relative to the positions' scale) the robots coincide and
 * a bearing is undefined. */
#define R2R_COINCIDE 1e-12

typedef struct r2r_user {
    const sfm_r2r_step *steps;
    double inv_sd, inv_sb;
} r2r_user;

/* Tangent residuals of the measured bearing m (not necessarily unit) against
 * the predicted direction v; with dv (3 x 6, row-major: d v / d (w, p)) the
 * two Jacobian rows into J (2 x 6). */
static void bearing_residual(const double *m, const double *v, const double *dv, double inv_sb,
                             double *r, double *J)
{
    double mu[3], e[2][3], u[3];
    double mn = sqrt(sfmi_dot3(m, m)), vn = sqrt(sfmi_dot3(v, v));
    for (int i = 0; i < 3; i++) {
        mu[i] = m[i] / mn;
        u[i] = v[i] / vn;
    }
    sfmi_tangent_basis(mu, e[0], e[1]);
    for (int k = 0; k < 2; k++) {
        double rk = sfmi_dot3(e[k], u);
        r[k] = rk * inv_sb;
        if (J == NULL)
            continue;
        double g[3]; /* d r_k / d v */
        for (int i = 0; i < 3; i++)
            g[i] = (e[k][i] - rk * u[i]) / vn * inv_sb;
        for (int c = 0; c < 6; c++)
            J[6 * k + c] = g[0] * dv[c] + g[1] * dv[6 + c] + g[2] * dv[12 + c];
    }
}

static int r2r_residual(const void *user, const double *const *x, int i, double *r, double *J)
{
    const r2r_user *U = user;
    const sfm_r2r_step *s = &U->steps[i / 3];
    const int kind = i % 3;
    static const unsigned bit[3] = {SFM_R2R_D, SFM_R2R_B1, SFM_R2R_B2};
    if (!(s->has & bit[kind]))
        return 0;
    const double *C = x[0], *p = x[1];
    double a[3], w[3];
    sfmi_matvec3(C, s->t2.v, a);
    for (int k = 0; k < 3; k++)
        w[k] = a[k] + p[k] - s->t1.v[k];
    const double wn = sqrt(sfmi_dot3(w, w));
    const double scale = sqrt(sfmi_dot3(s->t1.v, s->t1.v)) + sqrt(sfmi_dot3(s->t2.v, s->t2.v)) +
                         sqrt(sfmi_dot3(p, p));
    if (!(wn > R2R_COINCIDE * scale) || !(wn > 0.0))
        return -1; /* no bearing, no distance gradient: the step is rejected */
    if (kind == 0) {
        r[0] = (wn - s->d) * U->inv_sd;
        r[1] = 0.0;
        if (J != NULL) {
            double g[3] = {w[0] / wn * U->inv_sd, w[1] / wn * U->inv_sd, w[2] / wn * U->inv_sd};
            /* d|w|/d w_rot = g^T (-[a]x) = (a x g)^T */
            sfmi_cross3(a, g, J);
            J[3] = g[0];
            J[4] = g[1];
            J[5] = g[2];
        }
        return 1;
    }
    double v[3], dv[18];
    if (kind == 1) {
        sfmi_matvec3_t(s->R1.m, w, v);
        if (J != NULL) {
            /* dv = R1^T [-[a]x | I]: row r of R1^T is column r of R1 */
            for (int row = 0; row < 3; row++) {
                double q[3] = {s->R1.m[row], s->R1.m[3 + row], s->R1.m[6 + row]};
                /* q^T (-[a]x) = (a x q)^T */
                sfmi_cross3(a, q, dv + 6 * row);
                dv[6 * row + 3] = q[0];
                dv[6 * row + 4] = q[1];
                dv[6 * row + 5] = q[2];
            }
        }
        bearing_residual(s->b1.v, v, dv, U->inv_sb, r, J);
    } else {
        double q[3], y[3];
        for (int k = 0; k < 3; k++)
            q[k] = s->t1.v[k] - p[k];
        sfmi_matvec3_t(C, q, y);
        for (int k = 0; k < 3; k++)
            y[k] -= s->t2.v[k];
        sfmi_matvec3_t(s->R2.m, y, v);
        if (J != NULL) {
            /* M = R2^T C^T; dv/dw_rot = M [q]x, dv/dp = -M */
            double M[9];
            for (int rr = 0; rr < 3; rr++)
                for (int cc = 0; cc < 3; cc++)
                    M[3 * rr + cc] = s->R2.m[rr] * C[3 * cc] + s->R2.m[3 + rr] * C[3 * cc + 1] +
                                     s->R2.m[6 + rr] * C[3 * cc + 2];
            for (int row = 0; row < 3; row++) {
                const double *m = M + 3 * row;
                /* m^T [q]x = (m x q)^T */
                sfmi_cross3(m, q, dv + 6 * row);
                dv[6 * row + 3] = -m[0];
                dv[6 * row + 4] = -m[1];
                dv[6 * row + 5] = -m[2];
            }
        }
        bearing_residual(s->b2.v, v, dv, U->inv_sb, r, J);
    }
    return 1;
}

int sfm_r2r_refine_default_options(sfm_r2r_refine_options *opt)
{
    if (opt == NULL)
        return SFM_E_ARGUMENT;
    opt->sigma_d = 0.01;
    opt->sigma_b = 0.01;
    opt->max_iterations = 50;
    opt->function_tolerance = 1e-12;
    opt->gradient_tolerance = 1e-12;
    opt->step_tolerance = 1e-12;
    opt->loss = SFM_R2R_LOSS_SQUARED;
    opt->loss_scale = 3.0;
    return SFM_OK;
}

/* R^T R = I within tol and det R > 0. */
/* Status of one step's content: SFM_OK, SFM_E_NONFINITE, SFM_E_ARGUMENT;
 * adds its equations to *neq. */
static int check_step(const sfm_r2r_step *s, int *neq)
{
    if (s->has & ~(SFM_R2R_D | SFM_R2R_B1 | SFM_R2R_B2))
        return SFM_E_ARGUMENT;
    if (!sfmi_la_all_finite(s->R1.m, 9) || !sfmi_la_all_finite(s->t1.v, 3) || !sfmi_la_all_finite(s->R2.m, 9) ||
        !sfmi_la_all_finite(s->t2.v, 3))
        return SFM_E_NONFINITE;
    if ((s->has & SFM_R2R_D) && !isfinite(s->d))
        return SFM_E_NONFINITE;
    if ((s->has & SFM_R2R_B1) && !sfmi_la_all_finite(s->b1.v, 3))
        return SFM_E_NONFINITE;
    if ((s->has & SFM_R2R_B2) && !sfmi_la_all_finite(s->b2.v, 3))
        return SFM_E_NONFINITE;
    if (!sfmi_la_is_rotation(s->R1.m, 1e-6) || !sfmi_la_is_rotation(s->R2.m, 1e-6))
        return SFM_E_ARGUMENT;
    if ((s->has & SFM_R2R_D) && !(s->d > 0.0))
        return SFM_E_ARGUMENT;
    if ((s->has & SFM_R2R_B1) && !(sfmi_dot3(s->b1.v, s->b1.v) > 0.0))
        return SFM_E_ARGUMENT;
    if ((s->has & SFM_R2R_B2) && !(sfmi_dot3(s->b2.v, s->b2.v) > 0.0))
        return SFM_E_ARGUMENT;
    *neq += ((s->has & SFM_R2R_D) ? 1 : 0) + ((s->has & SFM_R2R_B1) ? 2 : 0) +
            ((s->has & SFM_R2R_B2) ? 2 : 0);
    return SFM_OK;
}

static int check_options(const sfm_r2r_refine_options *o)
{
    const double v[6] = {o->sigma_d, o->sigma_b, o->function_tolerance, o->gradient_tolerance,
                         o->step_tolerance, o->loss_scale};
    if (!sfmi_la_all_finite(v, 6))
        return SFM_E_NONFINITE;
    if (!(o->sigma_d > 0.0) || !(o->sigma_b > 0.0) || o->max_iterations < 0 ||
        o->function_tolerance < 0.0 || o->gradient_tolerance < 0.0 || o->step_tolerance < 0.0)
        return SFM_E_ARGUMENT;
    if (o->loss != SFM_R2R_LOSS_SQUARED && o->loss != SFM_R2R_LOSS_HUBER &&
        o->loss != SFM_R2R_LOSS_CAUCHY)
        return SFM_E_ARGUMENT;
    if (o->loss != SFM_R2R_LOSS_SQUARED && !(o->loss_scale > 0.0))
        return SFM_E_ARGUMENT;
    return SFM_OK;
}

int sfm_r2r_refine(const sfm_r2r_step *steps, int n_steps, const sfm_r2r_transform *init,
                   const sfm_r2r_refine_options *opt, sfm_r2r_transform *out, double *cov,
                   sfm_r2r_refine_stats *stats)
{
    if (steps == NULL || n_steps < 1 || init == NULL || out == NULL)
        return SFM_E_ARGUMENT;
    if (n_steps > (0x7fffffff / 3))
        return SFM_E_ARGUMENT;
    sfm_r2r_refine_options o;
    if (opt == NULL)
        sfm_r2r_refine_default_options(&o);
    else
        o = *opt;
    int st = check_options(&o);
    if (st != SFM_OK)
        return st;
    int neq = 0;
    for (int k = 0; k < n_steps; k++) {
        st = check_step(&steps[k], &neq);
        if (st != SFM_OK)
            return st;
    }
    if (neq < 6)
        return SFM_E_ARGUMENT;
    if (!sfmi_la_all_finite(init->C.m, 9) || !sfmi_la_all_finite(init->p.v, 3))
        return SFM_E_NONFINITE;
    if (!sfmi_la_is_rotation(init->C.m, 1e-6))
        return SFM_E_ARGUMENT;

    double C[9], p[3];
    memcpy(C, init->C.m, sizeof C);
    memcpy(p, init->p.v, sizeof p);
    const r2r_user user = {steps, 1.0 / o.sigma_d, 1.0 / o.sigma_b};
    const sfmi_lm_block blocks[2] = {{C, 9, SFMI_LM_SO3, 0, NULL, NULL},
                                     {p, 3, SFMI_LM_EUCLIDEAN, 0, NULL, NULL}};
    static const sfmi_lm_loss losses[3] = {SFMI_LM_LOSS_SQUARED, SFMI_LM_LOSS_HUBER,
                                           SFMI_LM_LOSS_CAUCHY};
    const sfmi_lm_problem prob = {blocks, 2, 3 * n_steps, 2, r2r_residual, &user,
                                  losses[o.loss], o.loss_scale, NULL};
    sfmi_lm_options lo;
    sfmi_lm_default_options(&lo);
    lo.max_iterations = o.max_iterations;
    lo.function_tolerance = o.function_tolerance;
    lo.gradient_tolerance = o.gradient_tolerance;
    lo.step_tolerance = o.step_tolerance;
    lo.want_covariance = 1;
    double ws[SFMI_LM_DENSE_WS_DOUBLES(12, 6, 2)];
    double cv[36];
    sfmi_lm_summary sum;
    st = sfmi_lm_dense_solve(&prob, &lo, ws, sizeof ws, &sum, cv);
    if (st == SFM_E_NONFINITE)
        return SFM_E_SINGULAR; /* inputs are finite: the cost is undefined at init */
    if (st != SFM_OK)
        return st;
    if (sum.covariance_status != SFM_OK)
        return SFM_E_DEGENERATE;
    /* the driver's SO(3) update keeps C a rotation to rounding; re-project
     * nothing, but refuse a result that left the manifold */
    if (!sfmi_la_is_rotation(C, 1e-9) || !sfmi_la_all_finite(p, 3))
        return SFM_E_NO_CONVERGENCE;
    memcpy(out->C.m, C, sizeof C);
    memcpy(out->p.v, p, sizeof p);
    if (cov != NULL)
        memcpy(cov, cv, sizeof cv);
    if (stats != NULL) {
        stats->iterations = sum.iterations;
        stats->successful_steps = sum.successful_steps;
        stats->initial_cost = sum.initial_cost;
        stats->final_cost = sum.final_cost;
        stats->stop_reason = (sfm_r2r_stop)sum.stop;
        stats->n_equations = neq;
    }
    return SFM_OK;
}
