/*
 * sfm_r2r_ransac against known answers: sequences with 30 % of their
 * measurements replaced by gross outliers must give back the truth within
 * the noise and flag the outliers; the same seed the same answer; the
 * contract on bad inputs.
 */
#include <math.h>
#include <stdint.h>
#include <string.h>

#include "r2r_scene.h"
#include "sfm_test.h"

#define NS 10

/* Replaces a share of the measurements by outliers (a distance 1..3 m off,
 * a bearing drawn at random); *is_out gets the has-mask of those. */
static int corrupt(sfm_test_ctx *t, sfm_r2r_step *s, int n, double share, unsigned *is_out)
{
    int nm = 0, k_out = 0;
    for (int k = 0; k < n; k++)
        nm += (s[k].has & 1u) + ((s[k].has >> 1) & 1u) + ((s[k].has >> 2) & 1u);
    int want = (int)(share * nm + 0.5);
    memset(is_out, 0, sizeof(unsigned) * (size_t)n);
    while (k_out < want) {
        int k = (int)sfm_rng_bounded(&t->rng, (uint32_t)n);
        unsigned bit = 1u << sfm_rng_bounded(&t->rng, 3);
        if (!(s[k].has & bit) || (is_out[k] & bit))
            continue;
        is_out[k] |= bit;
        k_out++;
        if (bit == SFM_R2R_D)
            s[k].d += sfm_test_uniform(t, 1.0, 3.0);
        else
            sfm_test_random_unit(t, bit == SFM_R2R_B1 ? s[k].b1.v : s[k].b2.v);
    }
    return k_out;
}

static unsigned char g_ws[1 << 18];

SFM_TEST(r2r_ransac_recovers_truth_with_30pct_outliers)
{
    const int trials = SFM_TEST_ITERS(30);
    const double sd = 0.02, sb = 0.01;
    size_t need = sfm_r2r_ransac_workspace_size(NS);
    SFM_CHECK(need > 0 && need <= sizeof g_ws);
    int good = 0, flagged = 0, n_out_all = 0, kept = 0, n_in_all = 0;
    double worst_r = 0.0, worst_p = 0.0;
    for (int it = 0; it < trials; it++) {
        sfm_r2r_transform T, out;
        sfm_r2r_step s[NS];
        unsigned is_out[NS], inl[NS];
        r2r_scene_truth(t, &T);
        r2r_scene_steps(t, &T, NS, 3.0, s);
        r2r_scene_noise(t, sd, sb, s, NS);
        int n_out = corrupt(t, s, NS, 0.3, is_out);
        sfm_r2r_ransac_options o;
        sfm_r2r_ransac_default_options(&o);
        o.refine.sigma_d = sd;
        o.refine.sigma_b = sb;
        o.ransac.seed = 1000u + (unsigned)it;
        sfm_ransac_stats st;
        double cov[36];
        int n = sfm_r2r_ransac(s, NS, &o, &out, inl, cov, &st, g_ws, need);
        if (n < 1) {
            SFM_TEST_LOG("trial %d: status %d", it, n);
            continue;
        }
        double pe, re = r2r_scene_error(&out, &T, NULL, &pe);
        worst_r = fmax(worst_r, re);
        worst_p = fmax(worst_p, pe);
        /* 21 inlier measurements at 0.02 m / 0.01 rad: errors of a few
         * hundredths; a wrong model is off by tenths or more */
        if (re < 0.03 && pe < 0.1)
            good++;
        for (int k = 0; k < NS; k++)
            for (unsigned bit = 1u; bit <= 4u; bit <<= 1) {
                if (is_out[k] & bit)
                    flagged += !(inl[k] & bit);
                else if (s[k].has & bit)
                    kept += (inl[k] & bit) != 0;
            }
        n_out_all += n_out;
        n_in_all += 3 * NS - n_out;
        SFM_CHECK_EQ_INT(st.num_inliers, n);
        SFM_CHECK_EQ_INT(st.cov_dim, 6);
    }
    SFM_TEST_LOG("truth recovered in %d of %d; worst %.4f rad, %.4f m; outliers flagged %d of %d, "
                 "inliers kept %d of %d",
                 good, trials, worst_r, worst_p, flagged, n_out_all, kept, n_in_all);
    SFM_CHECK_EQ_INT(good, trials);
    SFM_CHECK(flagged >= n_out_all - n_out_all / 50);
    SFM_CHECK(kept >= n_in_all - n_in_all / 20);
}

