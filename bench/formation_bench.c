/*
 * The leader-follower next motion (sfm_r2r_motion_next, every KKT critical
 * point) beside a grid search over the same admissible disk (the paper's
 * GBS baseline), on the same random states: CPU microseconds per call, the
 * ratio grid / KKT, and how far the grid's best stays above the KKT optimum
 * (relative to the trace), which shrinks with the grid's resolution while
 * its cost grows.
 *
 * The grid is given its best chance: the propagated covariance, which does
 * not depend on the follower's translation, is computed once per state, and
 * each grid point costs only the closed-form posterior trace
 * tr(P') - |P' h|^2 / (h P' h + s^2).
 *
 *   formation_bench [STATES]        (default 2000 states per sensor)
 *   formation_bench --calls K SENSOR [NR NT]
 *                                   K calls only, cycling over 500 fixed
 *                                   states, no output: the KKT solver, or
 *                                   with NR NT the grid search, for
 *                                   instruction counts under callgrind with
 *                                   two values of K (bench/formation_callgrind.sh)
 * SENSOR: range or bearing.
 */
#define _POSIX_C_SOURCE 199309L
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <time.h>

#include "sfm/sfm.h"

static double now_us(void)
{
    struct timespec ts;
    clock_gettime(CLOCK_THREAD_CPUTIME_ID, &ts); /* CPU time: the machine is shared */
    return ts.tv_sec * 1e6 + ts.tv_nsec * 1e-3;
}

typedef struct state {
    double x[3], P[9], d0[2], r;
    sfm_r2r_motion_step u;
} state;

static double uni(sfm_rng *g, double lo, double hi)
{
    return lo + (hi - lo) * sfm_rng_uniform(g);
}

static void random_state(sfm_rng *g, state *s)
{
    for (;;) {
        s->x[0] = uni(g, -4, 4);
        s->x[1] = uni(g, -4, 4);
        s->x[2] = uni(g, -3, 3);
        double L[9];
        const double sc = uni(g, 0.05, 0.5);
        for (int i = 0; i < 9; i++)
            L[i] = uni(g, -sc, sc);
        for (int i = 0; i < 3; i++)
            for (int j = 0; j < 3; j++) {
                double v = 0.0;
                for (int k = 0; k < 3; k++)
                    v += L[3 * i + k] * L[3 * j + k];
                s->P[3 * i + j] = v + (i == j ? 1e-3 : 0.0);
            }
        s->u.leader_d.v[0] = uni(g, -0.4, 0.4);
        s->u.leader_d.v[1] = uni(g, -0.4, 0.4);
        s->u.leader_w = uni(g, -0.3, 0.3);
        s->u.follower_w = uni(g, -0.3, 0.3);
        s->u.follower_d.v[0] = s->u.follower_d.v[1] = 0.0;
        s->d0[0] = uni(g, -0.5, 0.5);
        s->d0[1] = uni(g, -0.5, 0.5);
        s->r = uni(g, 0.1, 1.0);
        const double cp = cos(s->x[2]), sp = sin(s->x[2]);
        const double cw = cos(s->u.follower_w), sw = sin(s->u.follower_w);
        const double ax = s->x[0] + cp * s->u.leader_d.v[0] - sp * s->u.leader_d.v[1];
        const double ay = s->x[1] + sp * s->u.leader_d.v[0] + cp * s->u.leader_d.v[1];
        const double mx = cw * ax + sw * ay - s->d0[0], my = -sw * ax + cw * ay - s->d0[1];
        if (sqrt(mx * mx + my * my) > s->r + 0.3)
            return;
    }
}

/* the best posterior trace over a polar grid nr x nt of the admissible disk */
static double grid_search(const state *s, const sfm_r2r_motion_noise *nz, int sensor, int nr,
                          int nt, double fd_best[2])
{
    double xp[3], Pp[9];
    if (sfm_r2r_motion_propagate(s->x, s->P, &s->u, nz, xp, Pp) != SFM_OK)
        return HUGE_VAL;
    /* xp is the leader's predicted position with no follower translation */
    const double tr = Pp[0] + Pp[4] + Pp[8], s2 = nz->sigma_meas * nz->sigma_meas;
    double best = HUGE_VAL;
    for (int j = 0; j < nt; j++) {
        const double th = -3.14159265358979323846 + 6.28318530717958647692 * j / nt;
        const double ct = cos(th), st = sin(th);
        for (int i = (j == 0 ? 0 : 1); i < nr; i++) {
            const double rho = s->r * i / (nr - 1);
            const double fx = s->d0[0] + rho * ct, fy = s->d0[1] + rho * st;
            const double qx = xp[0] - fx, qy = xp[1] - fy, q2 = qx * qx + qy * qy;
            double h0, h1;
            if (sensor == SFM_R2R_MOTION_RANGE) {
                const double q = sqrt(q2);
                h0 = qx / q;
                h1 = qy / q;
            } else {
                h0 = -qy / q2;
                h1 = qx / q2;
            }
            const double a = Pp[0] * h0 + Pp[1] * h1, b = Pp[3] * h0 + Pp[4] * h1,
                         c = Pp[6] * h0 + Pp[7] * h1;
            const double f = tr - (a * a + b * b + c * c) / (h0 * a + h1 * b + s2);
            if (f < best) {
                best = f;
                fd_best[0] = fx;
                fd_best[1] = fy;
            }
        }
    }
    return best;
}

