/*
 * The six-distance robot-to-robot system D6 (libsfm/solvers/r2r_d6.c, a
 * parameter homotopy from a generated start system) on random noise-free
 * scenes built from the measurement model written out in the tests
 * (r2r_sim.h, r2r_scene.h), not through the library: the truth among the
 * solutions, every solution a proper rotation meeting the six equations,
 * at most 40 real solutions and an even number of them (the 40 complex
 * solutions of real data come in conjugate pairs), the dispatcher's
 * recognition of six distances in any order, degenerate motion refused,
 * and the generated start system checked against the formulation.
 */
#include <math.h>
#include <string.h>

#include "r2r_scene.h"
#include "r2r_sim.h"
#include "solvers/generated/r2r_d6_start.h"
#include "solvers/r2r_solve_internal.h"

static double d6_ws[1 << 14];

/* A solve is about 67 M instructions (40 tracked paths): emulated targets
 * (SFM_TEST_REDUCED) run a fiftieth of the instances, enough to prove the
 * code runs there; the native run has the thousands. */
#ifdef SFM_TEST_REDUCED
#define D6_ITERS(n) ((n) / 50 > 0 ? (n) / 50 : 1)
#else
#define D6_ITERS(n) (n)
#endif

/* The truth within 1e-6 among the solutions in at least 99.9 %; every
 * solution a rotation meeting its six distances to 1e-9 of their scale.
 * Counts: how often the number of real solutions is odd (a conjugate pair
 * that a path failure or a near-double real root split), and the largest. */
SFM_TEST(r2r_d6_truth_among_solutions)
{
    const sfmi_r2r_system_desc *desc = &sfmi_r2r_d6;
    int trials = D6_ITERS(2000), found = 0, status = 0, most = 0, odd = 0, bad = 0;
    long total = 0;
    double worst = 0.0;
    for (int it = 0; it < trials; it++) {
        sfm_r2r_step steps[6];
        sfm_r2r_transform truth, out[SFM_R2R_MAX_SOLUTIONS];
        r2r_sim_scene(t, desc, 3.0, steps, &truth);
        int n = desc->solve(steps, out, d6_ws);
        if (n < 0) {
            status++;
            continue;
        }
        most = n > most ? n : most;
        odd += n % 2;
        total += n;
        double best = HUGE_VAL;
        for (int j = 0; j < n; j++) {
            best = fmin(best, r2r_sim_error(&out[j], &truth));
            double scale = 1.0;
            for (int k = 0; k < 6; k++)
                scale = fmax(scale, steps[k].d);
            if (!r2r_sim_is_rotation(out[j].C.m, 1e-9) ||
                !(r2r_sim_residual(steps, 6, &out[j]) < 1e-9 * scale))
                bad++;
        }
        if (best < 1e-6) {
            found++;
            worst = fmax(worst, best);
        }
    }
    SFM_TEST_LOG("d6: truth in %d of %d (%.3f %%), status failures %d, real solutions %.2f per "
                 "instance, most %d, odd counts %d, bad solutions %d, worst error %.2g",
                 found, trials, 100.0 * found / trials, status, (double)total / trials, most, odd,
                 bad, worst);
    SFM_CHECK_MSG(found * 1000 >= trials * 999, "truth in %d of %d", found, trials);
    SFM_CHECK(most <= 40);
    SFM_CHECK_EQ_INT(bad, 0);
    SFM_CHECK_MSG(odd * 1000 <= trials, "odd counts in %d of %d", odd, trials);
}

/* Six distances through sfm_r2r_solve, steps in a random order (the
 * dispatcher re-references them to the step it puts first) and with
 * arbitrary ego-motion at the first step given: classified as D6, the
 * truth among the answers, each answer meeting every distance. */
