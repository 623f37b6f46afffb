/*
 * Features: detector, descriptor, matcher and three-view association on
 * synthetic images built here with known geometry (160x120, static buffers).
 */
#include <math.h>
#include <string.h>

#include "features/brief_pattern.h"
#include "sfm/sfm.h"
#include "sfm_test.h"

#define W 160
#define H 120
#define MAXF 300
#define WS_BYTES (256 * 1024)

static uint8_t img_a[W * H], img_b[W * H];
static unsigned char ws_buf[WS_BYTES + 64];
static sfm_keypoint kp_a[MAXF], kp_b[MAXF];
static uint8_t desc_a[MAXF * 32], desc_b[MAXF * 32];
static int pairs[2 * MAXF], pairs_ref[2 * MAXF], dists[MAXF];

/* Length of [a0, a1] inside [b0, b1]. */
static double overlap(double a0, double a1, double b0, double b1)
{
    double lo = a0 > b0 ? a0 : b0, hi = a1 < b1 ? a1 : b1;
    return hi > lo ? hi - lo : 0.0;
}

/* Axis-aligned bright squares on a dark ground, exact area coverage per
 * pixel (pixel (i, j) covers [i - 0.5, i + 0.5] x [j - 0.5, j + 0.5]). */
static void render_squares(uint8_t *img, const double (*sq)[3], int n)
{
    for (int y = 0; y < H; y++)
        for (int x = 0; x < W; x++) {
            double cover = 0.0;
            for (int k = 0; k < n; k++)
                cover += overlap(x - 0.5, x + 0.5, sq[k][0], sq[k][0] + sq[k][2]) *
                         overlap(y - 0.5, y + 0.5, sq[k][1], sq[k][1] + sq[k][2]);
            img[y * W + x] = (uint8_t)floor(50.0 + 150.0 * cover + 0.5);
        }
}

static int detect(const uint8_t *img, int w, int h, const sfm_features_params *p, sfm_keypoint *kp,
                  uint8_t *desc)
{
    sfm_image_u8 im = {img, w, h, w};
    size_t need = sfm_features_workspace_size(p, w, h);
    if (need == 0 || need > WS_BYTES)
        return -100;
    return sfm_features_detect(&im, p, kp, desc, MAXF, ws_buf, need);
}

SFM_TEST(features_corners_subpixel)
{
    /* 3 x 2 squares of side 18.x at random sub-pixel positions: 24 L-corners */
    double sq[6][3];
    for (int k = 0; k < 6; k++) {
        sq[k][0] = 28.0 + 40.0 * (k % 3) + sfm_test_uniform(t, 0.0, 1.0);
        sq[k][1] = 28.0 + 40.0 * (k / 3) + sfm_test_uniform(t, 0.0, 1.0);
        sq[k][2] = 18.0 + sfm_test_uniform(t, 0.0, 1.0);
    }
    render_squares(img_a, (const double(*)[3])sq, 6);
    sfm_features_params p;
    SFM_CHECK_EQ_INT(sfm_features_default_params(&p), SFM_OK);
    p.n_levels = 1;
    p.max_features = 100;
    int n = detect(img_a, W, H, &p, kp_a, desc_a);
    SFM_CHECK(n >= 24);
    double worst = 0.0, sum = 0.0;
    for (int k = 0; k < 6; k++)
        for (int c = 0; c < 4; c++) {
            double cx = sq[k][0] + ((c & 1) ? sq[k][2] : 0.0), cy = sq[k][1] + ((c & 2) ? sq[k][2] : 0.0);
            double best = 1e9;
            for (int i = 0; i < n; i++) {
                double d = hypot(kp_a[i].x - cx, kp_a[i].y - cy);
                best = d < best ? d : best;
            }
            worst = best > worst ? best : worst;
            sum += best;
        }
    /* integers only: printing doubles needs a heap in some embedded libcs */
    SFM_TEST_LOG("corner error: mean %d, worst %d (thousandths of a pixel)", (int)(1000.0 * sum / 24.0),
                 (int)(1000.0 * worst));
    SFM_CHECK(worst < 0.3);
    SFM_CHECK(sum / 24.0 < 0.2);
    for (int i = 0; i < n; i++) {
        SFM_CHECK_EQ_INT(kp_a[i].level, 0);
        SFM_CHECK_NEAR(kp_a[i].scale, 1.0, 0.0);
    }
}

/* Texture: random rotated rectangles with random gray levels, evaluated
 * analytically in world coordinates with 2x2 supersampling; the second image
 * sees the world through a known rotation + translation. */
#define NRECT 70
typedef struct rect {
    double cx, cy, c, s, hw, hh, v;
} rect;

static double world(const rect *r, double X, double Y)
{
    /* later rectangles cover earlier ones: the last one containing X wins */
    for (int k = NRECT - 1; k >= 0; k--) {
        double dx = X - r[k].cx, dy = Y - r[k].cy;
        double u = r[k].c * dx + r[k].s * dy, w = -r[k].s * dx + r[k].c * dy;
        if (fabs(u) <= r[k].hw && fabs(w) <= r[k].hh)
            return r[k].v;
    }
    return 128.0;
}

/* image point x maps to world X = A x + b, A a rotation by th about the centre */
static void render_world(uint8_t *img, const rect *r, double th, double tx, double ty)
{
    const double c = cos(th), s = sin(th), x0 = 0.5 * (W - 1), y0 = 0.5 * (H - 1);
    for (int y = 0; y < H; y++)
        for (int x = 0; x < W; x++) {
            double acc = 0.0;
            for (int j = 0; j < 2; j++)
                for (int i = 0; i < 2; i++) {
                    double px = x - 0.25 + 0.5 * i - x0, py = y - 0.25 + 0.5 * j - y0;
                    double X = c * px - s * py + x0 + tx, Y = s * px + c * py + y0 + ty;
                    acc += world(r, X, Y);
                }
            img[y * W + x] = (uint8_t)floor(acc / 4.0 + 0.5);
        }
}

