/*
 * Stereo entry points under hostile input: coincident and nearly coincident
 * cameras, a vertical baseline, 1x1 images, disparity ranges of zero,
 * negative or wider than the image, strides below the width, NaN cameras,
 * sizes whose products overflow. Every call must return a status and leave
 * its outputs as they were (pre-filled with a canary).
 */
#include <math.h>
#include <stdint.h>
#include <string.h>

#include "sfm/sfm_stereo.h"
#include "sfm_test.h"

#define HW 64
#define HH 48

static uint8_t h_img[HW * HH], h_img2[HW * HH], h_dst[HW * HH];
static float h_disp[HW * HH];
static int32_t h_map[2 * HW * HH];
static unsigned char h_ws[400000];

static sfm_camera hcam(double f)
{
    sfm_camera c;
    memset(&c, 0, sizeof c);
    c.model = SFM_CAMERA_PINHOLE;
    c.fx = c.fy = f;
    c.cx = (HW - 1) / 2.0;
    c.cy = (HH - 1) / 2.0;
    return c;
}

static const double I3[9] = {1, 0, 0, 0, 1, 0, 0, 0, 1};

/* Rectify with a canary in out: a refusal must return `want` and leave it. */
static void rect_refused(sfm_test_ctx *t, const sfm_camera *c1, const sfm_camera *c2, int w,
                         int h, const double *R, const double *tv, double alpha, int want)
{
    sfm_stereo_rectification out, canary;
    sfm_test_fill_canary(&canary, sizeof canary);
    out = canary;
    int st = sfm_stereo_rectify(c1, c2, w, h, R, tv, alpha, 0, 0, &out);
    SFM_CHECK_MSG(st == want, "rectify: status %d, want %d", st, want);
    SFM_CHECK(memcmp(&out, &canary, sizeof out) == 0);
}

