/* The sequence pipeline under hostile input: NaN / Inf intrinsics and
 * parameters, a workspace one byte short or misaligned, frames of another
 * size mid-stream, a NULL or short buffer (stride below the width, a camera
 * that vanishes: data NULL, size 0), timestamps going back or repeated,
 * gravity of extreme magnitude, black / constant / noise frames, 1000
 * identical frames. Every refused call leaves the result canary and the
 * pipeline's state as they were (the next frame index goes on from the
 * last accepted frame); every accepted frame reports a finite pose or
 * none, and the same frames give the same bits. */
#include <math.h>
#include <stdint.h>
#include <string.h>

#include "sfm/sfm_vo.h"
#include "vo/vo_internal.h"
#include "sfm_test.h"
#include "vo_scene.h"

#define HW VO_SCENE_W
#define HH VO_SCENE_H
#define HPAD VO_SCENE_PAD
#define HNF VO_SCENE_NF
#define HWIN VO_SCENE_WIN
#define HWS (1024u * 1024u)
#ifndef H_SAME
#define H_SAME 1000
#endif

static unsigned char h_ws[HWS + 64], h_ws2[HWS];
static uint8_t h_tex[HH * (HW + 2 * HPAD)];
static uint8_t h_frame[(HW + 8) * (HH + 1)];

static void texture(sfm_test_ctx *t) { vo_scene_texture(t, h_tex); }

static void crop(int off) { vo_scene_crop(h_tex, h_frame, HPAD - 40, off); }

static int result_finite(const sfm_vo_frame_result *r)
{
    if (!r->has_pose)
        return 1;
    for (int i = 0; i < 9; i++)
        if (!isfinite(r->R_cw[i]) || !isfinite(r->R_wc[i]))
            return 0;
    for (int i = 0; i < 3; i++)
        if (!isfinite(r->t_cw[i]) || !isfinite(r->c_w[i]))
            return 0;
    return 1;
}

SFM_TEST(hostile_vo_init)
{
    sfm_vo_dims d;
    sfm_vo_params p;
    vo_scene_setup(&d, &p);
    size_t need = sfm_vo_workspace_size(&d);
    SFM_CHECK(need > 0 && need <= HWS);
    int tried = 0;
    const double bad[] = {(double)NAN, (double)INFINITY, -(double)INFINITY};
    for (int k = 0; k < 3; k++) {
        for (int f = 0; f < 4; f++) {
            sfm_vo_params q = p;
            double *fl[4] = {&q.camera.fx, &q.camera.fy, &q.camera.cx, &q.camera.cy};
            *fl[f] = bad[k];
            for (int cal = 0; cal < 2; cal++) {
                q.calibrated = cal;
                sfm_vo *vo = (sfm_vo *)(uintptr_t)0x1234;
                int st = sfm_vo_init(&d, &q, &vo, h_ws, need);
                tried++;
                /* self-calibration replaces cx, cy by the image centre and
                 * fy by fx: a NaN there must still be refused */
                SFM_CHECK_MSG(st == SFM_E_NONFINITE || st == SFM_E_ARGUMENT,
                              "camera field %d = %g calibrated %d: status %d", f, bad[k], cal, st);
                SFM_CHECK(vo == (sfm_vo *)(uintptr_t)0x1234);
            }
        }
        /* a Brown camera with a NaN distortion coefficient */
        sfm_vo_params q = p;
        q.camera.model = SFM_CAMERA_BROWN;
        q.camera.dist[0] = bad[k];
        sfm_vo *vo = NULL;
        SFM_CHECK(sfm_vo_init(&d, &q, &vo, h_ws, need) < 0);
        SFM_CHECK(vo == NULL);
        /* detector parameters */
        q = p;
        q.features.scale_factor = bad[k];
        SFM_CHECK(sfm_vo_init(&d, &q, &vo, h_ws, need) < 0);
        q = p;
        q.frame_budget = bad[k];
        SFM_CHECK_EQ_INT(sfm_vo_init(&d, &q, &vo, h_ws, need), SFM_E_NONFINITE);
        SFM_CHECK(vo == NULL);
        tried += 3;
    }
    /* one byte short, NULL, and a workspace that starts misaligned */
    sfm_vo *vo = NULL;
    SFM_CHECK_EQ_INT(sfm_vo_init(&d, &p, &vo, h_ws, need - 1), SFM_E_WORKSPACE);
    SFM_CHECK(vo == NULL);
    SFM_CHECK_EQ_INT(sfm_vo_init(&d, &p, &vo, h_ws + 1, need - 1), SFM_E_WORKSPACE);
    SFM_CHECK(vo == NULL);
    int st = sfm_vo_init(&d, &p, &vo, h_ws + 1, need);
    SFM_CHECK_MSG(st == SFM_OK || st == SFM_E_WORKSPACE, "misaligned: %d", st);
    if (st == SFM_OK)
        SFM_CHECK(((uintptr_t)vo) % sizeof(double) == 0);
    tried += 3;
    /* dims out of range */
    sfm_vo_dims e = d;
    e.width = -HW;
    SFM_CHECK(sfm_vo_workspace_size(&e) == 0);
    e = d;
    e.height = 1;
    SFM_CHECK(sfm_vo_workspace_size(&e) == 0);
    e = d;
    e.width = 1 << 30;
    SFM_CHECK(sfm_vo_workspace_size(&e) == 0);
    tried += 3;
    SFM_CHECK_EQ_INT(tried, 39);
}