/* Sequences whose steps carry random subsets of the measurements (8-20
 * steps), 30 % of them outliers. */
SFM_TEST(r2r_ransac_partial_measurements)
{
    enum { MAXS = 20 };
    const int trials = SFM_TEST_ITERS(40);
    const double sd = 0.02, sb = 0.01;
    int good = 0, missed = 0, n_out_all = 0;
    for (int it = 0; it < trials; it++) {
        sfm_r2r_transform T, out;
        sfm_r2r_step s[MAXS];
        unsigned is_out[MAXS], inl[MAXS];
        const int n = 8 + (int)sfm_rng_bounded(&t->rng, MAXS - 7);
        r2r_scene_truth(t, &T);
        r2r_scene_steps(t, &T, n, 3.0, s);
        r2r_scene_noise(t, sd, sb, s, n);
        for (int k = 0; k < n; k++)
            s[k].has = 1u + sfm_rng_bounded(&t->rng, 7);
        n_out_all += corrupt(t, s, n, 0.3, is_out);
        sfm_r2r_ransac_options o;
        sfm_r2r_ransac_default_options(&o);
        o.refine.sigma_d = sd;
        o.refine.sigma_b = sb;
        size_t need = sfm_r2r_ransac_workspace_size(n);
        SFM_CHECK(need > 0 && need <= sizeof g_ws);
        int r = sfm_r2r_ransac(s, n, &o, &out, inl, NULL, NULL, g_ws, need);
        if (r < 1) {
            SFM_TEST_LOG("trial %d (%d steps): status %d", it, n, r);
            continue;
        }
        double pe, re = r2r_scene_error(&out, &T, NULL, &pe);
        if (re < 0.05 && pe < 0.15)
            good++;
        else
            SFM_TEST_LOG("trial %d (%d steps): %.4f rad, %.4f m", it, n, re, pe);
        for (int k = 0; k < n; k++)
            missed += (inl[k] & is_out[k]) != 0;
    }
    SFM_TEST_LOG("truth recovered in %d of %d; %d of %d outliers accepted", good, trials, missed,
                 n_out_all);
    SFM_CHECK(good >= trials - trials / 20);
    SFM_CHECK(missed <= n_out_all / 50);
}

SFM_TEST(r2r_ransac_noise_free_exact_and_deterministic)
{
    sfm_r2r_transform T, a, b;
    sfm_r2r_step s[6];
    unsigned is_out[6], ia[6], ib[6];
    r2r_scene_truth(t, &T);
    r2r_scene_steps(t, &T, 6, 3.0, s);
    corrupt(t, s, 6, 0.2, is_out);
    size_t need = sfm_r2r_ransac_workspace_size(6);
    SFM_CHECK(need > 0 && need <= sizeof g_ws);
    sfm_r2r_ransac_options o;
    sfm_r2r_ransac_default_options(&o);
    int na = sfm_r2r_ransac(s, 6, &o, &a, ia, NULL, NULL, g_ws, need);
    int nb = sfm_r2r_ransac(s, 6, &o, &b, ib, NULL, NULL, g_ws, need);
    SFM_CHECK(na >= 1);
    SFM_CHECK_EQ_INT(na, nb);
    SFM_CHECK(memcmp(&a, &b, sizeof a) == 0 && memcmp(ia, ib, sizeof ia) == 0);
    double pe, re = r2r_scene_error(&a, &T, NULL, &pe);
    SFM_CHECK(re < 1e-8 && pe < 1e-8);
    for (int k = 0; k < 6; k++)
        SFM_CHECK_EQ_INT(ia[k], s[k].has & ~is_out[k]);
}

