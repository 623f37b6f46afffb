/*
 * The robot-to-robot base systems with a step of three or more equations
 * (libsfm/solvers/r2r_db1b2_d.c ... r2r_db1_d_d_d.c) against known answers:
 * random transforms, ego-motions and the measurements they imply (the model
 * of sfm_r2r.h written out here, independently of the library), each solver
 * called in canonical form. The truth must be among the solutions in at
 * least 99.9 % of the instances, every returned solution must reproduce the
 * measurements, and no system may return more real solutions than its
 * complex count.
 */
#include <math.h>
#include <string.h>

#include "sfm_test.h"
#include "sfm/sfm_linalg.h"
#include "solvers/r2r_internal.h"

typedef struct r2r_truth {
    double C[9], p[3];
} r2r_truth;

static void mat_vec(const double *M, const double *x, double *y)
{
    for (int r = 0; r < 3; r++)
        y[r] = M[3 * r] * x[0] + M[3 * r + 1] * x[1] + M[3 * r + 2] * x[2];
}

static void mat_tvec(const double *M, const double *x, double *y)
{
    for (int c = 0; c < 3; c++)
        y[c] = M[c] * x[0] + M[3 + c] * x[1] + M[6 + c] * x[2];
}

/* d, b1, b2 of one step under (C, p), straight from the definitions. */
static void measure(const sfm_r2r_step *s, const double *C, const double *p, double *d,
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
static void make_instance(sfm_test_ctx *t, const sfmi_r2r_system_desc *sys, r2r_truth *T,
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

static double transform_err(const sfm_r2r_transform *X, const r2r_truth *T)
{
    double e = 0.0;
    for (int i = 0; i < 9; i++)
        e = fmax(e, fabs(X->C.m[i] - T->C[i]));
    for (int i = 0; i < 3; i++)
        e = fmax(e, fabs(X->p.v[i] - T->p[i]) / 3.0);
    return e;
}

/* Largest misfit of (C, p) to the measurements the steps carry. */
static double misfit(const sfm_r2r_step *steps, int n, const sfm_r2r_transform *X)
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

static int is_rotation(const double *C)
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
static void run_system(sfm_test_ctx *t, const sfmi_r2r_system_desc *sys, int n)
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

SFM_TEST(r2r_db1b2_d_truth)
{
    run_system(t, &sfmi_r2r_db1b2_d, SFM_TEST_ITERS(10000));
}

SFM_TEST(r2r_b1b2_b1_truth)
{
    run_system(t, &sfmi_r2r_b1b2_b1, SFM_TEST_ITERS(10000));
}

SFM_TEST(r2r_b1b2_d_d_truth)
{
    run_system(t, &sfmi_r2r_b1b2_d_d, SFM_TEST_ITERS(10000));
}

SFM_TEST(r2r_db1_b1_d_truth)
{
    run_system(t, &sfmi_r2r_db1_b1_d, SFM_TEST_ITERS(10000));
}

SFM_TEST(r2r_db1_b2_d_truth)
{
    run_system(t, &sfmi_r2r_db1_b2_d, SFM_TEST_ITERS(10000));
}

SFM_TEST(r2r_db1_d_d_d_truth)
{
    run_system(t, &sfmi_r2r_db1_d_d_d, SFM_TEST_ITERS(5000));
}

/* R_n(theta) M for a unit axis n (Rodrigues), written out here. */
static void turn_about(const double n[3], double th, const double *M, double *out)
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

/* DB1_DB1 and DB1_DB2 have rank 5: the whole circle of rotations about the
 * one vector their second step fixes reproduces every measurement, so the
 * solvers must refuse (SFM_E_DEGENERATE) and write nothing. */
static void check_family(sfm_test_ctx *t, const sfmi_r2r_system_desc *sys, int n)
{
    int fits = 0;
    for (int it = 0; it < n; it++) {
        r2r_truth T;
        sfm_r2r_step steps[2];
        make_instance(t, sys, &T, steps);
        double w[3], axis[3], C2[9];
        if (sys->pattern[1] & SFM_R2R_B1) {
            mat_vec(T.C, steps[1].t2.v, w); /* C t2_1 is pinned */
        } else {
            for (int i = 0; i < 3; i++)
                w[i] = steps[1].t1.v[i] - T.p[i]; /* C maps a known u onto t1_1 - p */
        }
        double l = sqrt(w[0] * w[0] + w[1] * w[1] + w[2] * w[2]);
        for (int i = 0; i < 3; i++)
            axis[i] = w[i] / l;
        turn_about(axis, sfm_test_uniform(t, 0.5, 2.5), T.C, C2);
        sfm_r2r_transform other;
        memcpy(other.C.m, C2, sizeof C2);
        memcpy(other.p.v, T.p, sizeof T.p);
        double dc = 0.0;
        for (int i = 0; i < 9; i++)
            dc = fmax(dc, fabs(C2[i] - T.C[i]));
        fits += misfit(steps, 2, &other) < 1e-12 && dc > 0.1;
        sfm_r2r_transform out[2], canary[2];
        memset(out, 0x5a, sizeof out);
        memset(canary, 0x5a, sizeof canary);
        SFM_CHECK_EQ_INT(sys->solve(steps, out, NULL), SFM_E_DEGENERATE);
        SFM_CHECK(memcmp(out, canary, sizeof out) == 0);
    }
    SFM_CHECK_MSG(fits == n, "%s: a second transform fits in %d of %d", sys->name, fits, n);
}

SFM_TEST(r2r_db1_db1_is_a_family)
{
    check_family(t, &sfmi_r2r_db1_db1, SFM_TEST_ITERS(200));
}

SFM_TEST(r2r_db1_db2_is_a_family)
{
    check_family(t, &sfmi_r2r_db1_db2, SFM_TEST_ITERS(200));
}

/* Degenerate motion: no ego-motion at all (every step the first one again),
 * or one robot standing still while the other moves. A status, zero
 * solutions, or (where the motion still determines the transform) the
 * truth among finite solutions; never NaN, never only wrong answers. */
static void degenerate_motion(sfm_test_ctx *t, int mode, int n)
{
    const sfmi_r2r_system_desc *sys[] = {&sfmi_r2r_db1b2_d, &sfmi_r2r_b1b2_b1,
                                         &sfmi_r2r_b1b2_d_d, &sfmi_r2r_db1_b1_d,
                                         &sfmi_r2r_db1_b2_d, &sfmi_r2r_db1_d_d_d};
    static double ws[2048];
    for (unsigned k = 0; k < sizeof sys / sizeof sys[0]; k++) {
        int answered = 0;
        for (int it = 0; it < n; it++) {
            r2r_truth T;
            sfm_r2r_step steps[6];
            make_instance(t, sys[k], &T, steps);
            for (int j = 1; j < sys[k]->n_steps; j++) {
                sfm_r2r_step *s = &steps[j];
                if (mode == 0) {
                    unsigned has = s->has;
                    *s = steps[0];
                    s->has = has;
                    continue;
                }
                sfm_mat3 *R = mode == 1 ? &s->R1 : &s->R2;
                sfm_vec3 *p = mode == 1 ? &s->t1 : &s->t2;
                memset(R, 0, sizeof *R);
                memset(p, 0, sizeof *p);
                R->m[0] = R->m[4] = R->m[8] = 1.0;
                measure(s, T.C, T.p, &s->d, s->b1.v, s->b2.v);
            }
            sfm_r2r_transform out[SFM_R2R_MAX_SOLUTIONS];
            int m = sys[k]->solve(steps, out, ws), hit = 0;
            SFM_CHECK_MSG(m == 0 || m == SFM_E_SINGULAR || m > 0, "%s: %d", sys[k]->name, m);
            for (int j = 0; j < m; j++) {
                for (int i = 0; i < 9; i++)
                    SFM_CHECK(isfinite(out[j].C.m[i]));
                hit |= transform_err(&out[j], &T) < 1e-6;
            }
            SFM_CHECK_MSG(m <= 0 || hit, "%s, motion %d: %d solutions, none the truth",
                          sys[k]->name, mode, m);
            answered += m > 0;
        }
        SFM_TEST_LOG("%s: %s, answered %d of %d", sys[k]->name,
                     mode == 0 ? "no ego-motion" : mode == 1 ? "robot 1 still" : "robot 2 still",
                     answered, n);
        /* nothing observes the transform without motion */
        if (mode == 0)
            SFM_CHECK(answered == 0);
    }
}

SFM_TEST(r2r_a_no_ego_motion)
{
    degenerate_motion(t, 0, 1);
}

SFM_TEST(r2r_a_one_robot_still)
{
    degenerate_motion(t, 1, SFM_TEST_ITERS(200));
    degenerate_motion(t, 2, SFM_TEST_ITERS(200));
}

/* Stacked measurements of the steps under (C, p): d, then b1 and b2 in
 * full (a bearing's three components carry its two equations). */
static int measurement_vector(const sfm_r2r_step *steps, int n, const double *C, const double *p,
                              double *z)
{
    int m = 0;
    for (int k = 0; k < n; k++) {
        double d, b1[3], b2[3];
        measure(&steps[k], C, p, &d, b1, b2);
        if (steps[k].has & SFM_R2R_D)
            z[m++] = d;
        for (int i = 0; i < 3; i++)
            if (steps[k].has & SFM_R2R_B1)
                z[m++] = b1[i];
        for (int i = 0; i < 3; i++)
            if (steps[k].has & SFM_R2R_B2)
                z[m++] = b2[i];
    }
    return m;
}

/* Minimality, independently of the solvers: the Jacobian of the
 * measurements with respect to (rotation increment, p) at the truth has
 * rank 6 for the six finite systems (so the truth is an isolated solution)
 * and rank 5 for DB1_DB1 and DB1_DB2. */
SFM_TEST(r2r_a_jacobian_rank)
{
    const sfmi_r2r_system_desc *sys[] = {&sfmi_r2r_db1b2_d, &sfmi_r2r_b1b2_b1,
                                         &sfmi_r2r_b1b2_d_d, &sfmi_r2r_db1_b1_d,
                                         &sfmi_r2r_db1_b2_d, &sfmi_r2r_db1_d_d_d,
                                         &sfmi_r2r_db1_db1,  &sfmi_r2r_db1_db2};
    static double svd_ws[4096];
    SFM_CHECK(sfm_svd_workspace_size(42, 6) <= sizeof svd_ws);
    for (unsigned s = 0; s < sizeof sys / sizeof sys[0]; s++) {
        int want = sys[s]->max_solutions > 0 ? 6 : 5, agree = 0, n = SFM_TEST_ITERS(100);
        for (int it = 0; it < n; it++) {
            r2r_truth T;
            sfm_r2r_step steps[6];
            make_instance(t, sys[s], &T, steps);
            double J[42 * 6], zp[42], zm[42], S[6], h = 1e-6;
            int m = 0;
            for (int c = 0; c < 6; c++) {
                double Cp[9], Cm[9], pp[3], pm[3];
                memcpy(Cp, T.C, sizeof Cp);
                memcpy(Cm, T.C, sizeof Cm);
                memcpy(pp, T.p, sizeof pp);
                memcpy(pm, T.p, sizeof pm);
                if (c < 3) {
                    double axis[3] = {0.0, 0.0, 0.0};
                    axis[c] = 1.0;
                    turn_about(axis, h, T.C, Cp);
                    turn_about(axis, -h, T.C, Cm);
                } else {
                    pp[c - 3] += h;
                    pm[c - 3] -= h;
                }
                m = measurement_vector(steps, sys[s]->n_steps, Cp, pp, zp);
                measurement_vector(steps, sys[s]->n_steps, Cm, pm, zm);
                for (int r = 0; r < m; r++)
                    J[6 * r + c] = (zp[r] - zm[r]) / (2.0 * h);
            }
            if (sfm_svd(J, m, 6, NULL, S, NULL, svd_ws, sizeof svd_ws) != SFM_OK)
                continue;
            int rank = 0;
            for (int i = 0; i < 6; i++)
                rank += S[i] > 1e-6 * S[0];
            agree += rank == want;
        }
        SFM_CHECK_MSG(agree >= n - n / 50, "%s: rank %d in %d of %d", sys[s]->name, want, agree, n);
    }
}