SFM_TEST(hostile_vo_frames)
{
    sfm_vo_dims d;
    sfm_vo_params p;
    vo_scene_setup(&d, &p);
    sfm_vo *vo = NULL;
    SFM_CHECK_EQ_INT(sfm_vo_init(&d, &p, &vo, h_ws, HWS), SFM_OK);
    texture(t);
    crop(0);
    sfm_image_u8 img = {h_frame, HW, HH, HW};
    sfm_vo_frame_result r, canary;
    sfm_test_fill_canary(&canary, sizeof canary);
    SFM_CHECK_EQ_INT(sfm_vo_push_frame(vo, &img, 100, NULL, 0, &r), SFM_OK);
    SFM_CHECK_EQ_INT(r.frame_index, 0);
    int tried = 1;
    /* refused frames, each leaving r and the state untouched */
    const sfm_image_u8 badimg[] = {
        {NULL, HW, HH, HW},          /* the capture returned no buffer */
        {NULL, 0, 0, 0},             /* the camera vanished */
        {h_frame, HW, HH, HW - 1},   /* stride below the width */
        {h_frame, HW, HH, -HW},      /* negative stride */
        {h_frame, HW, HH, 0},
        {h_frame, HW + 8, HH, HW + 8}, /* another size mid-stream */
        {h_frame, HW, HH + 1, HW},
        {h_frame, HW / 2, HH / 2, HW},
        {h_frame, -HW, HH, HW},
    };
    for (int k = 0; k < (int)(sizeof badimg / sizeof badimg[0]); k++) {
        r = canary;
        SFM_CHECK_MSG(sfm_vo_push_frame(vo, &badimg[k], 200, NULL, 0, &r) == SFM_E_ARGUMENT, "image %d", k);
        SFM_CHECK(memcmp(&r, &canary, sizeof r) == 0);
        tried++;
    }
    /* time going backwards, even by 1 ns, and from INT64_MAX */
    r = canary;
    SFM_CHECK_EQ_INT(sfm_vo_push_frame(vo, &img, 99, NULL, 0, &r), SFM_E_ARGUMENT);
    SFM_CHECK_EQ_INT(sfm_vo_push_frame(vo, &img, INT64_MIN, NULL, 0, &r), SFM_E_ARGUMENT);
    SFM_CHECK(memcmp(&r, &canary, sizeof r) == 0);
    /* gravity: NaN, Inf, zero refused; extreme but finite magnitudes are a
     * direction like any other and must not turn into NaN */
    double gn[3] = {0, (double)NAN, 0}, gi[3] = {0, (double)INFINITY, 0}, gz[3] = {0, -0.0, 0};
    SFM_CHECK_EQ_INT(sfm_vo_push_frame(vo, &img, 200, gn, 0, &r), SFM_E_NONFINITE);
    SFM_CHECK_EQ_INT(sfm_vo_push_frame(vo, &img, 200, gi, 0, &r), SFM_E_NONFINITE);
    SFM_CHECK_EQ_INT(sfm_vo_push_frame(vo, &img, 200, gz, 0, &r), SFM_E_ARGUMENT);
    SFM_CHECK(memcmp(&r, &canary, sizeof r) == 0);
    tried += 5;
    /* the refusals changed nothing: the next frame is frame 1; a repeated
     * timestamp is allowed (two frames of one capture instant) */
    SFM_CHECK_EQ_INT(sfm_vo_push_frame(vo, &img, 100, NULL, 0, &r), SFM_OK);
    SFM_CHECK_EQ_INT(r.frame_index, 1);
    SFM_CHECK(!r.has_pose || result_finite(&r));
    /* gravity of 1e300 and of a subnormal: norms overflow / underflow */
    const double gmag[] = {1e300, 1e-310, 1e-160, 1e160};
    for (int k = 0; k < 4; k++) {
        double g[3] = {0, gmag[k], 0};
        crop(2 * (k + 1));
        int st = sfm_vo_push_frame(vo, &img, 1000 + k, g, 1, &r);
        SFM_CHECK_MSG(st == SFM_OK || st == SFM_E_ARGUMENT, "gravity %g: %d", gmag[k], st);
        if (st == SFM_OK) {
            SFM_CHECK_MSG(result_finite(&r), "gravity %g: non-finite pose", gmag[k]);
            SFM_CHECK(isfinite(r.median_parallax_deg));
        }
        tried++;
    }
    SFM_CHECK_EQ_INT(tried, 19);
}

