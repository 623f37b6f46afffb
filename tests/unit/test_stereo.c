/*
 * Stereo: rectification against the geometry it must produce (rows aligned,
 * disparity = f B / Z), the remap against exact bilinear interpolation, the
 * matchers against images with known disparities, the contracts.
 */
#include <math.h>
#include <stdlib.h>
#include <string.h>

#include "sfm/sfm_rotation.h"
#include "sfm/sfm_stereo.h"
#include "sfm_test.h"

#define IW 96
#define IH 64
#define ND 16

static uint8_t g_left[IW * IH], g_right[IW * IH], g_tex[IH][IW + 64];
static float g_disp[IW * IH];
static unsigned char g_ws[700000];
static int32_t g_map[2 * 160 * 120];

static sfm_camera pinhole(double f, double cx, double cy)
{
    sfm_camera c;
    memset(&c, 0, sizeof c);
    c.model = SFM_CAMERA_PINHOLE;
    c.fx = c.fy = f;
    c.cx = cx;
    c.cy = cy;
    return c;
}

static void matvec(const double *M, const double *x, double *y)
{
    for (int r = 0; r < 3; r++)
        y[r] = M[3 * r] * x[0] + M[3 * r + 1] * x[1] + M[3 * r + 2] * x[2];
}

/* A random rig: camera 2 mostly to the right of camera 1, turned by up to
 * 8 degrees. */
static void random_rig(sfm_test_ctx *t, double R[9], double tv[3], double *B)
{
    double axis[3], aa[3];
    sfm_test_random_unit(t, axis);
    double ang = sfm_test_uniform(t, 0.0, 8.0) * 3.14159265358979 / 180.0;
    for (int k = 0; k < 3; k++)
        aa[k] = axis[k] * ang;
    sfm_rot_from_axis_angle(aa, R);
    *B = sfm_test_uniform(t, 0.1, 1.0);
    double c2[3] = {*B, sfm_test_uniform(t, -0.15, 0.15) * *B, sfm_test_uniform(t, -0.2, 0.2) * *B};
    double n = sqrt(c2[0] * c2[0] + c2[1] * c2[1] + c2[2] * c2[2]);
    for (int k = 0; k < 3; k++)
        c2[k] *= *B / n;
    matvec(R, c2, tv);
    for (int k = 0; k < 3; k++)
        tv[k] = -tv[k]; /* t = -R c2 */
}

/* Matches of random points seen by both cameras (pixels), with their depth
 * in camera 1; returns how many were written. */
static int random_matches(sfm_test_ctx *t, const sfm_camera *c1, const sfm_camera *c2,
                          const double *R, const double *tv, int w, int h, double *x1, double *x2,
                          double *X1, int n)
{
    int k = 0;
    for (int tries = 0; tries < 50 * n && k < n; tries++) {
        double px[2] = {sfm_test_uniform(t, 0, w - 1), sfm_test_uniform(t, 0, h - 1)}, b[3];
        if (sfm_camera_unproject(c1, px, b) != SFM_OK)
            continue;
        double z = sfm_test_uniform(t, 2.0, 12.0);
        double X[3] = {b[0] / b[2] * z, b[1] / b[2] * z, z}, Y[3], q[2];
        matvec(R, X, Y);
        for (int i = 0; i < 3; i++)
            Y[i] += tv[i];
        if (sfm_camera_project(c2, Y, q, NULL) != SFM_OK || q[0] < 0 || q[0] > w - 1 || q[1] < 0 ||
            q[1] > h - 1)
            continue;
        x1[2 * k] = px[0];
        x1[2 * k + 1] = px[1];
        x2[2 * k] = q[0];
        x2[2 * k + 1] = q[1];
        if (X1)
            memcpy(X1 + 3 * k, X, sizeof X);
        k++;
    }
    return k;
}

