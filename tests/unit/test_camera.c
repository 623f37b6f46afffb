/*
 * Camera models against truth: pixel values OpenCV 4 computed for the same
 * cameras and points (cv2.projectPoints, cv2.fisheye.projectPoints; the
 * figures are copied below), the pinhole written out by hand, bearings of
 * known points after project + unproject, Jacobians against central finite
 * differences, and distortion maps built to fold at a known radius.
 */
#include <float.h>
#include <string.h>

#include "sfm/sfm.h"
#include "sfm_test.h"

#define PI 3.14159265358979323846

static sfm_camera make_cam(int model, const double *dist, int nd)
{
    sfm_camera c;
    memset(&c, 0, sizeof c);
    c.model = model;
    c.fx = 500.0;
    c.fy = 480.0;
    c.cx = 320.0;
    c.cy = 240.0;
    for (int i = 0; i < nd; i++)
        c.dist[i] = dist[i];
    return c;
}

static const double BROWN[5] = {-0.28, 0.07, 1e-3, -5e-4, 0.01};
static const double FISH[4] = {-0.01, 0.02, -0.005, 0.001};

SFM_TEST(camera_matches_opencv_values)
{
    const double X[3][3] = {{0.3, -0.2, 1.5}, {-0.9, 0.7, 1.1}, {0.05, 0.02, 3.0}};
    /* cv2.projectPoints(X, 0, 0, K, BROWN) and cv2.fisheye.projectPoints(X,
     * 0, 0, K, FISH) with K = [500 0 320; 0 480 240; 0 0 1], OpenCV 4 */
    const double brown_px[6] = {418.34467189026066, 177.07789887912207, -5.2775960143213752,
                                483.18908987251143, 328.33247320871681, 243.19985531214724};
    const double fish_px[6] = {418.08958610844184, 177.22266489059723, 2.7210404015831955,
                               476.90162316681784, 328.33241161870205, 243.19964606158157};
    sfm_camera b = make_cam(SFM_CAMERA_BROWN, BROWN, 5), f = make_cam(SFM_CAMERA_FISHEYE, FISH, 4);
    for (int i = 0; i < 3; i++) {
        double px[2];
        SFM_CHECK_EQ_INT(sfm_camera_project(&b, X[i], px, NULL), SFM_OK);
        SFM_CHECK_NEAR(px[0], brown_px[2 * i], 1e-9);
        SFM_CHECK_NEAR(px[1], brown_px[2 * i + 1], 1e-9);
        SFM_CHECK_EQ_INT(sfm_camera_project(&f, X[i], px, NULL), SFM_OK);
        SFM_CHECK_NEAR(px[0], fish_px[2 * i], 1e-9);
        SFM_CHECK_NEAR(px[1], fish_px[2 * i + 1], 1e-9);
    }
}

SFM_TEST(camera_pinhole_by_hand)
{
    sfm_camera c = make_cam(SFM_CAMERA_PINHOLE, NULL, 0);
    c.dist[0] = (double)NAN; /* unused by the pinhole: ignored */
    const double X[3] = {1.0, 2.0, 4.0};
    double px[2], J[6], b[3];
    SFM_CHECK_EQ_INT(sfm_camera_project(&c, X, px, J), SFM_OK);
    SFM_CHECK_NEAR(px[0], 320.0 + 500.0 * 0.25, 1e-12);
    SFM_CHECK_NEAR(px[1], 240.0 + 480.0 * 0.5, 1e-12);
    const double Jt[6] = {500.0 / 4, 0.0, -500.0 * 1.0 / 16, 0.0, 480.0 / 4, -480.0 * 2.0 / 16};
    for (int k = 0; k < 6; k++)
        SFM_CHECK_NEAR(J[k], Jt[k], 1e-12);
    SFM_CHECK_EQ_INT(sfm_camera_unproject(&c, px, b), SFM_OK);
    const double n = sqrt(21.0);
    SFM_CHECK_NEAR(b[0], 1.0 / n, 1e-15);
    SFM_CHECK_NEAR(b[1], 2.0 / n, 1e-15);
    SFM_CHECK_NEAR(b[2], 4.0 / n, 1e-15);
    /* the principal point is the optical axis */
    const double pp[2] = {320.0, 240.0};
    SFM_CHECK_EQ_INT(sfm_camera_unproject(&c, pp, b), SFM_OK);
    SFM_CHECK(b[0] == 0.0 && b[1] == 0.0 && b[2] == 1.0);
}