SFM_TEST(r2r_ransac_bad_inputs)
{
    sfm_r2r_transform T, out;
    sfm_r2r_step s[4], b[4];
    unsigned inl[8];
    double cov[36];
    sfm_ransac_stats st;
    r2r_scene_truth(t, &T);
    r2r_scene_steps(t, &T, 4, 3.0, s);
    size_t need = sfm_r2r_ransac_workspace_size(4);
    SFM_CHECK(need > 0);
    SFM_CHECK_EQ_INT(sfm_r2r_ransac_workspace_size(0), 0);
    SFM_CHECK_EQ_INT(sfm_r2r_ransac_default_options(NULL), SFM_E_ARGUMENT);
    sfm_r2r_ransac_options o;
    sfm_r2r_ransac_default_options(&o);
#define EXPECT(call, status)                                                                       \
    do {                                                                                           \
        sfm_test_fill_canary(&out, sizeof out);                                                    \
        sfm_test_fill_canary(inl, sizeof inl);                                                     \
        sfm_test_fill_canary(cov, sizeof cov);                                                     \
        sfm_test_fill_canary(&st, sizeof st);                                                      \
        SFM_CHECK_EQ_INT(call, status);                                                            \
        SFM_CHECK(sfm_test_canary_intact(&out, sizeof out) &&                                      \
                  sfm_test_canary_intact(inl, sizeof inl) &&                                       \
                  sfm_test_canary_intact(cov, sizeof cov) &&                                       \
                  sfm_test_canary_intact(&st, sizeof st));                                         \
    } while (0)
    EXPECT(sfm_r2r_ransac(NULL, 4, &o, &out, inl, cov, &st, g_ws, need), SFM_E_ARGUMENT);
    EXPECT(sfm_r2r_ransac(s, 0, &o, &out, inl, cov, &st, g_ws, need), SFM_E_ARGUMENT);
    EXPECT(sfm_r2r_ransac(s, 4, &o, &out, inl, cov, &st, g_ws, need - 1), SFM_E_WORKSPACE);
    EXPECT(sfm_r2r_ransac(s, 4, &o, &out, inl, cov, &st, NULL, need), SFM_E_WORKSPACE);
    memcpy(b, s, sizeof b);
    b[2].b2.v[0] = (double)NAN;
    EXPECT(sfm_r2r_ransac(b, 4, &o, &out, inl, cov, &st, g_ws, need), SFM_E_NONFINITE);
    memcpy(b, s, sizeof b);
    b[0].has = SFM_R2R_D | SFM_R2R_B1;
    b[1].has = SFM_R2R_D;
    EXPECT(sfm_r2r_ransac(b, 2, &o, &out, inl, cov, &st, g_ws, need), SFM_E_ARGUMENT);
    memcpy(b, s, sizeof b);
    b[3].d = -1.0;
    EXPECT(sfm_r2r_ransac(b, 4, &o, &out, inl, cov, &st, g_ws, need), SFM_E_ARGUMENT);
    memcpy(b, s, sizeof b);
    b[3].R2.m[8] = -b[3].R2.m[8];
    EXPECT(sfm_r2r_ransac(b, 4, &o, &out, inl, cov, &st, g_ws, need), SFM_E_ARGUMENT);
    sfm_r2r_ransac_options ob = o;
    ob.ransac.threshold = 0.0;
    EXPECT(sfm_r2r_ransac(s, 4, &ob, &out, inl, cov, &st, g_ws, need), SFM_E_ARGUMENT);
    ob = o;
    ob.refine.sigma_b = (double)NAN;
    EXPECT(sfm_r2r_ransac(s, 4, &ob, &out, inl, cov, &st, g_ws, need), SFM_E_NONFINITE);
    ob = o;
    ob.ransac.confidence = 1.5;
    EXPECT(sfm_r2r_ransac(s, 4, &ob, &out, inl, cov, &st, g_ws, need), SFM_E_ARGUMENT);
    /* exactly six equations: every sample fits itself, nothing confirms it */
    memcpy(b, s, sizeof b);
    b[0].has = SFM_R2R_D | SFM_R2R_B1 | SFM_R2R_B2;
    b[1].has = SFM_R2R_D;
    EXPECT(sfm_r2r_ransac(b, 2, &o, &out, inl, cov, &st, g_ws, need), SFM_E_NO_MODEL);
    /* both robots standing still: every measurement repeats the first */
    sfm_r2r_step still[8];
    for (int k = 0; k < 8; k++) {
        still[k] = s[0];
        still[k].has = k % 2 ? SFM_R2R_D : SFM_R2R_D | SFM_R2R_B1;
    }
    size_t need8 = sfm_r2r_ransac_workspace_size(8);
    EXPECT(sfm_r2r_ransac(still, 8, &o, &out, inl, cov, &st, g_ws, need8), SFM_E_DEGENERATE);
#undef EXPECT
}