SFM_TEST(features_descriptors_follow_known_rotation)
{
    static rect r[NRECT];
    for (int k = 0; k < NRECT; k++) {
        double a = sfm_test_uniform(t, 0.0, 3.14159265358979);
        r[k].cx = sfm_test_uniform(t, -20.0, W + 20.0);
        r[k].cy = sfm_test_uniform(t, -20.0, H + 20.0);
        r[k].c = cos(a);
        r[k].s = sin(a);
        r[k].hw = sfm_test_uniform(t, 3.0, 14.0);
        r[k].hh = sfm_test_uniform(t, 3.0, 14.0);
        r[k].v = sfm_test_uniform(t, 20.0, 235.0);
    }
    const double th = 0.5, tx = 4.3, ty = -2.7;
    render_world(img_a, r, 0.0, 0.0, 0.0);
    render_world(img_b, r, th, tx, ty);
    sfm_features_params p;
    sfm_features_default_params(&p);
    p.max_features = 250;
    p.n_levels = 3;
    p.cell_size = 32;
    int na = detect(img_a, W, H, &p, kp_a, desc_a), nb = detect(img_b, W, H, &p, kp_b, desc_b);
    SFM_CHECK(na > 60 && nb > 60);
    sfm_match_params mp;
    sfm_features_default_match_params(&mp);
    size_t need = sfm_features_match_workspace_size(na, nb);
    SFM_CHECK(need <= WS_BYTES);
    int m = sfm_features_match(desc_a, na, desc_b, nb, &mp, pairs, dists, MAXF, ws_buf, need);
    SFM_CHECK(m > 0);
    /* a point x_b of image b shows world A x_b + b = x_a (world = image a) */
    const double c = cos(th), s = sin(th), x0 = 0.5 * (W - 1), y0 = 0.5 * (H - 1);
    int good = 0;
    double angle_err = 0.0;
    for (int k = 0; k < m; k++) {
        const sfm_keypoint *a = &kp_a[pairs[2 * k]], *b = &kp_b[pairs[2 * k + 1]];
        double px = b->x - x0, py = b->y - y0;
        double X = c * px - s * py + x0 + tx, Y = s * px + c * py + y0 + ty;
        if (hypot(X - a->x, Y - a->y) <= 2.0) {
            good++;
            /* the world rotated by -th in image b: orientation decreases by th */
            double d = (b->angle + th) - a->angle;
            d = atan2(sin(d), cos(d));
            angle_err += fabs(d);
        }
    }
    SFM_TEST_LOG("%d features / %d features, %d matches, %d where the warp says (%d%%), mean angle error %d.%d deg",
                 na, nb, m, good, m ? 100 * good / m : 0, good ? (int)(angle_err / good * 57.2958) : 0,
                 good ? (int)(angle_err / good * 572.958) % 10 : 0);
    SFM_CHECK(good >= 30);
    SFM_CHECK(good >= 0.85 * m);
    SFM_CHECK(good > 0 && angle_err / good < 0.12);
}

/* Smooth texture for the alignment test: Gaussian blobs (sigma 2.5 to 5
 * px, random gray levels of either sign) evaluated at the pixel centres of a
 * view whose point x shows world R (x - c) + c + t; smooth enough that a
 * sub-pixel motion of the world is a sub-pixel motion of the image. */
#define NBLOB 60
static void render_blobs(uint8_t *img, const double (*b)[4], double th, double tx, double ty)
{
    const double c = cos(th), s = sin(th), x0 = 0.5 * (W - 1), y0 = 0.5 * (H - 1);
    for (int y = 0; y < H; y++)
        for (int x = 0; x < W; x++) {
            const double px = x - x0, py = y - y0;
            const double X = c * px - s * py + x0 + tx, Y = s * px + c * py + y0 + ty;
            double v = 128.0;
            for (int k = 0; k < NBLOB; k++) {
                const double dx = X - b[k][0], dy = Y - b[k][1], r2 = dx * dx + dy * dy, s2 = b[k][2] * b[k][2];
                if (r2 < 16.0 * s2)
                    v += b[k][3] * exp(-0.5 * r2 / s2);
            }
            v = v < 0.0 ? 0.0 : (v > 255.0 ? 255.0 : v);
            img[y * W + x] = (uint8_t)floor(v + 0.5);
        }
}

/* Lucas-Kanade alignment against a known motion: image b sees the world of
 * image a through a rotation of th and a sub-pixel shift; points on a grid
 * of image a start in image b at the integer pixel nearest the truth. */
SFM_TEST(features_align_points_recovers_known_motion)
{
    static double blob[NBLOB][4];
    for (int k = 0; k < NBLOB; k++) {
        blob[k][0] = sfm_test_uniform(t, -10.0, W + 10.0);
        blob[k][1] = sfm_test_uniform(t, -10.0, H + 10.0);
        blob[k][2] = sfm_test_uniform(t, 2.5, 5.0);
        blob[k][3] = sfm_test_uniform(t, 40.0, 90.0) * (k % 2 ? 1.0 : -1.0);
    }
    const double ths[2] = {0.0, 0.02};
    for (int m = 0; m < 2; m++) {
        const double th = ths[m], tx = sfm_test_uniform(t, -2.0, 2.0), ty = sfm_test_uniform(t, -2.0, 2.0);
        render_blobs(img_a, (const double(*)[4])blob, 0.0, 0.0, 0.0);
        render_blobs(img_b, (const double(*)[4])blob, th, tx, ty);
        const double c = cos(th), s = sin(th), x0 = 0.5 * (W - 1), y0 = 0.5 * (H - 1);
        /* the points: the detector's corners of image a (what the alignment
         * is for), each started at the integer pixel nearest its truth */
        enum { NP = 96 };
        sfm_features_params fp;
        sfm_features_default_params(&fp);
        fp.n_levels = 1;
        fp.max_features = NP;
        fp.cell_size = 16;
        fp.fast_threshold = 8;
        const int nd = detect(img_a, W, H, &fp, kp_a, desc_a);
        SFM_CHECK(nd >= 20);
        const int np = nd < 0 ? 0 : nd;
        double xa[2 * NP], xb[2 * NP], truth[2 * NP], out[2 * NP];
        uint8_t ok[NP];
        for (int k = 0; k < np; k++) {
            xa[2 * k] = kp_a[k].x;
            xa[2 * k + 1] = kp_a[k].y;
            /* x_a = R (x_b - c) + c + t  =>  x_b = R^T (x_a - c - t) + c */
            const double u = xa[2 * k] - x0 - tx, v = xa[2 * k + 1] - y0 - ty;
            truth[2 * k] = c * u + s * v + x0;
            truth[2 * k + 1] = -s * u + c * v + y0;
            xb[2 * k] = floor(truth[2 * k] + 0.5);
            xb[2 * k + 1] = floor(truth[2 * k + 1] + 0.5);
        }
        sfm_align_params p;
        SFM_CHECK_EQ_INT(sfm_features_default_align_params(&p), SFM_OK);
        sfm_image_u8 ia = {img_a, W, H, W}, ib = {img_b, W, H, W};
        const int n = sfm_features_align_points(&ia, xa, &ib, xb, np, &p, out, ok);
        double se = 0.0, se0 = 0.0, worst = 0.0;
        int cnt = 0;
        for (int k = 0; k < np; k++) {
            if (!ok[k]) {
                SFM_CHECK(out[2 * k] == xb[2 * k] && out[2 * k + 1] == xb[2 * k + 1]);
                continue;
            }
            const double e = hypot(out[2 * k] - truth[2 * k], out[2 * k + 1] - truth[2 * k + 1]);
            se += e * e;
            se0 += pow(xb[2 * k] - truth[2 * k], 2) + pow(xb[2 * k + 1] - truth[2 * k + 1], 2);
            worst = e > worst ? e : worst;
            cnt++;
        }
        SFM_CHECK_EQ_INT(n, cnt);
        SFM_TEST_LOG("rotation %d mrad: %d of %d aligned, RMS %d (start %d), worst %d (thousandths of a pixel)",
                     (int)(1000.0 * th), cnt, np, cnt ? (int)(1000.0 * sqrt(se / cnt)) : -1,
                     cnt ? (int)(1000.0 * sqrt(se0 / cnt)) : -1, (int)(1000.0 * worst));
        SFM_CHECK(cnt >= 3 * np / 4);
        SFM_CHECK(cnt > 0 && sqrt(se / cnt) < 0.08);
        SFM_CHECK(worst < 0.3);
        /* in place gives the same bits */
        double inplace[2 * NP];
        memcpy(inplace, xb, sizeof xb);
        SFM_CHECK_EQ_INT(sfm_features_align_points(&ia, xa, &ib, inplace, np, &p, inplace, ok), n);
        SFM_CHECK(memcmp(inplace, out, sizeof(double) * 2 * (size_t)np) == 0);
    }
}

