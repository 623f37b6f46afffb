/*
 * sfm_r2r_refine against known answers: convergence from perturbed truth on
 * noise-free sequences of every measurement pattern, the covariance against
 * a finite-difference Jacobian of the test's own measurement model, NEES
 * under noise (a consistent estimator gives 6 on average), and the
 * contract on bad inputs.
 */
#include <math.h>
#include <string.h>

#include "r2r_scene.h"
#include "sfm/sfm_linalg.h"
#include "sfm_test.h"

static void matmul(const double *A, const double *B, int n, double *C)
{
    for (int r = 0; r < n; r++)
        for (int c = 0; c < n; c++) {
            double v = 0.0;
            for (int k = 0; k < n; k++)
                v += A[n * r + k] * B[n * k + c];
            C[n * r + c] = v;
        }
}

/* A random has-mask for each step, at least six equations in all. */
static void random_masks(sfm_test_ctx *t, sfm_r2r_step *s, int n)
{
    for (;;) {
        int neq = 0;
        for (int k = 0; k < n; k++) {
            s[k].has = 1u + sfm_rng_bounded(&t->rng, 7);
            neq += ((s[k].has & SFM_R2R_D) ? 1 : 0) + ((s[k].has & SFM_R2R_B1) ? 2 : 0) +
                   ((s[k].has & SFM_R2R_B2) ? 2 : 0);
        }
        if (neq >= 8)
            return;
    }
}

SFM_TEST(r2r_refine_converges_to_truth_noise_free)
{
    const int trials = SFM_TEST_ITERS(300);
    int ok = 0, worst_it = 0;
    double worst_r = 0.0, worst_p = 0.0;
    for (int it = 0; it < trials; it++) {
        sfm_r2r_transform T, T0, out;
        sfm_r2r_step s[8];
        int n = 3 + (int)sfm_rng_bounded(&t->rng, 6);
        r2r_scene_truth(t, &T);
        r2r_scene_steps(t, &T, n, 3.0, s);
        random_masks(t, s, n);
        r2r_scene_perturb(t, &T, 0.15, 0.3, &T0);
        sfm_r2r_refine_options o;
        sfm_r2r_refine_default_options(&o);
        sfm_r2r_refine_stats st;
        int rc = sfm_r2r_refine(s, n, &T0, &o, &out, NULL, &st);
        if (rc != SFM_OK)
            continue;
        double pe, re = r2r_scene_error(&out, &T, NULL, &pe);
        if (re < 1e-8 && pe < 1e-8)
            ok++;
        if (re > worst_r) {
            worst_r = re;
            worst_it = it;
        }
        worst_p = fmax(worst_p, pe);
        SFM_CHECK(st.final_cost <= st.initial_cost);
    }
    SFM_TEST_LOG("%d of %d converged to 1e-8; worst rotation %.3g rad (trial %d), position %.3g",
                 ok, trials, worst_r, worst_it, worst_p);
    /* a 0.15 rad / 0.3 m start lies in the basin of every generic instance
     * with two equations to spare */
    SFM_CHECK_MSG(ok >= trials - trials / 100, "%d of %d", ok, trials);
}

/* Whitened residuals of all measurements of s under (C, p), written by the
 * test from the model in sfm_r2r.h; bearing residuals as angles projected
 * on the tangent basis of the measurement are replaced by the difference
 * of unit vectors projected on the same basis (equal to first order). */
