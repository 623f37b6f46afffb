/* The RANSAC engine on a toy estimator with known truth: 2D line fitting. */
#include <math.h>
#include <string.h>
#include <stdlib.h>

#include "sfm/sfm.h"
#include "sfm_test.h"

/* Figures go to the log on hosts only: newlib's float formatting allocates,
 * and the emulated Cortex-M7 board has no heap for it. */
#ifdef SFM_TEST_REDUCED
#define RANSAC_LOG(...) ((void)0)
#else
#define RANSAC_LOG(...) SFM_TEST_LOG(__VA_ARGS__)
#endif

#define NPTS 400

typedef struct line_ctx {
    const double *xy; /* n x 2 */
    int refine_calls;
    double scale; /* robust scale of the refit (the threshold) */
} line_ctx;

/* Model: (a, b, c) with a^2 + b^2 = 1, line a x + b y + c = 0. */
static int line_solve(void *ctx, const int *s, double *models)
{
    const line_ctx *L = ctx;
    const double *p = L->xy + 2 * s[0], *q = L->xy + 2 * s[1];
    double dx = q[0] - p[0], dy = q[1] - p[1];
    double nrm = sqrt(dx * dx + dy * dy);
    if (nrm < 1e-12)
        return 0;
    models[0] = -dy / nrm;
    models[1] = dx / nrm;
    models[2] = -(models[0] * p[0] + models[1] * p[1]);
    return 1;
}

static double line_residual(void *ctx, const double *m, int i)
{
    const line_ctx *L = ctx;
    double r = m[0] * L->xy[2 * i] + m[1] * L->xy[2 * i + 1] + m[2];
    return r * r;
}

/* Weighted total least squares on the listed points (closed-form 2x2
 * eigenvector), Cauchy weights from the current model's residuals. */
static int line_refine(void *ctx, const int *inl, int n, double *m)
{
    line_ctx *L = ctx;
    const double scale = L->scale;
    L->refine_calls++;
    double mx = 0, my = 0, sw = 0;
    for (int i = 0; i < n; i++) {
        double w = scale > 0 ? 1.0 / (1.0 + line_residual(ctx, m, inl[i]) / (scale * scale)) : 1.0;
        mx += w * L->xy[2 * inl[i]];
        my += w * L->xy[2 * inl[i] + 1];
        sw += w;
    }
    mx /= sw;
    my /= sw;
    double sxx = 0, sxy = 0, syy = 0;
    for (int i = 0; i < n; i++) {
        double w = scale > 0 ? 1.0 / (1.0 + line_residual(ctx, m, inl[i]) / (scale * scale)) : 1.0;
        double dx = L->xy[2 * inl[i]] - mx, dy = L->xy[2 * inl[i] + 1] - my;
        sxx += w * dx * dx;
        sxy += w * dx * dy;
        syy += w * dy * dy;
    }
    /* normal = eigenvector of the smaller eigenvalue */
    double theta = 0.5 * atan2(2 * sxy, sxx - syy); /* direction of the line */
    m[0] = -sin(theta);
    m[1] = cos(theta);
    m[2] = -(m[0] * mx + m[1] * my);
    return 0;
}

static int line_degenerate(void *ctx, const int *s)
{
    const line_ctx *L = ctx;
    return L->xy[2 * s[0]] == L->xy[2 * s[1]] && L->xy[2 * s[0] + 1] == L->xy[2 * s[1] + 1];
}

static void line_estimator(sfm_ransac_estimator *e, line_ctx *L)
{
    memset(e, 0, sizeof *e);
    e->sample_size = 2;
    e->max_models = 1;
    e->model_size = 3;
    e->solve = line_solve;
    e->residual = line_residual;
    e->refine = line_refine;
    e->degenerate = line_degenerate;
    e->ctx = L;
}

/* Points on y = slope x + icpt with noise sigma; outliers uniform in the box.
 * Outliers are placed at random positions in the list. truth[i] = 1 for
 * points drawn from the line. */