/* Black, constant and noise frames, then 1000 identical textured frames:
 * no crash, no pose without parallax, frame indices counting, and two
 * pipelines fed the same frames agree bit for bit. */
SFM_TEST(hostile_vo_degenerate_sequences)
{
    sfm_vo_dims d;
    sfm_vo_params p;
    vo_scene_setup(&d, &p);
    sfm_vo *a = NULL, *b = NULL;
    SFM_CHECK_EQ_INT(sfm_vo_init(&d, &p, &a, h_ws, HWS), SFM_OK);
    SFM_CHECK_EQ_INT(sfm_vo_init(&d, &p, &b, h_ws2, HWS), SFM_OK);
    texture(t);
    sfm_image_u8 img = {h_frame, HW, HH, HW};
    sfm_vo_frame_result ra, rb;
    int n = 0, posed = 0, differ = 0;
    for (int k = 0; k < 30; k++) {
        int kind = k % 3;
        for (int i = 0; i < HW * HH; i++)
            h_frame[i] = kind == 0 ? 0 : kind == 1 ? 128 : (uint8_t)sfm_test_uniform(t, 0, 256);
        SFM_CHECK_EQ_INT(sfm_vo_push_frame(a, &img, k, NULL, 1, &ra), SFM_OK);
        SFM_CHECK_EQ_INT(sfm_vo_push_frame(b, &img, k, NULL, 1, &rb), SFM_OK);
        SFM_CHECK_EQ_INT(ra.frame_index, n);
        if (kind < 2)
            SFM_CHECK_EQ_INT(ra.n_features, 0);
        posed += ra.has_pose && ra.state == SFM_VO_TRACKING;
        SFM_CHECK(result_finite(&ra));
        ra.stage_seconds[0] = rb.stage_seconds[0]; /* no clock: both 0 anyway */
        differ += memcmp(&ra, &rb, sizeof ra) != 0;
        n++;
    }
    crop(0);
    for (int k = 0; k < H_SAME; k++) {
        SFM_CHECK_EQ_INT(sfm_vo_push_frame(a, &img, 100 + k, NULL, 0, &ra), SFM_OK);
        SFM_CHECK_EQ_INT(sfm_vo_push_frame(b, &img, 100 + k, NULL, 0, &rb), SFM_OK);
        SFM_CHECK_EQ_INT(ra.frame_index, n);
        posed += ra.state == SFM_VO_TRACKING;
        SFM_CHECK(result_finite(&ra));
        differ += memcmp(&ra, &rb, sizeof ra) != 0;
        n++;
    }
    SFM_CHECK_EQ_INT(posed, 0);
    SFM_CHECK_EQ_INT(differ, 0);
    SFM_CHECK_EQ_INT(n, 30 + H_SAME);
}

/* A search radius of 1e300 is finite and accepted; it must search the whole
 * image as a radius of 1e6 does (both cover every grid cell of a 160 x 120
 * frame), frame by frame the same answers. The grid cell of uv + 1e300 was
 * an out-of-range double-to-int conversion (undefined; INT_MIN on x86,
 * which searched only the first cell). */