SFM_TEST(features_align_points_contract)
{
    for (int i = 0; i < W * H; i++)
        img_a[i] = (uint8_t)((i * 2654435761u) >> 24);
    sfm_image_u8 im = {img_a, W, H, W};
    sfm_align_params p;
    SFM_CHECK_EQ_INT(sfm_features_default_align_params(NULL), SFM_E_ARGUMENT);
    sfm_features_default_align_params(&p);
    double x[4] = {40.0, 40.0, 80.0, 60.0}, out[4];
    uint8_t ok[2];
    sfm_test_fill_canary(out, sizeof out);
    sfm_test_fill_canary(ok, sizeof ok);
    SFM_CHECK_EQ_INT(sfm_features_align_points(NULL, x, &im, x, 2, &p, out, ok), SFM_E_ARGUMENT);
    SFM_CHECK_EQ_INT(sfm_features_align_points(&im, NULL, &im, x, 2, &p, out, ok), SFM_E_ARGUMENT);
    SFM_CHECK_EQ_INT(sfm_features_align_points(&im, x, &im, x, 2, NULL, out, ok), SFM_E_ARGUMENT);
    SFM_CHECK_EQ_INT(sfm_features_align_points(&im, x, &im, x, 2, &p, NULL, ok), SFM_E_ARGUMENT);
    SFM_CHECK_EQ_INT(sfm_features_align_points(&im, x, &im, x, 2, &p, out, NULL), SFM_E_ARGUMENT);
    SFM_CHECK_EQ_INT(sfm_features_align_points(&im, x, &im, x, -1, &p, out, ok), SFM_E_ARGUMENT);
    sfm_image_u8 bad = im;
    bad.stride = W - 1;
    SFM_CHECK_EQ_INT(sfm_features_align_points(&im, x, &bad, x, 2, &p, out, ok), SFM_E_ARGUMENT);
    sfm_align_params q = p;
    q.radius = SFM_FEATURES_ALIGN_MAX_RADIUS + 1;
    SFM_CHECK_EQ_INT(sfm_features_align_points(&im, x, &im, x, 2, &q, out, ok), SFM_E_ARGUMENT);
    q = p;
    q.max_shift = (double)NAN;
    SFM_CHECK_EQ_INT(sfm_features_align_points(&im, x, &im, x, 2, &q, out, ok), SFM_E_ARGUMENT);
    q = p;
    q.min_zncc = 1.5;
    SFM_CHECK_EQ_INT(sfm_features_align_points(&im, x, &im, x, 2, &q, out, ok), SFM_E_ARGUMENT);
    double xn[4] = {40.0, 40.0, (double)INFINITY, 60.0};
    SFM_CHECK_EQ_INT(sfm_features_align_points(&im, x, &im, xn, 2, &p, out, ok), SFM_E_NONFINITE);
    SFM_CHECK_EQ_INT(sfm_features_align_points(&im, xn, &im, x, 2, &p, out, ok), SFM_E_NONFINITE);
    SFM_CHECK(sfm_test_canary_intact(out, sizeof out));
    SFM_CHECK(sfm_test_canary_intact(ok, sizeof ok));
    SFM_CHECK_EQ_INT(sfm_features_align_points(&im, NULL, &im, NULL, 0, &p, NULL, NULL), 0);
    /* a point whose patch leaves the image keeps its start */
    double edge[4] = {2.0, 50.0, 80.0, H - 3.0};
    SFM_CHECK_EQ_INT(sfm_features_align_points(&im, edge, &im, edge, 2, &p, out, ok), 0);
    SFM_CHECK(ok[0] == 0 && ok[1] == 0 && memcmp(out, edge, sizeof edge) == 0);
    /* a flat patch has no gradient to align on */
    memset(img_b, 90, sizeof img_b);
    sfm_image_u8 flat = {img_b, W, H, W};
    SFM_CHECK_EQ_INT(sfm_features_align_points(&flat, x, &im, x, 2, &p, out, ok), 0);
    /* a point aligned with itself stays put */
    SFM_CHECK_EQ_INT(sfm_features_align_points(&im, x, &im, x, 2, &p, out, ok), 2);
    SFM_CHECK_NEAR(out[0], x[0], 1e-6);
    SFM_CHECK_NEAR(out[3], x[3], 1e-6);
}

static int popcount_ref(const uint8_t *a, const uint8_t *b)
{
    int n = 0;
    for (int i = 0; i < 32; i++)
        for (int k = 0; k < 8; k++)
            n += ((a[i] ^ b[i]) >> k) & 1;
    return n;
}