static void make_line(sfm_test_ctx *t, int n, double outlier_ratio, double sigma, double *xy,
                      unsigned char *truth, double line[3])
{
    double ang = sfm_test_uniform(t, 0, 3.14159);
    double a = -sin(ang), b = cos(ang), c = sfm_test_uniform(t, -0.5, 0.5);
    line[0] = a;
    line[1] = b;
    line[2] = c;
    for (int i = 0; i < n; i++) {
        truth[i] = sfm_test_uniform(t, 0, 1) >= outlier_ratio;
        if (truth[i]) {
            double s = sfm_test_uniform(t, -1, 1);
            /* foot point -c*(a,b) plus s along the direction (b, -a) */
            xy[2 * i] = -c * a + s * b + sfm_test_normal(t, sigma) * a;
            xy[2 * i + 1] = -c * b - s * a + sfm_test_normal(t, sigma) * b;
        } else {
            xy[2 * i] = sfm_test_uniform(t, -1.5, 1.5);
            xy[2 * i + 1] = sfm_test_uniform(t, -1.5, 1.5);
        }
    }
}

static double line_angle_err(const double *m, const double *truth)
{
    double d = fabs(m[0] * truth[0] + m[1] * truth[1]);
    if (d > 1)
        d = 1;
    return acos(d);
}

static double line_offset_err(const double *m, const double *truth)
{
    double sgn = (m[0] * truth[0] + m[1] * truth[1]) < 0 ? -1.0 : 1.0;
    return fabs(sgn * m[2] - truth[2]);
}

static unsigned char ws_buf[SFM_RANSAC_WS_SIZE(NPTS, 2, 1, 3)];
static double pts[2 * NPTS];
static unsigned char truth_mask[NPTS];
static uint8_t mask[NPTS], mask2[NPTS];

/* The estimator over pts and the default options with the wide band, the
 * given inlier threshold also the refit's robust scale. */
static void line_setup(line_ctx *L, sfm_ransac_estimator *est, sfm_ransac_options *opt, double threshold)
{
    L->xy = pts;
    L->refine_calls = 0;
    L->scale = threshold;
    line_estimator(est, L);
    sfm_ransac_default_options(opt);
    opt->wide_mult = SFM_RANSAC_WIDE_MULT;
    opt->threshold = threshold;
}

/* One run on all NPTS points with the whole workspace. */
static int line_run(const sfm_ransac_estimator *est, const sfm_ransac_options *opt, double *model,
                    uint8_t *inl, sfm_ransac_stats *st)
{
    return sfm_ransac_run(est, NPTS, opt, model, inl, st, ws_buf, sizeof ws_buf);
}

SFM_TEST(ransac_ws_macro_matches_function)
{
    sfm_ransac_dims d = {NPTS, 2, 1, 3};
    SFM_CHECK_EQ_INT(sfm_ransac_workspace_size(&d), sizeof ws_buf);
    int ns[] = {1, 7, 100, 1000, 12345};
    int ks[] = {2, 3, 5, 7, 16};
    int ms[] = {1, 4, 10, 64, 3};
    int ss[] = {3, 12, 21, 9, 64};
    for (int i = 0; i < 5; i++) {
        sfm_ransac_dims e = {ns[i], ks[i], ms[i], ss[i]};
        SFM_CHECK_EQ_INT(sfm_ransac_workspace_size(&e), SFM_RANSAC_WS_SIZE(ns[i], ks[i], ms[i], ss[i]));
    }
    sfm_ransac_dims bad = {0, 2, 1, 3};
    SFM_CHECK_EQ_INT(sfm_ransac_workspace_size(&bad), 0);
    bad.n = 10;
    bad.sample_size = SFM_RANSAC_MAX_SAMPLE + 1;
    SFM_CHECK_EQ_INT(sfm_ransac_workspace_size(&bad), 0);
    SFM_CHECK_EQ_INT(sfm_ransac_workspace_size(NULL), 0);
}

