/*
 * Robot-to-robot solve, refine and RANSAC under hostile measurements: zero
 * and negative distances, NaN and zero bearings, bearings not of unit
 * length, too few equations, unknown has bits, robots that coincide,
 * workspaces one byte short, counts out of range. A refusal returns a
 * status and leaves out / cov / inliers as they were (canaries).
 */
#include <math.h>
#include <string.h>

#include "r2r_api_scene.h"
#include "sfm/sfm_r2r.h"
#include "sfm_test.h"

static unsigned char r_ws[1 << 20];
static sfm_r2r_transform r_out[SFM_R2R_MAX_SOLUTIONS], r_canary[SFM_R2R_MAX_SOLUTIONS];

static void reset_out(void)
{
    sfm_test_fill_canary(r_canary, sizeof r_canary);
    memcpy(r_out, r_canary, sizeof r_out);
}

static int out_untouched(void) { return memcmp(r_out, r_canary, sizeof r_out) == 0; }

static int solve(const sfm_r2r_step *s, int n)
{
    return sfm_r2r_solve(s, n, r_out, r_ws, sizeof r_ws);
}

/* Truth among the solutions. */
static double best_err(int n, const sfm_r2r_transform *T)
{
    double e = HUGE_VAL;
    for (int i = 0; i < n; i++)
        e = fmin(e, terr(r_out + i, T));
    return e;
}

SFM_TEST(hostile_r2r_solve)
{
    static scene sc;
    unsigned has[2] = {B1_ | B2_, B1_};
    make_scene(t, &sc, 2, has);
    sfm_r2r_step s[2];
    memcpy(s, sc.s, sizeof s);
    reset_out();
    int n = solve(s, 2);
    SFM_CHECK(n >= 1);
    SFM_CHECK(best_err(n, &sc.T) < 1e-8);
    /* bearings of any nonzero length are directions */
    for (int k = 0; k < 2; k++)
        for (int i = 0; i < 3; i++) {
            s[k].b1.v[i] *= 7.0;
            s[k].b2.v[i] *= 1e-3;
        }
    reset_out();
    n = solve(s, 2);
    SFM_CHECK(n >= 1);
    SFM_CHECK_MSG(best_err(n, &sc.T) < 1e-8, "scaled bearings: error %g", best_err(n, &sc.T));

    int tried = 0;
#define REFUSE(want)                                                                               \
    do {                                                                                           \
        reset_out();                                                                               \
        int st_ = solve(s, 2);                                                                     \
        SFM_CHECK_MSG(st_ == (want), "line %d: status %d, want %d", __LINE__, st_, (want));       \
        SFM_CHECK(out_untouched());                                                                \
        memcpy(s, sc.s, sizeof s);                                                                 \
        tried++;                                                                                   \
    } while (0)
    memcpy(s, sc.s, sizeof s);
    s[1].b1.v[2] = (double)NAN;
    REFUSE(SFM_E_NONFINITE);
    s[0].b2.v[0] = (double)INFINITY;
    REFUSE(SFM_E_NONFINITE);
    s[0].b2.v[0] = s[0].b2.v[1] = s[0].b2.v[2] = 0.0;
    REFUSE(SFM_E_ARGUMENT);
    s[0].b1.v[0] = 1e-320; /* subnormal: no direction */
    s[0].b1.v[1] = s[0].b1.v[2] = 0.0;
    REFUSE(SFM_E_ARGUMENT);
    s[1].has = B1_ | 8u;
    REFUSE(SFM_E_ARGUMENT);
    s[1].has = 0; /* four equations */
    REFUSE(SFM_E_ARGUMENT);
    s[1].R1.m[0] = 1.5;
    REFUSE(SFM_E_ARGUMENT);
    s[1].t2.v[1] = (double)NAN;
    REFUSE(SFM_E_NONFINITE);
    /* a NaN in a field the mask leaves unused is ignored */
    s[1].d = (double)NAN;
    s[1].b2.v[0] = (double)NAN;
    reset_out();
    SFM_CHECK(solve(s, 2) >= 1);
    memcpy(s, sc.s, sizeof s);
    /* distances: zero, negative, NaN */
    unsigned hd[4] = {D_ | B1_, D_, D_, D_};
    static scene sd;
    make_scene(t, &sd, 4, hd);
    sfm_r2r_step u[4];
    memcpy(u, sd.s, sizeof u);
    u[2].d = 0.0;
    reset_out();
    SFM_CHECK_EQ_INT(sfm_r2r_solve(u, 4, r_out, r_ws, sizeof r_ws), SFM_E_ARGUMENT);
    u[2].d = -0.0;
    SFM_CHECK_EQ_INT(sfm_r2r_solve(u, 4, r_out, r_ws, sizeof r_ws), SFM_E_ARGUMENT);
    u[2].d = (double)NAN;
    SFM_CHECK_EQ_INT(sfm_r2r_solve(u, 4, r_out, r_ws, sizeof r_ws), SFM_E_NONFINITE);
    u[2].d = (double)INFINITY;
    SFM_CHECK_EQ_INT(sfm_r2r_solve(u, 4, r_out, r_ws, sizeof r_ws), SFM_E_NONFINITE);
    SFM_CHECK(out_untouched());
    tried += 4;
    /* counts and workspace */
    memcpy(u, sd.s, sizeof u);
    size_t need = sfm_r2r_solve_workspace_size(4);
    SFM_CHECK(need > 0 && need <= sizeof r_ws);
    SFM_CHECK_EQ_INT(sfm_r2r_solve(u, 4, r_out, r_ws, need - 1), SFM_E_WORKSPACE);
    SFM_CHECK_EQ_INT(sfm_r2r_solve(u, 0, r_out, r_ws, need), SFM_E_ARGUMENT);
    SFM_CHECK_EQ_INT(sfm_r2r_solve(u, -3, r_out, r_ws, need), SFM_E_ARGUMENT);
    SFM_CHECK_EQ_INT(sfm_r2r_solve(u, 4, NULL, r_ws, need), SFM_E_ARGUMENT);
    SFM_CHECK_EQ_INT(sfm_r2r_solve(u, 4, r_out, NULL, need), SFM_E_ARGUMENT);
    SFM_CHECK_EQ_INT(sfm_r2r_solve(NULL, 4, r_out, r_ws, need), SFM_E_ARGUMENT);
    SFM_CHECK(sfm_r2r_solve_workspace_size(0) == 0);
    SFM_CHECK(sfm_r2r_solve_workspace_size(-1) == 0);
    SFM_CHECK(out_untouched());
    tried += 9;
    /* identical robots: both stand still, each step the same measurement */
    for (int k = 1; k < 4; k++) {
        u[k] = u[0];
        u[k].has = D_;
    }
    reset_out();
    int st = sfm_r2r_solve(u, 4, r_out, r_ws, sizeof r_ws);
    SFM_CHECK_MSG(st == SFM_E_DEGENERATE, "robots standing still: %d", st);
    SFM_CHECK(out_untouched());
    tried++;
    SFM_TEST_LOG("%d hostile inputs to sfm_r2r_solve", tried + 3);
#undef REFUSE
}