/* Straightforward reference: nearest, second nearest, mutual. */
static int match_ref(const uint8_t *d1, int n1, const uint8_t *d2, int n2, double ratio, int mutual, int maxd,
                     int *out)
{
    int n = 0;
    for (int i = 0; i < n1; i++) {
        int b1 = 1000, b2 = 1000, bj = -1;
        for (int j = 0; j < n2; j++) {
            int d = popcount_ref(d1 + 32 * i, d2 + 32 * j);
            if (d < b1) {
                b2 = b1;
                b1 = d;
                bj = j;
            } else if (d < b2) {
                b2 = d;
            }
        }
        if (bj < 0 || b1 > maxd)
            continue;
        if (ratio < 1.0 && b2 < 1000 && !(b1 < ratio * b2))
            continue;
        if (mutual) {
            int best_i = -1, bd = 1000;
            for (int k = 0; k < n1; k++) {
                int d = popcount_ref(d1 + 32 * k, d2 + 32 * bj);
                if (d < bd) {
                    bd = d;
                    best_i = k;
                }
            }
            if (best_i != i)
                continue;
        }
        out[2 * n] = i;
        out[2 * n + 1] = bj;
        n++;
    }
    return n;
}

SFM_TEST(features_matcher_equals_bruteforce_reference)
{
    const int iters = SFM_TEST_ITERS(20);
    for (int it = 0; it < iters; it++) {
        const int n1 = 1 + (int)(sfm_rng_next(&t->rng) % 90), n2 = 1 + (int)(sfm_rng_next(&t->rng) % 90);
        for (int i = 0; i < 32 * n2; i++)
            desc_b[i] = (uint8_t)sfm_rng_next(&t->rng);
        for (int i = 0; i < n1; i++) {
            /* half are noisy copies of a train descriptor (some bits flipped) */
            if ((sfm_rng_next(&t->rng) & 1) != 0) {
                int j = (int)(sfm_rng_next(&t->rng) % (uint64_t)n2);
                memcpy(desc_a + 32 * i, desc_b + 32 * j, 32);
                int flips = (int)(sfm_rng_next(&t->rng) % 60);
                for (int f = 0; f < flips; f++) {
                    int bit = (int)(sfm_rng_next(&t->rng) % 256);
                    desc_a[32 * i + bit / 8] ^= (uint8_t)(1u << (bit % 8));
                }
            } else {
                for (int k = 0; k < 32; k++)
                    desc_a[32 * i + k] = (uint8_t)sfm_rng_next(&t->rng);
            }
        }
        for (int i = 0; i < n1; i++)
            SFM_CHECK_EQ_INT(sfm_features_hamming(desc_a + 32 * i, desc_b), popcount_ref(desc_a + 32 * i, desc_b));
        const double ratios[3] = {0.7, 0.8, 1.0};
        for (int r = 0; r < 3; r++)
            for (int mutual = 0; mutual <= 1; mutual++) {
                sfm_match_params mp = {ratios[r], mutual, it % 2 ? 256 : 100};
                int m = sfm_features_match(desc_a, n1, desc_b, n2, &mp, pairs, dists, MAXF, ws_buf, WS_BYTES);
                int mr = match_ref(desc_a, n1, desc_b, n2, ratios[r], mutual, mp.max_distance, pairs_ref);
                SFM_CHECK_EQ_INT(m, mr);
                if (m == mr && m >= 0) {
                    SFM_CHECK(memcmp(pairs, pairs_ref, sizeof(int) * 2 * (size_t)m) == 0);
                    for (int k = 0; k < m; k++)
                        SFM_CHECK_EQ_INT(dists[k], popcount_ref(desc_a + 32 * pairs[2 * k], desc_b + 32 * pairs[2 * k + 1]));
                }
            }
    }
}

SFM_TEST(features_cyclic_association_on_known_permutation)
{
    enum { N = 40 };
    int p12[N], p23[N], m12[2 * N], m23[2 * N], m31[2 * N], out[3 * N];
    for (int i = 0; i < N; i++)
        p12[i] = p23[i] = i;
    for (int i = N - 1; i > 0; i--) { /* Fisher-Yates */
        int j = (int)sfm_rng_bounded(&t->rng, (uint32_t)(i + 1)), k = (int)sfm_rng_bounded(&t->rng, (uint32_t)(i + 1));
        int a = p12[i]; p12[i] = p12[j]; p12[j] = a;
        a = p23[i]; p23[i] = p23[k]; p23[k] = a;
    }
    /* m12: i -> p12[i]; m23: j -> p23[j]; m31 closes the cycle except for
     * view-1 features i % 5 == 0 (sent to the wrong view-1 feature) and
     * i % 7 == 0 (missing from m12). */
    int n12 = 0, n31 = 0;
    for (int i = 0; i < N; i++) {
        if (i % 7 != 0) {
            m12[2 * n12] = i;
            m12[2 * n12 + 1] = p12[i];
            n12++;
        }
        m23[2 * i] = i;
        m23[2 * i + 1] = p23[i];
    }
    for (int i = 0; i < N; i++) {
        int k = p23[p12[i]];
        m31[2 * n31] = k;
        m31[2 * n31 + 1] = i % 5 == 0 ? (i + 1) % N : i;
        n31++;
    }
    size_t need = sfm_features_associate_workspace_size(N, N, N);
    int n = sfm_features_associate_three_views(m12, n12, m23, N, m31, n31, N, N, N, out, N, ws_buf, need);
    int expect = 0;
    for (int i = 0; i < N; i++)
        if (i % 5 != 0 && i % 7 != 0) {
            SFM_CHECK(expect < n);
            if (expect < n) {
                SFM_CHECK_EQ_INT(out[3 * expect], i);
                SFM_CHECK_EQ_INT(out[3 * expect + 1], p12[i]);
                SFM_CHECK_EQ_INT(out[3 * expect + 2], p23[p12[i]]);
            }
            expect++;
        }
    SFM_CHECK_EQ_INT(n, expect);
    /* a repeated source index is a broken contract: nothing written */
    m23[2 * 1] = m23[2 * 0];
    sfm_test_fill_canary(out, sizeof out);
    SFM_CHECK_EQ_INT(sfm_features_associate_three_views(m12, n12, m23, N, m31, n31, N, N, N, out, N, ws_buf, need),
                     SFM_E_ARGUMENT);
    SFM_CHECK(sfm_test_canary_intact(out, sizeof out));
    m23[2 * 1] = 1;
    m23[2 * 1 + 1] = N; /* out of range */
    SFM_CHECK_EQ_INT(sfm_features_associate_three_views(m12, n12, m23, N, m31, n31, N, N, N, out, N, ws_buf, need),
                     SFM_E_ARGUMENT);
    m23[2 * 1 + 1] = p23[1];
    SFM_CHECK_EQ_INT(sfm_features_associate_three_views(m12, n12, m23, N, m31, n31, N, N, N, out, N, ws_buf, need - 1),
                     SFM_E_WORKSPACE);
    SFM_CHECK_EQ_INT(sfm_features_associate_three_views(m12, n12, m23, N, m31, n31, N, N, N, out, n12 - 1, ws_buf, need),
                     SFM_E_CAPACITY);
    SFM_CHECK(sfm_test_canary_intact(out, sizeof out));
    SFM_CHECK_EQ_INT(sfm_features_associate_three_views(NULL, n12, m23, N, m31, n31, N, N, N, out, N, ws_buf, need),
                     SFM_E_ARGUMENT);
    SFM_CHECK_EQ_INT(sfm_features_associate_three_views(NULL, 0, m23, N, m31, n31, N, N, N, out, N, ws_buf, need), 0);
    SFM_CHECK_EQ_INT(sfm_features_associate_three_views(m12, n12, m23, N, m31, n31, N, N, N, out, N, NULL, need),
                     SFM_E_ARGUMENT);
    SFM_CHECK_EQ_INT(sfm_features_associate_three_views(m12, -1, m23, N, m31, n31, N, N, N, out, N, ws_buf, need),
                     SFM_E_ARGUMENT);
}