/* Random point in front of the camera within a cone of half-angle max_th. */
static void random_point(sfm_test_ctx *t, double max_th, double X[3])
{
    const double th = sfm_test_uniform(t, 0.0, max_th), ph = sfm_test_uniform(t, -PI, PI);
    const double d = sfm_test_uniform(t, 0.2, 20.0);
    X[0] = d * sin(th) * cos(ph);
    X[1] = d * sin(th) * sin(ph);
    X[2] = d * cos(th);
}

static void round_trip_and_jacobian(sfm_test_ctx *t, const sfm_camera *c, double max_th, int iters)
{
    double worst_b = 0.0, worst_j = 0.0;
    for (int it = 0; it < iters; it++) {
        double X[3], px[2], J[6], b[3];
        random_point(t, max_th, X);
        if (it == 0) { /* exactly on the axis */
            X[0] = X[1] = 0.0;
            X[2] = 2.0;
        }
        SFM_CHECK_EQ_INT(sfm_camera_project(c, X, px, J), SFM_OK);
        int st = sfm_camera_unproject(c, px, b);
        SFM_CHECK_EQ_INT(st, SFM_OK);
        if (st != SFM_OK)
            return;
        const double n = sqrt(X[0] * X[0] + X[1] * X[1] + X[2] * X[2]);
        for (int k = 0; k < 3; k++)
            worst_b = fmax(worst_b, fabs(b[k] - X[k] / n));
        /* central differences, step relative to the distance */
        const double h = 1e-6 * n;
        double jmax = 0.0, dmax = 0.0;
        for (int j = 0; j < 3; j++) {
            double Xp[3] = {X[0], X[1], X[2]}, Xm[3] = {X[0], X[1], X[2]}, pp[2], pm[2];
            Xp[j] += h;
            Xm[j] -= h;
            SFM_CHECK_EQ_INT(sfm_camera_project(c, Xp, pp, NULL), SFM_OK);
            SFM_CHECK_EQ_INT(sfm_camera_project(c, Xm, pm, NULL), SFM_OK);
            for (int r = 0; r < 2; r++) {
                const double fd = (pp[r] - pm[r]) / (2.0 * h);
                dmax = fmax(dmax, fabs(fd - J[3 * r + j]));
                jmax = fmax(jmax, fabs(J[3 * r + j]));
            }
        }
        worst_j = fmax(worst_j, dmax / jmax);
    }
    SFM_CHECK(worst_b <= 1e-12);
    SFM_CHECK(worst_j <= 1e-6);
#ifndef SFM_TEST_REDUCED /* newlib's printf of a double needs a heap */
    SFM_TEST_LOG("model %d: worst bearing error %.2g, worst Jacobian vs central differences %.2g",
                 c->model, worst_b, worst_j);
#endif
}

SFM_TEST(camera_round_trip_and_jacobian)
{
    sfm_camera p = make_cam(SFM_CAMERA_PINHOLE, NULL, 0);
    sfm_camera b = make_cam(SFM_CAMERA_BROWN, BROWN, 5);
    sfm_camera f = make_cam(SFM_CAMERA_FISHEYE, FISH, 4);
    round_trip_and_jacobian(t, &p, 1.2, SFM_TEST_ITERS(2000));
    /* a lens calibrated with BROWN is only trusted over its field of view */
    round_trip_and_jacobian(t, &b, 0.75, SFM_TEST_ITERS(2000));
    /* the fisheye sees behind the camera plane, up to 170 degrees here */
    round_trip_and_jacobian(t, &f, 170.0 * PI / 180.0, SFM_TEST_ITERS(2000));
    /* a skewed principal point and unequal focal lengths change nothing */
    b.cx = 10.5;
    b.fy = -700.0; /* a flipped y axis is allowed */
    round_trip_and_jacobian(t, &b, 0.6, SFM_TEST_ITERS(300));
}

