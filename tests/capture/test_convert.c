/* Pixel-format converters against the reference formulas: the luma sample
 * of YUYV (byte 0 and 2 of each 4-byte group) and NV12 (the first plane),
 * BT.601 luma for RGB, and a JPEG round trip through libjpeg. */
#define _DEFAULT_SOURCE
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "cap_test.h"
#include "capture/capture_impl.h"
#include "sfm_test.h"

enum { W = 38, H = 10, PAD = 5 };

static uint8_t rnd8(sfm_test_ctx *t) { return (uint8_t)(sfm_rng_next(&t->rng) >> 56); }

SFM_TEST(convert_yuyv_takes_luma)
{
    static uint8_t src[H * (2 * W + PAD)], dst[H * (W + 3)];
    const int ss = 2 * W + PAD, ds = W + 3;
    for (size_t i = 0; i < sizeof src; i++)
        src[i] = rnd8(t);
    SFM_CHECK_EQ_INT(sfm_convert_to_gray(SFM_PIX_YUYV, src, sizeof src, W, H, ss, dst, ds), SFM_OK);
    for (int y = 0; y < H; y++)
        for (int x = 0; x < W; x++) {
            /* Y0 U Y1 V: pixel x is byte 4*(x/2) + 2*(x%2) */
            uint8_t ref = src[y * ss + 4 * (x / 2) + 2 * (x % 2)];
            SFM_CHECK_EQ_INT(dst[y * ds + x], ref);
        }
    size_t need = sfm_pixfmt_min_size(SFM_PIX_YUYV, W, H, ss);
    SFM_CHECK_EQ_INT((long)need, (long)((H - 1) * ss + 2 * W));
    memset(dst, 7, sizeof dst);
    SFM_CHECK_EQ_INT(sfm_convert_to_gray(SFM_PIX_YUYV, src, need - 1, W, H, ss, dst, ds),
                     SFM_E_FORMAT);
    SFM_CHECK_EQ_INT(dst[0], 7);
    SFM_CHECK_EQ_INT(sfm_convert_to_gray(SFM_PIX_YUYV, src, sizeof src, W + 1, H, 0, dst, W + 1),
                     SFM_E_ARGUMENT); /* odd width */
    SFM_CHECK_EQ_INT(sfm_convert_to_gray(SFM_PIX_YUYV, src, sizeof src, W, H, W, dst, ds),
                     SFM_E_ARGUMENT); /* stride shorter than a row */
}

SFM_TEST(convert_nv12_takes_luma_plane)
{
    const int ss = W + PAD, ds = W;
    static uint8_t src[(W + PAD) * H * 3 / 2], dst[W * H];
    for (size_t i = 0; i < sizeof src; i++)
        src[i] = rnd8(t);
    size_t need = sfm_pixfmt_min_size(SFM_PIX_NV12, W, H, ss);
    SFM_CHECK_EQ_INT((long)need, (long)(ss * H + ss * (H / 2 - 1) + W));
    SFM_CHECK(need <= sizeof src);
    SFM_CHECK_EQ_INT(sfm_convert_to_gray(SFM_PIX_NV12, src, need, W, H, ss, dst, ds), SFM_OK);
    for (int y = 0; y < H; y++)
        for (int x = 0; x < W; x++)
            SFM_CHECK_EQ_INT(dst[y * ds + x], src[y * ss + x]);
    SFM_CHECK_EQ_INT(sfm_convert_to_gray(SFM_PIX_NV12, src, need - 1, W, H, ss, dst, ds),
                     SFM_E_FORMAT); /* chroma plane cut short */
    SFM_CHECK_EQ_INT(sfm_pixfmt_min_size(SFM_PIX_NV12, W, H + 1, ss), 0); /* odd height */
}

SFM_TEST(convert_rgb24_matches_bt601)
{
    const int ss = 3 * W + PAD;
    static uint8_t src[(3 * W + PAD) * H], dst[W * H];
    for (size_t i = 0; i < sizeof src; i++)
        src[i] = rnd8(t);
    /* corners of the cube */
    for (int k = 0; k < 8; k++) {
        src[3 * k] = (k & 1) ? 255 : 0;
        src[3 * k + 1] = (k & 2) ? 255 : 0;
        src[3 * k + 2] = (k & 4) ? 255 : 0;
    }
    SFM_CHECK_EQ_INT(sfm_convert_to_gray(SFM_PIX_RGB24, src, sizeof src, W, H, ss, dst, W), SFM_OK);
    double err_sum = 0.0;
    int worst = 0;
    for (int y = 0; y < H; y++)
        for (int x = 0; x < W; x++) {
            const uint8_t *p = src + y * ss + 3 * x;
            double ref = 0.299 * p[0] + 0.587 * p[1] + 0.114 * p[2];
            double d = fabs(dst[y * W + x] - ref);
            err_sum += d;
            if (d > worst)
                worst = (int)ceil(d);
        }
    SFM_CHECK(worst <= 1);                /* fixed point within one level */
    SFM_CHECK(err_sum / (W * H) < 0.6);   /* and rounded, not truncated */
    SFM_CHECK_EQ_INT(dst[0], 0);
    SFM_CHECK_EQ_INT(dst[7], 255);
}

