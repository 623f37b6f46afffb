/* Visual odometry: the contract of every entry point, honesty on frames
 * without parallax, and a known motion (a textured plane facing the camera,
 * the camera sliding sideways: the image shifts by a fixed number of pixels
 * a frame, so the true centres lie on the x axis at equal steps). */
#include <math.h>
#include <string.h>

#include "sfm/sfm_vo.h"
#include "sfm_test.h"
#include "vo_scene.h"

#define VW VO_SCENE_W
#define VH VO_SCENE_H
#define VPAD VO_SCENE_PAD
#define VNF VO_SCENE_NF
#define VWIN VO_SCENE_WIN
#define VWS (1024u * 1024u)

static unsigned char g_vo_ws[VWS];
static uint8_t g_tex[VH * (VW + 2 * VPAD)];
static uint8_t g_frame[VW * VH];

static void make_texture(sfm_test_ctx *t) { vo_scene_texture(t, g_tex); }

static void crop2(int base, int shift) { vo_scene_crop(g_tex, g_frame, base, shift); }

static void crop(int off) { crop2(off, 0); }

/* A pipeline with the test parameters on the static workspace, and a fresh
 * texture. */
static sfm_vo *start_default(sfm_test_ctx *t)
{
    sfm_vo_dims d;
    sfm_vo_params p;
    vo_scene_setup(&d, &p);
    sfm_vo *vo = NULL;
    SFM_CHECK_EQ_INT(sfm_vo_init(&d, &p, &vo, g_vo_ws, VWS), SFM_OK);
    make_texture(t);
    return vo;
}