SFM_TEST(camera_fisheye_limits)
{
    sfm_camera f = make_cam(SFM_CAMERA_FISHEYE, FISH, 4);
    double px[2], J[6], b[3];
    /* on the axis: J = diag(f / Z) in the first two columns, zero third */
    const double ax[3] = {0.0, 0.0, 5.0};
    SFM_CHECK_EQ_INT(sfm_camera_project(&f, ax, px, J), SFM_OK);
    SFM_CHECK_NEAR(J[0], 100.0, 1e-12);
    SFM_CHECK_NEAR(J[4], 96.0, 1e-12);
    SFM_CHECK(J[1] == 0.0 && J[2] == 0.0 && J[3] == 0.0 && J[5] == 0.0);
    /* exactly 90 degrees (Z = 0) projects; theta_d = theta (1 + ...) */
    const double side[3] = {2.0, 0.0, 0.0};
    SFM_CHECK_EQ_INT(sfm_camera_project(&f, side, px, J), SFM_OK);
    const double th = PI / 2, t2 = th * th;
    const double td = th * (1 + t2 * (FISH[0] + t2 * (FISH[1] + t2 * (FISH[2] + t2 * FISH[3]))));
    SFM_CHECK_NEAR(px[0], 320.0 + 500.0 * td, 1e-9);
    SFM_CHECK_NEAR(px[1], 240.0, 1e-12);
    SFM_CHECK_EQ_INT(sfm_camera_unproject(&f, px, b), SFM_OK);
    SFM_CHECK_NEAR(b[0], 1.0, 1e-12);
    SFM_CHECK_NEAR(b[2], 0.0, 1e-12);
    /* the negative axis and the origin have no image */
    const double back[3] = {0.0, 0.0, -1.0}, origin[3] = {0.0, 0.0, 0.0};
    sfm_test_fill_canary(px, sizeof px);
    SFM_CHECK_EQ_INT(sfm_camera_project(&f, back, px, J), SFM_E_SINGULAR);
    SFM_CHECK_EQ_INT(sfm_camera_project(&f, origin, px, J), SFM_E_SINGULAR);
    SFM_CHECK(sfm_test_canary_intact(px, sizeof px));
    /* huge and tiny but finite points project like their direction */
    const double big[3] = {3e300, -1e300, 2e300}, tiny[3] = {3e-300, -1e-300, 2e-300};
    const double unit[3] = {3.0, -1.0, 2.0};
    double p1[2], p2[2], p3[2];
    SFM_CHECK_EQ_INT(sfm_camera_project(&f, big, p1, NULL), SFM_OK);
    SFM_CHECK_EQ_INT(sfm_camera_project(&f, tiny, p2, NULL), SFM_OK);
    SFM_CHECK_EQ_INT(sfm_camera_project(&f, unit, p3, NULL), SFM_OK);
    SFM_CHECK_NEAR(p1[0], p3[0], 1e-9);
    SFM_CHECK_NEAR(p2[1], p3[1], 1e-9);
}

