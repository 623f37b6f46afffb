/* Synthetic two-view and absolute-pose scenes with known truth, shared by
 * the RANSAC estimator tests (unit and native). Pixels of a 640 x 480 camera
 * K = [[500,0,320],[0,500,240],[0,0,1]] unless the caller sets another. */
#ifndef SFM_TEST_RANSAC_SCENE_H
#define SFM_TEST_RANSAC_SCENE_H

#include <math.h>
#include <string.h>

#include "sfm/sfm.h"
#include "sfm_test.h"

#define SCENE_W 640.0
#define SCENE_H 480.0

static inline sfm_camera scene_pinhole(void)
{
    sfm_camera c;
    memset(&c, 0, sizeof c);
    c.model = SFM_CAMERA_PINHOLE;
    c.fx = c.fy = 500.0;
    c.cx = 320.0;
    c.cy = 240.0;
    return c;
}

static inline void scene_matvec(const double *M, const double *x, double *y)
{
    for (int r = 0; r < 3; r++)
        y[r] = M[3 * r] * x[0] + M[3 * r + 1] * x[1] + M[3 * r + 2] * x[2];
}

/* Rotation by a random axis and an angle uniform in [0, max_deg]. */
static inline void scene_rotation(sfm_test_ctx *t, double max_deg, double R[9])
{
    double axis[3];
    sfm_test_random_unit(t, axis);
    double ang = sfm_test_uniform(t, 0.0, max_deg) * 3.14159265358979323846 / 180.0;
    double aa[3] = {axis[0] * ang, axis[1] * ang, axis[2] * ang};
    sfm_rot_from_axis_angle(aa, R);
}

static inline double scene_rot_err_deg(const double *Ra, const double *Rb)
{
    double tr = 0.0;
    for (int r = 0; r < 3; r++)
        for (int c = 0; c < 3; c++)
            tr += Ra[3 * r + c] * Rb[3 * r + c];
    double c = (tr - 1.0) / 2.0;
    c = c > 1.0 ? 1.0 : (c < -1.0 ? -1.0 : c);
    return acos(c) * 180.0 / 3.14159265358979323846;
}

static inline double scene_dir_err_deg(const double *a, const double *b)
{
    double la = sqrt(a[0] * a[0] + a[1] * a[1] + a[2] * a[2]);
    double lb = sqrt(b[0] * b[0] + b[1] * b[1] + b[2] * b[2]);
    double c = (a[0] * b[0] + a[1] * b[1] + a[2] * b[2]) / (la * lb);
    c = c > 1.0 ? 1.0 : (c < -1.0 ? -1.0 : c);
    return acos(c) * 180.0 / 3.14159265358979323846;
}

/*
 * Two views: x2 = R x1 + t. mode 0: general scene (depth 2..10); mode 1: all
 * points on one plane; mode 2: pure rotation (t = 0, reported t is zero).
 * Outliers replace the second pixel by a uniform one; truth[i] = 1 for inliers.
 * cam may have distortion (pixels go through sfm_camera_project).
 */