SFM_TEST(stereo_rectify_aligns_rows_and_gives_depth)
{
    double worst_dy = 0.0, worst_z = 0.0;
    for (int it = 0; it < SFM_TEST_ITERS(40); it++) {
        sfm_camera c1 = pinhole(sfm_test_uniform(t, 400, 700), 319.5 + sfm_test_normal(t, 5), 239.5);
        sfm_camera c2 = pinhole(sfm_test_uniform(t, 400, 700), 319.5, 239.5 + sfm_test_normal(t, 5));
        if (it % 2) { /* Brown distortion on both */
            c1.model = c2.model = SFM_CAMERA_BROWN;
            c1.dist[0] = -0.2;
            c1.dist[1] = 0.05;
            c2.dist[0] = -0.15;
            c2.dist[2] = 0.001;
        }
        double R[9], tv[3], B;
        random_rig(t, R, tv, &B);
        sfm_stereo_rectification r;
        int st = sfm_stereo_rectify(&c1, &c2, 640, 480, R, tv, it % 3 == 0 ? 0.0 : -1.0, 0, 0, &r);
        SFM_CHECK_EQ_INT(st, SFM_OK);
        if (st != SFM_OK)
            continue;
        SFM_CHECK_NEAR(r.baseline, B, 1e-12);
        SFM_CHECK_NEAR(r.K1[0], r.K2[0], 0.0);
        SFM_CHECK_NEAR(r.K1[5], r.K2[5], 0.0);
        double x1[2 * 60], x2[2 * 60], X1[3 * 60], med, mx;
        int n = random_matches(t, &c1, &c2, R, tv, 640, 480, x1, x2, X1, 60);
        SFM_CHECK(n >= 30);
        SFM_CHECK(sfm_stereo_rectification_error(&c1, &c2, &r, NULL, NULL, x1, x2, n, &med, &mx) == n);
        if (mx > worst_dy)
            worst_dy = mx;
        /* disparity = f B / Z_rect + (cx1 - cx2) */
        for (int i = 0; i < n; i++) {
            double b1[3], b2[3], p1[3], p2[3];
            sfm_camera_unproject(&c1, x1 + 2 * i, b1);
            sfm_camera_unproject(&c2, x2 + 2 * i, b2);
            matvec(r.R1, b1, p1);
            matvec(r.R2, b2, p2);
            double u1 = r.K1[0] * p1[0] / p1[2] + r.K1[2], u2 = r.K2[0] * p2[0] / p2[2] + r.K2[2];
            double zr[3];
            matvec(r.R1, X1 + 3 * i, zr);
            double d_expect = r.K1[0] * B / zr[2] + (r.K1[2] - r.K2[2]);
            double e = fabs((u1 - u2) - d_expect);
            if (e > worst_z)
                worst_z = e;
        }
    }
    SFM_TEST_LOG("max |v1 - v2| %.3g px, max disparity error %.3g px", worst_dy, worst_z);
    SFM_CHECK(worst_dy < 1e-6);
    SFM_CHECK(worst_z < 1e-6);
}

SFM_TEST(stereo_rectify_camera_left_turns_views_but_keeps_image1_left)
{
    sfm_camera c = pinhole(500, 319.5, 239.5);
    double R[9] = {1, 0, 0, 0, 1, 0, 0, 0, 1}, tv[3] = {0.3, 0, 0}; /* c2 = (-0.3, 0, 0) */
    sfm_stereo_rectification r;
    SFM_CHECK_EQ_INT(sfm_stereo_rectify(&c, &c, 640, 480, R, tv, -1.0, 0, 0, &r), SFM_OK);
    SFM_CHECK_NEAR(r.R1[0], -1.0, 1e-12); /* x axis towards camera 2 */
    SFM_CHECK_NEAR(r.R1[4], -1.0, 1e-12); /* turned half a turn about z */
    double X[3] = {0.4, -0.2, 5.0}, p1[2], p2[2], Y[3] = {0.7, -0.2, 5.0};
    sfm_camera_project(&c, X, p1, NULL);
    sfm_camera_project(&c, Y, p2, NULL);
    double a[3], b[3];
    matvec(r.R1, X, a);
    matvec(r.R2, Y, b);
    double d = (r.K1[0] * a[0] / a[2] + r.K1[2]) - (r.K2[0] * b[0] / b[2] + r.K2[2]);
    SFM_CHECK_NEAR(d - (r.K1[2] - r.K2[2]), 500.0 * 0.3 / 5.0, 1e-9);
}

