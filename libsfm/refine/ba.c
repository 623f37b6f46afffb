/*
 * Bundle adjustment: the public entry. Argument checks (counts against the
 * workspace first, then the arrays), the layout (ba_layout.c), the library's
 * Levenberg-Marquardt driver (core/lm.h) over the Schur-complement system
 * (ba_schur.c), the covariance (ba_covariance.c), the distance gauge's
 * rescaling and the outputs.
 */
#include "sfm/sfm_ba.h"

#include <math.h>
#include <string.h>

#include "core/arena.h"
#include "core/linalg_util.h"
#include "core/lm.h"
#include "refine/ba_internal.h"

size_t sfm_ba_workspace_size(const sfm_ba_dims *dims)
{
    if (!sfmi_ba_dims_valid(dims))
        return 0;
    sfmi_arena a;
    sfmi_ba_ws w;
    int q, nc;
    sfmi_arena_measure(&a);
    sfmi_ba_carve(&a, dims, &w, &q, &nc);
    return sfmi_arena_required(&a);
}

int sfm_ba_default_options(sfm_ba_options *o)
{
    if (o == NULL)
        return SFM_E_ARGUMENT;
    memset(o, 0, sizeof *o);
    sfmi_lm_options lm;
    sfmi_lm_default_options(&lm);
    o->mode = SFM_BA_MODE_FULL;
    o->intrinsics = SFM_BA_INTRINSICS_FIXED;
    o->refine_intrinsics = 0;
    o->loss = SFM_BA_LOSS_SQUARED;
    o->loss_scale = 1.0;
    o->gauge = SFM_BA_GAUGE_FIRST_CAMERA;
    o->scale_gauge = SFM_BA_SCALE_NONE;
    o->scale_camera = 1;
    o->scale_coordinate = 0;
    o->scale_distance = 1.0;
    o->max_iterations = lm.max_iterations;
    o->function_tolerance = lm.function_tolerance;
    o->gradient_tolerance = lm.gradient_tolerance;
    o->parameter_tolerance = lm.step_tolerance;
    o->initial_trust_radius = lm.initial_radius;
    o->want_covariance = 0;
    return SFM_OK;
}

/* ---- argument checks ------------------------------------------------------ */

/* Options alone (no problem array is read). */
static int check_options(const sfm_ba_options *o, int m)
{
    const double reals[6] = {o->loss_scale, o->scale_distance, o->function_tolerance,
                             o->gradient_tolerance, o->parameter_tolerance,
                             o->initial_trust_radius};
    for (int k = 0; k < 6; k++)
        if (isnan(reals[k]))
            return SFM_E_NONFINITE;
    if ((unsigned)o->mode > (unsigned)SFM_BA_MODE_POINTS_ONLY)
        return SFM_E_ARGUMENT;
    if ((unsigned)o->intrinsics > (unsigned)SFM_BA_INTRINSICS_PER_CAMERA)
        return SFM_E_ARGUMENT;
    if (o->refine_intrinsics < 0 || o->refine_intrinsics > (SFM_BA_REFINE_ALL | SFM_BA_REFINE_K1))
        return SFM_E_ARGUMENT;
    if ((unsigned)o->loss > (unsigned)SFM_BA_LOSS_TRUNCATED)
        return SFM_E_ARGUMENT;
    if (!isfinite(o->loss_scale) || !(o->loss_scale > 0.0))
        return SFM_E_ARGUMENT;
    if (o->gauge != SFM_BA_GAUGE_NONE && o->gauge != SFM_BA_GAUGE_FIRST_CAMERA)
        return SFM_E_ARGUMENT;
    if ((unsigned)o->scale_gauge > (unsigned)SFM_BA_SCALE_DISTANCE)
        return SFM_E_ARGUMENT;
    if (o->scale_gauge != SFM_BA_SCALE_NONE) {
        if (o->gauge != SFM_BA_GAUGE_FIRST_CAMERA || o->scale_camera < 1 || o->scale_camera >= m)
            return SFM_E_ARGUMENT;
        if (o->scale_gauge == SFM_BA_SCALE_COORDINATE &&
            (o->scale_coordinate < 0 || o->scale_coordinate > 2))
            return SFM_E_ARGUMENT;
        if (o->scale_gauge == SFM_BA_SCALE_DISTANCE &&
            (!isfinite(o->scale_distance) || !(o->scale_distance > 0.0)))
            return SFM_E_ARGUMENT;
    }
    if (o->max_iterations < 0 || !(o->function_tolerance >= 0.0) ||
        !(o->gradient_tolerance >= 0.0) || !(o->parameter_tolerance >= 0.0) ||
        !isfinite(o->initial_trust_radius) || !(o->initial_trust_radius > 0.0))
        return SFM_E_ARGUMENT;
    return SFM_OK;
}

