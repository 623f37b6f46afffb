/*
 * Degeneracy of a two-view inlier set. A pure rotation maps bearings by
 * b2 = R b1: R is the orthogonal Procrustes fit (Kabsch), refit once on the
 * points it explains. A dominant plane maps them by a homography: the
 * normalised DLT on the z = 1 plane, refit once likewise. Either model is
 * accepted when it explains SFM_DEGENERACY_FRACTION of the inliers within
 * SFM_DEGENERACY_TAU_MULT times the inlier threshold. A rotation explains
 * every homography-free scene with no parallax, so it is tested first.
 */
#include "robust/twoview_degeneracy.h"

#include <math.h>

#include "robust/epipolar.h"
#include "sfm/sfm_ransac.h"
#include "sfm/sfm_rotation.h"
#include "sfm/sfm_solvers.h"

static int rotation_count(const double *b1, const double *b2, const int *idx, int n,
                          const double *R, double tol, int *sel)
{
    int c = 0;
    for (int j = 0; j < n; j++) {
        int i = idx[j];
        double Rb[3], x[3];
        sfm_matvec3(R, b1 + 3 * i, Rb);
        sfm_cross3(Rb, b2 + 3 * i, x);
        if (sfm_dot3(Rb, b2 + 3 * i) > 0.0 && sfm_dot3(x, x) < tol * tol)
            sel[c++] = i;
    }
    return c;
}

static int fit_rotation(const double *b1, const double *b2, const int *idx, int n, double *R)
{
    double M[9] = {0, 0, 0, 0, 0, 0, 0, 0, 0};
    for (int j = 0; j < n; j++) {
        const double *x = b1 + 3 * idx[j], *y = b2 + 3 * idx[j];
        for (int r = 0; r < 3; r++)
            for (int c = 0; c < 3; c++)
                M[3 * r + c] += y[r] * x[c];
    }
    return sfm_rot_nearest(M, R);
}

static int homography_count(const double *p1, const double *p2, int n, const double *H,
                            double tol, int *sel)
{
    int c = 0;
    for (int i = 0; i < n; i++) {
        double x = p1[2 * i], y = p1[2 * i + 1];
        double w = H[6] * x + H[7] * y + H[8];
        if (fabs(w) < 1e-12)
            continue;
        double u = (H[0] * x + H[1] * y + H[2]) / w - p2[2 * i];
        double v = (H[3] * x + H[4] * y + H[5]) / w - p2[2 * i + 1];
        if (u * u + v * v < tol * tol)
            sel[c++] = i;
    }
    return c;
}

int sfm_robust_twoview_degeneracy(const double *b1, const double *b2, const int *idx, int n,
                                  double tau, double *p1, double *p2, int *sel)
{
    if (n < 5)
        return 0;
    const double tol = SFM_DEGENERACY_TAU_MULT * tau;
    const int need = (int)ceil(SFM_DEGENERACY_FRACTION * n);
    double R[9];
    if (fit_rotation(b1, b2, idx, n, R) == 0) {
        int c = rotation_count(b1, b2, idx, n, R, tol, sel);
        if (c >= 3 && c < need && fit_rotation(b1, b2, sel, c, R) == 0)
            c = rotation_count(b1, b2, idx, n, R, tol, sel);
        if (c >= need)
            return SFM_RANSAC_FLAG_PURE_ROTATION;
    }
    /* homography on the z = 1 plane, over the inliers seen in front */
    int m = 0;
    for (int j = 0; j < n; j++) {
        const double *x = b1 + 3 * idx[j], *y = b2 + 3 * idx[j];
        if (x[2] <= 1e-3 || y[2] <= 1e-3)
            continue;
        p1[2 * m] = x[0] / x[2];
        p1[2 * m + 1] = x[1] / x[2];
        p2[2 * m] = y[0] / y[2];
        p2[2 * m + 1] = y[1] / y[2];
        m++;
    }
    if (m < need || m < 5)
        return 0;
    sfm_mat3 H;
    if (sfm_homography_dlt(p1, p2, m, &H) != 1)
        return 0;
    int c = homography_count(p1, p2, m, H.m, tol, sel);
    if (c >= 4 && c < need) {
        /* refit on the explained points: compact them to the front */
        for (int k = 0; k < c; k++) {
            int i = sel[k];
            p1[2 * k] = p1[2 * i];
            p1[2 * k + 1] = p1[2 * i + 1];
            p2[2 * k] = p2[2 * i];
            p2[2 * k + 1] = p2[2 * i + 1];
        }
        (void)c;
        /* the refit only sees the explained subset; recount over all needs the
         * original points, rebuilt below */
        sfm_mat3 H2;
        if (sfm_homography_dlt(p1, p2, c, &H2) == 1) {
            m = 0;
            for (int j = 0; j < n; j++) {
                const double *x = b1 + 3 * idx[j], *y = b2 + 3 * idx[j];
                if (x[2] <= 1e-3 || y[2] <= 1e-3)
                    continue;
                p1[2 * m] = x[0] / x[2];
                p1[2 * m + 1] = x[1] / x[2];
                p2[2 * m] = y[0] / y[2];
                p2[2 * m + 1] = y[1] / y[2];
                m++;
            }
            c = homography_count(p1, p2, m, H2.m, tol, sel);
        }
    }
    return c >= need ? SFM_RANSAC_FLAG_PLANAR : 0;
}