static int calls_only(int k, int sensor, int nr, int nt)
{
    enum { NS = 500 };
    static state st[NS];
    sfm_rng g;
    sfm_rng_seed(&g, 7u);
    for (int i = 0; i < NS; i++)
        random_state(&g, &st[i]);
    const sfm_r2r_motion_noise nz = {0.02, 0.01, 0.015, 0.008,
                                     sensor == SFM_R2R_MOTION_RANGE ? 0.05 : 0.02};
    volatile double sink = 0.0;
    for (int c = 0; c < k; c++) {
        const state *s = &st[c % NS];
        if (nr > 0) {
            double fd[2];
            sink += grid_search(s, &nz, sensor, nr, nt, fd);
        } else {
            sfm_r2r_motion_plan plan;
            if (sfm_r2r_motion_next(s->x, s->P, &s->u, s->d0, s->r, 0.0, &nz, sensor, &plan) == SFM_OK)
                sink += plan.trace;
        }
    }
    (void)sink;
    return 0;
}

int main(int argc, char **argv)
{
    if (argc >= 4 && strcmp(argv[1], "--calls") == 0) {
        const int sensor = strcmp(argv[3], "bearing") == 0 ? SFM_R2R_MOTION_BEARING
                                                           : SFM_R2R_MOTION_RANGE;
        const int nr = argc >= 6 ? atoi(argv[4]) : 0, nt = argc >= 6 ? atoi(argv[5]) : 0;
        return calls_only(atoi(argv[2]), sensor, nr, nt);
    }
    const int n = argc > 1 ? atoi(argv[1]) : 2000;
    if (n < 1)
        return 2;
    state *st = malloc(sizeof(state) * (size_t)n);
    if (!st)
        return 2;
    static const int grids[3][2] = {{21, 72}, {51, 360}, {201, 1440}};
    printf("leader-follower next motion: %d random states per sensor, CPU us per call\n", n);
    printf("%-8s %-22s %10s %8s %14s %14s\n", "sensor", "method", "us/call", "ratio",
           "mean gap", "max gap");
    for (int sensor = SFM_R2R_MOTION_RANGE; sensor <= SFM_R2R_MOTION_BEARING; sensor++) {
        sfm_rng g;
        sfm_rng_seed(&g, 20110925u + (unsigned)sensor);
        for (int i = 0; i < n; i++)
            random_state(&g, &st[i]);
        const sfm_r2r_motion_noise nz = {0.02, 0.01, 0.015, 0.008,
                                         sensor == SFM_R2R_MOTION_RANGE ? 0.05 : 0.02};
        double *opt = malloc(sizeof(double) * (size_t)n);
        if (!opt)
            return 2;
        /* KKT: repeat until the timing is long enough to read */
        int reps = 0, fails = 0;
        double t0 = now_us(), t1;
        do {
            for (int i = 0; i < n; i++) {
                sfm_r2r_motion_plan plan;
                if (sfm_r2r_motion_next(st[i].x, st[i].P, &st[i].u, st[i].d0, st[i].r, 0.0, &nz,
                                        sensor, &plan) != SFM_OK) {
                    fails++;
                    opt[i] = HUGE_VAL;
                } else {
                    opt[i] = plan.trace;
                }
            }
            reps++;
            t1 = now_us();
        } while (t1 - t0 < 2e5);
        const double us_kkt = (t1 - t0) / ((double)reps * n);
        const char *name = sensor == SFM_R2R_MOTION_RANGE ? "range" : "bearing";
        printf("%-8s %-22s %10.3f %8s %14s %14s%s\n", name, "KKT (sfm_r2r_motion_next)", us_kkt,
               "1.0", "0", "0", fails ? "  (failures!)" : "");
        for (int k = 0; k < 3; k++) {
            const int nr = grids[k][0], nt = grids[k][1];
            double gap_sum = 0.0, gap_max = 0.0, worse = 0.0;
            t0 = now_us();
            for (int i = 0; i < n; i++) {
                double fd[2];
                const double f = grid_search(&st[i], &nz, sensor, nr, nt, fd);
                const double gap = (f - opt[i]) / opt[i];
                gap_sum += gap;
                gap_max = gap > gap_max ? gap : gap_max;
                worse = gap < worse ? gap : worse;
            }
            t1 = now_us();
            const double us = (t1 - t0) / n;
            char label[40];
            snprintf(label, sizeof label, "grid %dx%d", nr, nt);
            printf("%-8s %-22s %10.1f %8.0f %14.2e %14.2e%s\n", name, label, us, us / us_kkt,
                   gap_sum / n, gap_max, worse < -1e-12 ? "  (grid beat KKT!)" : "");
        }
        free(opt);
    }
    free(st);
    return 0;
}