/* Counts and pointers: nothing behind a pointer is read. */
static int check_counts(const sfm_ba_problem *p, const sfm_ba_options *o, const sfm_ba_result *result,
                        const double *cov, size_t cov_len)
{
    int m = p->n_cameras, n = p->n_points, no = p->n_observations;
    if (m < 1 || n < 0 || no < 1 || result == NULL)
        return SFM_E_ARGUMENT;
    if (!p->rotations || !p->translations || !p->cameras || (n > 0 && !p->points) ||
        !p->obs_camera || !p->obs_point || !p->obs_xy)
        return SFM_E_ARGUMENT;
    if (o->want_covariance && (cov == NULL || cov_len < 36 * (size_t)m))
        return SFM_E_ARGUMENT;
    return SFM_OK;
}

/* The arrays, once the workspace is known to fit the counts. */
static int check_arrays(const sfm_ba_problem *p, const sfm_ba_options *o)
{
    int m = p->n_cameras, n = p->n_points, no = p->n_observations;
    for (int k = 0; k < no; k++) {
        if (p->obs_camera[k] < 0 || p->obs_camera[k] >= m || p->obs_point[k] < 0 ||
            p->obs_point[k] >= n)
            return SFM_E_ARGUMENT;
    }
    if (p->obs_weight) {
        for (int k = 0; k < no; k++) {
            if (isnan(p->obs_weight[k]) || isinf(p->obs_weight[k]))
                return SFM_E_NONFINITE;
            if (p->obs_weight[k] < 0.0)
                return SFM_E_ARGUMENT;
        }
    }
    if (!sfmi_la_all_finite(p->rotations, 9 * (size_t)m) || !sfmi_la_all_finite(p->translations, 3 * (size_t)m) ||
        (n > 0 && !sfmi_la_all_finite(p->points, 3 * (size_t)n)) || !sfmi_la_all_finite(p->obs_xy, 2 * (size_t)no))
        return SFM_E_NONFINITE;
    for (int i = 0; i < m; i++) {
        int st = sfm_camera_validate(&p->cameras[i]);
        if (st != SFM_OK)
            return st;
        if (o->intrinsics == SFM_BA_INTRINSICS_SHARED && p->cameras[i].model != p->cameras[0].model)
            return SFM_E_ARGUMENT;
        /* a rotation: R^T R = I to 1e-6 and det R > 0 */
        if (!sfmi_la_is_rotation(p->rotations + 9 * i, 1e-6))
            return SFM_E_ARGUMENT;
    }
    return SFM_OK;
}

/* ---- outputs -------------------------------------------------------------- */

/* The distance gauge: scale the scene about camera 0's centre so that
 * |C_c - C_0| = scale_distance. */
static int rescale_distance(sfmi_ba_ctx *c)
{
    sfmi_ba_ws *w = &c->w;
    const double *R0 = w->R, *t0 = w->t;
    const double *Rc = w->R + 9 * c->scale_cam, *tc = w->t + 3 * c->scale_cam;
    double C0[3], Cc[3], dist2 = 0.0;
    for (int r = 0; r < 3; r++) {
        C0[r] = -(R0[r] * t0[0] + R0[3 + r] * t0[1] + R0[6 + r] * t0[2]);
        Cc[r] = -(Rc[r] * tc[0] + Rc[3 + r] * tc[1] + Rc[6 + r] * tc[2]);
        dist2 += (Cc[r] - C0[r]) * (Cc[r] - C0[r]);
    }
    if (!(dist2 > 0.0))
        return SFM_E_SINGULAR;
    double s = c->o->scale_distance / sqrt(dist2);
    for (int j = 0; j < c->n; j++)
        for (int r = 0; r < 3; r++)
            w->X[3 * j + r] = C0[r] + s * (w->X[3 * j + r] - C0[r]);
    for (int ci = 0; ci < c->m; ci++) {
        const double *R = w->R + 9 * ci;
        double *tt = w->t + 3 * ci;
        for (int r = 0; r < 3; r++)
            tt[r] = s * tt[r] - (1.0 - s) * (R[3 * r] * C0[0] + R[3 * r + 1] * C0[1] + R[3 * r + 2] * C0[2]);
    }
    return SFM_OK;
}