SFM_TEST(vo_contract)
{
    sfm_vo_dims d;
    sfm_vo_params p;
    vo_scene_setup(&d, &p);
    size_t need = sfm_vo_workspace_size(&d);
    SFM_CHECK(need > 0 && need <= VWS);
    sfm_vo_dims bad = d;
    bad.window = SFM_VO_MAX_WINDOW + 1;
    SFM_CHECK(sfm_vo_workspace_size(&bad) == 0);
    bad = d;
    bad.max_features = 4;
    SFM_CHECK(sfm_vo_workspace_size(&bad) == 0);
    SFM_CHECK(sfm_vo_workspace_size(NULL) == 0);
    SFM_CHECK_EQ_INT(sfm_vo_default_params(NULL, &p), SFM_E_ARGUMENT);

    sfm_vo *vo = NULL;
    SFM_CHECK_EQ_INT(sfm_vo_init(&d, &p, &vo, g_vo_ws, need - 1), SFM_E_WORKSPACE);
    SFM_CHECK(vo == NULL);
    SFM_CHECK_EQ_INT(sfm_vo_init(NULL, &p, &vo, g_vo_ws, need), SFM_E_ARGUMENT);
    SFM_CHECK_EQ_INT(sfm_vo_init(&d, NULL, &vo, g_vo_ws, need), SFM_E_ARGUMENT);
    SFM_CHECK_EQ_INT(sfm_vo_init(&d, &p, &vo, NULL, need), SFM_E_ARGUMENT);
    sfm_vo_params q = p;
    q.calibrated = 0;
    q.camera.model = SFM_CAMERA_FISHEYE; /* self-calibration finds a pinhole camera only */
    SFM_CHECK_EQ_INT(sfm_vo_init(&d, &q, &vo, g_vo_ws, need), SFM_E_UNSUPPORTED);
    SFM_CHECK(vo == NULL);
    q = p;
    q.calibrated = 2;
    SFM_CHECK_EQ_INT(sfm_vo_init(&d, &q, &vo, g_vo_ws, need), SFM_E_ARGUMENT);
    q = p;
    q.threshold = (double)NAN;
    SFM_CHECK_EQ_INT(sfm_vo_init(&d, &q, &vo, g_vo_ws, need), SFM_E_NONFINITE);
    q = p;
    q.camera.fx = 0;
    SFM_CHECK_EQ_INT(sfm_vo_init(&d, &q, &vo, g_vo_ws, need), SFM_E_ARGUMENT);
    q = p;
    q.window = VWIN + 1; /* above the workspace's window */
    SFM_CHECK_EQ_INT(sfm_vo_init(&d, &q, &vo, g_vo_ws, need), SFM_E_ARGUMENT);
    q = p;
    q.max_features = VNF + 1;
    SFM_CHECK_EQ_INT(sfm_vo_init(&d, &q, &vo, g_vo_ws, need), SFM_E_ARGUMENT);
    SFM_CHECK(vo == NULL);
    SFM_CHECK_EQ_INT(sfm_vo_init(&d, &p, &vo, g_vo_ws, need), SFM_OK);
    SFM_CHECK(vo != NULL);

    make_texture(t);
    crop(VPAD);
    sfm_image_u8 img = {g_frame, VW, VH, VW};
    sfm_vo_frame_result r, canary;
    sfm_test_fill_canary(&canary, sizeof canary);
    r = canary;
    SFM_CHECK_EQ_INT(sfm_vo_push_frame(NULL, &img, 0, NULL, 0, &r), SFM_E_ARGUMENT);
    SFM_CHECK_EQ_INT(sfm_vo_push_frame(vo, NULL, 0, NULL, 0, &r), SFM_E_ARGUMENT);
    SFM_CHECK_EQ_INT(sfm_vo_push_frame(vo, &img, 0, NULL, 0, NULL), SFM_E_ARGUMENT);
    sfm_image_u8 small = {g_frame, VW - 1, VH, VW};
    SFM_CHECK_EQ_INT(sfm_vo_push_frame(vo, &small, 0, NULL, 0, &r), SFM_E_ARGUMENT);
    double gnan[3] = {0, (double)NAN, 0}, gzero[3] = {0, 0, 0};
    SFM_CHECK_EQ_INT(sfm_vo_push_frame(vo, &img, 0, gnan, 0, &r), SFM_E_NONFINITE);
    SFM_CHECK_EQ_INT(sfm_vo_push_frame(vo, &img, 0, gzero, 0, &r), SFM_E_ARGUMENT);
    SFM_CHECK(memcmp(&r, &canary, sizeof r) == 0);
    SFM_CHECK_EQ_INT(sfm_vo_push_frame(vo, &img, 1000, NULL, 0, &r), SFM_OK);
    SFM_CHECK_EQ_INT(r.frame_index, 0);
    SFM_CHECK_EQ_INT(r.state, SFM_VO_INITIALISING);
    r = canary;
    SFM_CHECK_EQ_INT(sfm_vo_push_frame(vo, &img, 999, NULL, 0, &r), SFM_E_ARGUMENT);
    SFM_CHECK(memcmp(&r, &canary, sizeof r) == 0);
    double xyz[3];
    SFM_CHECK_EQ_INT(sfm_vo_map_points(vo, NULL, NULL, 1), SFM_E_ARGUMENT);
    SFM_CHECK_EQ_INT(sfm_vo_map_points(vo, xyz, NULL, -1), SFM_E_ARGUMENT);
    double fpx[2];
    int ff;
    SFM_CHECK_EQ_INT(sfm_vo_map_points_first_seen(NULL, NULL, fpx, &ff, 1), SFM_E_ARGUMENT);
    SFM_CHECK_EQ_INT(sfm_vo_map_points_first_seen(vo, NULL, NULL, &ff, 1), SFM_E_ARGUMENT);
    SFM_CHECK_EQ_INT(sfm_vo_map_points_first_seen(vo, NULL, fpx, NULL, 1), SFM_E_ARGUMENT);
    SFM_CHECK_EQ_INT(sfm_vo_map_points_first_seen(vo, NULL, fpx, &ff, -1), SFM_E_ARGUMENT);
    SFM_CHECK_EQ_INT(sfm_vo_reset(NULL), SFM_E_ARGUMENT);
    SFM_CHECK(strcmp(sfm_vo_state_str(SFM_VO_PURE_ROTATION), "pure_rotation") == 0);
    SFM_CHECK(strcmp(sfm_vo_state_str(99), "unknown") == 0);
}

/* The same frame again and again: no baseline, so no frame after the first
 * may claim a tracked pose. */