SFM_TEST(hostile_r2r_refine)
{
    static scene sc;
    unsigned has[4] = {D_ | B1_ | B2_, D_ | B1_, B2_, D_};
    make_scene(t, &sc, 4, has);
    sfm_r2r_step s[4];
    memcpy(s, sc.s, sizeof s);
    sfm_r2r_transform init = sc.T, out, canary;
    init.p.v[0] += 0.05;
    double cov[36], covc[36];
    sfm_test_fill_canary(&canary, sizeof canary);
    sfm_test_fill_canary(covc, sizeof covc);
    out = canary;
    memcpy(cov, covc, sizeof cov);
    SFM_CHECK_EQ_INT(sfm_r2r_refine(s, 4, &init, NULL, &out, cov, NULL), SFM_OK);
    SFM_CHECK(terr(&out, &sc.T) < 1e-8);
    int tried = 1;
#define RREFUSE(want, opt)                                                                         \
    do {                                                                                           \
        out = canary;                                                                              \
        memcpy(cov, covc, sizeof cov);                                                             \
        int st_ = sfm_r2r_refine(s, 4, &init, (opt), &out, cov, NULL);                             \
        SFM_CHECK_MSG(st_ == (want), "line %d: status %d, want %d", __LINE__, st_, (want));       \
        SFM_CHECK(memcmp(&out, &canary, sizeof out) == 0 && memcmp(cov, covc, sizeof cov) == 0);   \
        memcpy(s, sc.s, sizeof s);                                                                 \
        init = sc.T;                                                                               \
        init.p.v[0] += 0.05;                                                                       \
        tried++;                                                                                   \
    } while (0)
    s[1].b1.v[0] = (double)NAN;
    RREFUSE(SFM_E_NONFINITE, NULL);
    s[1].b1.v[0] = s[1].b1.v[1] = s[1].b1.v[2] = 0.0;
    RREFUSE(SFM_E_ARGUMENT, NULL);
    s[3].d = 0.0;
    RREFUSE(SFM_E_ARGUMENT, NULL);
    s[3].has = 16u;
    RREFUSE(SFM_E_ARGUMENT, NULL);
    s[0].has = s[1].has = 0; /* three equations left */
    RREFUSE(SFM_E_ARGUMENT, NULL);
    init.C.m[4] = (double)NAN;
    RREFUSE(SFM_E_NONFINITE, NULL);
    init.C.m[0] = -1.0; /* a reflection */
    RREFUSE(SFM_E_ARGUMENT, NULL);
    init.p.v[2] = (double)INFINITY;
    RREFUSE(SFM_E_NONFINITE, NULL);
    /* the robots coincide at step 0 under init */
    for (int i = 0; i < 3; i++)
        init.p.v[i] = s[0].t1.v[i] - (init.C.m[3 * i] * s[0].t2.v[0] +
                                      init.C.m[3 * i + 1] * s[0].t2.v[1] +
                                      init.C.m[3 * i + 2] * s[0].t2.v[2]);
    RREFUSE(SFM_E_SINGULAR, NULL);
    sfm_r2r_refine_options o;
    sfm_r2r_refine_default_options(&o);
    o.sigma_d = 0.0;
    RREFUSE(SFM_E_ARGUMENT, &o);
    sfm_r2r_refine_default_options(&o);
    o.sigma_b = (double)NAN;
    RREFUSE(SFM_E_NONFINITE, &o);
    sfm_r2r_refine_default_options(&o);
    o.max_iterations = -1;
    RREFUSE(SFM_E_ARGUMENT, &o);
    sfm_r2r_refine_default_options(&o);
    o.loss = 7;
    RREFUSE(SFM_E_ARGUMENT, &o);
    sfm_r2r_refine_default_options(&o);
    o.loss = SFM_R2R_LOSS_HUBER;
    o.loss_scale = 0.0;
    RREFUSE(SFM_E_ARGUMENT, &o);
    SFM_CHECK_EQ_INT(sfm_r2r_refine(s, 0, &init, NULL, &out, NULL, NULL), SFM_E_ARGUMENT);
    SFM_CHECK_EQ_INT(sfm_r2r_refine(s, -1, &init, NULL, &out, NULL, NULL), SFM_E_ARGUMENT);
    SFM_CHECK_EQ_INT(sfm_r2r_refine(NULL, 4, &init, NULL, &out, NULL, NULL), SFM_E_ARGUMENT);
    SFM_CHECK_EQ_INT(sfm_r2r_refine(s, 4, NULL, NULL, &out, NULL, NULL), SFM_E_ARGUMENT);
    SFM_CHECK_EQ_INT(sfm_r2r_refine(s, 4, &init, NULL, NULL, NULL, NULL), SFM_E_ARGUMENT);
    SFM_CHECK(memcmp(&out, &canary, sizeof out) == 0);
    /* non-unit bearings: the same optimum */
    for (int k = 0; k < 4; k++)
        for (int i = 0; i < 3; i++) {
            s[k].b1.v[i] *= 3.0;
            s[k].b2.v[i] *= 0.25;
        }
    SFM_CHECK_EQ_INT(sfm_r2r_refine(s, 4, &init, NULL, &out, NULL, NULL), SFM_OK);
    SFM_CHECK_MSG(terr(&out, &sc.T) < 1e-8, "non-unit bearings: error %g", terr(&out, &sc.T));
    SFM_TEST_LOG("%d hostile inputs to sfm_r2r_refine", tried + 6);
#undef RREFUSE
}

