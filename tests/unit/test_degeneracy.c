/* Degenerate inputs the estimators and the trifocal algebra used to accept
 * with a confident answer (issue 11, "what was seen"): each must now be a
 * status, with nothing written. Small sizes: these run on the emulated
 * Cortex-M7 too. */
#include <math.h>
#include <string.h>

#include "ransac_scene.h"
#include "sfm/sfm.h"
#include "sfm_test.h"

#define ND 120
#define NT 80 /* triplets */

static double X3[3 * ND], Q[3][2 * ND];
static unsigned char DWS[1 << 19];

/* Scene classes. */
enum { LINE, CLUSTER, PLANE, GENERAL };

/* Points of a class in camera 1's frame, in front of all three cameras. */
static void points(sfm_test_ctx *t, int cls, int n, double *X)
{
    double a[3] = {sfm_test_uniform(t, -1, 1), sfm_test_uniform(t, -0.7, 0.7), 6.0}, d[3];
    sfm_test_random_unit(t, d);
    for (int i = 0; i < n; i++) {
        double *p = X + 3 * i;
        if (cls == LINE) {
            double s = sfm_test_uniform(t, -2.5, 2.5);
            for (int k = 0; k < 3; k++)
                p[k] = a[k] + s * d[k] * (k == 2 ? 0.3 : 1.0);
        } else if (cls == CLUSTER) {
            double u[3];
            sfm_test_random_unit(t, u);
            double r = 0.1 * sfm_test_uniform(t, 0, 1);
            for (int k = 0; k < 3; k++)
                p[k] = a[k] + r * u[k];
        } else {
            double x = sfm_test_uniform(t, -0.6, 0.6), y = sfm_test_uniform(t, -0.45, 0.45);
            double z = cls == PLANE ? 6.0 / (1.0 + 0.2 * x - 0.1 * y) : sfm_test_uniform(t, 4, 10);
            p[0] = x * z;
            p[1] = y * z;
            p[2] = z;
        }
    }
}

/* Camera v: centre (v, 0.1 v, 0) rotated 3 v degrees about y. */
static void camera(int v, double R[9], double tr[3])
{
    double aa[3] = {0, 3.0 * v * 3.14159265358979323846 / 180.0, 0};
    sfm_rot_from_axis_angle(aa, R);
    double c[3] = {(double)v, 0.1 * v, 0};
    scene_matvec(R, c, tr);
    for (int k = 0; k < 3; k++)
        tr[k] = -tr[k];
}

/* Pixels of the n points in views 0..views-1 with noise sigma; a share
 * `out` of the points get random pixels in the views after the first. */
static void render(sfm_test_ctx *t, int n, int views, double sigma, double out)
{
    for (int v = 0; v < views; v++) {
        double R[9], tr[3];
        camera(v, R, tr);
        for (int i = 0; i < n; i++) {
            double x[3];
            scene_matvec(R, X3 + 3 * i, x);
            for (int k = 0; k < 3; k++)
                x[k] += tr[k];
            Q[v][2 * i] = 500.0 * x[0] / x[2] + 320.0 + sfm_test_normal(t, sigma);
            Q[v][2 * i + 1] = 500.0 * x[1] / x[2] + 240.0 + sfm_test_normal(t, sigma);
        }
    }
    for (int i = 0; i < n; i++)
        if (sfm_test_uniform(t, 0, 1) < out)
            for (int v = 1; v < views; v++) {
                Q[v][2 * i] = sfm_test_uniform(t, 0, SCENE_W);
                Q[v][2 * i + 1] = sfm_test_uniform(t, 0, SCENE_H);
            }
}

static void random_pixels(sfm_test_ctx *t, int n, int views)
{
    for (int v = 0; v < views; v++)
        for (int i = 0; i < n; i++) {
            Q[v][2 * i] = sfm_test_uniform(t, 0, SCENE_W);
            Q[v][2 * i + 1] = sfm_test_uniform(t, 0, SCENE_H);
        }
}