SFM_TEST(stereo_rectify_contract)
{
    sfm_camera c = pinhole(500, 319.5, 239.5);
    double I[9] = {1, 0, 0, 0, 1, 0, 0, 0, 1}, tv[3] = {-0.2, 0, 0};
    sfm_stereo_rectification r;
    sfm_test_fill_canary(&r, sizeof r);
    SFM_CHECK_EQ_INT(sfm_stereo_rectify(NULL, &c, 640, 480, I, tv, 0, 0, 0, &r), SFM_E_ARGUMENT);
    SFM_CHECK_EQ_INT(sfm_stereo_rectify(&c, &c, 640, 480, I, tv, 2.0, 0, 0, &r), SFM_E_ARGUMENT);
    SFM_CHECK_EQ_INT(sfm_stereo_rectify(&c, &c, 4, 480, I, tv, 0, 0, 0, &r), SFM_E_ARGUMENT);
    double Rbad[9] = {1, 0, 0, 0, 2, 0, 0, 0, 1};
    SFM_CHECK_EQ_INT(sfm_stereo_rectify(&c, &c, 640, 480, Rbad, tv, 0, 0, 0, &r), SFM_E_ARGUMENT);
    double tn[3] = {(double)NAN, 0, 0};
    SFM_CHECK_EQ_INT(sfm_stereo_rectify(&c, &c, 640, 480, I, tn, 0, 0, 0, &r), SFM_E_NONFINITE);
    double t0[3] = {0, 0, 0};
    SFM_CHECK_EQ_INT(sfm_stereo_rectify(&c, &c, 640, 480, I, t0, 0, 0, 0, &r), SFM_E_SINGULAR);
    double tz[3] = {0, 0, -0.5}; /* forward motion: epipoles inside the images */
    SFM_CHECK_EQ_INT(sfm_stereo_rectify(&c, &c, 640, 480, I, tz, 0, 0, 0, &r), SFM_E_SINGULAR);
    SFM_CHECK(sfm_test_canary_intact(&r, sizeof r));
}

SFM_TEST(stereo_rectify_identity_rig_maps_pixels_to_themselves)
{
    sfm_camera c = pinhole(120, 79.5, 59.5);
    double I[9] = {1, 0, 0, 0, 1, 0, 0, 0, 1}, tv[3] = {-0.2, 0, 0};
    sfm_stereo_rectification r;
    SFM_CHECK_EQ_INT(sfm_stereo_rectify(&c, &c, 160, 120, I, tv, -1.0, 0, 0, &r), SFM_OK);
    SFM_CHECK_EQ_INT(sfm_stereo_rectify_map(&c, 160, 120, &r, 1, g_map, sizeof g_map / sizeof g_map[0]), SFM_OK);
    int exact = 0;
    for (int v = 0; v < 120; v++)
        for (int u = 0; u < 160; u++)
            exact += g_map[2 * (v * 160 + u)] == u * SFM_STEREO_MAP_ONE &&
                     g_map[2 * (v * 160 + u) + 1] == v * SFM_STEREO_MAP_ONE;
    SFM_CHECK_EQ_INT(exact, 160 * 120);
    SFM_CHECK_EQ_INT(sfm_stereo_rectify_map(&c, 160, 120, &r, 3, g_map, sizeof g_map / sizeof g_map[0]), SFM_E_ARGUMENT);
    SFM_CHECK_EQ_INT(sfm_stereo_rectify_map(&c, 160, 120, &r, 1, g_map, 10), SFM_E_ARGUMENT);
}

SFM_TEST(stereo_remap_is_bilinear)
{
    for (int i = 0; i < IW * IH; i++)
        g_left[i] = (uint8_t)sfm_test_uniform(t, 0, 256);
    /* rectified = source - (0.5, 0.25): the map reads source (u + 0.5, v + 0.25) */
    sfm_mat3 H = {{1, 0, -0.5, 0, 1, -0.25, 0, 0, 1}};
    SFM_CHECK_EQ_INT(sfm_stereo_homography_map(&H, IW, IH, IW, IH, g_map, 2 * IW * IH), SFM_OK);
    SFM_CHECK_EQ_INT(sfm_stereo_remap(g_left, IW, IH, IW, g_map, IW, IH, 7, g_right, IW), SFM_OK);
    int worst = 0, filled = 0;
    for (int v = 0; v < IH; v++)
        for (int u = 0; u < IW; u++) {
            int got = g_right[v * IW + u];
            if (u == IW - 1 || v == IH - 1) { /* footprint leaves the image */
                filled += got == 7;
                continue;
            }
            const uint8_t *p = g_left + v * IW + u;
            double e = 0.75 * (0.5 * p[0] + 0.5 * p[1]) + 0.25 * (0.5 * p[IW] + 0.5 * p[IW + 1]);
            int d = abs(got - (int)floor(e + 0.5));
            if (d > worst)
                worst = d;
        }
    SFM_CHECK(worst <= 1);
    SFM_CHECK_EQ_INT(filled, IW + IH - 1);
    SFM_CHECK_EQ_INT(sfm_stereo_remap(NULL, IW, IH, IW, g_map, IW, IH, 0, g_right, IW), SFM_E_ARGUMENT);
    SFM_CHECK_EQ_INT(sfm_stereo_remap(g_left, IW, IH, IW - 1, g_map, IW, IH, 0, g_right, IW), SFM_E_ARGUMENT);
}