SFM_TEST(hostile_stereo_rectify)
{
    sfm_camera c = hcam(60.0), cn = c;
    double t0[3] = {0, 0, 0}, ttiny[3] = {1e-300, 0, 0}, tz[3] = {0, 0, 1.0};
    double tx[3] = {-0.1, 0, 0}, tv[3] = {0, -0.1, 0};
    /* coincident centres, and a baseline far below the scale */
    rect_refused(t, &c, &c, HW, HH, I3, t0, 0.0, SFM_E_SINGULAR);
    rect_refused(t, &c, &c, HW, HH, I3, ttiny, 0.0, SFM_E_SINGULAR);
    /* forward motion: epipoles inside the images */
    rect_refused(t, &c, &c, HW, HH, I3, tz, 0.0, SFM_E_SINGULAR);
    /* NaN / Inf in the camera, R, t, alpha */
    cn.cx = (double)NAN;
    rect_refused(t, &cn, &c, HW, HH, I3, tx, 0.0, SFM_E_NONFINITE);
    rect_refused(t, &c, &cn, HW, HH, I3, tx, 0.0, SFM_E_NONFINITE);
    cn = c;
    cn.fy = (double)INFINITY;
    rect_refused(t, &c, &cn, HW, HH, I3, tx, 0.0, SFM_E_NONFINITE);
    double Rn[9];
    memcpy(Rn, I3, sizeof Rn);
    Rn[4] = (double)NAN;
    rect_refused(t, &c, &c, HW, HH, Rn, tx, 0.0, SFM_E_NONFINITE);
    double tn[3] = {(double)NAN, 0, 0};
    rect_refused(t, &c, &c, HW, HH, I3, tn, 0.0, SFM_E_NONFINITE);
    rect_refused(t, &c, &c, HW, HH, I3, tx, (double)NAN, SFM_E_NONFINITE);
    /* 1x1 images, zero and negative sizes, a reflection for R */
    rect_refused(t, &c, &c, 1, 1, I3, tx, 0.0, SFM_E_ARGUMENT);
    rect_refused(t, &c, &c, 0, HH, I3, tx, 0.0, SFM_E_ARGUMENT);
    rect_refused(t, &c, &c, HW, -5, I3, tx, 0.0, SFM_E_ARGUMENT);
    double Rf[9] = {1, 0, 0, 0, 1, 0, 0, 0, -1};
    rect_refused(t, &c, &c, HW, HH, Rf, tx, 0.0, SFM_E_ARGUMENT);
    cn = c;
    cn.fx = 0;
    rect_refused(t, &cn, &c, HW, HH, I3, tx, 0.0, SFM_E_ARGUMENT);
    rect_refused(t, NULL, &c, HW, HH, I3, tx, 0.0, SFM_E_ARGUMENT);
    rect_refused(t, &c, &c, HW, HH, NULL, tx, 0.0, SFM_E_ARGUMENT);
    rect_refused(t, &c, &c, HW, HH, I3, NULL, 0.0, SFM_E_ARGUMENT);
    {
        sfm_stereo_rectification out;
        SFM_CHECK_EQ_INT(sfm_stereo_rectify(&c, &c, HW, HH, I3, tx, 0.0, 1 << 30, 1 << 30, &out),
                         SFM_E_ARGUMENT);
    }
    /* A vertical baseline is a valid pair: rows of the rectified images
     * align (the rectified x axis follows the baseline). */
    sfm_stereo_rectification r;
    SFM_CHECK_EQ_INT(sfm_stereo_rectify(&c, &c, HW, HH, I3, tv, 0.0, 0, 0, &r), SFM_OK);
    SFM_CHECK(r.baseline > 0.09 && r.baseline < 0.11);
    double X[3] = {0.3, -0.2, 2.0};
    double y1 = 0, y2 = 0;
    {
        /* camera 2: x2 = x1 + t */
        double x1[3], x2[3], Xc2[3] = {X[0] + tv[0], X[1] + tv[1], X[2] + tv[2]};
        for (int i = 0; i < 3; i++) {
            x1[i] = r.R1[3 * i] * X[0] + r.R1[3 * i + 1] * X[1] + r.R1[3 * i + 2] * X[2];
            x2[i] = r.R2[3 * i] * Xc2[0] + r.R2[3 * i + 1] * Xc2[1] + r.R2[3 * i + 2] * Xc2[2];
        }
        SFM_CHECK(x1[2] > 0 && x2[2] > 0);
        y1 = r.K1[4] * x1[1] / x1[2] + r.K1[5];
        y2 = r.K2[4] * x2[1] / x2[2] + r.K2[5];
    }
    SFM_CHECK_NEAR(y1, y2, 1e-9);
    /* the same check is deterministic to the bit */
    sfm_stereo_rectification r2;
    SFM_CHECK_EQ_INT(sfm_stereo_rectify(&c, &c, HW, HH, I3, tv, 0.0, 0, 0, &r2), SFM_OK);
    SFM_CHECK(memcmp(&r, &r2, sizeof r) == 0);
}