/* Relative and upright pose, nothing written on failure. */
static int relpose(sfm_test_ctx *t, int upright, int n)
{
    sfm_camera cam = scene_pinhole();
    sfm_pose pose;
    memset(&pose, 0x5a, sizeof pose);
    sfm_pose before = pose;
    sfm_mat3 E;
    sfm_ransac_stats st;
    int r;
    if (upright) {
        double d1[3] = {0, 1, 0}, R[9], tr[3], d2[3];
        camera(1, R, tr);
        scene_matvec(R, d1, d2);
        r = sfm_ransac_relpose_upright(Q[0], Q[1], n, &cam, &cam, d1, d2, NULL, &pose, &E, NULL,
                                       &st, DWS, sizeof DWS);
    } else {
        r = sfm_ransac_relpose(Q[0], Q[1], n, &cam, &cam, NULL, &pose, &E, NULL, &st, DWS,
                               sizeof DWS);
    }
    if (r < 0)
        SFM_CHECK(memcmp(&pose, &before, sizeof pose) == 0);
    return r;
}

SFM_TEST(degenerate_relpose_on_a_3d_line_and_a_cluster)
{
    for (int it = 0; it < 4; it++)
        for (int up = 0; up < 2; up++) {
            points(t, LINE, ND, X3);
            render(t, ND, 2, 0.3, 0.0);
            SFM_CHECK_EQ_INT(relpose(t, up, ND), SFM_E_DEGENERATE);
            points(t, CLUSTER, ND, X3);
            render(t, ND, 2, 0.3, 0.2);
            SFM_CHECK_EQ_INT(relpose(t, up, ND), SFM_E_DEGENERATE);
        }
}

SFM_TEST(degenerate_relpose_general_scene_has_covariance)
{
    sfm_camera cam = scene_pinhole();
    for (int it = 0; it < 4; it++) {
        points(t, GENERAL, ND, X3);
        render(t, ND, 2, 0.3, 0.2);
        sfm_pose pose;
        sfm_ransac_stats st;
        /* not asked: no covariance */
        int r = sfm_ransac_relpose(Q[0], Q[1], ND, &cam, &cam, NULL, &pose, NULL, NULL, &st, DWS,
                                   sizeof DWS);
        SFM_CHECK(r >= 50);
        SFM_CHECK_EQ_INT(st.cov_dim, 0);
        sfm_ransac_options o;
        sfm_ransac_default_options(&o);
        o.want_covariance = 1;
        r = sfm_ransac_relpose(Q[0], Q[1], ND, &cam, &cam, &o, &pose, NULL, NULL, &st, DWS,
                               sizeof DWS);
        SFM_CHECK(r >= 50);
        SFM_CHECK_EQ_INT(st.cov_dim, 6);
        double R[9], tr[3];
        camera(1, R, tr);
        double er = scene_rot_err_deg(pose.R, R) * 3.14159265358979323846 / 180.0;
        double sd = sqrt(st.covariance[0] + st.covariance[7] + st.covariance[14]);
        /* the truth within a few standard deviations, and those small */
        SFM_CHECK(sd > 0.0 && sd < 0.01);
        SFM_CHECK(er < 6.0 * sd + 1e-4);
        /* t's block lies in the tangent plane of the unit t: rank 2 */
        double Ct[3] = {0, 0, 0};
        for (int r2 = 0; r2 < 3; r2++)
            for (int c = 0; c < 3; c++)
                Ct[r2] += st.covariance[6 * (3 + r2) + 3 + c] * pose.t[c];
        SFM_CHECK(fabs(Ct[0]) + fabs(Ct[1]) + fabs(Ct[2]) < 1e-9 + 1e-6 * st.covariance[21]);
    }
}