SFM_TEST(stereo_uncalibrated_rectification_aligns_rows)
{
    double worst = 0.0;
    for (int it = 0; it < SFM_TEST_ITERS(30); it++) {
        sfm_camera c1 = pinhole(sfm_test_uniform(t, 400, 700), 319.5, 239.5);
        sfm_camera c2 = pinhole(sfm_test_uniform(t, 400, 700), 322.0, 236.0);
        double R[9], tv[3], B;
        random_rig(t, R, tv, &B);
        /* F = K2^-T [t]_x R K1^-1 */
        double K1i[9] = {1 / c1.fx, 0, -c1.cx / c1.fx, 0, 1 / c1.fy, -c1.cy / c1.fy, 0, 0, 1};
        double K2i[9] = {1 / c2.fx, 0, -c2.cx / c2.fx, 0, 1 / c2.fy, -c2.cy / c2.fy, 0, 0, 1};
        double Tx[9] = {0, -tv[2], tv[1], tv[2], 0, -tv[0], -tv[1], tv[0], 0}, E[9], A[9];
        sfm_mat3 F;
        for (int r = 0; r < 3; r++)
            for (int c = 0; c < 3; c++) {
                E[3 * r + c] = 0;
                for (int k = 0; k < 3; k++)
                    E[3 * r + c] += Tx[3 * r + k] * R[3 * k + c];
            }
        for (int r = 0; r < 3; r++)
            for (int c = 0; c < 3; c++) {
                A[3 * r + c] = 0;
                for (int k = 0; k < 3; k++)
                    A[3 * r + c] += E[3 * r + k] * K1i[3 * k + c];
            }
        for (int r = 0; r < 3; r++)
            for (int c = 0; c < 3; c++) {
                F.m[3 * r + c] = 0;
                for (int k = 0; k < 3; k++)
                    F.m[3 * r + c] += K2i[3 * k + r] * A[3 * k + c];
            }
        double x1[2 * 80], x2[2 * 80], med, mx;
        sfm_mat3 H1, H2;
        int n = random_matches(t, &c1, &c2, R, tv, 640, 480, x1, x2, NULL, 80);
        SFM_CHECK_EQ_INT(sfm_stereo_rectify_uncalibrated(&F, x1, x2, n, 640, 480, &H1, &H2), SFM_OK);
        SFM_CHECK(sfm_stereo_rectification_error(NULL, NULL, NULL, &H1, &H2, x1, x2, n, &med, &mx) == n);
        if (mx > worst)
            worst = mx;
        /* image 1 on the left: every match has a disparity >= 0 */
        for (int i = 0; i < n; i++) {
            double p[3] = {x1[2 * i], x1[2 * i + 1], 1}, q[3] = {x2[2 * i], x2[2 * i + 1], 1}, a[3], b[3];
            matvec(H1.m, p, a);
            matvec(H2.m, q, b);
            SFM_CHECK(a[0] / a[2] - b[0] / b[2] > -1e-6);
        }
    }
    SFM_TEST_LOG("max |v1 - v2| %.3g px", worst);
    SFM_CHECK(worst < 1e-6);
    /* forward motion: the epipole is inside the image */
    sfm_mat3 F = {{0, -1, 240, 1, 0, -320, -240, 320, 0}}, H1, H2;
    double x1[16], x2[16];
    for (int i = 0; i < 16; i++)
        x1[i] = x2[i] = 100 + 7 * i;
    SFM_CHECK_EQ_INT(sfm_stereo_rectify_uncalibrated(&F, x1, x2, 8, 640, 480, &H1, &H2), SFM_E_SINGULAR);
}