static int residuals(const sfm_r2r_step *s, int n, const sfm_r2r_transform *T, double sd,
                     double sb, double *r)
{
    int m = 0;
    for (int k = 0; k < n; k++) {
        sfm_r2r_step q = s[k];
        r2r_scene_measure(T, &q);
        if (s[k].has & SFM_R2R_D)
            r[m++] = (q.d - s[k].d) / sd;
        for (int j = 0; j < 2; j++) {
            unsigned bit = j == 0 ? SFM_R2R_B1 : SFM_R2R_B2;
            if (!(s[k].has & bit))
                continue;
            const double *mb = j == 0 ? s[k].b1.v : s[k].b2.v;
            const double *pb = j == 0 ? q.b1.v : q.b2.v;
            /* the same tangent basis as the library (least aligned axis) */
            double a[3] = {0, 0, 0}, e1[3], e2[3];
            int ax = fabs(mb[0]) <= fabs(mb[1]) ? (fabs(mb[0]) <= fabs(mb[2]) ? 0 : 2)
                                                : (fabs(mb[1]) <= fabs(mb[2]) ? 1 : 2);
            a[ax] = 1.0;
            e1[0] = mb[1] * a[2] - mb[2] * a[1];
            e1[1] = mb[2] * a[0] - mb[0] * a[2];
            e1[2] = mb[0] * a[1] - mb[1] * a[0];
            double l = sqrt(e1[0] * e1[0] + e1[1] * e1[1] + e1[2] * e1[2]);
            for (int i = 0; i < 3; i++)
                e1[i] /= l;
            e2[0] = mb[1] * e1[2] - mb[2] * e1[1];
            e2[1] = mb[2] * e1[0] - mb[0] * e1[2];
            e2[2] = mb[0] * e1[1] - mb[1] * e1[0];
            r[m++] = (e1[0] * pb[0] + e1[1] * pb[1] + e1[2] * pb[2]) / sb;
            r[m++] = (e2[0] * pb[0] + e2[1] * pb[1] + e2[2] * pb[2]) / sb;
        }
    }
    return m;
}

SFM_TEST(r2r_refine_covariance_matches_finite_differences)
{
    const int trials = SFM_TEST_ITERS(20);
    double worst = 0.0;
    for (int it = 0; it < trials; it++) {
        sfm_r2r_transform T, out;
        sfm_r2r_step s[6];
        r2r_scene_truth(t, &T);
        r2r_scene_steps(t, &T, 6, 3.0, s);
        random_masks(t, s, 6);
        const double sd = 0.03, sb = 0.02;
        sfm_r2r_refine_options o;
        sfm_r2r_refine_default_options(&o);
        o.sigma_d = sd;
        o.sigma_b = sb;
        double cov[36];
        SFM_CHECK_EQ_INT(sfm_r2r_refine(s, 6, &T, &o, &out, cov, NULL), SFM_OK);
        /* J by central differences along exp([e]x) C and p at the truth */
        double r0[30], rp[30], rm[30], J[30 * 6];
        int m = residuals(s, 6, &T, sd, sb, r0);
        const double h = 1e-6;
        for (int c = 0; c < 6; c++) {
            sfm_r2r_transform Tp = T, Tm = T;
            double aa[3] = {0, 0, 0}, E[9];
            if (c < 3) {
                aa[c] = h;
                sfm_rot_from_axis_angle(aa, E);
                matmul(E, T.C.m, 3, Tp.C.m);
                aa[c] = -h;
                sfm_rot_from_axis_angle(aa, E);
                matmul(E, T.C.m, 3, Tm.C.m);
            } else {
                Tp.p.v[c - 3] += h;
                Tm.p.v[c - 3] -= h;
            }
            residuals(s, 6, &Tp, sd, sb, rp);
            residuals(s, 6, &Tm, sd, sb, rm);
            for (int i = 0; i < m; i++)
                J[6 * i + c] = (rp[i] - rm[i]) / (2 * h);
        }
        double H[36] = {0}, Hc[36];
        for (int a = 0; a < 6; a++)
            for (int b = 0; b < 6; b++)
                for (int i = 0; i < m; i++)
                    H[6 * a + b] += J[6 * i + a] * J[6 * i + b];
        /* H * cov must be the identity */
        matmul(H, cov, 6, Hc);
        double e = 0.0;
        for (int a = 0; a < 36; a++)
            e = fmax(e, fabs(Hc[a] - ((a % 7) == 0 ? 1.0 : 0.0)));
        worst = fmax(worst, e);
    }
    SFM_TEST_LOG("max |H cov - I| = %.3g", worst);
    SFM_CHECK(worst < 1e-4);
}