static void write_problem(const sfmi_ba_ctx *c, sfm_ba_problem *p)
{
    const sfmi_ba_ws *w = &c->w;
    memcpy(p->rotations, w->R, sizeof(double) * 9 * (size_t)c->m);
    memcpy(p->translations, w->t, sizeof(double) * 3 * (size_t)c->m);
    memcpy(p->cameras, w->K, sizeof(sfm_camera) * (size_t)c->m);
    if (c->n > 0)
        memcpy(p->points, w->X, sizeof(double) * 3 * (size_t)c->n);
}

/* ---- solve ---------------------------------------------------------------- */

int sfm_ba_solve(sfm_ba_problem *p, const sfm_ba_options *o, sfm_ba_result *result,
                 double *pose_covariance, size_t pose_covariance_len, void *ws, size_t ws_size)
{
    if (p == NULL || o == NULL)
        return SFM_E_ARGUMENT;
    int st = check_options(o, p->n_cameras);
    if (st == SFM_OK)
        st = check_counts(p, o, result, pose_covariance, pose_covariance_len);
    if (st != SFM_OK)
        return st;
    sfm_ba_dims dims = {p->n_cameras, p->n_points, p->n_observations, o->intrinsics,
                        o->refine_intrinsics};
    if (!sfmi_ba_dims_valid(&dims))
        return SFM_E_ARGUMENT;
    size_t need = sfm_ba_workspace_size(&dims);
    if (ws == NULL || ws_size < need)
        return SFM_E_WORKSPACE;
    st = check_arrays(p, o);
    if (st != SFM_OK)
        return st;

    sfmi_ba_ctx c;
    memset(&c, 0, sizeof c);
    c.p = p;
    c.o = o;
    c.m = p->n_cameras;
    c.n = p->n_points;
    c.nobs = p->n_observations;
    c.a2 = o->loss_scale * o->loss_scale;
    sfmi_arena ar;
    int ncmax;
    sfmi_arena_init(&ar, ws, ws_size);
    sfmi_ba_carve(&ar, &dims, &c.w, &c.qmax, &ncmax);
    if (!sfmi_arena_ok(&ar))
        return SFM_E_WORKSPACE;
    st = sfmi_ba_setup(&c, ncmax);
    if (st != SFM_OK)
        return st;
    int npp = 0;
    for (int j = 0; j < c.n; j++)
        npp += c.w.pt_free[j] ? 3 : 0;

    sfmi_lm_options lo;
    lo.max_iterations = o->max_iterations;
    lo.function_tolerance = o->function_tolerance;
    lo.gradient_tolerance = o->gradient_tolerance;
    lo.step_tolerance = o->parameter_tolerance;
    lo.initial_radius = o->initial_trust_radius;
    lo.want_covariance = 0;
    const sfmi_lm_system sys = {&c, sfmi_ba_linearize, sfmi_ba_solve_step, sfmi_ba_trial,
                                sfmi_ba_accept, c.nc + npp};
    sfmi_lm_summary sum;
    st = sfmi_lm_run(&sys, &lo, &sum);
    if (st != SFM_OK)
        return st;

    sfm_ba_result res;
    memset(&res, 0, sizeof res);
    res.initial_cost = sum.initial_cost;
    res.final_cost = sum.final_cost;
    res.iterations = sum.iterations;
    res.successful_steps = sum.successful_steps;
    res.stop_reason = (sfm_ba_stop)sum.stop;
    res.n_camera_params = c.nc;
    res.n_point_params = npp;
    res.covariance_status = 1;
    if (o->want_covariance)
        res.covariance_status = sfmi_ba_covariance(&c);
    if (c.scale_gauge == SFM_BA_SCALE_DISTANCE) {
        st = rescale_distance(&c);
        if (st != SFM_OK)
            return st;
    }
    if (o->want_covariance && res.covariance_status == SFM_OK)
        sfmi_ba_write_covariance(&c, pose_covariance);
    write_problem(&c, p);
    *result = res;
    return SFM_OK;
}