SFM_TEST(hostile_r2r_ransac)
{
    static scene sc;
    unsigned has[8] = {D_ | B1_ | B2_, D_ | B1_, B2_, D_, D_ | B1_, B1_ | B2_, D_, B1_};
    make_scene(t, &sc, 8, has);
    sfm_r2r_step s[8];
    memcpy(s, sc.s, sizeof s);
    size_t need = sfm_r2r_ransac_workspace_size(8);
    SFM_CHECK(need > 0 && need <= sizeof r_ws);
    SFM_CHECK(sfm_r2r_ransac_workspace_size(0) == 0);
    SFM_CHECK(sfm_r2r_ransac_workspace_size(SFM_R2R_RANSAC_MAX_STEPS + 1) == 0);
    sfm_r2r_transform out, canary;
    unsigned inl[8], inlc[8];
    sfm_test_fill_canary(&canary, sizeof canary);
    sfm_test_fill_canary(inlc, sizeof inlc);
    out = canary;
    memcpy(inl, inlc, sizeof inl);
    int n = sfm_r2r_ransac(s, 8, NULL, &out, inl, NULL, NULL, r_ws, need);
    SFM_CHECK(n >= 6);
    SFM_CHECK(terr(&out, &sc.T) < 1e-6);
    int tried = 1;
#define AREFUSE(want, nn, wsz)                                                                     \
    do {                                                                                           \
        out = canary;                                                                              \
        memcpy(inl, inlc, sizeof inl);                                                             \
        int st_ = sfm_r2r_ransac(s, (nn), NULL, &out, inl, NULL, NULL, r_ws, (wsz));               \
        SFM_CHECK_MSG(st_ == (want), "line %d: status %d, want %d", __LINE__, st_, (want));       \
        SFM_CHECK(memcmp(&out, &canary, sizeof out) == 0 && memcmp(inl, inlc, sizeof inl) == 0);   \
        memcpy(s, sc.s, sizeof s);                                                                 \
        tried++;                                                                                   \
    } while (0)
    AREFUSE(SFM_E_WORKSPACE, 8, need - 1);
    AREFUSE(SFM_E_ARGUMENT, 0, need);
    AREFUSE(SFM_E_ARGUMENT, -8, need);
    AREFUSE(SFM_E_ARGUMENT, SFM_R2R_RANSAC_MAX_STEPS + 1, sizeof r_ws);
    s[5].b2.v[1] = (double)NAN;
    AREFUSE(SFM_E_NONFINITE, 8, need);
    s[6].d = -2.0;
    AREFUSE(SFM_E_ARGUMENT, 8, need);
    s[7].b1.v[0] = s[7].b1.v[1] = s[7].b1.v[2] = 0.0;
    AREFUSE(SFM_E_ARGUMENT, 8, need);
    s[2].has = 0xffu;
    AREFUSE(SFM_E_ARGUMENT, 8, need);
    for (int k = 0; k < 8; k++)
        s[k].has = k == 0 ? D_ : 0u; /* one equation */
    AREFUSE(SFM_E_ARGUMENT, 8, need);
    sfm_r2r_ransac_options o;
    sfm_r2r_ransac_default_options(&o);
    o.refine.sigma_d = -1.0;
    out = canary;
    SFM_CHECK_EQ_INT(sfm_r2r_ransac(s, 8, &o, &out, NULL, NULL, NULL, r_ws, need), SFM_E_ARGUMENT);
    sfm_r2r_ransac_default_options(&o);
    o.ransac.threshold = (double)NAN;
    int st = sfm_r2r_ransac(s, 8, &o, &out, NULL, NULL, NULL, r_ws, need);
    SFM_CHECK_MSG(st == SFM_E_NONFINITE || st == SFM_E_ARGUMENT, "NaN threshold: %d", st);
    SFM_CHECK(memcmp(&out, &canary, sizeof out) == 0);
    /* the same input gives the same bits */
    sfm_r2r_transform a, b;
    SFM_CHECK(sfm_r2r_ransac(s, 8, NULL, &a, NULL, NULL, NULL, r_ws, need) >= 6);
    SFM_CHECK(sfm_r2r_ransac(s, 8, NULL, &b, NULL, NULL, NULL, r_ws, need) >= 6);
    SFM_CHECK(memcmp(&a, &b, sizeof a) == 0);
    SFM_TEST_LOG("%d hostile inputs to sfm_r2r_ransac", tried + 4);
#undef AREFUSE
}