/* Left and right images of a scene with disparity d_top in the upper half
 * and d_bottom in the lower half: right(x) = left(x + d). */
static void make_pair(sfm_test_ctx *t, int d_top, int d_bottom)
{
    for (int y = 0; y < IH; y++)
        for (int x = 0; x < IW + 64; x++)
            g_tex[y][x] = (uint8_t)sfm_test_uniform(t, 0, 256);
    /* a little smoothing: real images are band-limited */
    for (int y = 0; y < IH; y++)
        for (int x = 0; x < IW + 63; x++)
            g_tex[y][x] = (uint8_t)((g_tex[y][x] + g_tex[y][x + 1] + 1) / 2);
    for (int y = 0; y < IH; y++) {
        int d = y < IH / 2 ? d_top : d_bottom;
        for (int x = 0; x < IW; x++) {
            g_left[y * IW + x] = g_tex[y][x + 32];
            int n = (int)sfm_test_normal(t, 1.0);
            int v = g_tex[y][x + 32 + d] + n;
            g_right[y * IW + x] = (uint8_t)(v < 0 ? 0 : (v > 255 ? 255 : v));
        }
    }
}

/* Share of pixels away from the left band and the step rows that are valid
 * and within 0.5 of the truth, and the share of valid ones that are not. */
static void score(int d_top, int d_bottom, double *good, double *bad)
{
    int n = 0, g = 0, v = 0, b = 0;
    for (int y = 2; y < IH - 2; y++) {
        if (y >= IH / 2 - 4 && y < IH / 2 + 4)
            continue;
        int d = y < IH / 2 ? d_top : d_bottom;
        for (int x = ND + 4; x < IW - 4; x++) {
            float e = g_disp[y * IW + x];
            n++;
            if (!isfinite(e))
                continue;
            v++;
            if (fabs((double)e - d) <= 0.5)
                g++;
            else
                b++;
        }
    }
    *good = (double)g / n;
    *bad = v ? (double)b / v : 0.0;
}

SFM_TEST(stereo_sgm_recovers_known_disparities)
{
    make_pair(t, 3, 9);
    int paths[3] = {SFM_STEREO_PATHS_5, SFM_STEREO_PATHS_4, SFM_STEREO_PATHS_8};
    for (int k = 0; k < 3; k++) {
        sfm_stereo_sgm_options o;
        sfm_stereo_sgm_default_options(&o);
        o.num_disparities = ND;
        o.paths = paths[k];
        size_t n = sfm_stereo_sgm_workspace_size(IW, IH, &o);
        SFM_CHECK(n > 0 && n <= sizeof g_ws);
        int valid = sfm_stereo_sgm(g_left, g_right, IW, IH, IW, &o, g_disp, g_ws, n);
        SFM_CHECK(valid > 0);
        double good, bad;
        score(3, 9, &good, &bad);
        SFM_TEST_LOG("%d paths: %.3f good, %.4f of valid wrong", paths[k], good, bad);
        SFM_CHECK(good > 0.95);
        SFM_CHECK(bad < 0.01);
    }
}

SFM_TEST(stereo_block_recovers_known_disparities)
{
    make_pair(t, 4, 10);
    sfm_stereo_block_options o;
    sfm_stereo_block_default_options(&o);
    o.num_disparities = ND;
    size_t n = sfm_stereo_block_workspace_size(IW, IH, &o);
    SFM_CHECK(n > 0 && n <= sizeof g_ws);
    SFM_CHECK(sfm_stereo_block(g_left, g_right, IW, IH, IW, &o, g_disp, g_ws, n) > 0);
    double good, bad;
    score(4, 10, &good, &bad);
    SFM_TEST_LOG("block: %.3f good, %.4f of valid wrong", good, bad);
    SFM_CHECK(good > 0.90);
    SFM_CHECK(bad < 0.01);
    /* a flat image has no texture: nothing is matched */
    memset(g_left, 100, sizeof g_left);
    memset(g_right, 100, sizeof g_right);
    SFM_CHECK_EQ_INT(sfm_stereo_block(g_left, g_right, IW, IH, IW, &o, g_disp, g_ws, n), 0);
}