SFM_TEST(camera_non_invertible_distortion_reported)
{
    double b[3];
    /* Brown, k1 = -0.5: r (1 - r^2 / 2) peaks at r = sqrt(2/3) with value
     * sqrt(2/3) * 2/3 = 0.5443; beyond that radius no pixel has a preimage */
    const double k[5] = {-0.5, 0.0, 0.0, 0.0, 0.0};
    sfm_camera c = make_cam(SFM_CAMERA_BROWN, k, 5);
    const double peak = sqrt(2.0 / 3.0) * 2.0 / 3.0;
    const double radii[4] = {0.3, 0.54, 0.55, 0.9};
    for (int i = 0; i < 4; i++) {
        const double px[2] = {320.0 + 500.0 * radii[i], 240.0};
        sfm_test_fill_canary(b, sizeof b);
        int st = sfm_camera_unproject(&c, px, b);
        if (radii[i] < peak) {
            SFM_CHECK_EQ_INT(st, SFM_OK);
            /* the preimage inside the fold, r (1 - r^2/2) = radius */
            const double r = b[0] / b[2];
            SFM_CHECK(r < sqrt(2.0 / 3.0));
            SFM_CHECK_NEAR(r * (1.0 - 0.5 * r * r), radii[i], 1e-10);
        } else {
            SFM_CHECK_EQ_INT(st, SFM_E_NO_CONVERGENCE);
            SFM_CHECK(sfm_test_canary_intact(b, sizeof b));
        }
    }
    /* fisheye, k1 = -0.3: theta (1 - 0.3 theta^2) peaks at theta = 1/sqrt(0.9) */
    const double kf[4] = {-0.3, 0.0, 0.0, 0.0};
    sfm_camera f = make_cam(SFM_CAMERA_FISHEYE, kf, 4);
    const double tp = 1.0 / sqrt(0.9), fpeak = tp * (1.0 - 0.3 * tp * tp);
    const double fr[4] = {0.2, 0.7, 0.71, 1.5};
    for (int i = 0; i < 4; i++) {
        const double px[2] = {320.0, 240.0 + 480.0 * fr[i]};
        sfm_test_fill_canary(b, sizeof b);
        int st = sfm_camera_unproject(&f, px, b);
        if (fr[i] < fpeak) {
            SFM_CHECK_EQ_INT(st, SFM_OK);
            const double th = acos(b[2]);
            SFM_CHECK(th < tp);
            SFM_CHECK_NEAR(th * (1.0 - 0.3 * th * th), fr[i], 1e-10);
        } else {
            SFM_CHECK_EQ_INT(st, SFM_E_NO_CONVERGENCE);
            SFM_CHECK(sfm_test_canary_intact(b, sizeof b));
        }
    }
    /* strong tangential terms fold the map too: never a silent wrong answer.
     * Every pixel that does unproject must reproject onto itself. */
    const double kt[5] = {-0.4, 0.1, 0.2, -0.15, 0.0};
    sfm_camera tc = make_cam(SFM_CAMERA_BROWN, kt, 5);
    int ok = 0, refused = 0;
    for (int i = 0; i < SFM_TEST_ITERS(2000); i++) {
        const double px[2] = {sfm_test_uniform(t, -600.0, 1240.0),
                              sfm_test_uniform(t, -600.0, 1080.0)};
        int st = sfm_camera_unproject(&tc, px, b);
        SFM_CHECK(st == SFM_OK || st == SFM_E_NO_CONVERGENCE);
        if (st != SFM_OK) {
            refused++;
            continue;
        }
        ok++;
        double back[2];
        SFM_CHECK_EQ_INT(sfm_camera_project(&tc, b, back, NULL), SFM_OK);
        SFM_CHECK_NEAR(back[0], px[0], 1e-7);
        SFM_CHECK_NEAR(back[1], px[1], 1e-7);
    }
    SFM_CHECK(ok > 0 && refused > 0);
    SFM_TEST_LOG("strong tangential distortion: %d pixels unprojected, %d refused", ok, refused);
}