SFM_TEST(ransac_line_outlier_levels)
{
    const double ratios[] = {0.25, 0.5, 0.75};
    for (int r = 0; r < 3; r++) {
        for (int trial = 0; trial < SFM_TEST_ITERS(20); trial++) {
            double line[3], model[3];
            make_line(t, NPTS, ratios[r], 0.01, pts, truth_mask, line);
            line_ctx L;
            sfm_ransac_estimator est;
            sfm_ransac_options opt;
            line_setup(&L, &est, &opt, 0.03);
            opt.seed = (uint64_t)trial;
            sfm_ransac_stats st;
            int ni = line_run(&est, &opt, model, mask, &st);
            SFM_CHECK(ni > 0);
            if (ni <= 0)
                continue;
            SFM_CHECK_EQ_INT(ni, st.num_inliers);
            /* 400 points over length 2: angle noise ~ sigma * sqrt(12 / n) / 2 */
            SFM_CHECK_MSG(line_angle_err(model, line) < 0.01, "ratio %.2f angle err %g", ratios[r],
                          line_angle_err(model, line));
            SFM_CHECK(line_offset_err(model, line) < 0.01);
            int tp = 0, fp = 0, ntrue = 0, cnt = 0;
            for (int i = 0; i < NPTS; i++) {
                ntrue += truth_mask[i];
                cnt += mask[i];
                tp += mask[i] && truth_mask[i];
                fp += mask[i] && !truth_mask[i];
            }
            SFM_CHECK_EQ_INT(cnt, ni);
            /* threshold 3 sigma keeps ~99.7 % of the true inliers */
            SFM_CHECK_MSG(tp >= (int)(0.97 * ntrue), "ratio %.2f: %d of %d true inliers", ratios[r],
                          tp, ntrue);
            /* an outlier falls in the +-0.03 band with probability ~0.04 */
            SFM_CHECK(fp <= (int)(0.1 * (NPTS - ntrue)) + 3);
            SFM_CHECK(st.stop_reason == SFM_RANSAC_STOP_CONFIDENCE);
            SFM_CHECK(st.iterations <= opt.max_iterations);
            SFM_CHECK(st.seed == opt.seed);
            SFM_CHECK(st.lo_runs >= 1);
        }
    }
}

/* Two runs gave the same answer: count, line bits, mask (mask, mask2),
 * samples and models. */
static void check_same_run(sfm_test_ctx *t, int a, int b, const double m1[3], const double m2[3],
                           const sfm_ransac_stats *s1, const sfm_ransac_stats *s2)
{
    SFM_CHECK(a > 0);
    SFM_CHECK_EQ_INT(a, b);
    SFM_CHECK(memcmp(m1, m2, 3 * sizeof(double)) == 0);
    SFM_CHECK(memcmp(mask, mask2, sizeof mask) == 0);
    SFM_CHECK_EQ_INT(s1->iterations, s2->iterations);
    SFM_CHECK_EQ_INT(s1->models, s2->models);
}

SFM_TEST(ransac_same_seed_identical)
{
    double line[3], m1[3], m2[3];
    make_line(t, NPTS, 0.6, 0.01, pts, truth_mask, line);
    line_ctx L;
    sfm_ransac_estimator est;
    sfm_ransac_options opt;
    line_setup(&L, &est, &opt, 0.02);
    opt.seed = 1234;
    sfm_ransac_stats s1, s2;
    int a = line_run(&est, &opt, m1, mask, &s1);
    int b = line_run(&est, &opt, m2, mask2, &s2);
    check_same_run(t, a, b, m1, m2, &s1, &s2);
    /* a different seed draws a different sample sequence */
    opt.seed = 99;
    b = line_run(&est, &opt, m2, mask2, &s2);
    SFM_CHECK(b > 0);
    SFM_CHECK(line_angle_err(m2, line) < 0.01);
}

/* The block residual: the same values as line_residual, counted. */
static int line_block_calls;
static void line_residuals(void *ctx, const double *m, const int *idx, int count, double *r2)
{
    line_block_calls++;
    for (int q = 0; q < count; q++)
        r2[q] = line_residual(ctx, m, idx[q]);
}

static void line_set_scale(void *ctx, double scale)
{
    ((line_ctx *)ctx)->scale = scale;
}

/* An estimator with a block residual runs the same as without it: same
 * model bits, mask and decisions (SPRT, bail-out and MSAC exits taken
 * point by point on the block's values), with and without set_scale (the
 * kept residuals, votes and LO bands read the block's values too), at the
 * outlier levels where SPRT rejects early and late. */
SFM_TEST(ransac_block_residual_same_run)
{
    const double ratios[] = {0.25, 0.5, 0.75};
    for (int r = 0; r < 3; r++) {
        for (int scaled = 0; scaled < 2; scaled++) {
            double line[3], m1[3], m2[3];
            make_line(t, NPTS, ratios[r], 0.01, pts, truth_mask, line);
            line_ctx L;
            sfm_ransac_estimator est;
            sfm_ransac_options opt;
            line_setup(&L, &est, &opt, 0.03);
            if (scaled)
                est.set_scale = line_set_scale;
            opt.seed = (uint64_t)(17 + r);
            sfm_ransac_stats s1, s2;
            int a = line_run(&est, &opt, m1, mask, &s1);
            L.scale = 0.03;
            est.residuals = line_residuals;
            line_block_calls = 0;
            int b = line_run(&est, &opt, m2, mask2, &s2);
            /* the Cortex-M7 variant builds the engine for size
             * (mk/cross.mk), which leaves block residuals unused */
#if !defined(__ARM_ARCH_7EM__)
            SFM_CHECK(line_block_calls > 0);
#else
            SFM_CHECK_EQ_INT(line_block_calls, 0);
#endif
            check_same_run(t, a, b, m1, m2, &s1, &s2);
            SFM_CHECK_EQ_INT(s1.sprt_rejected, s2.sprt_rejected);
            SFM_CHECK_EQ_INT(s1.lo_runs, s2.lo_runs);
            SFM_CHECK_EQ_INT(s1.inner_runs, s2.inner_runs);
            SFM_CHECK_EQ_INT(s1.polish_rounds, s2.polish_rounds);
            SFM_CHECK(s1.score == s2.score);
        }
    }
}