/* The multiple-window matcher against its definition computed directly,
 * pixel by pixel (sfm_stereo.h, libsfm/stereo/block.c): absolute
 * differences truncated at 63 (63 where the right pixel is outside the
 * image), rows and columns replicated at the borders, the centre window
 * plus the two smallest corner windows, the texture flag, winner-take-all
 * with the first index among ties, the border quarter, the uniqueness
 * margin, the right image's own winner on the same costs and the parabola.
 * Random sizes, ranges of either sign and options; every output bit equal. */
#define RW 44
#define RH 26
#define RD 16
static int16_t g_refw[RH][RW][RD]; /* window sums */

static int clampi_t(int v, int lo, int hi)
{
    return v < lo ? lo : (v > hi ? hi : v);
}

static int ref_ad(const uint8_t *L, const uint8_t *R, int w, int x, int y, int dmin, int d)
{
    int xr = x - dmin - d;
    if (xr < 0 || xr >= w)
        return 63;
    int a = L[y * w + x] - R[y * w + xr];
    a = a < 0 ? -a : a;
    return a < 63 ? a : 63;
}

static int ref_cost(int w, int h, int r, int x, int y, int d)
{
    int c[4], k = 0;
    for (int dy = -2 * r; dy <= 2 * r; dy += 4 * r)
        for (int dx = -2 * r; dx <= 2 * r; dx += 4 * r)
            c[k++] = g_refw[clampi_t(y + dy, 0, h - 1)][clampi_t(x + dx, 0, w - 1)][d];
    for (int i = 0; i < 2; i++) /* the two smallest first */
        for (int j = 3; j > i; j--)
            if (c[j] < c[j - 1]) {
                int tmp = c[j];
                c[j] = c[j - 1];
                c[j - 1] = tmp;
            }
    return g_refw[y][x][d] + c[0] + c[1];
}

static int ref_block(const uint8_t *L, const uint8_t *R, int w, int h,
                     const sfm_stereo_block_options *o, float *out)
{
    const int r = o->radius, D = o->num_disparities, dmin = o->min_disparity;
    for (int y = 0; y < h; y++)
        for (int x = 0; x < w; x++)
            for (int d = 0; d < D; d++) {
                int sum = 0;
                for (int yy = y - r; yy <= y + r; yy++)
                    for (int xx = x - r; xx <= x + r; xx++)
                        sum += ref_ad(L, R, w, clampi_t(xx, 0, w - 1), clampi_t(yy, 0, h - 1), dmin, d);
                g_refw[y][x][d] = (int16_t)sum;
            }
    int valid = 0;
    for (int y = 0; y < h; y++)
        for (int x = 0; x < w; x++) {
            float *px = out + y * w + x;
            *px = NAN;
            int g = 0;
            for (int yy = y - r; yy <= y + r; yy++)
                for (int xx = x - r; xx <= x + r; xx++) {
                    const uint8_t *row = L + clampi_t(yy, 0, h - 1) * w;
                    int xc = clampi_t(xx, 0, w - 1);
                    int a = row[clampi_t(xc + 1, 0, w - 1)] - row[clampi_t(xc - 1, 0, w - 1)];
                    g += a < 0 ? -a : a;
                }
            if (o->texture > 0 && g * 16 < o->texture * (2 * r + 1) * (2 * r + 1) * 2)
                continue;
            int dlo = x - dmin - (w - 1) > 0 ? x - dmin - (w - 1) : 0;
            int dhi = x - dmin < D - 1 ? x - dmin : D - 1;
            if (dlo > dhi)
                continue;
            int bd = dlo, bc = ref_cost(w, h, r, x, y, dlo), second = 0x7fff;
            for (int d = dlo + 1; d <= dhi; d++) {
                int c = ref_cost(w, h, r, x, y, d);
                if (c < bc) {
                    bc = c;
                    bd = d;
                }
            }
            for (int d = dlo; d <= dhi; d++) {
                int c = ref_cost(w, h, r, x, y, d);
                if ((d < bd - 1 || d > bd + 1) && c < second)
                    second = c;
            }
            if ((dlo > 0 && bd - dlo < D / 4) || (dhi < D - 1 && dhi - bd < D / 4))
                continue;
            if (o->uniqueness > 0 && second != 0x7fff && second * 100 <= bc * (100 + o->uniqueness))
                continue;
            if (o->lr_max_diff >= 0) {
                int xr = x - dmin - bd, rd = -1, rc = 0;
                for (int d = 0; d < D; d++) {
                    int xl = xr + dmin + d;
                    if (xl < 0 || xl >= w)
                        continue;
                    int c = ref_cost(w, h, r, xl, y, d);
                    if (rd < 0 || c < rc) {
                        rc = c;
                        rd = d;
                    }
                }
                if (rd < 0 || abs(rd - bd) > o->lr_max_diff)
                    continue;
            }
            float dv = (float)(dmin + bd);
            if (o->subpixel && bd > dlo && bd < dhi) {
                int c0 = ref_cost(w, h, r, x, y, bd - 1), c2 = ref_cost(w, h, r, x, y, bd + 1);
                int den = c0 + c2 - 2 * bc;
                if (den > 0)
                    dv += (float)(c0 - c2) / (float)(2 * den);
            }
            *px = dv;
            valid++;
        }
    return valid;
}