SFM_TEST(hostile_stereo_maps_and_remap)
{
    sfm_camera c = hcam(60.0);
    double tx[3] = {-0.1, 0, 0};
    sfm_stereo_rectification r;
    SFM_CHECK_EQ_INT(sfm_stereo_rectify(&c, &c, HW, HH, I3, tx, 0.0, 0, 0, &r), SFM_OK);
    size_t need = 2u * (size_t)r.width * (size_t)r.height;
    SFM_CHECK(need <= sizeof h_map / sizeof h_map[0]);
    int32_t canary = (int32_t)0x5a5a5a5a;
    for (size_t i = 0; i < need; i++)
        h_map[i] = canary;
    SFM_CHECK_EQ_INT(sfm_stereo_rectify_map(&c, HW, HH, &r, 1, h_map, need - 1), SFM_E_ARGUMENT);
    SFM_CHECK_EQ_INT(sfm_stereo_rectify_map(&c, HW, HH, &r, 3, h_map, need), SFM_E_ARGUMENT);
    SFM_CHECK_EQ_INT(sfm_stereo_rectify_map(&c, 0, HH, &r, 1, h_map, need), SFM_E_ARGUMENT);
    sfm_camera cn = c;
    cn.fx = (double)NAN;
    SFM_CHECK_EQ_INT(sfm_stereo_rectify_map(&cn, HW, HH, &r, 1, h_map, need), SFM_E_NONFINITE);
    sfm_stereo_rectification rn = r;
    rn.K1[0] = (double)NAN;
    SFM_CHECK_EQ_INT(sfm_stereo_rectify_map(&c, HW, HH, &rn, 1, h_map, need), SFM_E_NONFINITE);
    rn = r;
    rn.R2[0] = (double)INFINITY;
    SFM_CHECK_EQ_INT(sfm_stereo_rectify_map(&c, HW, HH, &rn, 2, h_map, need), SFM_E_NONFINITE);
    rn = r;
    rn.width = 0;
    SFM_CHECK_EQ_INT(sfm_stereo_rectify_map(&c, HW, HH, &rn, 1, h_map, need), SFM_E_ARGUMENT);
    rn = r;
    rn.width = rn.height = 1 << 16; /* 2 w h overflows 32 bits */
    SFM_CHECK_EQ_INT(sfm_stereo_rectify_map(&c, HW, HH, &rn, 1, h_map, need), SFM_E_ARGUMENT);
    int same = 1;
    for (size_t i = 0; i < need; i++)
        same &= h_map[i] == canary;
    SFM_CHECK(same);

    double Hn[9] = {1, 0, 0, 0, 1, 0, 0, 0, 0};
    SFM_CHECK_EQ_INT(sfm_stereo_homography_map((const sfm_mat3 *)Hn, HW, HH, HW, HH, h_map, need),
                     SFM_E_SINGULAR);
    Hn[8] = (double)NAN;
    SFM_CHECK_EQ_INT(sfm_stereo_homography_map((const sfm_mat3 *)Hn, HW, HH, HW, HH, h_map, need),
                     SFM_E_NONFINITE);
    SFM_CHECK_EQ_INT(sfm_stereo_homography_map((const sfm_mat3 *)I3, HW, HH, 1 << 16, 1 << 16,
                                               h_map, need),
                     SFM_E_ARGUMENT);
    same = 1;
    for (size_t i = 0; i < need; i++)
        same &= h_map[i] == canary;
    SFM_CHECK(same);

    /* remap: 1x1 works, strides below the width and zero sizes are refused */
    SFM_CHECK_EQ_INT(sfm_stereo_rectify_map(&c, HW, HH, &r, 1, h_map, need), SFM_OK);
    memset(h_dst, 0xa5, sizeof h_dst);
    for (int i = 0; i < HW * HH; i++)
        h_img[i] = (uint8_t)(i * 7);
    SFM_CHECK_EQ_INT(sfm_stereo_remap(h_img, HW, HH, HW - 1, h_map, r.width, r.height, 0, h_dst,
                                      HW),
                     SFM_E_ARGUMENT);
    SFM_CHECK_EQ_INT(sfm_stereo_remap(h_img, HW, HH, HW, h_map, r.width, r.height, 0, h_dst,
                                      r.width - 1),
                     SFM_E_ARGUMENT);
    SFM_CHECK_EQ_INT(sfm_stereo_remap(h_img, HW, HH, HW, h_map, 0, r.height, 0, h_dst, HW),
                     SFM_E_ARGUMENT);
    SFM_CHECK_EQ_INT(sfm_stereo_remap(h_img, HW, HH, HW, NULL, r.width, r.height, 0, h_dst, HW),
                     SFM_E_ARGUMENT);
    same = 1;
    for (int i = 0; i < HW * HH; i++)
        same &= h_dst[i] == 0xa5;
    SFM_CHECK(same);
    /* a map pointing far outside a 1x1 source: the fill, no read past it */
    int32_t m1[2] = {1000 * SFM_STEREO_MAP_ONE, 1000 * SFM_STEREO_MAP_ONE};
    uint8_t one = 77, d1 = 0;
    SFM_CHECK_EQ_INT(sfm_stereo_remap(&one, 1, 1, 1, m1, 1, 1, 9, &d1, 1), SFM_OK);
    SFM_CHECK_EQ_INT(d1, 9);
    int32_t m2[2] = {INT32_MAX, INT32_MAX};
    SFM_CHECK_EQ_INT(sfm_stereo_remap(&one, 1, 1, 1, m2, 1, 1, 9, &d1, 1), SFM_OK);
    SFM_CHECK_EQ_INT(d1, 9);
    int32_t m3[2] = {0, 0};
    SFM_CHECK_EQ_INT(sfm_stereo_remap(&one, 1, 1, 1, m3, 1, 1, 9, &d1, 1), SFM_OK);
    SFM_CHECK_EQ_INT(d1, 77);
}

