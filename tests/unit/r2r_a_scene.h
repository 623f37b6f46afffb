/*
 * Random robot-to-robot instances for the base-system tests (unit and
 * native): the measurement model of sfm_r2r.h written out independently of
 * the library, instances in each system's canonical form, and the truth-rate
 * run every test of a system shares.
 */
#ifndef SFM_TESTS_R2R_A_SCENE_H
#define SFM_TESTS_R2R_A_SCENE_H

#include <math.h>
#include <stdio.h>
#include <string.h>

#include "sfm_test.h"
#include "solvers/r2r_internal.h"

typedef struct r2r_truth {
    double C[9], p[3];
} r2r_truth;

static inline void mat_vec(const double *M, const double *x, double *y)
{
    for (int r = 0; r < 3; r++)
        y[r] = M[3 * r] * x[0] + M[3 * r + 1] * x[1] + M[3 * r + 2] * x[2];
}

static inline void mat_tvec(const double *M, const double *x, double *y)
{
    for (int c = 0; c < 3; c++)
        y[c] = M[c] * x[0] + M[3 + c] * x[1] + M[6 + c] * x[2];
}

/* d, b1, b2 of one step under (C, p), straight from the definitions. */
static inline void measure(const sfm_r2r_step *s, const double *C, const double *p, double *d,
                    double b1[3], double b2[3])
{
    double q[3], ct[3], a[3], w[3];
    mat_vec(C, s->t2.v, ct);
    for (int i = 0; i < 3; i++)
        q[i] = ct[i] + p[i] - s->t1.v[i];
    *d = sqrt(q[0] * q[0] + q[1] * q[1] + q[2] * q[2]);
    mat_tvec(s->R1.m, q, b1);
    for (int i = 0; i < 3; i++) {
        b1[i] /= *d;
        a[i] = s->t1.v[i] - p[i];
    }
    mat_tvec(C, a, w);
    for (int i = 0; i < 3; i++)
        w[i] -= s->t2.v[i];
    mat_tvec(s->R2.m, w, b2);
    for (int i = 0; i < 3; i++)
        b2[i] /= *d;
}

/* A random instance of the pattern: C uniform, p and every later position
 * within a few metres, later orientations uniform, step 0 the identity. */
static inline void make_instance(sfm_test_ctx *t, const sfmi_r2r_system_desc *sys, r2r_truth *T,
                          sfm_r2r_step *steps)
{
    sfm_test_random_rotation(t, T->C);
    for (int i = 0; i < 3; i++)
        T->p[i] = sfm_test_uniform(t, -3.0, 3.0);
    for (int k = 0; k < sys->n_steps; k++) {
        sfm_r2r_step *s = &steps[k];
        memset(s, 0, sizeof *s);
        if (k == 0) {
            s->R1.m[0] = s->R1.m[4] = s->R1.m[8] = 1.0;
            s->R2.m[0] = s->R2.m[4] = s->R2.m[8] = 1.0;
        } else {
            sfm_test_random_rotation(t, s->R1.m);
            sfm_test_random_rotation(t, s->R2.m);
            for (int i = 0; i < 3; i++) {
                s->t1.v[i] = sfm_test_uniform(t, -3.0, 3.0);
                s->t2.v[i] = sfm_test_uniform(t, -3.0, 3.0);
            }
        }
        s->has = sys->pattern[k];
        measure(s, T->C, T->p, &s->d, s->b1.v, s->b2.v);
    }
}

static inline double transform_err(const sfm_r2r_transform *X, const r2r_truth *T)
{
    double e = 0.0;
    for (int i = 0; i < 9; i++)
        e = fmax(e, fabs(X->C.m[i] - T->C[i]));
    for (int i = 0; i < 3; i++)
        e = fmax(e, fabs(X->p.v[i] - T->p[i]) / 3.0);
    return e;
}

/* Largest misfit of (C, p) to the measurements the steps carry. */
static inline double misfit(const sfm_r2r_step *steps, int n, const sfm_r2r_transform *X)
{
    double e = 0.0;
    for (int k = 0; k < n; k++) {
        double d, b1[3], b2[3];
        measure(&steps[k], X->C.m, X->p.v, &d, b1, b2);
        if (steps[k].has & SFM_R2R_D)
            e = fmax(e, fabs(d - steps[k].d) / steps[k].d);
        for (int i = 0; i < 3; i++) {
            if (steps[k].has & SFM_R2R_B1)
                e = fmax(e, fabs(b1[i] - steps[k].b1.v[i]));
            if (steps[k].has & SFM_R2R_B2)
                e = fmax(e, fabs(b2[i] - steps[k].b2.v[i]));
        }
    }
    return e;
}