SFM_TEST(stereo_block_equals_its_definition)
{
    static float ref[RW * RH];
    int cases = 0, differ = 0;
    long valid = 0, pixels = 0;
    for (int it = 0; it < SFM_TEST_ITERS(60); it++) {
        const int w = 16 + (int)sfm_test_uniform(t, 0, RW - 16 + 1 - 1e-9);
        sfm_stereo_block_options o;
        sfm_stereo_block_default_options(&o);
        o.radius = 1 + (int)sfm_test_uniform(t, 0, 5 - 1e-9);
        const int hmin = 4 * o.radius + 1 > 16 ? 4 * o.radius + 1 : 16;
        if (hmin > RH)
            o.radius = 1;
        const int h = (hmin > RH ? 16 : hmin) + (int)sfm_test_uniform(t, 0, 4 - 1e-9);
        o.num_disparities = sfm_test_uniform(t, 0, 1) < 0.5 ? 8 : 16;
        o.min_disparity = (int)sfm_test_uniform(t, -6, 7 - 1e-9);
        o.uniqueness = it % 3 == 0 ? 0 : (it % 3 == 1 ? 15 : 40);
        o.lr_max_diff = it % 4 - 1;
        o.texture = it % 5 == 0 ? 0 : (it % 5 < 3 ? 8 : 40);
        o.subpixel = it % 2;
        /* texture shifted by a disparity that steps across the image, with
         * noise, and a flat patch */
        int d0 = o.min_disparity + 1 + (int)sfm_test_uniform(t, 0, o.num_disparities - 2);
        for (int y = 0; y < h; y++)
            for (int x = 0; x < w + 64; x++)
                g_tex[y][x] = (uint8_t)sfm_test_uniform(t, 0, 256);
        for (int y = 0; y < h; y++)
            for (int x = 0; x < w; x++) {
                int flat = x > w / 2 && x < w / 2 + 6 && y > h / 3 && y < h / 3 + 5;
                int dt = d0 + (x > w / 3 ? 2 : 0);
                g_left[y * w + x] = flat ? 90 : g_tex[y][x + 32];
                int v = (flat ? 90 : g_tex[y][x + 32 - dt]) + (int)sfm_test_normal(t, 2.0);
                g_right[y * w + x] = (uint8_t)(v < 0 ? 0 : (v > 255 ? 255 : v));
            }
        size_t n = sfm_stereo_block_workspace_size(w, h, &o);
        if (n == 0 || n > sizeof g_ws)
            continue; /* a range wider than this image */
        int nv = sfm_stereo_block(g_left, g_right, w, h, w, &o, g_disp, g_ws, n);
        int nr = ref_block(g_left, g_right, w, h, &o, ref);
        cases++;
        valid += nr;
        pixels += w * h;
        int same = nv == nr;
        for (int i = 0; i < w * h; i++)
            if (!(isnan(g_disp[i]) && isnan(ref[i])) && memcmp(&g_disp[i], &ref[i], sizeof(float)) != 0)
                same = 0;
        differ += !same;
    }
    SFM_TEST_LOG("%d cases (%.2f of the pixels valid), %d differ from the definition", cases,
                 (double)valid / (double)(pixels > 0 ? pixels : 1), differ);
    SFM_CHECK(cases >= SFM_TEST_ITERS(60) / 2);
    SFM_CHECK_EQ_INT(differ, 0);
}