SFM_TEST(r2r_refine_nees_consistent)
{
    const int trials = SFM_TEST_ITERS(400);
    const double sd = 0.05, sb = 0.01;
    double nees = 0.0, before = 0.0, after = 0.0;
    int used = 0;
    for (int it = 0; it < trials; it++) {
        sfm_r2r_transform T, T0, out;
        sfm_r2r_step s[10];
        r2r_scene_truth(t, &T);
        r2r_scene_steps(t, &T, 10, 3.0, s);
        r2r_scene_noise(t, sd, sb, s, 10);
        r2r_scene_perturb(t, &T, 0.05, 0.1, &T0);
        sfm_r2r_refine_options o;
        sfm_r2r_refine_default_options(&o);
        o.sigma_d = sd;
        o.sigma_b = sb;
        double cov[36], e[6], L[36], y[6];
        if (sfm_r2r_refine(s, 10, &T0, &o, &out, cov, NULL) != SFM_OK)
            continue;
        double pe0, pe;
        before += r2r_scene_error(&T0, &T, NULL, &pe0);
        after += r2r_scene_error(&out, &T, e, &pe);
        memcpy(L, cov, sizeof L);
        memcpy(y, e, sizeof y);
        if (sfm_cholesky_factor(L, 6) != SFM_OK || sfm_cholesky_solve(L, 6, y, 1) != SFM_OK)
            continue;
        for (int i = 0; i < 6; i++)
            nees += e[i] * y[i];
        used++;
    }
    SFM_CHECK(used >= trials - trials / 100);
    nees /= used;
    /* the NEES of a consistent 6-dof estimator is chi^2_6: mean 6, variance
     * 12, so the mean of `used` is 6 +- 5 sqrt(12 / used) at five sigmas */
    double tol = 5.0 * sqrt(12.0 / used);
    SFM_TEST_LOG("mean NEES %.3f over %d trials (6 +- %.2f); rotation error %.4f -> %.4f rad",
                 nees, used, tol, before / used, after / used);
    SFM_CHECK_NEAR(nees, 6.0, tol);
    SFM_CHECK(after < before);
}

/* The robust loss keeps a gross distance outlier from dragging the answer. */
SFM_TEST(r2r_refine_cauchy_resists_outlier)
{
    sfm_r2r_transform T, out_sq, out_c;
    sfm_r2r_step s[8];
    r2r_scene_truth(t, &T);
    r2r_scene_steps(t, &T, 8, 3.0, s);
    r2r_scene_noise(t, 0.01, 0.005, s, 8);
    s[3].d += 2.0;
    sfm_r2r_refine_options o;
    sfm_r2r_refine_default_options(&o);
    o.sigma_d = 0.01;
    o.sigma_b = 0.005;
    SFM_CHECK_EQ_INT(sfm_r2r_refine(s, 8, &T, &o, &out_sq, NULL, NULL), SFM_OK);
    o.loss = SFM_R2R_LOSS_CAUCHY;
    o.loss_scale = 3.0;
    SFM_CHECK_EQ_INT(sfm_r2r_refine(s, 8, &T, &o, &out_c, NULL, NULL), SFM_OK);
    double pq, pc;
    r2r_scene_error(&out_sq, &T, NULL, &pq);
    r2r_scene_error(&out_c, &T, NULL, &pc);
    SFM_TEST_LOG("position error with a 2 m outlier: squared %.4f, Cauchy %.4f", pq, pc);
    SFM_CHECK(pc < 0.5 * pq);
    SFM_CHECK(pc < 0.02);
}