SFM_TEST(ransac_sprt_rejects_early_same_answer)
{
    double line[3], m1[3], m2[3];
    make_line(t, NPTS, 0.75, 0.01, pts, truth_mask, line);
    line_ctx L;
    sfm_ransac_estimator est;
    sfm_ransac_options opt;
    line_setup(&L, &est, &opt, 0.03);
    opt.min_iterations = 300;
    sfm_ransac_stats s1, s2;
    opt.use_sprt = 1;
    int a = line_run(&est, &opt, m1, mask, &s1);
    opt.use_sprt = 0;
    int b = line_run(&est, &opt, m2, mask2, &s2);
    SFM_CHECK(a > 0 && b > 0);
    SFM_CHECK(s1.sprt_rejected > s1.models / 2);
    SFM_CHECK_EQ_INT(s2.sprt_rejected, 0);
    SFM_CHECK(line_angle_err(m1, line) < 0.01);
    SFM_CHECK(line_angle_err(m2, line) < 0.01);
    SFM_CHECK(abs(a - b) <= 3);
}

SFM_TEST(ransac_lo_lowers_cost)
{
    double line[3], m1[3], m2[3];
    make_line(t, NPTS, 0.5, 0.01, pts, truth_mask, line);
    line_ctx L;
    sfm_ransac_estimator est;
    sfm_ransac_options opt;
    line_setup(&L, &est, &opt, 0.03);
    opt.polish_rounds = 0;
    sfm_ransac_stats s1, s2;
    int a = line_run(&est, &opt, m1, NULL, &s1);
    SFM_CHECK(L.refine_calls > 0);
    opt.lo_rounds = 0;
    L.refine_calls = 0;
    int b = line_run(&est, &opt, m2, NULL, &s2);
    SFM_CHECK_EQ_INT(L.refine_calls, 0);
    SFM_CHECK(a > 0 && b > 0);
    SFM_CHECK(s1.score <= s2.score);
    SFM_CHECK(line_angle_err(m1, line) <= line_angle_err(m2, line) + 1e-3);
}

SFM_TEST(ransac_polish_uses_the_wider_band)
{
    /* threshold = noise sigma keeps ~68 % of the true inliers; the polish
     * fits on those within 3 sigma and lands closer to the truth */
    double sum_p = 0.0, sum_n = 0.0;
    int kept = 0;
    const int trials = SFM_TEST_ITERS(40);
    for (int k = 0; k < trials; k++) {
        double line[3], m1[3], m2[3];
        make_line(t, NPTS, 0.5, 0.01, pts, truth_mask, line);
        line_ctx L;
        sfm_ransac_estimator est;
        sfm_ransac_options opt;
        line_setup(&L, &est, &opt, 0.01);
        opt.seed = (uint64_t)k;
        sfm_ransac_stats st;
        SFM_CHECK(line_run(&est, &opt, m1, NULL, &st) > 0);
        kept += st.polished;
        opt.polish_rounds = 0;
        SFM_CHECK(line_run(&est, &opt, m2, NULL, &st) > 0);
        SFM_CHECK_EQ_INT(st.polished, 0);
        sum_p += line_angle_err(m1, line);
        sum_n += line_angle_err(m2, line);
    }
    RANSAC_LOG("mean angle error %.5f with polish, %.5f without (%d of %d kept)", sum_p / trials,
                 sum_n / trials, kept, trials);
    SFM_CHECK(kept >= trials * 3 / 4);
    SFM_CHECK(sum_p < sum_n);
}