SFM_TEST(features_detect_contract)
{
    for (int i = 0; i < W * H; i++)
        img_a[i] = (uint8_t)((i * 2654435761u) >> 24); /* noise: plenty of corners */
    sfm_features_params p;
    SFM_CHECK_EQ_INT(sfm_features_default_params(NULL), SFM_E_ARGUMENT);
    sfm_features_default_params(&p);
    p.max_features = 200;
    sfm_image_u8 im = {img_a, W, H, W};
    const size_t need = sfm_features_workspace_size(&p, W, H);
    SFM_CHECK(need > 0 && need <= WS_BYTES);
    sfm_test_fill_canary(kp_a, sizeof kp_a);
    sfm_test_fill_canary(desc_a, sizeof desc_a);
    SFM_CHECK_EQ_INT(sfm_features_detect(NULL, &p, kp_a, desc_a, MAXF, ws_buf, need), SFM_E_ARGUMENT);
    SFM_CHECK_EQ_INT(sfm_features_detect(&im, NULL, kp_a, desc_a, MAXF, ws_buf, need), SFM_E_ARGUMENT);
    SFM_CHECK_EQ_INT(sfm_features_detect(&im, &p, kp_a, desc_a, MAXF, NULL, need), SFM_E_ARGUMENT);
    SFM_CHECK_EQ_INT(sfm_features_detect(&im, &p, NULL, desc_a, MAXF, ws_buf, need), SFM_E_ARGUMENT);
    SFM_CHECK_EQ_INT(sfm_features_detect(&im, &p, kp_a, NULL, MAXF, ws_buf, need), SFM_E_ARGUMENT);
    SFM_CHECK_EQ_INT(sfm_features_detect(&im, &p, kp_a, desc_a, MAXF, ws_buf, need - 1), SFM_E_WORKSPACE);
    SFM_CHECK_EQ_INT(sfm_features_detect(&im, &p, kp_a, desc_a, p.max_features - 1, ws_buf, need), SFM_E_CAPACITY);
    sfm_image_u8 bad = im;
    bad.stride = W - 1;
    SFM_CHECK_EQ_INT(sfm_features_detect(&bad, &p, kp_a, desc_a, MAXF, ws_buf, need), SFM_E_ARGUMENT);
    bad = im;
    bad.data = NULL;
    SFM_CHECK_EQ_INT(sfm_features_detect(&bad, &p, kp_a, desc_a, MAXF, ws_buf, need), SFM_E_ARGUMENT);
    bad = im;
    bad.width = 0;
    SFM_CHECK_EQ_INT(sfm_features_detect(&bad, &p, kp_a, desc_a, MAXF, ws_buf, need), SFM_E_ARGUMENT);
    sfm_features_params q = p;
    q.scale_factor = (double)NAN;
    SFM_CHECK_EQ_INT(sfm_features_detect(&im, &q, kp_a, desc_a, MAXF, ws_buf, need), SFM_E_ARGUMENT);
    SFM_CHECK_EQ_INT(sfm_features_workspace_size(&q, W, H), 0);
    q = p;
    q.n_levels = SFM_FEATURES_MAX_LEVELS + 1;
    SFM_CHECK_EQ_INT(sfm_features_detect(&im, &q, kp_a, desc_a, MAXF, ws_buf, need), SFM_E_ARGUMENT);
    q = p;
    q.max_features = 0;
    SFM_CHECK_EQ_INT(sfm_features_detect(&im, &q, kp_a, desc_a, MAXF, ws_buf, need), SFM_E_ARGUMENT);
    q = p;
    q.fast_threshold = 0;
    SFM_CHECK_EQ_INT(sfm_features_detect(&im, &q, kp_a, desc_a, MAXF, ws_buf, need), SFM_E_ARGUMENT);
    SFM_CHECK(sfm_test_canary_intact(kp_a, sizeof kp_a));
    SFM_CHECK(sfm_test_canary_intact(desc_a, sizeof desc_a));

    /* exact size works at every alignment; same input, same bytes out */
    int n0 = -1;
    for (int off = 0; off < 16; off += 5) {
        int n = sfm_features_detect(&im, &p, kp_a, desc_a, MAXF, ws_buf + off, need);
        SFM_CHECK(n > 0 && n <= p.max_features);
        if (off == 0) {
            n0 = n;
            memcpy(kp_b, kp_a, sizeof(sfm_keypoint) * (size_t)n);
            memcpy(desc_b, desc_a, 32 * (size_t)n);
        } else {
            SFM_CHECK_EQ_INT(n, n0);
            SFM_CHECK(n == n0 && memcmp(kp_b, kp_a, sizeof(sfm_keypoint) * (size_t)n) == 0);
            SFM_CHECK(n == n0 && memcmp(desc_b, desc_a, 32 * (size_t)n) == 0);
        }
    }
    /* every keypoint stays inside the image, away from the border */
    for (int i = 0; i < n0; i++) {
        SFM_CHECK(kp_a[i].x >= SFM_FEATURES_BORDER - 3.5 && kp_a[i].x <= W - SFM_FEATURES_BORDER + 2.5);
        SFM_CHECK(kp_a[i].y >= SFM_FEATURES_BORDER - 3.5 && kp_a[i].y <= H - SFM_FEATURES_BORDER + 2.5);
        SFM_CHECK(kp_a[i].level >= 0 && kp_a[i].level < p.n_levels && kp_a[i].reserved == 0);
    }
    /* the budget is a hard cap */
    q = p;
    q.max_features = 7;
    SFM_CHECK_EQ_INT(sfm_features_detect(&im, &q, kp_a, desc_a, 7, ws_buf, WS_BYTES), 7);

    /* tiny images: valid, no room for a feature */
    const int sides[4][2] = {{1, 1}, {32, 32}, {W, 20}, {20, H}};
    for (int k = 0; k < 4; k++) {
        sfm_image_u8 tiny = {img_a, sides[k][0], sides[k][1], W};
        size_t tn = sfm_features_workspace_size(&p, sides[k][0], sides[k][1]);
        SFM_CHECK(tn > 0);
        SFM_CHECK_EQ_INT(sfm_features_detect(&tiny, &p, kp_a, desc_a, MAXF, ws_buf, tn), 0);
    }
    /* the smallest image that holds a feature */
    sfm_image_u8 small = {img_a, 2 * SFM_FEATURES_BORDER + 1, 2 * SFM_FEATURES_BORDER + 1, W};
    size_t sn = sfm_features_workspace_size(&p, small.width, small.height);
    SFM_CHECK(sfm_features_detect(&small, &p, kp_a, desc_a, MAXF, ws_buf, sn) >= 0);
}