SFM_TEST(vo_no_parallax_is_never_tracking)
{
    sfm_vo *vo = start_default(t);
    crop(VPAD);
    sfm_image_u8 img = {g_frame, VW, VH, VW};
    for (int k = 0; k < 6; k++) {
        sfm_vo_frame_result r;
        SFM_CHECK_EQ_INT(sfm_vo_push_frame(vo, &img, k * 1000, NULL, 0, &r), SFM_OK);
        SFM_CHECK_MSG(r.state != SFM_VO_TRACKING, "frame %d reported tracking", k);
        if (k == 0)
            SFM_CHECK(r.has_pose && r.state == SFM_VO_INITIALISING);
        else
            SFM_CHECK_MSG(!r.has_pose && (r.state == SFM_VO_INSUFFICIENT_PARALLAX ||
                                           r.state == SFM_VO_PURE_ROTATION ||
                                           r.state == SFM_VO_INITIALISING),
                          "frame %d: state %s, pose %d", k, sfm_vo_state_str(r.state), r.has_pose);
    }
}

/* Sideways slide past two fronto-parallel planes (depths Z and 2Z): the
 * true centres are at k * s on +x, the rotation is the identity. */
SFM_TEST(vo_sideways_slide_known_answer)
{
    sfm_vo *vo = start_default(t);
    sfm_image_u8 img = {g_frame, VW, VH, VW};
    const int step = 4, n = 20;
    double cx[20];
    int have[20] = {0}, tracked = 0;
    for (int k = 0; k < n; k++) {
        crop2(VPAD - 40, step * k);
        sfm_vo_frame_result r;
        SFM_CHECK_EQ_INT(sfm_vo_push_frame(vo, &img, k * 1000, NULL, 1, &r), SFM_OK);
        if (r.has_pose) {
            have[k] = 1;
            cx[k] = r.c_w[0];
            /* the centre stays on the x axis, the rotation stays identity */
            double off = hypot(r.c_w[1], r.c_w[2]);
            SFM_CHECK_MSG(off <= 0.05 * fabs(r.c_w[0]) + 1e-9, "frame %d: centre (%g %g %g)", k,
                          r.c_w[0], r.c_w[1], r.c_w[2]);
            SFM_CHECK_MSG(fabs(r.R_wc[0] - 1) < 1e-3 && fabs(r.R_wc[4] - 1) < 1e-3 &&
                              fabs(r.R_wc[8] - 1) < 1e-3,
                          "frame %d: rotation not identity", k);
            /* R_wc is the transpose of R_cw and c_w = -R_cw^T t_cw */
            double c0 = -(r.R_cw[0] * r.t_cw[0] + r.R_cw[3] * r.t_cw[1] + r.R_cw[6] * r.t_cw[2]);
            SFM_CHECK_NEAR(c0, r.c_w[0], 1e-9);
        }
        if (r.state == SFM_VO_TRACKING) {
            tracked++;
            SFM_CHECK(r.has_covariance);
        }
    }
    SFM_CHECK_MSG(tracked >= n - 6, "tracked %d of %d", tracked, n);
    /* Where each live point was first seen: an earlier frame, inside the
     * image, and the same order and ids as sfm_vo_map_points. */
    {
        static double pxy[VNF * VWIN * 2], pts[VNF * VWIN * 3];
        static int pf[VNF * VWIN];
        static uint32_t id1[VNF * VWIN], id2[VNF * VWIN];
        int m1 = sfm_vo_map_points(vo, pts, id1, VNF * VWIN);
        int m2 = sfm_vo_map_points_first_seen(vo, id2, pxy, pf, VNF * VWIN);
        SFM_CHECK(m1 > 0 && m1 == m2);
        for (int q = 0; q < m2 && q < m1; q++) {
            SFM_CHECK(id1[q] == id2[q]);
            SFM_CHECK(pf[q] >= 0 && pf[q] < n);
            SFM_CHECK(pxy[2 * q] >= 0 && pxy[2 * q] < VW && pxy[2 * q + 1] >= 0 && pxy[2 * q + 1] < VH);
        }
    }
    /* Equal steps: c(k) / c(k_last) = k / k_last (scale-free). */
    int last = n - 1;
    SFM_CHECK(have[last]);
    for (int k = 1; k < n; k++)
        if (have[k] && have[last])
            SFM_CHECK_MSG(fabs(cx[k] / cx[last] - (double)k / last) < 0.03,
                          "frame %d: c %g, expected %g", k, cx[k] / cx[last], (double)k / last);
    SFM_CHECK(cx[last] > 0);
}