SFM_TEST(hostile_stereo_matchers)
{
    for (int i = 0; i < HW * HH; i++) {
        h_img[i] = (uint8_t)((i * 2654435761u) >> 24);
        h_img2[i] = h_img[i];
    }
    sfm_stereo_sgm_options o;
    sfm_stereo_sgm_default_options(&o);
    o.num_disparities = 16;
    size_t need = sfm_stereo_sgm_workspace_size(HW, HH, &o);
    SFM_CHECK(need > 0 && need <= sizeof h_ws);
    float fc;
    memset(&fc, 0x7b, sizeof fc);
    for (int i = 0; i < HW * HH; i++)
        h_disp[i] = fc;
    sfm_stereo_sgm_options b = o;
    b.num_disparities = 0;
    SFM_CHECK(sfm_stereo_sgm_workspace_size(HW, HH, &b) == 0);
    SFM_CHECK_EQ_INT(sfm_stereo_sgm(h_img, h_img2, HW, HH, HW, &b, h_disp, h_ws, sizeof h_ws),
                     SFM_E_ARGUMENT);
    b.num_disparities = -8;
    SFM_CHECK_EQ_INT(sfm_stereo_sgm(h_img, h_img2, HW, HH, HW, &b, h_disp, h_ws, sizeof h_ws),
                     SFM_E_ARGUMENT);
    b = o;
    b.num_disparities = 72; /* wider than the 64-pixel image */
    SFM_CHECK_EQ_INT(sfm_stereo_sgm(h_img, h_img2, HW, HH, HW, &b, h_disp, h_ws, sizeof h_ws),
                     SFM_E_ARGUMENT);
    b = o;
    b.min_disparity = HW; /* searches only disparities beyond the image */
    SFM_CHECK_EQ_INT(sfm_stereo_sgm(h_img, h_img2, HW, HH, HW, &b, h_disp, h_ws, sizeof h_ws),
                     SFM_E_ARGUMENT);
    b = o;
    b.min_disparity = INT32_MAX - 4; /* min + num overflows */
    SFM_CHECK(sfm_stereo_sgm_workspace_size(HW, HH, &b) == 0 ||
              sfm_stereo_sgm(h_img, h_img2, HW, HH, HW, &b, h_disp, h_ws, sizeof h_ws) ==
                  SFM_E_ARGUMENT);
    SFM_CHECK_EQ_INT(sfm_stereo_sgm(h_img, h_img2, HW, HH, HW, &b, h_disp, h_ws, sizeof h_ws),
                     SFM_E_ARGUMENT);
    b = o;
    b.min_disparity = INT32_MIN + 4;
    SFM_CHECK_EQ_INT(sfm_stereo_sgm(h_img, h_img2, HW, HH, HW, &b, h_disp, h_ws, sizeof h_ws),
                     SFM_E_ARGUMENT);
    SFM_CHECK_EQ_INT(sfm_stereo_sgm(h_img, h_img2, HW, HH, HW - 1, &o, h_disp, h_ws, sizeof h_ws),
                     SFM_E_ARGUMENT);
    SFM_CHECK_EQ_INT(sfm_stereo_sgm(h_img, h_img2, 1, 1, 1, &o, h_disp, h_ws, sizeof h_ws),
                     SFM_E_ARGUMENT);
    SFM_CHECK_EQ_INT(sfm_stereo_sgm(h_img, h_img2, HW, HH, HW, &o, h_disp, h_ws, need - 1),
                     SFM_E_WORKSPACE);
    SFM_CHECK(sfm_stereo_sgm_workspace_size(1 << 20, 1 << 20, &o) == 0);
    SFM_CHECK(sfm_stereo_sgm_workspace_size(HW, -1, &o) == 0);
    SFM_CHECK(sfm_stereo_sgm_workspace_size(HW, HH, NULL) == 0);

    sfm_stereo_block_options bo;
    sfm_stereo_block_default_options(&bo);
    bo.num_disparities = 16;
    sfm_stereo_block_options bb = bo;
    bb.num_disparities = 0;
    SFM_CHECK_EQ_INT(sfm_stereo_block(h_img, h_img2, HW, HH, HW, &bb, h_disp, h_ws, sizeof h_ws),
                     SFM_E_ARGUMENT);
    bb = bo;
    bb.num_disparities = 72;
    SFM_CHECK_EQ_INT(sfm_stereo_block(h_img, h_img2, HW, HH, HW, &bb, h_disp, h_ws, sizeof h_ws),
                     SFM_E_ARGUMENT);
    bb = bo;
    bb.min_disparity = INT32_MAX - 4;
    SFM_CHECK_EQ_INT(sfm_stereo_block(h_img, h_img2, HW, HH, HW, &bb, h_disp, h_ws, sizeof h_ws),
                     SFM_E_ARGUMENT);
    bb = bo;
    bb.min_disparity = -HW - 16; /* every searched disparity is negative beyond the width */
    SFM_CHECK_EQ_INT(sfm_stereo_block(h_img, h_img2, HW, HH, HW, &bb, h_disp, h_ws, sizeof h_ws),
                     SFM_E_ARGUMENT);
    bb = bo;
    bb.radius = 0;
    SFM_CHECK_EQ_INT(sfm_stereo_block(h_img, h_img2, HW, HH, HW, &bb, h_disp, h_ws, sizeof h_ws),
                     SFM_E_ARGUMENT);
    SFM_CHECK_EQ_INT(sfm_stereo_block(h_img, h_img2, HW, HH, HW - 1, &bo, h_disp, h_ws,
                                      sizeof h_ws),
                     SFM_E_ARGUMENT);
    int same = 1;
    for (int i = 0; i < HW * HH; i++)
        same &= memcmp(&h_disp[i], &fc, sizeof fc) == 0;
    SFM_CHECK(same);

    /* a constant pair and a black pair: no crash, every disparity NaN or in range */
    memset(h_img, 128, sizeof h_img);
    memset(h_img2, 128, sizeof h_img2);
    int nv = sfm_stereo_sgm(h_img, h_img2, HW, HH, HW, &o, h_disp, h_ws, sizeof h_ws);
    SFM_CHECK(nv >= 0);
    int inrange = 1;
    for (int i = 0; i < HW * HH; i++)
        inrange &= isnan(h_disp[i]) || (h_disp[i] >= o.min_disparity - 1 &&
                                        h_disp[i] <= o.min_disparity + o.num_disparities);
    SFM_CHECK(inrange);
    nv = sfm_stereo_block(h_img, h_img2, HW, HH, HW, &bo, h_disp, h_ws, sizeof h_ws);
    SFM_CHECK(nv == 0); /* flat: the texture floor rejects every pixel */
}