SFM_TEST(features_match_contract)
{
    for (int i = 0; i < 32 * 10; i++) {
        desc_a[i] = (uint8_t)sfm_rng_next(&t->rng);
        desc_b[i] = (uint8_t)sfm_rng_next(&t->rng);
    }
    sfm_match_params mp;
    SFM_CHECK_EQ_INT(sfm_features_default_match_params(NULL), SFM_E_ARGUMENT);
    sfm_features_default_match_params(&mp);
    const size_t need = sfm_features_match_workspace_size(10, 10);
    SFM_CHECK(need > 0);
    sfm_test_fill_canary(pairs, sizeof pairs);
    sfm_test_fill_canary(dists, sizeof dists);
    SFM_CHECK_EQ_INT(sfm_features_match(NULL, 10, desc_b, 10, &mp, pairs, dists, 10, ws_buf, need), SFM_E_ARGUMENT);
    SFM_CHECK_EQ_INT(sfm_features_match(desc_a, 10, NULL, 10, &mp, pairs, dists, 10, ws_buf, need), SFM_E_ARGUMENT);
    SFM_CHECK_EQ_INT(sfm_features_match(desc_a, 10, desc_b, 10, NULL, pairs, dists, 10, ws_buf, need), SFM_E_ARGUMENT);
    SFM_CHECK_EQ_INT(sfm_features_match(desc_a, 10, desc_b, 10, &mp, pairs, dists, 10, NULL, need), SFM_E_ARGUMENT);
    SFM_CHECK_EQ_INT(sfm_features_match(desc_a, 10, desc_b, 10, &mp, NULL, dists, 10, ws_buf, need), SFM_E_ARGUMENT);
    SFM_CHECK_EQ_INT(sfm_features_match(desc_a, -1, desc_b, 10, &mp, pairs, dists, 10, ws_buf, need), SFM_E_ARGUMENT);
    SFM_CHECK_EQ_INT(sfm_features_match(desc_a, 10, desc_b, 10, &mp, pairs, dists, 10, ws_buf, need - 1), SFM_E_WORKSPACE);
    SFM_CHECK_EQ_INT(sfm_features_match(desc_a, 10, desc_b, 10, &mp, pairs, dists, 9, ws_buf, need), SFM_E_CAPACITY);
    sfm_match_params bad = mp;
    bad.ratio = (double)NAN;
    SFM_CHECK_EQ_INT(sfm_features_match(desc_a, 10, desc_b, 10, &bad, pairs, dists, 10, ws_buf, need), SFM_E_ARGUMENT);
    bad = mp;
    bad.ratio = 0.0;
    SFM_CHECK_EQ_INT(sfm_features_match(desc_a, 10, desc_b, 10, &bad, pairs, dists, 10, ws_buf, need), SFM_E_ARGUMENT);
    bad = mp;
    bad.max_distance = 257;
    SFM_CHECK_EQ_INT(sfm_features_match(desc_a, 10, desc_b, 10, &bad, pairs, dists, 10, ws_buf, need), SFM_E_ARGUMENT);
    SFM_CHECK(sfm_test_canary_intact(pairs, sizeof pairs));
    SFM_CHECK(sfm_test_canary_intact(dists, sizeof dists));
    /* empty sets are valid; distances may be NULL */
    SFM_CHECK_EQ_INT(sfm_features_match(NULL, 0, desc_b, 10, &mp, pairs, NULL, 0, ws_buf, WS_BYTES), 0);
    SFM_CHECK_EQ_INT(sfm_features_match(desc_a, 10, NULL, 0, &mp, pairs, NULL, 10, ws_buf, WS_BYTES), 0);
    /* one train descriptor: no second neighbour, the ratio test passes */
    SFM_CHECK_EQ_INT(sfm_features_match(desc_a, 1, desc_a, 1, &mp, pairs, dists, 1, ws_buf, WS_BYTES), 1);
    SFM_CHECK_EQ_INT(dists[0], 0);
    SFM_CHECK_EQ_INT(sfm_features_hamming(NULL, desc_a), SFM_E_ARGUMENT);
}

SFM_TEST(features_brief_pattern_fits_patch)
{
    /* any rotation of the pattern stays inside the disc the border protects */
    int distinct = 1;
    for (int i = 0; i < SFM_BRIEF_PAIRS; i++) {
        signed char q[4];
        for (int c = 0; c < 4; c++)
            q[c] = sfmi_brief_pattern[c][i];
        SFM_CHECK(q[0] * q[0] + q[1] * q[1] <= SFM_BRIEF_RADIUS * SFM_BRIEF_RADIUS);
        SFM_CHECK(q[2] * q[2] + q[3] * q[3] <= SFM_BRIEF_RADIUS * SFM_BRIEF_RADIUS);
        SFM_CHECK(q[0] != q[2] || q[1] != q[3]);
        for (int j = 0; j < i; j++)
            if (sfmi_brief_pattern[0][j] == q[0] && sfmi_brief_pattern[1][j] == q[1] &&
                sfmi_brief_pattern[2][j] == q[2] && sfmi_brief_pattern[3][j] == q[3])
                distinct = 0;
    }
    SFM_CHECK(distinct);
    SFM_CHECK(SFM_BRIEF_RADIUS + 1 <= SFM_FEATURES_BORDER);
}

/* Hostile inputs of sfm_features_align_points: images of 1 x 1 up, strides
 * with padding, points on and outside the border (up to 1e300 px and the
 * int range), parameters at and past their limits. The outputs are canaries
 * first: nothing written on a negative status; otherwise every point
 * written, refined[k] 0 or 1, an unrefined point at its start, a refined
 * one finite and within max_shift of it. */