SFM_TEST(r2r_d6_dispatcher_any_order)
{
    int trials = D6_ITERS(200), found = 0;
    size_t wsz = sfm_r2r_solve_workspace_size(6);
    SFM_CHECK(wsz <= sizeof d6_ws);
    for (int it = 0; it < trials; it++) {
        sfm_r2r_transform T, out[SFM_R2R_MAX_SOLUTIONS];
        sfm_r2r_step s[6], tmp;
        r2r_scene_truth(t, &T);
        r2r_scene_steps(t, &T, 6, 3.0, s);
        for (int k = 0; k < 6; k++)
            s[k].has = SFM_R2R_D;
        for (int k = 5; k > 0; k--) { /* Fisher-Yates */
            int j = (int)(sfm_rng_uniform(&t->rng) * (k + 1));
            j = j > k ? k : j;
            tmp = s[k];
            s[k] = s[j];
            s[j] = tmp;
        }
        SFM_CHECK_EQ_INT(sfm_r2r_classify(s, 6), SFM_R2R_SYS_D6);
        int n = sfm_r2r_solve(s, 6, out, d6_ws, wsz);
        SFM_CHECK(n >= 1 && n <= 40);
        int hit = 0;
        for (int j = 0; j < n; j++) {
            hit |= r2r_sim_error(&out[j], &T) < 1e-6;
            for (int k = 0; k < 6; k++) {
                sfm_r2r_step m = s[k];
                r2r_scene_measure(&out[j], &m);
                SFM_CHECK(fabs(m.d - s[k].d) < 1e-6 * s[k].d);
            }
        }
        found += hit;
    }
    SFM_TEST_LOG("d6 through sfm_r2r_solve: truth among the answers in %d of %d", found, trials);
    SFM_CHECK(found * 100 >= trials * 99);
}

/* More than six distances: the dispatcher solves a six-distance subset and
 * verifies on the rest, so the truth comes back first (and alone). */
SFM_TEST(r2r_d6_overdetermined_distances)
{
    int trials = D6_ITERS(100), first = 0;
    for (int it = 0; it < trials; it++) {
        sfm_r2r_transform T, out[SFM_R2R_MAX_SOLUTIONS];
        sfm_r2r_step s[9];
        r2r_scene_truth(t, &T);
        r2r_scene_steps(t, &T, 9, 3.0, s);
        for (int k = 0; k < 9; k++)
            s[k].has = SFM_R2R_D;
        int n = sfm_r2r_solve(s, 9, out, d6_ws, sfm_r2r_solve_workspace_size(9));
        first += n >= 1 && r2r_sim_error(&out[0], &T) < 1e-6;
    }
    SFM_TEST_LOG("nine distances: truth first in %d of %d", first, trials);
    SFM_CHECK(first * 100 >= trials * 99);
}

/* Degenerate motion is a status, never an answer, and nothing is written:
 * both robots standing still, robot 2 (or robot 1) moving on one line,
 * both on parallel lines; non-finite data. */
SFM_TEST(r2r_d6_degenerate_motion_refused)
{
    sfm_r2r_transform T, out[SFM_R2R_MAX_SOLUTIONS];
    sfm_r2r_step s[6];
    double u[3];
    for (int c = 0; c < 5; c++) {
        r2r_scene_truth(t, &T);
        r2r_scene_steps(t, &T, 6, 3.0, s);
        sfm_test_random_unit(t, u);
        for (int k = 1; k < 6; k++)
            for (int i = 0; i < 3; i++) {
                if (c == 0) /* both still (turning on the spot) */
                    s[k].t1.v[i] = s[k].t2.v[i] = 0.0;
                if (c == 1 || c == 3) /* robot 2 on a line through its start */
                    s[k].t2.v[i] = 0.4 * k * u[i];
                if (c == 2 || c == 3) /* robot 1 on a line (parallel when c == 3) */
                    s[k].t1.v[i] = -0.3 * k * u[i];
            }
        for (int k = 0; k < 6; k++) {
            r2r_scene_measure(&T, &s[k]);
            s[k].has = SFM_R2R_D;
        }
        if (c == 4)
            s[3].d = (double)NAN;
        int want = c == 4 ? SFM_E_NONFINITE : SFM_E_DEGENERATE;
        sfm_test_fill_canary(out, sizeof out);
        SFM_CHECK_EQ_INT(sfmi_r2r_d6.solve(s, out, d6_ws), want);
        SFM_CHECK_EQ_INT(sfm_r2r_solve(s, 6, out, d6_ws, sizeof d6_ws), want);
        SFM_CHECK(sfm_test_canary_intact(out, sizeof out));
    }
}

/* The registry holds the homotopy with its complex solution count. */
SFM_TEST(r2r_d6_registered)
{
    SFM_CHECK(sfmi_r2r_table[SFM_R2R_SYS_D6] == &sfmi_r2r_d6);
    SFM_CHECK_EQ_INT(sfmi_r2r_d6.max_solutions, 40);
    SFM_CHECK_EQ_INT(sfmi_r2r_d6.n_steps, 6);
}