SFM_TEST(hostile_stereo_depth_points_error)
{
    sfm_camera c = hcam(60.0);
    double tx[3] = {-0.1, 0, 0};
    sfm_stereo_rectification r;
    SFM_CHECK_EQ_INT(sfm_stereo_rectify(&c, &c, HW, HH, I3, tx, 0.0, 0, 0, &r), SFM_OK);
    for (int i = 0; i < HW * HH; i++)
        h_disp[i] = (i % 3 == 0) ? (float)NAN : (i % 3 == 1 ? (float)INFINITY : -5.0f);
    float *depth = (float *)h_ws;
    int n = sfm_stereo_depth(h_disp, HW, HH, &r, depth);
    SFM_CHECK(n >= 0);
    int ok = 1;
    for (int i = 0; i < HW * HH; i++)
        ok &= isnan(depth[i]) || (depth[i] > 0 && isfinite(depth[i]));
    SFM_CHECK(ok);
    sfm_stereo_rectification rn = r;
    rn.Q[11] = (double)NAN;
    SFM_CHECK_EQ_INT(sfm_stereo_depth(h_disp, HW, HH, &rn, depth), SFM_E_NONFINITE);
    rn = r;
    rn.baseline = (double)NAN;
    SFM_CHECK_EQ_INT(sfm_stereo_depth(h_disp, HW, HH, &rn, depth), SFM_E_NONFINITE);
    SFM_CHECK_EQ_INT(sfm_stereo_depth(h_disp, 0, HH, &r, depth), SFM_E_ARGUMENT);
    double pts[3];
    int np = sfm_stereo_points(h_disp, HW, HH, &r, 0.0, NULL, NULL, 0);
    SFM_CHECK(np >= 0);
    SFM_CHECK_EQ_INT(sfm_stereo_points(h_disp, HW, HH, &r, 0.0, pts, NULL, -1), SFM_E_ARGUMENT);
    SFM_CHECK_EQ_INT(sfm_stereo_points(h_disp, HW, HH, &r, (double)NAN, pts, NULL, 1),
                     SFM_E_NONFINITE);

    /* rectification error: n of 0, negative n, NaN matches */
    double x1[4] = {10, 10, (double)NAN, 5}, x2[4] = {12, 10, 3, 5}, med = -7, mx = -7;
    int u = sfm_stereo_rectification_error(&c, &c, &r, NULL, NULL, x1, x2, 0, &med, &mx);
    SFM_CHECK(u == 0 || u == SFM_E_ARGUMENT);
    med = mx = -7;
    SFM_CHECK_EQ_INT(sfm_stereo_rectification_error(&c, &c, &r, NULL, NULL, x1, x2, -1, &med, &mx),
                     SFM_E_ARGUMENT);
    SFM_CHECK_EQ_INT(sfm_stereo_rectification_error(&c, &c, &r, NULL, NULL, x1, x2, 2, &med, &mx),
                     SFM_E_NONFINITE);
    SFM_CHECK_EQ_INT(sfm_stereo_rectification_error(&c, &c, NULL, NULL, NULL, x1, x2, 1, &med, &mx),
                     SFM_E_ARGUMENT);
    /* a corrupted rectification or camera: a status, not a median of 0 */
    double y1[2] = {10, 10}, y2[2] = {12, 10};
    rn = r;
    rn.R1[0] = (double)NAN;
    SFM_CHECK_EQ_INT(sfm_stereo_rectification_error(&c, &c, &rn, NULL, NULL, y1, y2, 1, &med, &mx),
                     SFM_E_NONFINITE);
    rn = r;
    rn.K2[4] = (double)INFINITY;
    SFM_CHECK_EQ_INT(sfm_stereo_rectification_error(&c, &c, &rn, NULL, NULL, y1, y2, 1, &med, &mx),
                     SFM_E_NONFINITE);
    sfm_camera cn = c;
    cn.cy = (double)NAN;
    SFM_CHECK_EQ_INT(sfm_stereo_rectification_error(&cn, &c, &r, NULL, NULL, y1, y2, 1, &med, &mx),
                     SFM_E_NONFINITE);
    SFM_CHECK(med == -7 && mx == -7);
    SFM_CHECK_EQ_INT(sfm_stereo_rectification_error(&c, &c, &r, NULL, NULL, y1, y2, 1, &med, &mx),
                     1);
    SFM_CHECK(isfinite(med) && med == mx);
}
