/*
 * Synthetic bundle adjustment scenes for the tests: cameras on an arc looking
 * at a cloud of points around the origin, with a known truth. The projection
 * and rotations here are written out independently of the library.
 */
#ifndef SFM_TEST_BA_SCENE_H
#define SFM_TEST_BA_SCENE_H

#include <math.h>
#include <string.h>

#include "sfm/sfm_ba.h"
#include "sfm_test.h"

typedef struct ba_scene {
    int m, n, nobs;
    double *R, *t, *K, *X;       /* truth */
    double *R0, *t0, *K0, *X0;   /* start (perturbed) */
    int *oc, *op;
    double *xy;
} ba_scene;

static void bas_rodrigues(const double w[3], double R[9])
{
    double th = sqrt(w[0] * w[0] + w[1] * w[1] + w[2] * w[2]);
    double a, b;
    if (th < 1e-6) {
        a = 1.0 - th * th / 6.0;
        b = 0.5 - th * th / 24.0;
    } else {
        a = sin(th) / th;
        b = (1.0 - cos(th)) / (th * th);
    }
    double x = w[0], y = w[1], z = w[2];
    R[0] = 1 - b * (y * y + z * z); R[1] = -a * z + b * x * y;    R[2] = a * y + b * x * z;
    R[3] = a * z + b * x * y;       R[4] = 1 - b * (x * x + z * z); R[5] = -a * x + b * y * z;
    R[6] = -a * y + b * x * z;      R[7] = a * x + b * y * z;     R[8] = 1 - b * (x * x + y * y);
}

static void bas_matmul3(const double *A, const double *B, double *C)
{
    double T[9];
    for (int r = 0; r < 3; r++)
        for (int c = 0; c < 3; c++)
            T[3 * r + c] = A[3 * r] * B[c] + A[3 * r + 1] * B[3 + c] + A[3 * r + 2] * B[6 + c];
    memcpy(C, T, sizeof T);
}

/* Pixel of X in camera (R, t, K = {fx, fy, cx, cy, k1, k2}); 0 if behind. */
static int bas_project(const double *R, const double *t, const double *K, const double *X, double uv[2])
{
    double xc[3];
    for (int r = 0; r < 3; r++)
        xc[r] = R[3 * r] * X[0] + R[3 * r + 1] * X[1] + R[3 * r + 2] * X[2] + t[r];
    if (xc[2] <= 0.1)
        return 0;
    double xn = xc[0] / xc[2], yn = xc[1] / xc[2], r2 = xn * xn + yn * yn;
    double d = 1 + K[4] * r2 + K[5] * r2 * r2;
    uv[0] = K[0] * d * xn + K[2];
    uv[1] = K[1] * d * yn + K[3];
    return 1;
}

/* Camera i looks at the origin from distance 6 on an arc of +-40 degrees. */
static void bas_camera(sfm_test_ctx *t, int i, int m, double *R, double *tt)
{
    double ang = (m > 1 ? -0.7 + 1.4 * i / (m - 1) : 0.0);
    double C[3] = {6.0 * sin(ang), sfm_test_uniform(t, -0.5, 0.5), -6.0 * cos(ang)};
    /* z axis towards the origin, y roughly down */
    double z[3] = {-C[0], -C[1], -C[2]};
    double nz = sqrt(z[0] * z[0] + z[1] * z[1] + z[2] * z[2]);
    for (int k = 0; k < 3; k++)
        z[k] /= nz;
    double down[3] = {0, 1, 0};
    double x[3] = {down[1] * z[2] - down[2] * z[1], down[2] * z[0] - down[0] * z[2], down[0] * z[1] - down[1] * z[0]};
    double nx = sqrt(x[0] * x[0] + x[1] * x[1] + x[2] * x[2]);
    for (int k = 0; k < 3; k++)
        x[k] /= nx;
    double y[3] = {z[1] * x[2] - z[2] * x[1], z[2] * x[0] - z[0] * x[2], z[0] * x[1] - z[1] * x[0]};
    for (int k = 0; k < 3; k++) {
        R[k] = x[k];
        R[3 + k] = y[k];
        R[6 + k] = z[k];
    }
    for (int r = 0; r < 3; r++)
        tt[r] = -(R[3 * r] * C[0] + R[3 * r + 1] * C[1] + R[3 * r + 2] * C[2]);
}

/* Fills s (arrays supplied by the caller, sized m, n, m*n) with a scene in
 * which every point is seen by every camera; noise sigma px on observations;
 * start perturbed by rot_deg degrees, trans (units), pt (units). */