SFM_TEST(stereo_matchers_contract)
{
    make_pair(t, 2, 2);
    sfm_stereo_sgm_options o;
    sfm_stereo_sgm_default_options(&o);
    o.num_disparities = ND;
    size_t n = sfm_stereo_sgm_workspace_size(IW, IH, &o);
    sfm_test_fill_canary(g_disp, sizeof g_disp);
    SFM_CHECK_EQ_INT(sfm_stereo_sgm(g_left, g_right, IW, IH, IW, &o, g_disp, g_ws, n - 1), SFM_E_WORKSPACE);
    SFM_CHECK_EQ_INT(sfm_stereo_sgm(NULL, g_right, IW, IH, IW, &o, g_disp, g_ws, n), SFM_E_ARGUMENT);
    SFM_CHECK_EQ_INT(sfm_stereo_sgm(g_left, g_right, IW, IH, IW - 1, &o, g_disp, g_ws, n), SFM_E_ARGUMENT);
    o.num_disparities = 12;
    SFM_CHECK(sfm_stereo_sgm_workspace_size(IW, IH, &o) == 0);
    SFM_CHECK_EQ_INT(sfm_stereo_sgm(g_left, g_right, IW, IH, IW, &o, g_disp, g_ws, n), SFM_E_ARGUMENT);
    o.num_disparities = 128; /* wider than the image */
    SFM_CHECK_EQ_INT(sfm_stereo_sgm(g_left, g_right, IW, IH, IW, &o, g_disp, g_ws, sizeof g_ws), SFM_E_ARGUMENT);
    o.num_disparities = ND;
    o.p2 = o.p1;
    SFM_CHECK_EQ_INT(sfm_stereo_sgm(g_left, g_right, IW, IH, IW, &o, g_disp, g_ws, n), SFM_E_ARGUMENT);
    sfm_stereo_block_options b;
    sfm_stereo_block_default_options(&b);
    b.num_disparities = ND;
    size_t nb = sfm_stereo_block_workspace_size(IW, IH, &b);
    SFM_CHECK_EQ_INT(sfm_stereo_block(g_left, g_right, IW, IH, IW, &b, g_disp, g_ws, nb - 1), SFM_E_WORKSPACE);
    b.radius = 9;
    SFM_CHECK_EQ_INT(sfm_stereo_block(g_left, g_right, IW, IH, IW, &b, g_disp, g_ws, sizeof g_ws), SFM_E_ARGUMENT);
    SFM_CHECK(sfm_test_canary_intact(g_disp, sizeof g_disp));
}

SFM_TEST(stereo_points_at_the_depth_of_their_disparity)
{
    sfm_camera c = pinhole(100, 47.5, 31.5);
    double I[9] = {1, 0, 0, 0, 1, 0, 0, 0, 1}, tv[3] = {-0.5, 0, 0};
    sfm_stereo_rectification r;
    SFM_CHECK_EQ_INT(sfm_stereo_rectify(&c, &c, IW, IH, I, tv, -1.0, 0, 0, &r), SFM_OK);
    for (int i = 0; i < IW * IH; i++)
        g_disp[i] = (i % 7 == 0) ? NAN : 10.0f;
    static double pts[3 * IW * IH];
    static int32_t idx[IW * IH];
    int n = sfm_stereo_points(g_disp, IW, IH, &r, 0.0, NULL, NULL, 0);
    SFM_CHECK(n > 0);
    SFM_CHECK_EQ_INT(sfm_stereo_points(g_disp, IW, IH, &r, 0.0, pts, idx, n - 1), SFM_E_CAPACITY);
    SFM_CHECK_EQ_INT(sfm_stereo_points(g_disp, IW, IH, &r, 0.0, pts, idx, n), n);
    double worst = 0.0;
    for (int k = 0; k < n; k++) {
        int u = idx[k] % IW, v = idx[k] / IW;
        double z = 100.0 * 0.5 / 10.0;
        double e = fabs(pts[3 * k + 2] - z) + fabs(pts[3 * k] - (u - 47.5) * z / 100.0) +
                   fabs(pts[3 * k + 1] - (v - 31.5) * z / 100.0);
        if (e > worst)
            worst = e;
    }
    SFM_CHECK(worst < 1e-9);
    static float depth[IW * IH];
    SFM_CHECK_EQ_INT(sfm_stereo_depth(g_disp, IW, IH, &r, depth), n);
    SFM_CHECK_NEAR((double)depth[1], 5.0, 1e-6);
    SFM_CHECK(isnan(depth[0]));
}
