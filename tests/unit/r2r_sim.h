/*
 * Synthetic robot-to-robot scenes for the base-system solver tests: a random
 * true (C, p), random ego-motions of both robots at a few metres (step 0 the
 * identity, as the solvers' canonical form wants) and the measurements the
 * pattern asks for, computed from the model in include/sfm/sfm_r2r.h
 * directly (not through the library).
 */
#ifndef SFM_TESTS_R2R_SIM_H
#define SFM_TESTS_R2R_SIM_H

#include <math.h>
#include <string.h>

#include "sfm_test.h"
#include "solvers/r2r_internal.h"

static inline void r2r_sim_mulv(const double *R, const double *x, double *y)
{
    for (int r = 0; r < 3; r++)
        y[r] = R[3 * r] * x[0] + R[3 * r + 1] * x[1] + R[3 * r + 2] * x[2];
}

static inline void r2r_sim_mulvt(const double *R, const double *x, double *y)
{
    for (int r = 0; r < 3; r++)
        y[r] = R[r] * x[0] + R[3 + r] * x[1] + R[6 + r] * x[2];
}

/* Measurements of step s under the truth T, for the has-mask s->has. */
static inline void r2r_sim_measure(sfm_r2r_step *s, const sfm_r2r_transform *T)
{
    double r[3], q[3];
    r2r_sim_mulv(T->C.m, s->t2.v, r);
    for (int i = 0; i < 3; i++)
        r[i] += T->p.v[i] - s->t1.v[i];
    double d = sqrt(r[0] * r[0] + r[1] * r[1] + r[2] * r[2]);
    s->d = d;
    r2r_sim_mulvt(s->R1.m, r, q);
    for (int i = 0; i < 3; i++)
        s->b1.v[i] = q[i] / d;
    double cr[3];
    r2r_sim_mulvt(T->C.m, r, cr); /* C^T r */
    r2r_sim_mulvt(s->R2.m, cr, q);
    for (int i = 0; i < 3; i++)
        s->b2.v[i] = -q[i] / d;
}

/* A random scene for the pattern of desc (steps[0] identity ego-motion).
 * Positions within `span` metres of the origin, robot 2 start 1..5 m away. */
static inline void r2r_sim_scene(sfm_test_ctx *t, const sfmi_r2r_system_desc *desc, double span,
                          sfm_r2r_step *steps, sfm_r2r_transform *truth)
{
    sfm_test_random_rotation(t, truth->C.m);
    double dir[3], rho = sfm_test_uniform(t, 1.0, 5.0);
    sfm_test_random_unit(t, dir);
    for (int i = 0; i < 3; i++)
        truth->p.v[i] = rho * dir[i];
    for (int k = 0; k < desc->n_steps; k++) {
        sfm_r2r_step *s = &steps[k];
        memset(s, 0, sizeof *s);
        if (k == 0) {
            for (int i = 0; i < 9; i++)
                s->R1.m[i] = s->R2.m[i] = (i % 4 == 0) ? 1.0 : 0.0;
        } else {
            sfm_test_random_rotation(t, s->R1.m);
            sfm_test_random_rotation(t, s->R2.m);
            for (int i = 0; i < 3; i++) {
                s->t1.v[i] = sfm_test_uniform(t, -span, span);
                s->t2.v[i] = sfm_test_uniform(t, -span, span);
            }
        }
        s->has = desc->pattern[k];
        r2r_sim_measure(s, truth);
    }
}

/* Largest deviation of a solution from the truth (rotation entries, and
 * position in metres). */
static inline double r2r_sim_error(const sfm_r2r_transform *a, const sfm_r2r_transform *b)
{
    double e = 0.0;
    for (int i = 0; i < 9; i++)
        e = fmax(e, fabs(a->C.m[i] - b->C.m[i]));
    for (int i = 0; i < 3; i++)
        e = fmax(e, fabs(a->p.v[i] - b->p.v[i]));
    return e;
}

/* Residual of a returned solution on the measurements it was solved from:
 * the largest of the distance errors (m) and bearing errors (unit vectors). */
static inline double r2r_sim_residual(const sfm_r2r_step *steps, int n, const sfm_r2r_transform *T)
{
    double e = 0.0;
    for (int k = 0; k < n; k++) {
        sfm_r2r_step s = steps[k];
        r2r_sim_measure(&s, T);
        if (steps[k].has & SFM_R2R_D)
            e = fmax(e, fabs(s.d - steps[k].d));
        for (int i = 0; i < 3; i++) {
            if (steps[k].has & SFM_R2R_B1)
                e = fmax(e, fabs(s.b1.v[i] - steps[k].b1.v[i]));
            if (steps[k].has & SFM_R2R_B2)
                e = fmax(e, fabs(s.b2.v[i] - steps[k].b2.v[i]));
        }
    }
    return e;
}

/* Proper rotation check: |C^T C - I| and det C. */
static inline int r2r_sim_is_rotation(const double *C, double tol)
{
    for (int a = 0; a < 3; a++)
        for (int b = 0; b < 3; b++) {
            double s = C[a] * C[b] + C[3 + a] * C[3 + b] + C[6 + a] * C[6 + b];
            if (fabs(s - (a == b ? 1.0 : 0.0)) > tol)
                return 0;
        }
    double det = C[0] * (C[4] * C[8] - C[5] * C[7]) - C[1] * (C[3] * C[8] - C[5] * C[6]) +
                 C[2] * (C[3] * C[7] - C[4] * C[6]);
    return fabs(det - 1.0) < tol;
}

typedef struct r2r_sim_stats {
    int trials, found, failed_status, most, spurious;
    double worst_found; /* largest error of the closest solution when found */
} r2r_sim_stats;

/* Solve `trials` random noise-free instances of desc; count how often the
 * truth is among the solutions (within tol), and check every returned
 * solution is a proper rotation that reproduces the measurements. */
static inline r2r_sim_stats r2r_sim_run(sfm_test_ctx *t, const sfmi_r2r_system_desc *desc, int trials,
                                 double tol, double *ws)
{
    r2r_sim_stats st = {trials, 0, 0, 0, 0, 0.0};
    for (int it = 0; it < trials; it++) {
        sfm_r2r_step steps[6];
        sfm_r2r_transform truth, out[SFM_R2R_MAX_SOLUTIONS];
        r2r_sim_scene(t, desc, 3.0, steps, &truth);
        int n = desc->solve(steps, out, ws);
        if (n < 0) {
            st.failed_status++;
            continue;
        }
        if (n > st.most)
            st.most = n;
        double best = HUGE_VAL;
        for (int j = 0; j < n; j++) {
            best = fmin(best, r2r_sim_error(&out[j], &truth));
            if (!r2r_sim_is_rotation(out[j].C.m, 1e-9) ||
                !(r2r_sim_residual(steps, desc->n_steps, &out[j]) < 1e-5))
                st.spurious++;
        }
        if (best < tol) {
            st.found++;
            st.worst_found = fmax(st.worst_found, best);
        }
    }
    return st;
}

#endif