static void bas_make(sfm_test_ctx *t, ba_scene *s, int m, int n, double sigma, double rot_deg,
                     double trans, double pt)
{
    s->m = m;
    s->n = n;
    for (int i = 0; i < m; i++) {
        bas_camera(t, i, m, s->R + 9 * i, s->t + 3 * i);
        double *K = s->K + 6 * i;
        K[0] = 800.0; K[1] = 800.0; K[2] = 320.0; K[3] = 240.0; K[4] = 0.0; K[5] = 0.0;
    }
    for (int j = 0; j < n; j++)
        for (int k = 0; k < 3; k++)
            s->X[3 * j + k] = sfm_test_uniform(t, -1.5, 1.5);
    int no = 0;
    for (int j = 0; j < n; j++) {
        for (int i = 0; i < m; i++) {
            double uv[2];
            if (!bas_project(s->R + 9 * i, s->t + 3 * i, s->K + 6 * i, s->X + 3 * j, uv))
                continue;
            s->oc[no] = i;
            s->op[no] = j;
            s->xy[2 * no] = uv[0] + sfm_test_normal(t, sigma);
            s->xy[2 * no + 1] = uv[1] + sfm_test_normal(t, sigma);
            no++;
        }
    }
    s->nobs = no;
    memcpy(s->R0, s->R, sizeof(double) * 9 * m);
    memcpy(s->t0, s->t, sizeof(double) * 3 * m);
    memcpy(s->K0, s->K, sizeof(double) * 6 * m);
    memcpy(s->X0, s->X, sizeof(double) * 3 * n);
    for (int i = 1; i < m; i++) {
        double w[3], dR[9];
        sfm_test_random_unit(t, w);
        double a = rot_deg * 3.14159265358979323846 / 180.0;
        for (int k = 0; k < 3; k++)
            w[k] *= a;
        bas_rodrigues(w, dR);
        bas_matmul3(dR, s->R0 + 9 * i, s->R0 + 9 * i);
        for (int k = 0; k < 3; k++)
            s->t0[3 * i + k] += sfm_test_normal(t, trans);
    }
    for (int j = 0; j < 3 * n; j++)
        s->X0[j] += sfm_test_normal(t, pt);
}

/* Intrinsics rows {fx, fy, cx, cy, k1, k2} of the scenes as Brown-Conrady
 * cameras (p1 = p2 = k3 = 0), and back. */
static inline void bas_cameras_from_rows(const double *K, int m, sfm_camera *cams)
{
    for (int i = 0; i < m; i++) {
        memset(&cams[i], 0, sizeof cams[i]);
        cams[i].model = SFM_CAMERA_BROWN;
        cams[i].fx = K[6 * i];
        cams[i].fy = K[6 * i + 1];
        cams[i].cx = K[6 * i + 2];
        cams[i].cy = K[6 * i + 3];
        cams[i].dist[0] = K[6 * i + 4];
        cams[i].dist[1] = K[6 * i + 5];
    }
}

static inline void bas_rows_from_cameras(const sfm_camera *cams, int m, double *K)
{
    for (int i = 0; i < m; i++) {
        K[6 * i] = cams[i].fx;
        K[6 * i + 1] = cams[i].fy;
        K[6 * i + 2] = cams[i].cx;
        K[6 * i + 3] = cams[i].cy;
        K[6 * i + 4] = cams[i].dist[0];
        K[6 * i + 5] = cams[i].dist[1];
    }
}

/* The problem from the scene's start; cams (m entries) from its rows. */
static void bas_problem(ba_scene *s, sfm_ba_problem *p, double *R, double *tt, sfm_camera *cams, double *X)
{
    memcpy(R, s->R0, sizeof(double) * 9 * s->m);
    memcpy(tt, s->t0, sizeof(double) * 3 * s->m);
    bas_cameras_from_rows(s->K0, s->m, cams);
    memcpy(X, s->X0, sizeof(double) * 3 * s->n);
    memset(p, 0, sizeof *p);
    p->n_cameras = s->m;
    p->n_points = s->n;
    p->n_observations = s->nobs;
    p->rotations = R;
    p->translations = tt;
    p->cameras = cams;
    p->points = X;
    p->obs_camera = s->oc;
    p->obs_point = s->op;
    p->obs_xy = s->xy;
}

static double bas_max_abs_diff(const double *a, const double *b, int n)
{
    double d = 0;
    for (int i = 0; i < n; i++)
        d = fmax(d, fabs(a[i] - b[i]));
    return d;
}

#endif