static int align_hostile_call(sfm_test_ctx *t, const char *what, const sfm_image_u8 *a, const double *xa,
                              const sfm_image_u8 *b, const double *xb, int n, const sfm_align_params *p)
{
    double out[2 * 16];
    uint8_t ok[16];
    sfm_test_fill_canary(out, sizeof out);
    sfm_test_fill_canary(ok, sizeof ok);
    const int st = sfm_features_align_points(a, xa, b, xb, n, p, out, ok);
    if (st < 0) {
        SFM_CHECK_MSG(st == SFM_E_ARGUMENT || st == SFM_E_NONFINITE, "%s: unlisted status %d", what, st);
        SFM_CHECK_MSG(sfm_test_canary_intact(out, sizeof out) && sfm_test_canary_intact(ok, sizeof ok),
                      "%s: status %d wrote an output", what, st);
        return st;
    }
    int cnt = 0;
    for (int k = 0; k < n; k++) {
        SFM_CHECK_MSG(ok[k] == 0 || ok[k] == 1, "%s: refined[%d] = %d", what, k, ok[k]);
        if (ok[k] == 1) {
            cnt++;
            SFM_CHECK_MSG(isfinite(out[2 * k]) && isfinite(out[2 * k + 1]) &&
                              fabs(out[2 * k] - xb[2 * k]) <= p->max_shift &&
                              fabs(out[2 * k + 1] - xb[2 * k + 1]) <= p->max_shift,
                          "%s: point %d refined to (%g, %g) from (%g, %g)", what, k, out[2 * k], out[2 * k + 1],
                          xb[2 * k], xb[2 * k + 1]);
            /* the refined patch lies inside img (its bilinear footprint) */
            SFM_CHECK_MSG(out[2 * k] >= p->radius && out[2 * k] < b->width - 1 - p->radius &&
                              out[2 * k + 1] >= p->radius && out[2 * k + 1] < b->height - 1 - p->radius,
                          "%s: point %d refined outside the image", what, k);
        } else {
            SFM_CHECK_MSG(out[2 * k] == xb[2 * k] && out[2 * k + 1] == xb[2 * k + 1],
                          "%s: point %d not refined but moved", what, k);
        }
    }
    SFM_CHECK_MSG(sfm_test_canary_intact(out + 2 * n, sizeof out - sizeof(double) * 2 * (size_t)n) &&
                      sfm_test_canary_intact(ok + n, sizeof ok - (size_t)n),
                  "%s: written past n", what);
    SFM_CHECK_EQ_INT(st, cnt);
    return st;
}