SFM_TEST(convert_gray_copy_and_contracts)
{
    static uint8_t src[W * H], dst[W * H];
    for (size_t i = 0; i < sizeof src; i++)
        src[i] = rnd8(t);
    SFM_CHECK_EQ_INT(sfm_convert_to_gray(SFM_PIX_GRAY8, src, sizeof src, W, H, 0, dst, W), SFM_OK);
    SFM_CHECK(memcmp(src, dst, sizeof src) == 0);
    SFM_CHECK_EQ_INT(sfm_convert_to_gray(SFM_PIX_GRAY8, NULL, 1, W, H, 0, dst, W), SFM_E_ARGUMENT);
    SFM_CHECK_EQ_INT(sfm_convert_to_gray(SFM_PIX_GRAY8, src, sizeof src, W, H, 0, NULL, W),
                     SFM_E_ARGUMENT);
    SFM_CHECK_EQ_INT(sfm_convert_to_gray(99, src, sizeof src, W, H, 0, dst, W), SFM_E_ARGUMENT);
    SFM_CHECK_EQ_INT(sfm_convert_to_gray(SFM_PIX_GRAY8, src, sizeof src, 0, H, 0, dst, W),
                     SFM_E_ARGUMENT);
    SFM_CHECK_EQ_INT(sfm_convert_to_gray(SFM_PIX_GRAY8, src, sizeof src, W, H, 0, dst, W - 1),
                     SFM_E_ARGUMENT);
    SFM_CHECK(strcmp(sfm_pixfmt_name(SFM_PIX_NV12), "NV12") == 0);
    SFM_CHECK(strcmp(sfm_pixfmt_name(0), "?") == 0);
}

SFM_TEST(convert_mjpeg_decodes_jpeg)
{
#ifndef SFM_HAVE_LIBJPEG
    (void)t;
    printf("SKIP: built without libjpeg\n");
#else
    enum { JW = 64, JH = 48 };
    static uint8_t img[JW * JH], out[JW * JH], jpg[65536];
    for (int y = 0; y < JH; y++)
        for (int x = 0; x < JW; x++)
            img[y * JW + x] = (uint8_t)(40 + 2 * x + y); /* smooth: JPEG keeps it well */
    char dir[512], path[600];
    SFM_CHECK(cap_tmpdir(dir, sizeof dir) == 0);
    snprintf(path, sizeof path, "%s/f.jpg", dir);
    SFM_CHECK_EQ_INT(sfm_jpeg_write(path, img, JW, JH, JW, 1, 95), SFM_OK);
    long n = cap_read_file(path, jpg, sizeof jpg);
    SFM_CHECK(n > 100);
    SFM_CHECK_EQ_INT(sfm_convert_to_gray(SFM_PIX_MJPEG, jpg, (size_t)n, JW, JH, 0, out, JW), SFM_OK);
    double se = 0.0;
    for (int i = 0; i < JW * JH; i++)
        se += (double)(out[i] - img[i]) * (out[i] - img[i]);
    double psnr = 10.0 * log10(255.0 * 255.0 / (se / (JW * JH) + 1e-12));
    SFM_TEST_LOG("JPEG q95 round trip PSNR %.1f dB", psnr);
    SFM_CHECK(psnr > 40.0);
    /* Wrong size, truncated, garbage: refused. */
    SFM_CHECK_EQ_INT(sfm_convert_to_gray(SFM_PIX_MJPEG, jpg, (size_t)n, JW, JH + 2, 0, out, JW),
                     SFM_E_FORMAT);
    SFM_CHECK_EQ_INT(sfm_convert_to_gray(SFM_PIX_MJPEG, jpg, (size_t)n / 2, JW, JH, 0, out, JW),
                     SFM_E_FORMAT);
    memset(jpg + 2, 0x55, 64);
    SFM_CHECK_EQ_INT(sfm_convert_to_gray(SFM_PIX_MJPEG, jpg, (size_t)n, JW, JH, 0, out, JW),
                     SFM_E_FORMAT);
    cap_rmtree(dir);
#endif
}