SFM_TEST(ransac_iteration_cap_and_minimum)
{
    double line[3], model[3];
    make_line(t, NPTS, 0.9, 0.01, pts, truth_mask, line);
    line_ctx L;
    sfm_ransac_estimator est;
    sfm_ransac_options opt;
    line_setup(&L, &est, &opt, 0.03);
    opt.max_iterations = 7;
    opt.confidence = 0.999999;
    sfm_ransac_stats st;
    int a = line_run(&est, &opt, model, NULL, &st);
    SFM_CHECK(a > 0);
    SFM_CHECK_EQ_INT(st.iterations, 7);
    SFM_CHECK_EQ_INT(st.stop_reason, SFM_RANSAC_STOP_MAX_ITERATIONS);
    /* clean data stops after a handful of samples, unless a minimum is set */
    make_line(t, NPTS, 0.0, 0.001, pts, truth_mask, line);
    opt.max_iterations = 1000;
    opt.confidence = 0.99;
    a = line_run(&est, &opt, model, NULL, &st);
    SFM_CHECK(a > 0);
    SFM_CHECK(st.iterations < 10);
    SFM_CHECK_EQ_INT(st.stop_reason, SFM_RANSAC_STOP_CONFIDENCE);
    opt.min_iterations = 50;
    a = line_run(&est, &opt, model, NULL, &st);
    SFM_CHECK_EQ_INT(st.iterations, 50);
}

static double fake_clock(void *c)
{
    double *now = c;
    *now += 1.0; /* each reading advances one "second" */
    return *now;
}

SFM_TEST(ransac_time_budget_uses_caller_clock)
{
    double line[3], model[3];
    make_line(t, NPTS, 0.9, 0.01, pts, truth_mask, line);
    line_ctx L;
    sfm_ransac_estimator est;
    sfm_ransac_options opt;
    line_setup(&L, &est, &opt, 0.03);
    opt.confidence = 0.999999;
    double now = 0.0;
    opt.clock = fake_clock;
    opt.clock_ctx = &now;
    opt.time_budget = 10.0;
    sfm_ransac_stats st;
    int a = line_run(&est, &opt, model, NULL, &st);
    SFM_CHECK(a > 0);
    SFM_CHECK_EQ_INT(st.stop_reason, SFM_RANSAC_STOP_TIME);
    /* start reading at 1, then 2..: the 10th later reading ends the run and
     * is the last one; inner RANSACs read the clock too, so at most 9
     * samples were drawn */
    SFM_CHECK(now == 11.0);
    SFM_CHECK(st.iterations >= 1 && st.iterations <= 9);
}

SFM_TEST(ransac_prosac_uses_quality)
{
    static double quality[NPTS];
    double line[3], model[3];
    make_line(t, NPTS, 0.8, 0.01, pts, truth_mask, line);
    for (int i = 0; i < NPTS; i++)
        quality[i] = truth_mask[i] ? 1.0 + sfm_test_uniform(t, 0, 1) : sfm_test_uniform(t, 0, 1.2);
    line_ctx L;
    sfm_ransac_estimator est;
    sfm_ransac_options opt;
    line_setup(&L, &est, &opt, 0.03);
    opt.quality = quality;
    sfm_ransac_stats st;
    int a = line_run(&est, &opt, model, mask, &st);
    SFM_CHECK(a > 0);
    SFM_CHECK(line_angle_err(model, line) < 0.01);
    /* the first samples come from the top-ranked points, all on the line */
    SFM_CHECK(st.iterations <= 300);
    quality[3] = (double)NAN;
    SFM_CHECK_EQ_INT(line_run(&est, &opt, model, mask, &st),
                     SFM_E_NONFINITE);
}