static inline int is_rotation(const double *C)
{
    double e = 0.0;
    for (int r = 0; r < 3; r++)
        for (int c = 0; c < 3; c++) {
            double s = C[r] * C[c] + C[3 + r] * C[3 + c] + C[6 + r] * C[6 + c];
            e = fmax(e, fabs(s - (r == c ? 1.0 : 0.0)));
        }
    double det = C[0] * (C[4] * C[8] - C[5] * C[7]) - C[1] * (C[3] * C[8] - C[5] * C[6]) +
                 C[2] * (C[3] * C[7] - C[4] * C[6]);
    return e < 1e-9 && fabs(det - 1.0) < 1e-9;
}

/* Runs n instances of the system; checks and logs truth rate and counts. */
static inline void run_system(sfm_test_ctx *t, const sfmi_r2r_system_desc *sys, int n)
{
    static double ws[2048];
    SFM_CHECK(sys->ws_doubles <= sizeof ws / sizeof ws[0]);
    int found = 0, bad_fit = 0, errors = 0, hist[SFM_R2R_MAX_SOLUTIONS + 1] = {0};
    for (int it = 0; it < n; it++) {
        r2r_truth T;
        sfm_r2r_step steps[6];
        sfm_r2r_transform out[SFM_R2R_MAX_SOLUTIONS];
        make_instance(t, sys, &T, steps);
        size_t tail = sizeof ws - sys->ws_doubles * sizeof(double);
        sfm_test_fill_canary(ws + sys->ws_doubles, tail);
        int m = sys->solve(steps, out, ws);
        SFM_CHECK_MSG(sfm_test_canary_intact(ws + sys->ws_doubles, tail),
                      "%s wrote past its %zu doubles of ws", sys->name, sys->ws_doubles);
        if (m < 0) {
            errors++;
            continue;
        }
        SFM_CHECK(m <= sys->max_solutions);
        if (m > sys->max_solutions)
            return;
        hist[m]++;
        int hit = 0, fit = 1;
        for (int j = 0; j < m; j++) {
            hit |= transform_err(&out[j], &T) < 1e-6;
            fit &= misfit(steps, sys->n_steps, &out[j]) < 1e-6 && is_rotation(out[j].C.m);
        }
        found += hit;
        bad_fit += !fit;
    }
    char h[160];
    int len = 0;
    for (int k = 0; k <= sys->max_solutions && len < 150; k++)
        len += snprintf(h + len, sizeof h - (size_t)len, " %d:%d", k, hist[k]);
    SFM_TEST_LOG("%s: truth in %d of %d (%.3f %%), %d errors, %d with a misfit solution; "
                 "real solutions (count:instances)%s",
                 sys->name, found, n, 100.0 * found / n, errors, bad_fit, h);
    SFM_CHECK_MSG(found >= n - n / 1000, "%s: truth in %d of %d", sys->name, found, n);
#ifndef SFM_TEST_REDUCED
    /* the count is tight: some instances have every complex solution real */
    SFM_CHECK_MSG(hist[sys->max_solutions] > 0, "%s: never %d real solutions", sys->name,
                  sys->max_solutions);
#endif
    SFM_CHECK_MSG(bad_fit <= n / 1000, "%s: %d instances with a misfit", sys->name, bad_fit);
}

/* R_n(theta) M for a unit axis n (Rodrigues), written out here. */
static inline void turn_about(const double n[3], double th, const double *M, double *out)
{
    double c = cos(th), s = sin(th), R[9];
    double K[9] = {0, -n[2], n[1], n[2], 0, -n[0], -n[1], n[0], 0};
    for (int i = 0; i < 3; i++)
        for (int j = 0; j < 3; j++)
            R[3 * i + j] = (i == j ? c : 0.0) + s * K[3 * i + j] + (1.0 - c) * n[i] * n[j];
    for (int i = 0; i < 3; i++)
        for (int j = 0; j < 3; j++)
            out[3 * i + j] = R[3 * i] * M[j] + R[3 * i + 1] * M[3 + j] + R[3 * i + 2] * M[6 + j];
}

#endif
