/* Calibrated three-view pose: a small synthetic scene with known poses, and
 * the contract of sfm_recon_three_view_pose. */
#include <math.h>
#include <string.h>

#include "sfm/sfm.h"
#include "sfm_test.h"

enum { N = 60 };

static unsigned char ws[1 << 20];
static double px[3][2 * N];
static sfm_pose truth[3];
static const sfm_camera cam = {SFM_CAMERA_PINHOLE, 700, 700, 320, 240, {0}};

static void scene(sfm_test_ctx *t)
{
    memset(&truth[0], 0, sizeof truth[0]);
    truth[0].R[0] = truth[0].R[4] = truth[0].R[8] = 1;
    for (int v = 1; v < 3; v++) {
        double aa[3];
        for (int k = 0; k < 3; k++) {
            aa[k] = sfm_test_normal(t, 0.1);
            truth[v].t[k] = sfm_test_normal(t, 0.5);
        }
        sfm_rot_from_axis_angle(aa, truth[v].R);
    }
    for (int i = 0; i < N;) {
        double X[3] = {sfm_test_uniform(t, -2, 2), sfm_test_uniform(t, -1.5, 1.5), sfm_test_uniform(t, 5, 9)};
        int ok = 1;
        double y[3][2];
        for (int v = 0; v < 3 && ok; v++) {
            double Y[3];
            for (int r = 0; r < 3; r++)
                Y[r] = truth[v].R[3 * r] * X[0] + truth[v].R[3 * r + 1] * X[1] + truth[v].R[3 * r + 2] * X[2] + truth[v].t[r];
            ok = sfm_camera_project(&cam, Y, y[v], NULL) == SFM_OK;
        }
        if (!ok)
            continue;
        for (int v = 0; v < 3; v++)
            for (int k = 0; k < 2; k++)
                px[v][2 * i + k] = y[v][k] + sfm_test_normal(t, 0.3);
        i++;
    }
}

SFM_TEST(three_view_pose_recovers_truth_with_one_scale)
{
    scene(t);
    size_t need = sfm_recon_three_view_pose_workspace_size(N);
    SFM_CHECK(need > 0 && need <= sizeof ws);
    /* a fifth of the view-3 observations are wrong matches */
    for (int i = 0; i < N; i += 5) {
        px[2][2 * i] = sfm_test_uniform(t, 0, 640);
        px[2][2 * i + 1] = sfm_test_uniform(t, 0, 480);
    }
    sfm_ransac_options opt;
    sfm_ransac_default_options(&opt);
    opt.threshold = 1.5;
    sfm_pose est[3];
    uint8_t mask[N];
    int cnt = sfm_recon_three_view_pose(px[0], px[1], px[2], N, &cam, &cam, &cam, &opt, est, mask, NULL, ws, need);
    SFM_CHECK(cnt >= N * 3 / 4);
    if (cnt < 0)
        return;
    double s = sqrt(truth[1].t[0] * truth[1].t[0] + truth[1].t[1] * truth[1].t[1] + truth[1].t[2] * truth[1].t[2]);
    for (int v = 1; v < 3; v++) {
        double ang;
        sfm_rot_angle_between(est[v].R, truth[v].R, &ang);
        SFM_CHECK(ang < 0.5 * 3.14159265358979 / 180);
        for (int k = 0; k < 3; k++) /* t3 on the scale of |t2| = 1 */
            SFM_CHECK_NEAR(est[v].t[k] * s, truth[v].t[k], 0.05 * s);
    }
    for (int i = 0; i < N; i += 5)
        SFM_CHECK(mask[i] == 0);
}

SFM_TEST(three_view_pose_contracts)
{
    scene(t);
    size_t need = sfm_recon_three_view_pose_workspace_size(N);
    sfm_pose est[3];
    sfm_test_fill_canary(est, sizeof est);
    SFM_CHECK_EQ_INT(sfm_recon_three_view_pose_workspace_size(6), 0);
    SFM_CHECK_EQ_INT(sfm_recon_three_view_pose(NULL, px[1], px[2], N, &cam, &cam, &cam, NULL, est, NULL, NULL, ws, need),
                     SFM_E_ARGUMENT);
    SFM_CHECK_EQ_INT(sfm_recon_three_view_pose(px[0], px[1], px[2], 6, &cam, &cam, &cam, NULL, est, NULL, NULL, ws, need),
                     SFM_E_ARGUMENT);
    SFM_CHECK_EQ_INT(sfm_recon_three_view_pose(px[0], px[1], px[2], N, &cam, &cam, &cam, NULL, est, NULL, NULL, ws, need - 1),
                     SFM_E_WORKSPACE);
    sfm_camera bad = cam;
    bad.fx = 0;
    SFM_CHECK_EQ_INT(sfm_recon_three_view_pose(px[0], px[1], px[2], N, &cam, &bad, &cam, NULL, est, NULL, NULL, ws, need),
                     SFM_E_ARGUMENT);
    px[1][3] = (double)NAN;
    SFM_CHECK_EQ_INT(sfm_recon_three_view_pose(px[0], px[1], px[2], N, &cam, &cam, &cam, NULL, est, NULL, NULL, ws, need),
                     SFM_E_NONFINITE);
    SFM_CHECK(sfm_test_canary_intact(est, sizeof est));
}

/* The count returned, stats->num_inliers and the mask describe one set: the
 * inliers under the returned metric cameras, not those of the projective
 * tensor found on the way (noise near the threshold makes the two differ). */
SFM_TEST(three_view_pose_stats_count_the_returned_inliers)
{
    scene(t);
    for (int v = 0; v < 3; v++)
        for (int k = 0; k < 2 * N; k++)
            px[v][k] += sfm_test_normal(t, 0.6);
    size_t need = sfm_recon_three_view_pose_workspace_size(N);
    sfm_ransac_options opt;
    sfm_ransac_default_options(&opt);
    opt.threshold = 1.0;
    sfm_pose est[3];
    uint8_t mask[N];
    sfm_ransac_stats st;
    int cnt = sfm_recon_three_view_pose(px[0], px[1], px[2], N, &cam, &cam, &cam, &opt, est, mask, &st, ws, need);
    SFM_CHECK(cnt >= N / 2);
    if (cnt < 0)
        return;
    int in_mask = 0;
    for (int i = 0; i < N; i++)
        in_mask += mask[i];
    SFM_CHECK_EQ_INT(in_mask, cnt);
    SFM_CHECK_EQ_INT(st.num_inliers, cnt);
}