SFM_TEST(camera_batch_forms)
{
    sfm_camera f = make_cam(SFM_CAMERA_FISHEYE, FISH, 4);
    enum { N = 16 };
    double X[3 * N], px[2 * N], b[3 * N];
    for (int i = 0; i < N; i++)
        random_point(t, 1.3, X + 3 * i);
    SFM_CHECK_EQ_INT(sfm_camera_project_many(&f, X, N, px), SFM_OK);
    SFM_CHECK_EQ_INT(sfm_camera_unproject_many(&f, px, N, b), SFM_OK);
    for (int i = 0; i < N; i++) {
        double p1[2], b1[3];
        SFM_CHECK_EQ_INT(sfm_camera_project(&f, X + 3 * i, p1, NULL), SFM_OK);
        SFM_CHECK(p1[0] == px[2 * i] && p1[1] == px[2 * i + 1]);
        SFM_CHECK_EQ_INT(sfm_camera_unproject(&f, p1, b1), SFM_OK);
        SFM_CHECK(b1[0] == b[3 * i] && b1[1] == b[3 * i + 1] && b1[2] == b[3 * i + 2]);
    }
    SFM_CHECK_EQ_INT(sfm_camera_project_many(&f, X, 0, px), SFM_OK);
    /* a failure stops the batch: entries before it written, after it not */
    sfm_camera p = make_cam(SFM_CAMERA_PINHOLE, NULL, 0);
    for (int i = 0; i < N; i++)
        X[3 * i + 2] = fabs(X[3 * i + 2]) + 1.0;
    X[3 * 5 + 2] = -1.0;
    sfm_test_fill_canary(px, sizeof px);
    SFM_CHECK_EQ_INT(sfm_camera_project_many(&p, X, N, px), SFM_E_SINGULAR);
    SFM_CHECK(!sfm_test_canary_intact(px, 10 * sizeof(double)));
    SFM_CHECK(sfm_test_canary_intact(px + 10, (2 * N - 10) * sizeof(double)));
    double bad_px[2 * N];
    for (int i = 0; i < 2 * N; i++)
        bad_px[i] = 300.0 + i;
    bad_px[7] = (double)NAN;
    sfm_test_fill_canary(b, sizeof b);
    SFM_CHECK_EQ_INT(sfm_camera_unproject_many(&p, bad_px, N, b), SFM_E_NONFINITE);
    SFM_CHECK(sfm_test_canary_intact(b + 9, (3 * N - 9) * sizeof(double)));
}

