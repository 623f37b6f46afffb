/* Fuzz target: the leader-follower filter (sfm_r2r_motion_propagate,
 * _update, _cost, _next). The input is a sensor byte then raw doubles
 * (NaN, infinities, 1e308 and subnormals included): the state, the
 * covariance, one step, the noise, d0, the radius, min_distance and a
 * measurement. Every call must end (angles of any size wrap in bounded
 * time), return a status the header lists, leave its outputs untouched on
 * failure and write only finite values on success, the heading in
 * (-pi, pi]. */
#include <math.h>
#include <stdlib.h>
#include <string.h>

#include "sfm/sfm_r2r_motion.h"

int LLVMFuzzerTestOneInput(const uint8_t *data, size_t size);

#define PI_ 3.14159265358979323846

static double take_f64(const uint8_t **p, size_t *n, double dflt)
{
    double v = dflt;
    if (*n >= sizeof v) {
        memcpy(&v, *p, sizeof v);
        *p += sizeof v;
        *n -= sizeof v;
    }
    return v;
}

static int finite_all(const double *v, int n)
{
    for (int i = 0; i < n; i++)
        if (!isfinite(v[i]))
            return 0;
    return 1;
}

static int listed(int st)
{
    return st == SFM_OK || st == SFM_E_ARGUMENT || st == SFM_E_NONFINITE || st == SFM_E_SINGULAR;
}

int LLVMFuzzerTestOneInput(const uint8_t *data, size_t size)
{
    const uint8_t *p = data;
    size_t n = size;
    int sensor = 1;
    if (n > 0) {
        sensor = data[0] % 4; /* 0 and 3 are unknown sensors */
        p++;
        n--;
    }
    double x[3] = {2.0, 0.5, 0.1}, P[9] = {0.1, 0, 0, 0, 0.1, 0, 0, 0, 0.01};
    for (int i = 0; i < 3; i++)
        x[i] = take_f64(&p, &n, x[i]);
    for (int i = 0; i < 9; i++)
        P[i] = take_f64(&p, &n, P[i]);
    sfm_r2r_motion_step u = {{{0.1, 0}}, 0.05, 0.02, {{0.1, 0}}};
    u.leader_d.v[0] = take_f64(&p, &n, u.leader_d.v[0]);
    u.leader_d.v[1] = take_f64(&p, &n, u.leader_d.v[1]);
    u.leader_w = take_f64(&p, &n, u.leader_w);
    u.follower_w = take_f64(&p, &n, u.follower_w);
    u.follower_d.v[0] = take_f64(&p, &n, u.follower_d.v[0]);
    u.follower_d.v[1] = take_f64(&p, &n, u.follower_d.v[1]);
    sfm_r2r_motion_noise nz = {0.01, 0.01, 0.01, 0.01, 0.05};
    nz.sigma_leader_d = take_f64(&p, &n, nz.sigma_leader_d);
    nz.sigma_leader_w = take_f64(&p, &n, nz.sigma_leader_w);
    nz.sigma_follower_d = take_f64(&p, &n, nz.sigma_follower_d);
    nz.sigma_follower_w = take_f64(&p, &n, nz.sigma_follower_w);
    nz.sigma_meas = take_f64(&p, &n, nz.sigma_meas);
    double d0[2] = {take_f64(&p, &n, 0.0), take_f64(&p, &n, 0.0)};
    double radius = take_f64(&p, &n, 0.5), min_distance = take_f64(&p, &n, 0.0);
    double z = take_f64(&p, &n, 1.0);

    double xo[3], Po[9];
    const double canary = -12345.0;
    for (int i = 0; i < 3; i++)
        xo[i] = canary;
    for (int i = 0; i < 9; i++)
        Po[i] = canary;
    int st = sfm_r2r_motion_propagate(x, P, &u, &nz, xo, Po);
    if (!listed(st) || st == SFM_E_SINGULAR)
        abort();
    if (st == SFM_OK && (!finite_all(xo, 3) || !finite_all(Po, 9) || !(xo[2] > -PI_ && xo[2] <= PI_)))
        abort();
    if (st != SFM_OK && (xo[0] != canary || xo[2] != canary || Po[0] != canary || Po[8] != canary))
        abort();

    for (int i = 0; i < 3; i++)
        xo[i] = canary;
    for (int i = 0; i < 9; i++)
        Po[i] = canary;
    st = sfm_r2r_motion_update(x, P, sensor, z, &nz, xo, Po);
    if (!listed(st))
        abort();
    if (st == SFM_OK && (!finite_all(xo, 3) || !finite_all(Po, 9) || !(xo[2] > -PI_ && xo[2] <= PI_)))
        abort();
    if (st != SFM_OK && (xo[0] != canary || Po[0] != canary))
        abort();

    double tr = canary;
    st = sfm_r2r_motion_cost(x, P, &u, &nz, sensor, &tr);
    if (!listed(st))
        abort();
    if ((st == SFM_OK && !isfinite(tr)) || (st != SFM_OK && tr != canary))
        abort();

    sfm_r2r_motion_plan plan, ref;
    memset(&plan, 0x5a, sizeof plan);
    ref = plan;
    st = sfm_r2r_motion_next(x, P, &u, d0, radius, min_distance, &nz, sensor, &plan);
    if (!listed(st))
        abort();
    if (st == SFM_OK && (!finite_all(plan.follower_d.v, 2) || !finite_all(plan.q.v, 2) ||
                         !isfinite(plan.trace) || !isfinite(plan.trace_prior)))
        abort();
    if (st != SFM_OK && memcmp(&plan, &ref, sizeof plan) != 0)
        abort();
    return 0;
}