/* The generated start system against the formulation written out here:
 * each of the 40 start solutions x = (e, g) meets, at the start parameters,
 *   |e t2 - t1 e + 2 g|^2 = d^2 e.e (bilinear, quaternion products written
 *   out below), e . g = 0 and c . x = 1,
 * to 1e-12, and no two coincide (the homotopy needs all 40, distinct). */
typedef struct tcx {
    double re, im;
} tcx;

static tcx tc_mul(tcx a, tcx b) { return (tcx){a.re * b.re - a.im * b.im, a.re * b.im + a.im * b.re}; }
static tcx tc_add(tcx a, tcx b) { return (tcx){a.re + b.re, a.im + b.im}; }
static tcx tc_neg(tcx a) { return (tcx){-a.re, -a.im}; }

/* quaternion product p q (w first) over complex entries */
static void tq_mul(const tcx *p, const tcx *q, tcx *r)
{
    r[0] = tc_add(tc_add(tc_mul(p[0], q[0]), tc_neg(tc_mul(p[1], q[1]))),
                  tc_add(tc_neg(tc_mul(p[2], q[2])), tc_neg(tc_mul(p[3], q[3]))));
    r[1] = tc_add(tc_add(tc_mul(p[0], q[1]), tc_mul(p[1], q[0])),
                  tc_add(tc_mul(p[2], q[3]), tc_neg(tc_mul(p[3], q[2]))));
    r[2] = tc_add(tc_add(tc_mul(p[0], q[2]), tc_mul(p[2], q[0])),
                  tc_add(tc_mul(p[3], q[1]), tc_neg(tc_mul(p[1], q[3]))));
    r[3] = tc_add(tc_add(tc_mul(p[0], q[3]), tc_mul(p[3], q[0])),
                  tc_add(tc_mul(p[1], q[2]), tc_neg(tc_mul(p[2], q[1]))));
}

SFM_TEST(r2r_d6_start_system_is_consistent)
{
    double worst = 0.0, closest = HUGE_VAL;
    for (int j = 0; j < SFMI_R2R_D6_NSOL; j++) {
        tcx x[8], ee = {0.0, 0.0}, eg = {0.0, 0.0}, ch = {-1.0, 0.0};
        for (int i = 0; i < 8; i++)
            x[i] = (tcx){sfmi_r2r_d6_start_sol[j][i][0], sfmi_r2r_d6_start_sol[j][i][1]};
        for (int i = 0; i < 4; i++) {
            ee = tc_add(ee, tc_mul(x[i], x[i]));
            eg = tc_add(eg, tc_mul(x[i], x[4 + i]));
        }
        for (int i = 0; i < 8; i++)
            ch = tc_add(ch, tc_mul((tcx){sfmi_r2r_d6_chart[i][0], sfmi_r2r_d6_chart[i][1]}, x[i]));
        worst = fmax(worst, fmax(hypot(eg.re, eg.im), hypot(ch.re, ch.im)));
        for (int k = 0; k < 6; k++) {
            const double(*P)[2] = sfmi_r2r_d6_start_par + 7 * k;
            tcx t1[4] = {{0, 0}, {P[0][0], P[0][1]}, {P[1][0], P[1][1]}, {P[2][0], P[2][1]}};
            tcx t2[4] = {{0, 0}, {P[3][0], P[3][1]}, {P[4][0], P[4][1]}, {P[5][0], P[5][1]}};
            tcx d2 = {P[6][0], P[6][1]}, a[4], b[4], u = {0.0, 0.0};
            tq_mul(x, t2, a); /* e t2 */
            tq_mul(t1, x, b); /* t1 e */
            for (int i = 0; i < 4; i++) {
                tcx w = tc_add(tc_add(a[i], tc_neg(b[i])), tc_add(x[4 + i], x[4 + i]));
                u = tc_add(u, tc_mul(w, w));
            }
            tcx f = tc_add(u, tc_neg(tc_mul(d2, ee)));
            worst = fmax(worst, hypot(f.re, f.im));
        }
        for (int q = 0; q < j; q++) {
            double d = 0.0;
            for (int i = 0; i < 8; i++)
                d = fmax(d, hypot(sfmi_r2r_d6_start_sol[j][i][0] - sfmi_r2r_d6_start_sol[q][i][0],
                                  sfmi_r2r_d6_start_sol[j][i][1] - sfmi_r2r_d6_start_sol[q][i][1]));
            closest = fmin(closest, d);
        }
    }
    SFM_TEST_LOG("start system: largest residual %.2g, closest two solutions %.3g apart", worst, closest);
    SFM_CHECK(worst < 1e-12);
    SFM_CHECK(closest > 1e-3);
}