static inline void scene_twoview(sfm_test_ctx *t, const sfm_camera *cam, int n, double outliers,
                                 double sigma, int mode, double *p1, double *p2,
                                 unsigned char *truth, double R[9], double tr[3])
{
    double plane_n[3], plane_d = 5.0;
    sfm_test_random_unit(t, plane_n);
    if (plane_n[2] < 0) {
        plane_n[0] = -plane_n[0];
        plane_n[1] = -plane_n[1];
        plane_n[2] = -plane_n[2];
    }
    plane_n[2] += 1.5; /* facing the camera */
    double l = sqrt(plane_n[0] * plane_n[0] + plane_n[1] * plane_n[1] + plane_n[2] * plane_n[2]);
    for (int k = 0; k < 3; k++)
        plane_n[k] /= l;
    for (;;) {
        scene_rotation(t, 20.0, R);
        if (mode == 2) {
            tr[0] = tr[1] = tr[2] = 0.0;
        } else {
            sfm_test_random_unit(t, tr);
        }
        int got = 0, tries = 0;
        while (got < n && tries < 50 * n) {
            tries++;
            double px[2] = {sfm_test_uniform(t, 0, SCENE_W), sfm_test_uniform(t, 0, SCENE_H)};
            double b[3];
            if (sfm_camera_unproject(cam, px, b) != SFM_OK)
                continue;
            double depth;
            if (mode == 1) {
                double nb = plane_n[0] * b[0] + plane_n[1] * b[1] + plane_n[2] * b[2];
                if (nb < 0.2)
                    continue;
                depth = plane_d / nb;
            } else {
                depth = sfm_test_uniform(t, 2.0, 10.0);
            }
            double X1[3] = {b[0] * depth, b[1] * depth, b[2] * depth}, X2[3], q[2];
            scene_matvec(R, X1, X2);
            X2[0] += tr[0];
            X2[1] += tr[1];
            X2[2] += tr[2];
            if (X2[2] < 0.1 || sfm_camera_project(cam, X2, q, NULL) != SFM_OK)
                continue;
            if (q[0] < 0 || q[0] >= SCENE_W || q[1] < 0 || q[1] >= SCENE_H)
                continue;
            p1[2 * got] = px[0] + sfm_test_normal(t, sigma);
            p1[2 * got + 1] = px[1] + sfm_test_normal(t, sigma);
            p2[2 * got] = q[0] + sfm_test_normal(t, sigma);
            p2[2 * got + 1] = q[1] + sfm_test_normal(t, sigma);
            got++;
        }
        if (got == n)
            break;
    }
    for (int i = 0; i < n; i++) {
        truth[i] = sfm_test_uniform(t, 0, 1) >= outliers;
        if (!truth[i]) {
            p2[2 * i] = sfm_test_uniform(t, 0, SCENE_W);
            p2[2 * i + 1] = sfm_test_uniform(t, 0, SCENE_H);
        }
    }
}

/* Absolute pose: world points X seen at x_cam = R X + t. */
static inline void scene_abspose(sfm_test_ctx *t, const sfm_camera *cam, int n, double outliers,
                                 double sigma, double *p, double *X, unsigned char *truth,
                                 double R[9], double tr[3])
{
    scene_rotation(t, 180.0, R);
    for (int k = 0; k < 3; k++)
        tr[k] = sfm_test_normal(t, 1.0);
    for (int i = 0; i < n; i++) {
        double px[2] = {sfm_test_uniform(t, 0, SCENE_W), sfm_test_uniform(t, 0, SCENE_H)}, b[3];
        sfm_camera_unproject(cam, px, b);
        double depth = sfm_test_uniform(t, 2.0, 10.0);
        double Xc[3] = {b[0] * depth - tr[0], b[1] * depth - tr[1], b[2] * depth - tr[2]};
        /* X = R^T (Xc - t) */
        for (int r = 0; r < 3; r++)
            X[3 * i + r] = R[r] * Xc[0] + R[3 + r] * Xc[1] + R[6 + r] * Xc[2];
        truth[i] = sfm_test_uniform(t, 0, 1) >= outliers;
        if (truth[i]) {
            p[2 * i] = px[0] + sfm_test_normal(t, sigma);
            p[2 * i + 1] = px[1] + sfm_test_normal(t, sigma);
        } else {
            p[2 * i] = sfm_test_uniform(t, 0, SCENE_W);
            p[2 * i + 1] = sfm_test_uniform(t, 0, SCENE_H);
        }
    }
}

static inline double scene_median(double *v, int n)
{
    for (int i = 1; i < n; i++) {
        double x = v[i];
        int j = i - 1;
        while (j >= 0 && v[j] > x) {
            v[j + 1] = v[j];
            j--;
        }
        v[j + 1] = x;
    }
    return n % 2 ? v[n / 2] : 0.5 * (v[n / 2 - 1] + v[n / 2]);
}

#endif