SFM_TEST(features_align_points_hostile_inputs)
{
    static double blob[NBLOB][4];
    for (int k = 0; k < NBLOB; k++) {
        blob[k][0] = sfm_test_uniform(t, -10.0, W + 10.0);
        blob[k][1] = sfm_test_uniform(t, -10.0, H + 10.0);
        blob[k][2] = sfm_test_uniform(t, 2.5, 5.0);
        blob[k][3] = sfm_test_uniform(t, 40.0, 90.0) * (k % 2 ? 1.0 : -1.0);
    }
    render_blobs(img_a, (const double(*)[4])blob, 0.0, 0.0, 0.0);
    render_blobs(img_b, (const double(*)[4])blob, 0.0, 0.7, -0.4);
    sfm_image_u8 ia = {img_a, W, H, W}, ib = {img_b, W, H, W};
    sfm_align_params p;
    sfm_features_default_align_params(&p);
    int tried = 0;
    /* points far outside, on the int range and beyond: a status or a point
     * kept, never a read outside the image (UBSan: no overflowing cast) */
    const double far[] = {-1e300, 1e300, -2147483648.0, 2147483647.0, 2147483648.0, -2147483649.0, 4294967296.0,
                          -1e10, 1e10, -9.0, -8.5, -0.5, (double)W, W + 0.25, 1e-300, -1e-300};
    const int nfar = (int)(sizeof far / sizeof far[0]);
    for (int a = 0; a < nfar; a++) {
        double xs[4] = {far[a], 60.0, 80.0, far[a]};
        align_hostile_call(t, "far point in img", &ia, (const double[4]){80.0, 60.0, 80.0, 60.0}, &ib, xs, 2, &p);
        align_hostile_call(t, "far point in ref", &ia, xs, &ib, (const double[4]){80.0, 60.0, 80.0, 60.0}, 2, &p);
        tried += 2;
    }
    /* the border: the last positions whose footprint fits, and just past */
    for (int r = 2; r <= SFM_FEATURES_ALIGN_MAX_RADIUS; r++) {
        sfm_align_params q = p;
        q.radius = r;
        const double e[8] = {r + 1.0, r + 1.0, W - r - 3.0, H - r - 3.0, r + 0.999, H - r - 2.001, W - r - 2.0,
                             H - r - 2.0};
        align_hostile_call(t, "border", &ia, e, &ib, e, 4, &q);
        align_hostile_call(t, "border", &ib, e, &ia, e, 4, &q);
        tried += 2;
    }
    /* points converging onto the border: img b shows img a's world 1.3 px
     * further down and right, the truth of each point within 0.05 px of the
     * last position whose patch fits in b, the start 0.3 px short of it.
     * The last Gauss-Newton step is not sampled and may cross that limit
     * (before the fix: 43 of 1276 refined points across it on a sinusoid
     * texture). */
    {
        static uint8_t moved[W * H];
        render_blobs(moved, (const double(*)[4])blob, 0.0, -1.3, -1.3);
        sfm_image_u8 im = {moved, W, H, W};
        for (int r = 2; r <= SFM_FEATURES_ALIGN_MAX_RADIUS; r += 2) {
            sfm_align_params q = p;
            q.radius = r, q.min_zncc = 0.0, q.min_eigen_ratio = 0.0;
            for (int s = 0; s < 100; s++) {
                const double lim_x = W - r - 1.0, lim_y = H - r - 1.0, eps = -0.05 + 0.001 * s;
                const double e[8] = {10.0 + 1.37 * s, lim_y - 1.3 + eps, lim_x - 1.3 + eps, 10.0 + 0.97 * s,
                                     lim_x - 1.3 - eps, lim_y - 1.3 + 0.5 * eps, 20.0 + s, lim_y - 1.3 - eps};
                double st[8];
                for (int k = 0; k < 8; k++)
                    st[k] = e[k] + (k % 2 ? 1.0 : 1.3);
                align_hostile_call(t, "onto the border", &ia, e, &im, st, 4, &q);
                tried++;
            }
        }
    }
    /* tiny images, exact-size buffers (no padding to read into): 1 x 1 up to
     * a patch and a pixel */
    static uint8_t tiny[(2 * SFM_FEATURES_ALIGN_MAX_RADIUS + 4) * (2 * SFM_FEATURES_ALIGN_MAX_RADIUS + 4)];
    const int sizes[][2] = {{1, 1}, {1, 40}, {40, 1}, {2, 2}, {5, 5}, {18, 18}, {19, 19}, {20, 20}};
    for (size_t s = 0; s < sizeof sizes / sizeof sizes[0]; s++) {
        const int w = sizes[s][0], h = sizes[s][1];
        for (int y = 0; y < h; y++)
            for (int x = 0; x < w; x++)
                tiny[y * w + x] = img_a[(y + 50) * W + x + 70];
        sfm_image_u8 ti = {tiny, w, h, w};
        const double c[4] = {0.5 * (w - 1), 0.5 * (h - 1), 0.0, 0.0};
        sfm_align_params q = p;
        q.radius = 2;
        align_hostile_call(t, "tiny image", &ti, c, &ti, c, 2, &q);
        align_hostile_call(t, "tiny image as img", &ia, (const double[4]){80.0, 60.0, 70.0, 50.0}, &ti, c, 2, &q);
        tried += 2;
    }
    /* a padded stride: the padding (set to extremes) is never sampled, the
     * answer is the unpadded image's */
    {
        enum { PAD = 13 };
        static uint8_t padded[(W + PAD) * H];
        for (int y = 0; y < H; y++) {
            memcpy(&padded[y * (W + PAD)], &img_b[y * W], W);
            memset(&padded[y * (W + PAD) + W], (y & 1) ? 255 : 0, PAD);
        }
        sfm_image_u8 ip = {padded, W, H, W + PAD};
        double xs[2 * 8], o1[2 * 8], o2[2 * 8];
        uint8_t k1[8], k2[8];
        for (int k = 0; k < 8; k++)
            xs[2 * k] = W - 10.0 + k, xs[2 * k + 1] = 20.0 + 11 * k;
        const int n1 = sfm_features_align_points(&ia, xs, &ib, xs, 8, &p, o1, k1);
        const int n2 = sfm_features_align_points(&ia, xs, &ip, xs, 8, &p, o2, k2);
        SFM_CHECK(n1 == n2 && memcmp(o1, o2, sizeof o1) == 0 && memcmp(k1, k2, sizeof k1) == 0);
        tried++;
    }
    /* image views: NULL data, zero and negative sizes, stride below width */
    const sfm_image_u8 bad_im[] = {{NULL, W, H, W}, {img_a, 0, H, W}, {img_a, W, 0, W}, {img_a, -1, H, W},
                                   {img_a, W, -5, W}, {img_a, W, H, 0}, {img_a, W, H, -W}, {img_a, W, H, W - 1}};
    const double xs2[4] = {80.0, 60.0, 40.0, 30.0};
    for (size_t k = 0; k < sizeof bad_im / sizeof bad_im[0]; k++) {
        SFM_CHECK_EQ_INT(align_hostile_call(t, "bad ref view", &bad_im[k], xs2, &ib, xs2, 2, &p), SFM_E_ARGUMENT);
        SFM_CHECK_EQ_INT(align_hostile_call(t, "bad img view", &ia, xs2, &bad_im[k], xs2, 2, &p), SFM_E_ARGUMENT);
        tried += 2;
    }
    /* parameters past each end, NaN and infinities */
    for (int f = 0; f < 16; f++) {
        sfm_align_params q = p;
        switch (f) {
        case 0: q.radius = 1; break;
        case 1: q.radius = -2147483647 - 1; break;
        case 2: q.radius = SFM_FEATURES_ALIGN_MAX_RADIUS + 1; break;
        case 3: q.max_iterations = 0; break;
        case 4: q.max_iterations = 101; break;
        case 5: q.max_shift = 0.0; break;
        case 6: q.max_shift = -1.0; break;
        case 7: q.max_shift = (double)INFINITY; break;
        case 8: q.min_zncc = -1.0000001; break;
        case 9: q.min_zncc = (double)NAN; break;
        case 10: q.min_eigen_ratio = -0.1; break;
        case 11: q.min_eigen_ratio = 1.5; break;
        case 12: q.min_eigen_ratio = (double)NAN; break;
        case 13: q.max_shift = (double)NAN; break;
        case 14: q.min_zncc = (double)INFINITY; break;
        default: q.max_iterations = -2147483647 - 1; break;
        }
        SFM_CHECK_MSG(align_hostile_call(t, "bad params", &ia, xs2, &ib, xs2, 2, &q) == SFM_E_ARGUMENT,
                      "params case %d accepted", f);
        tried++;
    }
    /* parameters at their limits are valid */
    {
        sfm_align_params q = p;
        q.radius = SFM_FEATURES_ALIGN_MAX_RADIUS, q.max_iterations = 100, q.max_shift = 1e300;
        q.min_zncc = -1.0, q.min_eigen_ratio = 0.0;
        SFM_CHECK(align_hostile_call(t, "loosest params", &ia, xs2, &ib, xs2, 2, &q) >= 0);
        q.radius = 2, q.max_iterations = 1, q.max_shift = 1e-300, q.min_zncc = 1.0, q.min_eigen_ratio = 1.0;
        SFM_CHECK(align_hostile_call(t, "tightest params", &ia, xs2, &ib, xs2, 2, &q) >= 0);
        tried += 2;
    }
    /* non-finite points in either array, first or last */
    const double bad_v[3] = {(double)NAN, (double)INFINITY, -(double)INFINITY};
    for (int k = 0; k < 3; k++)
        for (int at = 0; at < 4; at += 3) {
            double xb[4] = {80.0, 60.0, 40.0, 30.0};
            xb[at] = bad_v[k];
            SFM_CHECK_EQ_INT(align_hostile_call(t, "non-finite x", &ia, xs2, &ib, xb, 2, &p), SFM_E_NONFINITE);
            SFM_CHECK_EQ_INT(align_hostile_call(t, "non-finite x_ref", &ia, xb, &ib, xs2, 2, &p), SFM_E_NONFINITE);
            tried += 2;
        }
    /* a saturated image (all 255) and a two-level one: no structure to align on */
    memset(img_b, 255, sizeof img_b);
    SFM_CHECK_EQ_INT(align_hostile_call(t, "saturated", &ib, xs2, &ib, xs2, 2, &p), 0);
    for (int k = 0; k < W * H; k++)
        img_b[k] = (uint8_t)(k % W < W / 2 ? 0 : 255);
    const double edge_pt[2] = {W / 2 - 0.5, 60.0};
    SFM_CHECK_EQ_INT(align_hostile_call(t, "step edge", &ib, edge_pt, &ib, edge_pt, 1, &p), 0);
    tried += 2;
    SFM_TEST_LOG("%d hostile input sets", tried);
}