static int untouched(const sfm_r2r_transform *o, const double *cov, const sfm_r2r_refine_stats *st)
{
    return sfm_test_canary_intact(o, sizeof *o) && sfm_test_canary_intact(cov, 36 * sizeof(double)) &&
           sfm_test_canary_intact(st, sizeof *st);
}

SFM_TEST(r2r_refine_bad_inputs)
{
    sfm_r2r_transform T, out;
    sfm_r2r_step s[4], b[4];
    double cov[36];
    sfm_r2r_refine_stats st;
    r2r_scene_truth(t, &T);
    r2r_scene_steps(t, &T, 4, 3.0, s);
    sfm_r2r_refine_options o;
    sfm_r2r_refine_default_options(&o);
#define EXPECT(call, status)                                                                       \
    do {                                                                                           \
        sfm_test_fill_canary(&out, sizeof out);                                                    \
        sfm_test_fill_canary(cov, sizeof cov);                                                     \
        sfm_test_fill_canary(&st, sizeof st);                                                      \
        SFM_CHECK_EQ_INT(call, status);                                                            \
        SFM_CHECK(untouched(&out, cov, &st));                                                      \
    } while (0)
    EXPECT(sfm_r2r_refine(NULL, 4, &T, &o, &out, cov, &st), SFM_E_ARGUMENT);
    EXPECT(sfm_r2r_refine(s, 0, &T, &o, &out, cov, &st), SFM_E_ARGUMENT);
    EXPECT(sfm_r2r_refine(s, 4, NULL, &o, &out, cov, &st), SFM_E_ARGUMENT);
    SFM_CHECK_EQ_INT(sfm_r2r_refine(s, 4, &T, &o, NULL, cov, &st), SFM_E_ARGUMENT);
    SFM_CHECK_EQ_INT(sfm_r2r_refine_default_options(NULL), SFM_E_ARGUMENT);
    /* five equations */
    memcpy(b, s, sizeof b);
    b[0].has = SFM_R2R_D | SFM_R2R_B1;
    b[1].has = SFM_R2R_B2;
    EXPECT(sfm_r2r_refine(b, 2, &T, &o, &out, cov, &st), SFM_E_ARGUMENT);
    memcpy(b, s, sizeof b);
    b[2].has = 8u;
    EXPECT(sfm_r2r_refine(b, 4, &T, &o, &out, cov, &st), SFM_E_ARGUMENT);
    memcpy(b, s, sizeof b);
    b[1].d = (double)NAN;
    EXPECT(sfm_r2r_refine(b, 4, &T, &o, &out, cov, &st), SFM_E_NONFINITE);
    memcpy(b, s, sizeof b);
    b[3].t2.v[1] = HUGE_VAL;
    EXPECT(sfm_r2r_refine(b, 4, &T, &o, &out, cov, &st), SFM_E_NONFINITE);
    /* a measurement the step does not carry may hold anything */
    memcpy(b, s, sizeof b);
    b[1].has = SFM_R2R_D | SFM_R2R_B1;
    b[1].b2.v[0] = (double)NAN;
    SFM_CHECK_EQ_INT(sfm_r2r_refine(b, 4, &T, &o, &out, NULL, NULL), SFM_OK);
    memcpy(b, s, sizeof b);
    b[1].d = 0.0;
    EXPECT(sfm_r2r_refine(b, 4, &T, &o, &out, cov, &st), SFM_E_ARGUMENT);
    memcpy(b, s, sizeof b);
    memset(b[2].b1.v, 0, sizeof b[2].b1.v);
    EXPECT(sfm_r2r_refine(b, 4, &T, &o, &out, cov, &st), SFM_E_ARGUMENT);
    memcpy(b, s, sizeof b);
    b[2].R1.m[0] = 2.0;
    EXPECT(sfm_r2r_refine(b, 4, &T, &o, &out, cov, &st), SFM_E_ARGUMENT);
    sfm_r2r_transform bad = T;
    bad.C.m[4] *= 1.01;
    EXPECT(sfm_r2r_refine(s, 4, &bad, &o, &out, cov, &st), SFM_E_ARGUMENT);
    for (int i = 0; i < 9; i++) /* a reflection */
        bad.C.m[i] = -T.C.m[i];
    EXPECT(sfm_r2r_refine(s, 4, &bad, &o, &out, cov, &st), SFM_E_ARGUMENT);
    bad = T;
    bad.p.v[2] = (double)NAN;
    EXPECT(sfm_r2r_refine(s, 4, &bad, &o, &out, cov, &st), SFM_E_NONFINITE);
    sfm_r2r_refine_options ob = o;
    ob.sigma_b = 0.0;
    EXPECT(sfm_r2r_refine(s, 4, &T, &ob, &out, cov, &st), SFM_E_ARGUMENT);
    ob = o;
    ob.sigma_d = (double)NAN;
    EXPECT(sfm_r2r_refine(s, 4, &T, &ob, &out, cov, &st), SFM_E_NONFINITE);
    ob = o;
    ob.loss = 7;
    EXPECT(sfm_r2r_refine(s, 4, &T, &ob, &out, cov, &st), SFM_E_ARGUMENT);
    ob = o;
    ob.max_iterations = -1;
    EXPECT(sfm_r2r_refine(s, 4, &T, &ob, &out, cov, &st), SFM_E_ARGUMENT);
    /* robot 2 on top of robot 1 at a step with a bearing */
    memcpy(b, s, sizeof b);
    for (int i = 0; i < 3; i++)
        b[2].t1.v[i] = T.C.m[3 * i] * b[2].t2.v[0] + T.C.m[3 * i + 1] * b[2].t2.v[1] +
                       T.C.m[3 * i + 2] * b[2].t2.v[2] + T.p.v[i];
    b[2].d = 1.0;
    EXPECT(sfm_r2r_refine(b, 4, &T, &o, &out, cov, &st), SFM_E_SINGULAR);
    /* robots standing still, six distances: only |p| is determined */
    sfm_r2r_step still[6];
    for (int k = 0; k < 6; k++) {
        still[k] = s[0];
        still[k].has = SFM_R2R_D;
    }
    EXPECT(sfm_r2r_refine(still, 6, &T, &o, &out, cov, &st), SFM_E_DEGENERATE);
#undef EXPECT
}

