/* The estimators' static workspace macros (SFM_RANSAC_<EST>_WS_SIZE(n)):
 * never below the size functions over the valid range of n, and a buffer of
 * exactly that size carries a run. */
#include <math.h>
#include <string.h>

#include "ransac_scene.h"
#include "sfm/sfm.h"
#include "sfm_test.h"

#define NS 120

typedef struct ws_pair {
    const char *name;
    int min_n;
    size_t (*fn)(int n);
} ws_pair;

static size_t macro_size(int which, int n)
{
    switch (which) {
    case 0:
        return SFM_RANSAC_RELPOSE_WS_SIZE(n);
    case 1:
        return SFM_RANSAC_RELPOSE_UPRIGHT_WS_SIZE(n);
    case 2:
        return SFM_RANSAC_ABSPOSE_WS_SIZE(n);
    case 3:
        return SFM_RANSAC_FUNDAMENTAL_WS_SIZE(n);
    default:
        return SFM_RANSAC_HOMOGRAPHY_WS_SIZE(n);
    }
}

static const ws_pair PAIRS[5] = {
    {"relpose", 5, sfm_ransac_relpose_workspace_size},
    {"relpose_upright", 3, sfm_ransac_relpose_upright_workspace_size},
    {"abspose", 3, sfm_ransac_abspose_workspace_size},
    {"fundamental", 8, sfm_ransac_fundamental_workspace_size},
    {"homography", 4, sfm_ransac_homography_workspace_size},
};

/* One n: the macro covers the function, and wastes at most one 16-byte
 * block per array (the two are meant to be equal). */
static int check_n(sfm_test_ctx *t, int which, int n)
{
    size_t f = PAIRS[which].fn(n), m = macro_size(which, n);
    int ok = f > 0 && m >= f && m - f <= 256;
    if (!ok)
        SFM_CHECK_MSG(0, "%s n=%d: macro %lu, function %lu", PAIRS[which].name, n,
                      (unsigned long)m, (unsigned long)f);
    return ok;
}

SFM_TEST(ransac_estimator_ws_macros_cover_functions)
{
    for (int w = 0; w < 5; w++) {
        int bad = 0;
        /* every small n, then geometric steps to the capacity */
        for (int n = PAIRS[w].min_n; n <= 1024 && bad < 3; n++)
            bad += !check_n(t, w, n);
        for (double x = 1025.0; x < (double)SFM_RANSAC_MAX_POINTS && bad < 3; x *= 1.37)
            bad += !check_n(t, w, (int)x);
        bad += !check_n(t, w, SFM_RANSAC_MAX_POINTS);
        SFM_CHECK_EQ_INT(bad, 0);
        /* below the sample size the function refuses; the macro is moot */
        SFM_CHECK(PAIRS[w].fn(PAIRS[w].min_n - 1) == 0);
    }
}

/* Buffers sized by the macros alone, as a microcontroller build would. */
static unsigned char WS_REL[SFM_RANSAC_RELPOSE_WS_SIZE(NS)];
static unsigned char WS_UP[SFM_RANSAC_RELPOSE_UPRIGHT_WS_SIZE(NS)];
static unsigned char WS_ABS[SFM_RANSAC_ABSPOSE_WS_SIZE(NS)];
static unsigned char WS_F[SFM_RANSAC_FUNDAMENTAL_WS_SIZE(NS)];
static unsigned char WS_H[SFM_RANSAC_HOMOGRAPHY_WS_SIZE(NS)];
static double Q1[2 * NS], Q2[2 * NS], QX[3 * NS];
static unsigned char QT[NS];

/* Fraction of the true inliers the mask marks. */
static double recall(const uint8_t *mask)
{
    int a = 0, b = 0;
    for (int i = 0; i < NS; i++) {
        a += QT[i];
        b += QT[i] && mask[i];
    }
    return a > 0 ? (double)b / a : 0.0;
}

SFM_TEST(ransac_estimators_run_in_macro_sized_buffers)
{
    sfm_camera cam = scene_pinhole();
    sfm_ransac_options opt;
    sfm_ransac_default_options(&opt);
    opt.threshold = 2.0;
    uint8_t mask[NS];
    double R[9], tr[3];
    sfm_mat3 M;
    sfm_pose pose;

    scene_twoview(t, &cam, NS, 0.3, 0.5, 0, Q1, Q2, QT, R, tr);
    int ni = sfm_ransac_relpose(Q1, Q2, NS, &cam, &cam, &opt, &pose, &M, mask, NULL, WS_REL,
                                sizeof WS_REL);
    SFM_CHECK(ni >= 5);
    if (ni >= 5) {
        SFM_CHECK(scene_rot_err_deg(pose.R, R) < 1.0);
        SFM_CHECK(recall(mask) > 0.9);
    }

    double d1[3], d2[3];
    sfm_test_random_unit(t, d1);
    scene_matvec(R, d1, d2);
    ni = sfm_ransac_relpose_upright(Q1, Q2, NS, &cam, &cam, d1, d2, &opt, &pose, &M, mask, NULL,
                                    WS_UP, sizeof WS_UP);
    SFM_CHECK(ni >= 3);
    if (ni >= 3)
        SFM_CHECK(scene_rot_err_deg(pose.R, R) < 1.0);

    ni = sfm_ransac_fundamental(Q1, Q2, NS, NULL, NULL, &opt, &M, mask, NULL, WS_F, sizeof WS_F);
    SFM_CHECK(ni >= 8);
    if (ni >= 8)
        SFM_CHECK(recall(mask) > 0.9);

    scene_twoview(t, &cam, NS, 0.3, 0.5, 1, Q1, Q2, QT, R, tr);
    ni = sfm_ransac_homography(Q1, Q2, NS, NULL, NULL, &opt, &M, mask, NULL, WS_H, sizeof WS_H);
    SFM_CHECK(ni >= 4);
    if (ni >= 4)
        SFM_CHECK(recall(mask) > 0.9);

    scene_abspose(t, &cam, NS, 0.3, 0.5, Q1, QX, QT, R, tr);
    ni = sfm_ransac_abspose(Q1, QX, NS, &cam, &opt, &pose, mask, NULL, WS_ABS, sizeof WS_ABS);
    SFM_CHECK(ni >= 3);
    if (ni >= 3) {
        SFM_CHECK(scene_rot_err_deg(pose.R, R) < 1.0);
        SFM_CHECK(recall(mask) > 0.9);
    }
}