SFM_TEST(hostile_vo_huge_search_radius)
{
    sfm_vo_dims d;
    sfm_vo_params p, q;
    vo_scene_setup(&d, &p);
    p.threshold = 1.0;
    q = p;
    p.track_radius = p.init_radius = 1e6;
    q.track_radius = q.init_radius = 1e300;
    sfm_vo *a = NULL, *b = NULL;
    SFM_CHECK_EQ_INT(sfm_vo_init(&d, &p, &a, h_ws, HWS), SFM_OK);
    SFM_CHECK_EQ_INT(sfm_vo_init(&d, &q, &b, h_ws2, HWS), SFM_OK);
    texture(t);
    sfm_image_u8 img = {h_frame, HW, HH, HW};
    int matched = 0, differ = 0;
    for (int k = 0; k < 10; k++) {
        crop(3 * k);
        sfm_vo_frame_result ra, rb;
        SFM_CHECK_EQ_INT(sfm_vo_push_frame(a, &img, k, NULL, 0, &ra), SFM_OK);
        SFM_CHECK_EQ_INT(sfm_vo_push_frame(b, &img, k, NULL, 0, &rb), SFM_OK);
        matched += ra.n_matches > 0;
        int same = ra.state == rb.state && ra.has_pose == rb.has_pose &&
                   ra.n_matches == rb.n_matches && ra.n_inliers == rb.n_inliers &&
                   ra.n_map_points == rb.n_map_points &&
                   memcmp(ra.R_cw, rb.R_cw, sizeof ra.R_cw) == 0 &&
                   memcmp(ra.t_cw, rb.t_cw, sizeof ra.t_cw) == 0;
        SFM_CHECK_MSG(same, "frame %d: radius 1e6 %d matches (%s), 1e300 %d matches (%s)", k,
                      ra.n_matches, sfm_vo_state_str(ra.state), rb.n_matches, sfm_vo_state_str(rb.state));
        differ += !same;
    }
    SFM_CHECK(matched >= 5); /* the comparison is not between two empty runs */
    SFM_CHECK_EQ_INT(differ, 0);
}

/* A stage failing after the frame's checks (here the relative pose's
 * workspace cut short from inside) leaves the pipeline reset, out
 * untouched, and the next frames start again as on a new pipeline. */
SFM_TEST(hostile_vo_internal_failure_resets)
{
    sfm_vo_dims d;
    sfm_vo_params p;
    vo_scene_setup(&d, &p);
    p.threshold = 1.0;
    sfm_vo *a = NULL, *b = NULL;
    SFM_CHECK_EQ_INT(sfm_vo_init(&d, &p, &a, h_ws, HWS), SFM_OK);
    SFM_CHECK_EQ_INT(sfm_vo_init(&d, &p, &b, h_ws2, HWS), SFM_OK);
    texture(t);
    sfm_image_u8 img = {h_frame, HW, HH, HW};
    sfm_vo_frame_result r;
    int k = 0, failed = 0;
    for (; k < 10 && !failed; k++) {
        crop(3 * k);
        if (k == 1) /* the initialisation's relative pose runs from the second frame on */
            a->ransac_ws_size = 16;
        memset(&r, 0x5a, sizeof r);
        int st = sfm_vo_push_frame(a, &img, k, NULL, 0, &r);
        if (st < 0) {
            SFM_CHECK_EQ_INT(st, SFM_E_WORKSPACE);
            unsigned char sentinel[sizeof r];
            memset(sentinel, 0x5a, sizeof sentinel);
            SFM_CHECK(memcmp(&r, sentinel, sizeof r) == 0);
            failed = 1;
        }
    }
    SFM_CHECK_MSG(failed, "no stage reached the relative pose in %d frames", k);
    static double xyz[3 * 4096];
    SFM_CHECK_EQ_INT(sfm_vo_map_points(a, xyz, NULL, 4096), 0);
    /* after the reset, a behaves as the fresh pipeline b on the same frames */
    a->ransac_ws_size = b->ransac_ws_size;
    int posed = 0;
    for (int j = 0; j < 8; j++) {
        crop(3 * (k + j));
        sfm_vo_frame_result ra, rb;
        SFM_CHECK_EQ_INT(sfm_vo_push_frame(a, &img, k + j, NULL, 0, &ra), SFM_OK);
        SFM_CHECK_EQ_INT(sfm_vo_push_frame(b, &img, k + j, NULL, 0, &rb), SFM_OK);
        SFM_CHECK_EQ_INT(ra.frame_index, j);
        SFM_CHECK_EQ_INT(ra.state, rb.state);
        SFM_CHECK_EQ_INT(ra.n_inliers, rb.n_inliers);
        SFM_CHECK(memcmp(ra.t_cw, rb.t_cw, sizeof ra.t_cw) == 0);
        posed += ra.has_pose;
    }
    SFM_CHECK(posed >= 3); /* the comparison is not between two runs without a pose */
}