/* Refinement from its own answer changes nothing; out may alias init. */
SFM_TEST(r2r_refine_fixed_point_and_alias)
{
    sfm_r2r_transform T, A;
    sfm_r2r_step s[5];
    r2r_scene_truth(t, &T);
    r2r_scene_steps(t, &T, 5, 3.0, s);
    r2r_scene_noise(t, 0.02, 0.01, s, 5);
    A = T;
    sfm_r2r_refine_stats st;
    SFM_CHECK_EQ_INT(sfm_r2r_refine(s, 5, &A, NULL, &A, NULL, &st), SFM_OK);
    SFM_CHECK_EQ_INT(st.n_equations, 25);
    sfm_r2r_transform B = A;
    SFM_CHECK_EQ_INT(sfm_r2r_refine(s, 5, &B, NULL, &B, NULL, &st), SFM_OK);
    double pe, re = r2r_scene_error(&B, &A, NULL, &pe);
    SFM_CHECK(re < 1e-9 && pe < 1e-9);
    SFM_CHECK(st.final_cost <= st.initial_cost);
}

/* Whitened cost of T on every measurement of s (the test's own model). */
static double whitened_cost(const sfm_r2r_step *s, int n, const sfm_r2r_transform *T, double sd,
                            double sb)
{
    double r[15 * 5], c = 0.0;
    int m = residuals(s, n, T, sd, sb, r);
    for (int i = 0; i < m; i++)
        c += r[i] * r[i];
    return c;
}