SFM_TEST(degenerate_homography_on_a_line_and_a_cluster)
{
    sfm_mat3 H = {{0}};
    for (int it = 0; it < 4; it++) {
        points(t, LINE, ND, X3);
        render(t, ND, 2, 0.3, 0.0);
        SFM_CHECK_EQ_INT(sfm_ransac_homography(Q[0], Q[1], ND, NULL, NULL, NULL, &H, NULL, NULL,
                                               DWS, sizeof DWS),
                         SFM_E_DEGENERATE);
        points(t, CLUSTER, ND, X3);
        render(t, ND, 2, 0.3, 0.2);
        SFM_CHECK_EQ_INT(sfm_ransac_homography(Q[0], Q[1], ND, NULL, NULL, NULL, &H, NULL, NULL,
                                               DWS, sizeof DWS),
                         SFM_E_DEGENERATE);
        SFM_CHECK(H.m[0] == 0.0 && H.m[8] == 0.0);
    }
}

SFM_TEST(degenerate_random_matches_are_no_model)
{
    sfm_camera cam = scene_pinhole();
    for (int it = 0; it < SFM_TEST_ITERS(3); it++) { /* each call runs to the iteration cap */
        random_pixels(t, ND, 3);
        SFM_CHECK_EQ_INT(relpose(t, 0, ND), SFM_E_NO_MODEL);
        SFM_CHECK_EQ_INT(relpose(t, 1, ND), SFM_E_NO_MODEL);
        sfm_pose pose;
        points(t, GENERAL, ND, X3);
        SFM_CHECK_EQ_INT(sfm_ransac_abspose(Q[1], X3, ND, &cam, NULL, &pose, NULL, NULL, DWS,
                                            sizeof DWS),
                         SFM_E_NO_MODEL);
        sfm_mat3 M;
        SFM_CHECK_EQ_INT(sfm_ransac_fundamental(Q[0], Q[1], ND, NULL, NULL, NULL, &M, NULL, NULL,
                                                DWS, sizeof DWS),
                         SFM_E_NO_MODEL);
        SFM_CHECK_EQ_INT(sfm_ransac_homography(Q[0], Q[1], ND, NULL, NULL, NULL, &M, NULL, NULL,
                                               DWS, sizeof DWS),
                         SFM_E_NO_MODEL);
        double T[27];
        SFM_CHECK(sfm_ransac_trifocal_workspace_size(NT) <= sizeof DWS);
        int r = sfm_ransac_trifocal(Q[0], Q[1], Q[2], NT, NULL, T, NULL, NULL, NULL, DWS,
                                    sizeof DWS);
        SFM_CHECK(r == SFM_E_NO_MODEL || r == SFM_E_DEGENERATE);
    }
}

SFM_TEST(degenerate_trifocal_ransac_and_three_view_pose)
{
    sfm_camera cam = scene_pinhole();
    SFM_CHECK(sfm_recon_three_view_pose_workspace_size(NT) <= sizeof DWS);
    const int classes[3] = {LINE, CLUSTER, PLANE};
    for (int c = 0; c < 3; c++) {
        points(t, classes[c], NT, X3);
        render(t, NT, 3, 0.3, classes[c] == LINE ? 0.0 : 0.2);
        double T[27];
        SFM_CHECK_EQ_INT(sfm_ransac_trifocal(Q[0], Q[1], Q[2], NT, NULL, T, NULL, NULL, NULL, DWS,
                                             sizeof DWS),
                         SFM_E_DEGENERATE);
        if (classes[c] != PLANE) {
            sfm_pose poses[3];
            SFM_CHECK_EQ_INT(sfm_recon_three_view_pose(Q[0], Q[1], Q[2], NT, &cam, &cam, &cam,
                                                       NULL, poses, NULL, NULL, DWS, sizeof DWS),
                             SFM_E_DEGENERATE);
        }
    }
}

/* Pixels of points X (n) in camera v, noise-free. */
static void exact(int v, const double *X, int n, double *px)
{
    double R[9], tr[3];
    camera(v, R, tr);
    for (int i = 0; i < n; i++) {
        double x[3];
        scene_matvec(R, X + 3 * i, x);
        px[2 * i] = 500.0 * (x[0] + tr[0]) / (x[2] + tr[2]) + 320.0;
        px[2 * i + 1] = 500.0 * (x[1] + tr[1]) / (x[2] + tr[2]) + 240.0;
    }
}

