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
#include "r2r_a_scene.h"

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