static double median(double *v, int n)
{
    for (int i = 1; i < n; i++)
        for (int j = i; j > 0 && v[j - 1] > v[j]; j--) {
            double x = v[j];
            v[j] = v[j - 1];
            v[j - 1] = x;
        }
    return n == 0 ? (double)NAN : (n % 2 ? v[n / 2] : 0.5 * (v[n / 2 - 1] + v[n / 2]));
}

static unsigned char g_solve_ws[1 << 16];

/* For each base system: a ten-step sequence carrying every measurement
 * under noise, the base system solved on its pattern over the first steps
 * (the solution with the lowest cost on all measurements kept), then
 * refined on all of them. The errors against the truth before and after:
 * refinement must lower both on average (the figures of bench/README.md
 * are this test's log on a host). */
SFM_TEST(r2r_refine_accuracy_per_system)
{
    enum { NSTEP = 10, MAXT = 200 };
    const int trials = SFM_TEST_ITERS(MAXT);
    const double sd = 0.05, sb = 0.01;
    static double rb[MAXT], ra[MAXT], pb[MAXT], pa[MAXT];
    static sfm_r2r_transform sol[SFM_R2R_MAX_SOLUTIONS];
    size_t need = sfm_r2r_solve_workspace_size(6);
    SFM_CHECK(need > 0 && need <= sizeof g_solve_ws);
    if (need == 0 || need > sizeof g_solve_ws)
        return;
    SFM_TEST_LOG("sigma_d %.2f m, sigma_b %.2f rad, %d steps, %d trials per system", sd, sb,
                 NSTEP, trials);
    SFM_TEST_LOG("%-11s %7s %21s %21s %21s", "system", "solved", "rot median deg b/a",
                 "pos median m b/a", "pos mean m b/a");
    for (int sys = 1; sys < SFM_R2R_SYS_COUNT_; sys++) {
        int ok = 0, unsupported = 0, refused = 0, none = 0;
        double mrb = 0, mra = 0, mpb = 0, mpa = 0;
        for (int it = 0; it < trials; it++) {
            sfm_r2r_transform T, best, out;
            sfm_r2r_step s[NSTEP], m[6];
            r2r_scene_truth(t, &T);
            r2r_scene_steps(t, &T, NSTEP, 3.0, s);
            r2r_scene_noise(t, sd, sb, s, NSTEP);
            const int n = r2r_scene_systems[sys].n;
            for (int k = 0; k < n; k++) {
                m[k] = s[k];
                m[k].has = r2r_scene_systems[sys].has[k];
            }
            int ns = sfm_r2r_solve(m, n, sol, g_solve_ws, need);
            if (ns == SFM_E_UNSUPPORTED) {
                unsupported = 1;
                break;
            }
            if (ns == SFM_E_DEGENERATE) {
                refused++;
                continue;
            }
            if (ns < 1) {
                none += ns == 0;
                continue;
            }
            double bc = HUGE_VAL;
            for (int j = 0; j < ns; j++) {
                double c = whitened_cost(s, NSTEP, &sol[j], sd, sb);
                if (c < bc) {
                    bc = c;
                    best = sol[j];
                }
            }
            sfm_r2r_refine_options o;
            sfm_r2r_refine_default_options(&o);
            o.sigma_d = sd;
            o.sigma_b = sb;
            if (sfm_r2r_refine(s, NSTEP, &best, &o, &out, NULL, NULL) != SFM_OK)
                continue;
            rb[ok] = r2r_scene_error(&best, &T, NULL, &pb[ok]) * 180.0 / 3.14159265358979323846;
            ra[ok] = r2r_scene_error(&out, &T, NULL, &pa[ok]) * 180.0 / 3.14159265358979323846;
            mrb += rb[ok];
            mra += ra[ok];
            mpb += pb[ok];
            mpa += pa[ok];
            ok++;
        }
        const char *name = r2r_scene_systems[sys].name;
        if (unsupported) {
            SFM_TEST_LOG("%-11s not built (SFM_E_UNSUPPORTED)", name);
            continue;
        }
        if (refused == trials) {
            SFM_TEST_LOG("%-11s refused: rank-deficient (SFM_E_DEGENERATE)", name);
            continue;
        }
        mpb /= ok > 0 ? ok : 1;
        mpa /= ok > 0 ? ok : 1;
        mrb /= ok > 0 ? ok : 1;
        mra /= ok > 0 ? ok : 1;
        double r_b = median(rb, ok), r_a = median(ra, ok), p_b = median(pb, ok),
               p_a = median(pa, ok);
        SFM_TEST_LOG("%-11s %3d/%3d %10.3f %10.3f %10.4f %10.4f %10.4f %10.4f  (%d: no real "
                     "solution)",
                     name, ok, trials, r_b, r_a, p_b, p_a, mpb, mpa, none);
        /* noisy minimal data may have no real solution (a distance the
         * circle of candidate positions cannot reach): 3-15 % of 200 here;
         * the bound only keeps the averages below meaningful */
        SFM_CHECK_MSG(ok >= trials / 2, "%s solved %d of %d", name, ok, trials);
        SFM_CHECK_MSG(mra < mrb && mpa < mpb && r_a < r_b && p_a < p_b,
                      "%s: refinement did not lower the error", name);
    }
}

