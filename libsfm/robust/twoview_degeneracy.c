/*
 * Degeneracy of a two-view inlier set. A pure rotation maps bearings by
 * b2 = R b1: R is the pose's rotation, refit by orthogonal Procrustes
 * (Kabsch) on the points it explains. A dominant plane maps them by a
 * homography: the best of a few 4-point homographies on the z = 1 plane,
 * refit by normalised DLT on its support. Either model is
 * accepted when it explains SFM_DEGENERACY_FRACTION of the inliers within
 * SFM_DEGENERACY_TAU_MULT times the inlier threshold. A pure rotation is
 * also a homography (the infinite one), so it is tested first.
 */
#include "robust/twoview_degeneracy.h"

#include <math.h>

#include "robust/epipolar.h"
#include "sfm/sfm_ransac.h"
#include "sfm/sfm_rng.h"
#include "sfm/sfm_rotation.h"
#include "sfm/sfm_solvers.h"

static int rotation_count(const double *b1, const double *b2, const int *idx, int n,
                          const double *R, double tol, int *sel)
{
    int c = 0;
    for (int j = 0; j < n; j++) {
        int i = idx[j];
        double Rb[3], x[3];
        sfmi_matvec3(R, b1 + 3 * i, Rb);
        sfmi_cross3(Rb, b2 + 3 * i, x);
        if (sfmi_dot3(Rb, b2 + 3 * i) > 0.0 && sfmi_dot3(x, x) < tol * tol)
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

/* Points the candidate homographies are counted on: an evenly spread
 * subset, enough to tell a dominant plane (SFM_DEGENERACY_FRACTION of the
 * points) from a general scene; the winner is then counted on all. */
#define SUBSET 128

/* Points among s evenly spread ones of p1/p2[0..m) that H transfers within
 * tol (s = m: all of them, in order); their indices go to sel unless it is
 * NULL. */
static int homography_count(const double *p1, const double *p2, int m, int s, const double *H,
                            double tol, int *sel)
{
    int c = 0;
    for (int j = 0; j < s; j++) {
        int i = (int)(((long long)j * m) / s);
        double x = p1[2 * i], y = p1[2 * i + 1];
        double w = H[6] * x + H[7] * y + H[8];
        if (fabs(w) < 1e-12)
            continue;
        double u = (H[0] * x + H[1] * y + H[2]) / w - p2[2 * i];
        double v = (H[3] * x + H[4] * y + H[5]) / w - p2[2 * i + 1];
        if (u * u + v * v < tol * tol) {
            if (sel)
                sel[c] = i;
            c++;
        }
    }
    return c;
}

/* Writes the z = 1 projections of the inliers seen in front by both
 * cameras; returns their count. */
static int project_plane(const double *b1, const double *b2, const int *idx, int n, double *p1,
                         double *p2)
{
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
    return m;
}

/* The PLANAR answer with its homography and the size of its support. */
static int planar(const double *H, int c, double *H_out, int *n_plane)
{
    if (H_out != NULL)
        for (int k = 0; k < 9; k++)
            H_out[k] = H[k];
    if (n_plane != NULL)
        *n_plane = c;
    return SFM_RANSAC_FLAG_PLANAR;
}

int sfmi_robust_twoview_degeneracy(const double *b1, const double *b2, const int *idx, int n,
                                  const double *R_pose, const double *t_pose, double tau,
                                  uint64_t seed, double *p1, double *p2, int *sel, double *H_out,
                                  int *n_plane)
{
    if (n < 5)
        return 0;
    const double tol = SFM_DEGENERACY_TAU_MULT * tau;
    const int need = (int)ceil(SFM_DEGENERACY_FRACTION * n);
    /* rotation: the estimated pose's own R (right whatever t is when there
     * is no parallax), then the Procrustes refit on what it explains */
    double R[9];
    int c = rotation_count(b1, b2, idx, n, R_pose, tol, sel);
    if (c >= need)
        return SFM_RANSAC_FLAG_PURE_ROTATION;
    if (c >= 3 && fit_rotation(b1, b2, sel, c, R) == 0 &&
        rotation_count(b1, b2, idx, n, R, tol, sel) >= need)
        return SFM_RANSAC_FLAG_PURE_ROTATION;
    /* without parallax cheirality cannot tell R from its twisted pair
     * (R turned 180 degrees about t), and the twisted one explains none of
     * the points: try the other, (2 t t^T / t.t - I) R */
    const double tt = t_pose != NULL ? sfmi_dot3(t_pose, t_pose) : 0.0;
    if (c < 3 && tt > 0.0) {
        double Q[9];
        for (int r = 0; r < 3; r++)
            for (int k = 0; k < 3; k++)
                Q[3 * r + k] = 2.0 * t_pose[r] * t_pose[k] / tt - (r == k ? 1.0 : 0.0);
        sfmi_matmul3(Q, R_pose, R);
        if (rotation_count(b1, b2, idx, n, R, tol, sel) >= need)
            return SFM_RANSAC_FLAG_PURE_ROTATION;
    }
    /* plane: a few 4-point homographies on the z = 1 plane (the inliers of a
     * relative pose may hold a few outliers, which would pull a plain
     * least-squares fit), then a DLT refit on the best one's support */
    int m = project_plane(b1, b2, idx, n, p1, p2);
    if (m < need || m < 5)
        return 0;
    sfm_rng rng;
    sfm_rng_seed(&rng, seed ^ 0x9e3779b97f4a7c15ULL);
    const int sub = m < SUBSET ? m : SUBSET;
    const int need_sub = (int)ceil(SFM_DEGENERACY_FRACTION * sub);
    double bestH[9];
    int best = -1;
    for (int it = 0; it < SFM_DEGENERACY_H_TRIALS && best < need_sub; it++) {
        int s[4];
        for (int k = 0; k < 4; k++) {
            int v, dup;
            do {
                v = (int)sfm_rng_bounded(&rng, (uint32_t)m);
                dup = 0;
                for (int q = 0; q < k; q++)
                    dup |= s[q] == v;
            } while (dup);
            s[k] = v;
        }
        double a[8], b[8];
        for (int k = 0; k < 4; k++) {
            a[2 * k] = p1[2 * s[k]];
            a[2 * k + 1] = p1[2 * s[k] + 1];
            b[2 * k] = p2[2 * s[k]];
            b[2 * k + 1] = p2[2 * s[k] + 1];
        }
        sfm_mat3 H;
        if (sfm_homography_4pt(a, b, &H) != 1)
            continue;
        int cnt = homography_count(p1, p2, m, sub, H.m, tol, NULL);
        if (cnt > best) {
            best = cnt;
            for (int k = 0; k < 9; k++)
                bestH[k] = H.m[k];
        }
    }
    if (best < 0)
        return 0;
    c = homography_count(p1, p2, m, m, bestH, tol, sel);
    if (c >= need)
        return planar(bestH, c, H_out, n_plane);
    /* a homography from four noisy points of a dominant plane still
     * explains most of it: below half the quota there is no plane to refit */
    if (c < 4 || 2 * c < need)
        return 0;
    /* refit on the best support, compacted to the front of p1 / p2 */
    for (int k = 0; k < c; k++) {
        int i = sel[k]; /* increasing, i >= k: safe in place */
        p1[2 * k] = p1[2 * i];
        p1[2 * k + 1] = p1[2 * i + 1];
        p2[2 * k] = p2[2 * i];
        p2[2 * k + 1] = p2[2 * i + 1];
    }
    sfm_mat3 H2;
    if (sfm_homography_dlt(p1, p2, c, &H2) != 1)
        return 0;
    m = project_plane(b1, b2, idx, n, p1, p2);
    c = homography_count(p1, p2, m, m, H2.m, tol, sel);
    return c >= need ? planar(H2.m, c, H_out, n_plane) : 0;
}