SFM_TEST(camera_contracts)
{
    sfm_camera c = make_cam(SFM_CAMERA_BROWN, BROWN, 5);
    const double X[3] = {0.1, 0.2, 2.0}, px[2] = {300.0, 200.0};
    double o2[2], o3[3], J[6];
    sfm_test_fill_canary(o2, sizeof o2);
    sfm_test_fill_canary(o3, sizeof o3);
    sfm_test_fill_canary(J, sizeof J);
    SFM_CHECK_EQ_INT(sfm_camera_validate(NULL), SFM_E_ARGUMENT);
    SFM_CHECK_EQ_INT(sfm_camera_validate(&c), SFM_OK);
    SFM_CHECK_EQ_INT(sfm_camera_project(NULL, X, o2, J), SFM_E_ARGUMENT);
    SFM_CHECK_EQ_INT(sfm_camera_project(&c, NULL, o2, J), SFM_E_ARGUMENT);
    SFM_CHECK_EQ_INT(sfm_camera_project(&c, X, NULL, J), SFM_E_ARGUMENT);
    SFM_CHECK_EQ_INT(sfm_camera_unproject(NULL, px, o3), SFM_E_ARGUMENT);
    SFM_CHECK_EQ_INT(sfm_camera_unproject(&c, NULL, o3), SFM_E_ARGUMENT);
    SFM_CHECK_EQ_INT(sfm_camera_unproject(&c, px, NULL), SFM_E_ARGUMENT);
    SFM_CHECK_EQ_INT(sfm_camera_project_many(&c, X, -1, o2), SFM_E_ARGUMENT);
    SFM_CHECK_EQ_INT(sfm_camera_project_many(&c, NULL, 1, o2), SFM_E_ARGUMENT);
    SFM_CHECK_EQ_INT(sfm_camera_unproject_many(&c, px, -1, o3), SFM_E_ARGUMENT);
    SFM_CHECK_EQ_INT(sfm_camera_unproject_many(&c, px, 1, NULL), SFM_E_ARGUMENT);
    sfm_camera bad = c;
    bad.model = 7;
    SFM_CHECK_EQ_INT(sfm_camera_validate(&bad), SFM_E_ARGUMENT);
    SFM_CHECK_EQ_INT(sfm_camera_project(&bad, X, o2, J), SFM_E_ARGUMENT);
    SFM_CHECK_EQ_INT(sfm_camera_unproject(&bad, px, o3), SFM_E_ARGUMENT);
    bad = c;
    bad.fy = 0.0;
    SFM_CHECK_EQ_INT(sfm_camera_project(&bad, X, o2, J), SFM_E_ARGUMENT);
    SFM_CHECK_EQ_INT(sfm_camera_unproject(&bad, px, o3), SFM_E_ARGUMENT);
    const double nonfinite[3] = {(double)NAN, (double)HUGE_VAL, -(double)HUGE_VAL};
    for (int k = 0; k < 3; k++) {
        double *fields[4] = {&bad.fx, &bad.cy, &bad.dist[2], &bad.dist[4]};
        for (int fi = 0; fi < 4; fi++) {
            bad = c;
            fields[fi][0] = nonfinite[k];
            SFM_CHECK_EQ_INT(sfm_camera_validate(&bad), SFM_E_NONFINITE);
            SFM_CHECK_EQ_INT(sfm_camera_project(&bad, X, o2, J), SFM_E_NONFINITE);
            SFM_CHECK_EQ_INT(sfm_camera_unproject(&bad, px, o3), SFM_E_NONFINITE);
        }
        /* dist[4] is unused by the fisheye model: ignored */
        bad = make_cam(SFM_CAMERA_FISHEYE, FISH, 4);
        bad.dist[4] = nonfinite[k];
        SFM_CHECK_EQ_INT(sfm_camera_validate(&bad), SFM_OK);
        for (int j = 0; j < 3; j++) {
            double Xb[3] = {X[0], X[1], X[2]};
            Xb[j] = nonfinite[k];
            SFM_CHECK_EQ_INT(sfm_camera_project(&c, Xb, o2, J), SFM_E_NONFINITE);
        }
        for (int j = 0; j < 2; j++) {
            double pb[2] = {px[0], px[1]};
            pb[j] = nonfinite[k];
            SFM_CHECK_EQ_INT(sfm_camera_unproject(&c, pb, o3), SFM_E_NONFINITE);
        }
    }
    /* behind or on the camera plane: not projectable for pinhole and Brown */
    const double behind[3] = {0.1, 0.2, -2.0}, plane[3] = {0.1, 0.2, 0.0};
    sfm_camera p = make_cam(SFM_CAMERA_PINHOLE, NULL, 0);
    SFM_CHECK_EQ_INT(sfm_camera_project(&c, behind, o2, J), SFM_E_SINGULAR);
    SFM_CHECK_EQ_INT(sfm_camera_project(&c, plane, o2, J), SFM_E_SINGULAR);
    SFM_CHECK_EQ_INT(sfm_camera_project(&p, behind, o2, J), SFM_E_SINGULAR);
    /* so close to the plane that the pixel overflows */
    const double grazing[3] = {1.0, 0.0, 1e-320};
    SFM_CHECK_EQ_INT(sfm_camera_project(&p, grazing, o2, J), SFM_E_SINGULAR);
    SFM_CHECK(sfm_test_canary_intact(o2, sizeof o2));
    SFM_CHECK(sfm_test_canary_intact(o3, sizeof o3));
    SFM_CHECK(sfm_test_canary_intact(J, sizeof J));
    /* J may be NULL */
    SFM_CHECK_EQ_INT(sfm_camera_project(&c, X, o2, NULL), SFM_OK);
}