/* The refiner's measurement model is sfm_r2r_predict's: its cost at a
 * transform (no step taken) equals the one built from the predictions,
 * residuals e_k . u on the measured bearing's tangent basis. */
SFM_TEST(r2r_refine_cost_matches_sfm_r2r_predict)
{
    double worst = 0.0;
    for (int it = 0; it < SFM_TEST_ITERS(50); it++) {
        sfm_r2r_transform T, A, out;
        sfm_r2r_step s[6];
        r2r_scene_truth(t, &T);
        r2r_scene_steps(t, &T, 6, 3.0, s);
        random_masks(t, s, 6);
        r2r_scene_noise(t, 0.05, 0.02, s, 6);
        r2r_scene_perturb(t, &T, 0.1, 0.2, &A);
        const double sd = 0.05, sb = 0.02;
        double c = 0.0;
        for (int k = 0; k < 6; k++) {
            double d;
            sfm_vec3 b[2];
            SFM_CHECK_EQ_INT(sfm_r2r_predict(&s[k], &A, &d, &b[0], &b[1]), SFM_OK);
            if (s[k].has & SFM_R2R_D)
                c += (d - s[k].d) * (d - s[k].d) / (sd * sd);
            for (int j = 0; j < 2; j++) {
                if (!(s[k].has & (j == 0 ? SFM_R2R_B1 : SFM_R2R_B2)))
                    continue;
                /* |r|^2 = |u|^2 - (m . u)^2 for any orthonormal tangent pair */
                const double *m = j == 0 ? s[k].b1.v : s[k].b2.v;
                double mu = (m[0] * b[j].v[0] + m[1] * b[j].v[1] + m[2] * b[j].v[2]) /
                            sqrt(m[0] * m[0] + m[1] * m[1] + m[2] * m[2]);
                c += (1.0 - mu * mu) / (sb * sb);
            }
        }
        c *= 0.5;
        sfm_r2r_refine_options o;
        sfm_r2r_refine_default_options(&o);
        o.sigma_d = sd;
        o.sigma_b = sb;
        o.max_iterations = 0;
        sfm_r2r_refine_stats st;
        SFM_CHECK_EQ_INT(sfm_r2r_refine(s, 6, &A, &o, &out, NULL, &st), SFM_OK);
        worst = fmax(worst, fabs(st.initial_cost - c) / c);
        SFM_CHECK(memcmp(&out, &A, sizeof A) == 0);
    }
    SFM_TEST_LOG("largest relative cost difference %.3g", worst);
    SFM_CHECK(worst < 1e-9);
}