SFM_TEST(ransac_contract)
{
    double line[3];
    make_line(t, NPTS, 0.3, 0.01, pts, truth_mask, line);
    line_ctx L;
    sfm_ransac_estimator est;
    sfm_ransac_options opt;
    line_setup(&L, &est, &opt, 0.03);
    double model[3];
    sfm_ransac_stats st;
    sfm_test_fill_canary(model, sizeof model);
    sfm_test_fill_canary(mask, sizeof mask);
    sfm_test_fill_canary(&st, sizeof st);
#define UNTOUCHED()                                                                   \
    do {                                                                              \
        SFM_CHECK(sfm_test_canary_intact(model, sizeof model));                       \
        SFM_CHECK(sfm_test_canary_intact(mask, sizeof mask));                         \
        SFM_CHECK(sfm_test_canary_intact(&st, sizeof st));                            \
    } while (0)
    SFM_CHECK_EQ_INT(sfm_ransac_run(NULL, NPTS, &opt, model, mask, &st, ws_buf, sizeof ws_buf), SFM_E_ARGUMENT);
    SFM_CHECK_EQ_INT(sfm_ransac_run(&est, NPTS, NULL, model, mask, &st, ws_buf, sizeof ws_buf), SFM_E_ARGUMENT);
    SFM_CHECK_EQ_INT(line_run(&est, &opt, NULL, mask, &st), SFM_E_ARGUMENT);
    SFM_CHECK_EQ_INT(sfm_ransac_run(&est, NPTS, &opt, model, mask, &st, NULL, sizeof ws_buf), SFM_E_ARGUMENT);
    SFM_CHECK_EQ_INT(sfm_ransac_run(&est, 1, &opt, model, mask, &st, ws_buf, sizeof ws_buf), SFM_E_ARGUMENT);
    SFM_CHECK_EQ_INT(sfm_ransac_run(&est, -5, &opt, model, mask, &st, ws_buf, sizeof ws_buf), SFM_E_ARGUMENT);
    /* a workspace one byte short */
    SFM_CHECK_EQ_INT(sfm_ransac_run(&est, NPTS, &opt, model, mask, &st, ws_buf, sizeof ws_buf - 1), SFM_E_WORKSPACE);
    /* any caller alignment works with exactly the reported size */
    {
        sfm_ransac_dims d = {NPTS - 8, 2, 1, 3};
        size_t need = sfm_ransac_workspace_size(&d);
        SFM_CHECK(need + 1 <= sizeof ws_buf);
        double m2[3];
        SFM_CHECK(sfm_ransac_run(&est, NPTS - 8, &opt, m2, NULL, NULL, ws_buf + 1, need) > 0);
    }
    opt.threshold = (double)NAN;
    SFM_CHECK_EQ_INT(line_run(&est, &opt, model, mask, &st), SFM_E_NONFINITE);
    opt.threshold = -1;
    SFM_CHECK_EQ_INT(line_run(&est, &opt, model, mask, &st), SFM_E_ARGUMENT);
    opt.threshold = 0.03;
    L.scale = opt.threshold;
    opt.confidence = 1.0;
    SFM_CHECK_EQ_INT(line_run(&est, &opt, model, mask, &st), SFM_E_ARGUMENT);
    opt.confidence = 0.99;
    opt.max_iterations = 0;
    SFM_CHECK_EQ_INT(line_run(&est, &opt, model, mask, &st), SFM_E_ARGUMENT);
    opt.max_iterations = 10;
    opt.min_iterations = 11;
    SFM_CHECK_EQ_INT(line_run(&est, &opt, model, mask, &st), SFM_E_ARGUMENT);
    opt.min_iterations = 0;
    est.residual = NULL;
    SFM_CHECK_EQ_INT(line_run(&est, &opt, model, mask, &st), SFM_E_ARGUMENT);
    line_estimator(&est, &L);
    est.sample_size = 0;
    SFM_CHECK_EQ_INT(line_run(&est, &opt, model, mask, &st), SFM_E_ARGUMENT);
    UNTOUCHED();
    SFM_CHECK_EQ_INT(sfm_ransac_default_options(NULL), SFM_E_ARGUMENT);
}

static int failing_solve(void *ctx, const int *s, double *m)
{
    (void)ctx;
    (void)s;
    (void)m;
    return SFM_E_SINGULAR;
}

static int empty_solve(void *ctx, const int *s, double *m)
{
    (void)ctx;
    (void)s;
    (void)m;
    return 0;
}

SFM_TEST(ransac_solver_status_and_no_model)
{
    double line[3], model[3];
    make_line(t, NPTS, 0.3, 0.01, pts, truth_mask, line);
    line_ctx L;
    sfm_ransac_estimator est;
    sfm_ransac_options opt;
    line_setup(&L, &est, &opt, 0.03);
    opt.max_iterations = 20;
    sfm_test_fill_canary(model, sizeof model);
    est.solve = failing_solve;
    SFM_CHECK_EQ_INT(line_run(&est, &opt, model, NULL, NULL), SFM_E_SINGULAR);
    est.solve = empty_solve;
    SFM_CHECK_EQ_INT(line_run(&est, &opt, model, NULL, NULL), SFM_E_NO_CONVERGENCE);
    SFM_CHECK(sfm_test_canary_intact(model, sizeof model));
}