SFM_TEST(degenerate_trifocal_7pt_collinear_and_coplanar_samples)
{
    static unsigned char ws7[64 * 1024];
    SFM_CHECK(sfm_trifocal_7pt_workspace_size() <= sizeof ws7);
    for (int c = 0; c < 3; c++) {
        int cls = c == 0 ? LINE : (c == 1 ? PLANE : GENERAL);
        points(t, cls, 7, X3);
        double a[14], b[14], d[14], T[27];
        exact(0, X3, 7, a);
        exact(1, X3, 7, b);
        exact(2, X3, 7, d);
        int r = sfm_trifocal_7pt(a, b, d, 7, T, ws7, sizeof ws7);
        SFM_CHECK_EQ_INT(r, cls == GENERAL ? SFM_OK : SFM_E_SINGULAR);
    }
}

SFM_TEST(degenerate_trifocal_algebra)
{
    double T[27], e2[3], e3[3], P2[12], P3[12];
    memset(T, 0, sizeof T);
    SFM_CHECK_EQ_INT(sfm_trifocal_epipoles(T, e2, e3), SFM_E_SINGULAR);
    SFM_CHECK_EQ_INT(sfm_trifocal_cameras(T, P2, P3), SFM_E_SINGULAR);
    double P[3][12];
    for (int v = 0; v < 3; v++) {
        double R[9], tr[3];
        camera(v, R, tr);
        for (int r = 0; r < 3; r++) {
            for (int c = 0; c < 3; c++)
                P[v][4 * r + c] = R[3 * r + c];
            P[v][4 * r + 3] = tr[r];
        }
    }
    SFM_CHECK_EQ_INT(sfm_trifocal_from_cameras(P[0], P[1], P[2], T), SFM_OK);
    double Tk[27];
    memcpy(Tk, T, sizeof T);
    SFM_CHECK_EQ_INT(sfm_trifocal_from_cameras(P[0], P[0], P[2], T), SFM_E_SINGULAR);
    SFM_CHECK_EQ_INT(sfm_trifocal_from_cameras(P[0], P[1], P[1], T), SFM_E_SINGULAR);
    SFM_CHECK(memcmp(T, Tk, sizeof T) == 0);
}

SFM_TEST(degenerate_essential_rank_one_and_scaled_bearings)
{
    double u[3] = {0.3, -0.5, 0.8}, v[3] = {0.6, 0.2, -0.1};
    sfm_mat3 E;
    for (int r = 0; r < 3; r++)
        for (int c = 0; c < 3; c++)
            E.m[3 * r + c] = u[r] * v[c];
    sfm_pose poses[4];
    SFM_CHECK_EQ_INT(sfm_essential_to_poses(&E, NULL, NULL, 0, poses, NULL), 0);
    /* 5-point: only directions matter */
    points(t, GENERAL, 5, X3);
    double R[9], tr[3], b1[15], b2[15];
    camera(1, R, tr);
    for (int i = 0; i < 5; i++) {
        double x[3];
        scene_matvec(R, X3 + 3 * i, x);
        for (int k = 0; k < 3; k++) {
            b1[3 * i + k] = X3[3 * i + k];
            b2[3 * i + k] = x[k] + tr[k];
        }
    }
    sfm_mat3 Es[SFM_RELPOSE_5PT_MAX_SOLUTIONS];
    int n0 = sfm_relpose_5pt(b1, b2, Es);
    SFM_CHECK(n0 > 0);
    const double scales[2] = {1e100, 1e-100};
    for (int s = 0; s < 2; s++) {
        double c1[15], c2[15];
        for (int k = 0; k < 15; k++) {
            c1[k] = b1[k] * scales[s];
            c2[k] = b2[k] * scales[1 - s];
        }
        SFM_CHECK_EQ_INT(sfm_relpose_5pt(c1, c2, Es), n0);
    }
}