/* A clock that advances 1 ms at every read: with a 6 ms budget every frame
 * overruns, so the detector is asked for fewer features from the second
 * frame on (down to a quarter), keyframes skip their bundle adjustment, and
 * the frames say so in result.degraded. */
static double fake_clock(void *ctx)
{
    double *t = ctx;
    *t += 0.001;
    return *t;
}

SFM_TEST(vo_time_budget_degrades)
{
    sfm_vo_dims d;
    sfm_vo_params p;
    vo_scene_setup(&d, &p);
    double now = 0;
    p.clock = fake_clock;
    p.clock_ctx = &now;
    p.frame_budget = 0.006;
    p.min_inliers = 8; /* a quarter of the features must still initialise */
    sfm_vo *vo;
    SFM_CHECK_EQ_INT(sfm_vo_init(&d, &p, &vo, g_vo_ws, VWS), SFM_OK);
    make_texture(t);
    sfm_image_u8 img = {g_frame, VW, VH, VW};
    int fewer = 0, skipped = 0, min_feat = VNF, kf_tracked = 0, states[5] = {0};
    for (int k = 0; k < 25; k++) {
        crop2(VPAD - 40, 4 * k);
        sfm_vo_frame_result r;
        SFM_CHECK_EQ_INT(sfm_vo_push_frame(vo, &img, k * 1000, NULL, 0, &r), SFM_OK);
        /* frame 0 reads the clock only a few times: within budget */
        if (k > 1)
            SFM_CHECK_MSG(r.degraded & SFM_VO_DEGRADED_FEATURES, "frame %d not degraded", k);
        if (r.is_keyframe && r.state == SFM_VO_TRACKING && r.n_keyframes > 2) {
            kf_tracked++;
            SFM_CHECK(r.degraded & SFM_VO_DEGRADED_BA_SKIPPED);
        }
        fewer += (r.degraded & SFM_VO_DEGRADED_FEATURES) != 0;
        states[r.state]++;
        skipped += (r.degraded & SFM_VO_DEGRADED_BA_SKIPPED) != 0;
        if (r.n_features < min_feat)
            min_feat = r.n_features;
        if (r.has_pose && k > 1)
            SFM_CHECK(r.quality != SFM_VO_QUALITY_GOOD);
        SFM_CHECK(r.stage_seconds[SFM_VO_STAGE_FEATURES] > 0);
    }
    SFM_CHECK(fewer >= 23);
    SFM_CHECK(kf_tracked > 0 && skipped == kf_tracked);
    SFM_CHECK(min_feat <= VNF / 4);
    SFM_TEST_LOG("features down to %d of %d, %d of %d later keyframes without BA; states: "
                 "%d initialising, %d tracking, %d lost, %d parallax, %d rotation",
                 min_feat, VNF, skipped, kf_tracked, states[0], states[1], states[2], states[3],
                 states[4]);
}

/* Unknown intrinsics on the sideways slide: a pure translation does not
 * determine the focal length (every focal explains the two planes' shifts),
 * so the self-calibration must refuse and no frame may claim a tracked pose
 * or a focal length. */
SFM_TEST(vo_self_calibration_refuses_pure_translation)
{
    sfm_vo_dims d;
    sfm_vo_params p;
    vo_scene_setup(&d, &p);
    p.calibrated = 0;
    sfm_vo *vo;
    SFM_CHECK_EQ_INT(sfm_vo_init(&d, &p, &vo, g_vo_ws, VWS), SFM_OK);
    make_texture(t);
    sfm_image_u8 img = {g_frame, VW, VH, VW};
    for (int k = 0; k < 20; k++) {
        crop2(VPAD - 40, 4 * k);
        sfm_vo_frame_result r;
        SFM_CHECK_EQ_INT(sfm_vo_push_frame(vo, &img, k * 1000, NULL, 0, &r), SFM_OK);
        SFM_CHECK_MSG(r.state != SFM_VO_TRACKING, "frame %d tracked without a focal length", k);
        SFM_CHECK_MSG(r.focal == 0.0, "frame %d: focal %g from a pure translation", k, r.focal);
        SFM_CHECK(!r.has_pose || k == 0);
    }
}
