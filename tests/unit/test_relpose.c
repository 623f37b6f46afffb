/*
 * Relative pose solvers against synthetic problems with known answers:
 * sfm_relpose_5pt, sfm_fundamental_7pt, sfm_relpose_8pt, sfm_fundamental_8pt.
 * Convention checked: x_cam2 = R x_cam1 + t, E = [t]x R, x2^T E x1 = 0,
 * F = K2^-T E K1^-1, p2h^T F p1h = 0.
 */
#include <math.h>
#include <string.h>

#include "sfm/sfm_solvers.h"
#include "sfm_test.h"

/* Scene kinds: the hard corners users report, plus the general case. */
enum {
    SC_GENERAL,
    SC_SMALL_ROT,
    SC_FORWARD,
    SC_SIDEWAYS,
    SC_NEAR_180,
    SC_NEAR_PLANAR,
    SC_FAR,
    SC_VERY_FAR,
    SC_COUNT
};
static const char *const SC_NAME[SC_COUNT] = {"general", "small-rotation", "forward",
                                              "sideways", "near-180", "near-planar", "far",
                                              "very-far"};

typedef struct scene {
    double R[9], t[3];   /* x_cam2 = R x_cam1 + t */
    double E[9];         /* [t]x R, unit Frobenius */
    double K1[9], K2[9]; /* intrinsics for pixel problems */
    double F[9];         /* K2^-T E K1^-1, unit Frobenius */
} scene;

static void rot_axis_angle(const double axis[3], double ang, double R[9])
{
    double c = cos(ang), s = sin(ang), C = 1.0 - c;
    double x = axis[0], y = axis[1], z = axis[2];
    R[0] = c + x * x * C;     R[1] = x * y * C - z * s; R[2] = x * z * C + y * s;
    R[3] = y * x * C + z * s; R[4] = c + y * y * C;     R[5] = y * z * C - x * s;
    R[6] = z * x * C - y * s; R[7] = z * y * C + x * s; R[8] = c + z * z * C;
}

static void matmul3(const double *A, const double *B, double *C)
{
    for (int r = 0; r < 3; r++)
        for (int c = 0; c < 3; c++)
            C[3 * r + c] = A[3 * r] * B[c] + A[3 * r + 1] * B[3 + c] + A[3 * r + 2] * B[6 + c];
}

static void unit9(double *M)
{
    double s = 0.0;
    for (int i = 0; i < 9; i++)
        s += M[i] * M[i];
    s = 1.0 / sqrt(s);
    for (int i = 0; i < 9; i++)
        M[i] *= s;
}

/* Distance between two matrices up to scale and sign (both normalized). */
static double dist_proj(const double *A, const double *B)
{
    double a[9], b[9], dp = 0.0, dm = 0.0;
    memcpy(a, A, sizeof a);
    memcpy(b, B, sizeof b);
    unit9(a);
    unit9(b);
    for (int i = 0; i < 9; i++) {
        dp += (a[i] - b[i]) * (a[i] - b[i]);
        dm += (a[i] + b[i]) * (a[i] + b[i]);
    }
    return sqrt(dp < dm ? dp : dm);
}

static void random_intrinsics(sfm_test_ctx *t, double K[9])
{
    double f = sfm_test_uniform(t, 400.0, 1500.0);
    memset(K, 0, 9 * sizeof(double));
    K[0] = f;
    K[4] = f * sfm_test_uniform(t, 0.95, 1.05);
    K[2] = sfm_test_uniform(t, 300.0, 700.0);
    K[5] = sfm_test_uniform(t, 200.0, 500.0);
    K[8] = 1.0;
}

/* Builds the cameras; x_cam2 = R (X - C2), t = -R C2 with X in camera 1. */
static void make_scene(sfm_test_ctx *t, int kind, scene *s)
{
    double axis[3], C2[3], ang;
    sfm_test_random_unit(t, axis);
    switch (kind) {
    case SC_SMALL_ROT:
        ang = sfm_test_uniform(t, 1e-4, 1e-2);
        rot_axis_angle(axis, ang, s->R);
        sfm_test_random_unit(t, C2);
        break;
    case SC_FORWARD:
        sfm_test_random_rotation(t, s->R);
        ang = sfm_test_uniform(t, 0.0, 0.3);
        rot_axis_angle(axis, ang, s->R);
        C2[0] = 0.0; C2[1] = 0.0; C2[2] = sfm_test_uniform(t, 0.2, 2.0);
        break;
    case SC_SIDEWAYS:
        ang = sfm_test_uniform(t, 0.0, 0.3);
        rot_axis_angle(axis, ang, s->R);
        C2[0] = sfm_test_uniform(t, 0.2, 2.0); C2[1] = 0.0; C2[2] = 0.0;
        break;
    case SC_NEAR_180: {
        /* Camera 2 faces camera 1 across the points: a half turn about an
         * axis near y, off by up to 1e-3 rad. */
        double ax[3] = {sfm_test_normal(t, 0.1), 1.0, sfm_test_normal(t, 0.1)};
        double n = sqrt(ax[0] * ax[0] + ax[1] * ax[1] + ax[2] * ax[2]);
        for (int i = 0; i < 3; i++)
            ax[i] /= n;
        ang = 3.14159265358979323846 - sfm_test_uniform(t, 0.0, 1e-3);
        rot_axis_angle(ax, ang, s->R);
        C2[0] = sfm_test_normal(t, 0.5); C2[1] = sfm_test_normal(t, 0.5);
        C2[2] = sfm_test_uniform(t, 8.0, 12.0);
        break;
    }
    default:
        sfm_test_random_rotation(t, s->R);
        sfm_test_random_unit(t, C2);
        break;
    }
    for (int i = 0; i < 3; i++)
        s->t[i] = -(s->R[3 * i] * C2[0] + s->R[3 * i + 1] * C2[1] + s->R[3 * i + 2] * C2[2]);
    double T[9] = {0.0, -s->t[2], s->t[1], s->t[2], 0.0, -s->t[0], -s->t[1], s->t[0], 0.0};
    matmul3(T, s->R, s->E);
    unit9(s->E);
    random_intrinsics(t, s->K1);
    random_intrinsics(t, s->K2);
    /* F = K2^-T E K1^-1 with K^-1 of an upper-triangular K written out. */
    double K1i[9] = {1.0 / s->K1[0], 0.0, -s->K1[2] / s->K1[0],
                     0.0, 1.0 / s->K1[4], -s->K1[5] / s->K1[4], 0.0, 0.0, 1.0};
    double K2i[9] = {1.0 / s->K2[0], 0.0, -s->K2[2] / s->K2[0],
                     0.0, 1.0 / s->K2[4], -s->K2[5] / s->K2[4], 0.0, 0.0, 1.0};
    double K2iT[9] = {K2i[0], K2i[3], K2i[6], K2i[1], K2i[4], K2i[7], K2i[2], K2i[5], K2i[8]};
    double M[9];
    matmul3(K2iT, s->E, M);
    matmul3(M, K1i, s->F);
    unit9(s->F);
}

/* A point in camera 1's frame for this scene kind; X2 = R X + t. Returns 0
 * when the point is not usable for pixel projection (behind a camera). */
static int make_point(sfm_test_ctx *t, int kind, const scene *s, int plane_kind_seed, double X[3],
                      double X2[3])
{
    (void)plane_kind_seed;
    double depth;
    switch (kind) {
    case SC_NEAR_PLANAR:
        depth = 5.0 + sfm_test_uniform(t, -1e-3, 1e-3);
        break;
    case SC_FAR: /* 20 to 100 baselines away */
        depth = sfm_test_uniform(t, 20.0, 100.0);
        break;
    case SC_VERY_FAR: /* 100 to 1000 baselines: close to pure rotation */
        depth = sfm_test_uniform(t, 100.0, 1000.0);
        break;
    case SC_NEAR_180:
        depth = sfm_test_uniform(t, 3.0, 7.0);
        break;
    default:
        depth = sfm_test_uniform(t, 2.0, 10.0);
        break;
    }
    X[0] = depth * sfm_test_uniform(t, -0.6, 0.6);
    X[1] = depth * sfm_test_uniform(t, -0.45, 0.45);
    X[2] = depth;
    for (int i = 0; i < 3; i++)
        X2[i] = s->R[3 * i] * X[0] + s->R[3 * i + 1] * X[1] + s->R[3 * i + 2] * X[2] + s->t[i];
    return X2[2] > 0.1;
}

static void bearing(const double X[3], double *b)
{
    double n = sqrt(X[0] * X[0] + X[1] * X[1] + X[2] * X[2]);
    b[0] = X[0] / n; b[1] = X[1] / n; b[2] = X[2] / n;
}

static void pixel(const double K[9], const double X[3], double *p)
{
    p[0] = K[0] * X[0] / X[2] + K[2];
    p[1] = K[4] * X[1] / X[2] + K[5];
}

/* n bearing pairs for scene s. */
static void make_bearings(sfm_test_ctx *t, int kind, const scene *s, int n, double *x1, double *x2)
{
    for (int i = 0; i < n; i++) {
        double X[3], X2[3];
        (void)make_point(t, kind, s, 0, X, X2);
        bearing(X, x1 + 3 * i);
        bearing(X2, x2 + 3 * i);
    }
}

/* n pixel pairs, all points in front of both cameras. */
static void make_pixels(sfm_test_ctx *t, int kind, const scene *s, int n, double *p1, double *p2)
{
    for (int i = 0; i < n; i++) {
        double X[3], X2[3];
        int tries = 0;
        while (!make_point(t, kind, s, 0, X, X2) && ++tries < 1000) {
        }
        pixel(s->K1, X, p1 + 2 * i);
        pixel(s->K2, X2, p2 + 2 * i);
    }
}

static int all_finite(const sfm_mat3 *M, int n)
{
    for (int k = 0; k < n; k++)
        for (int i = 0; i < 9; i++)
            if (!isfinite(M[k].m[i]))
                return 0;
    return 1;
}

static double best_dist(const sfm_mat3 *M, int n, const double *truth)
{
    double best = HUGE_VAL;
    for (int k = 0; k < n; k++) {
        double d = dist_proj(M[k].m, truth);
        if (d < best)
            best = d;
    }
    return best;
}

/* Logs one scene kind's rate (and the mean number of solutions when nsol
 * is not negative) and, when held, requires 99.9 % of the samples found. */
static void rate_report(sfm_test_ctx *t, const char *solver, int n, int kind, int found, long nsol,
                        int iters, int held)
{
    if (nsol >= 0)
        SFM_TEST_LOG("%-14s found %d/%d (%.3f%%), %.2f solutions per call", SC_NAME[kind], found,
                     iters, 100.0 * found / iters, (double)nsol / iters);
    else
        SFM_TEST_LOG("n=%d %-14s found %d/%d (%.3f%%)", n, SC_NAME[kind], found, iters,
                     100.0 * found / iters);
    if (held)
        SFM_CHECK_MSG(found >= 0.999 * iters, "%s n=%d %s: found %d of %d", solver, n, SC_NAME[kind],
                      found, iters);
}

/* ---- 5-point ---------------------------------------------------------- */

SFM_TEST(relpose_5pt_ground_truth_rate)
{
    const int iters = SFM_TEST_ITERS(3000);
    int total = 0, found_all = 0;
    for (int kind = 0; kind < SC_COUNT; kind++) {
        int found = 0;
        long nsol = 0;
        for (int it = 0; it < iters; it++) {
            scene s;
            double x1[15], x2[15];
            sfm_mat3 E[SFM_RELPOSE_5PT_MAX_SOLUTIONS];
            make_scene(t, kind, &s);
            make_bearings(t, kind, &s, 5, x1, x2);
            int n = sfm_relpose_5pt(x1, x2, E);
            SFM_CHECK(n >= 0 && n <= SFM_RELPOSE_5PT_MAX_SOLUTIONS);
            if (n < 0)
                continue;
            SFM_CHECK(all_finite(E, n));
            nsol += n;
            /* every solution satisfies the five constraints */
            for (int k = 0; k < n; k++)
                for (int i = 0; i < 5; i++) {
                    const double *a = x1 + 3 * i, *b = x2 + 3 * i;
                    double r = 0.0;
                    for (int u = 0; u < 3; u++)
                        for (int v = 0; v < 3; v++)
                            r += b[u] * E[k].m[3 * u + v] * a[v];
                    SFM_CHECK(fabs(r) < 1e-8);
                }
            if (best_dist(E, n, s.E) < 1e-6)
                found++;
        }
        /* Beyond 100 baselines the five-point problem nears the pure-rotation
         * degeneracy (a continuum of E); the rate there is logged, not held. */
        rate_report(t, "5pt", 5, kind, found, nsol, iters, kind != SC_VERY_FAR);
        if (kind == SC_VERY_FAR)
            continue;
        total += iters;
        found_all += found;
    }
    SFM_TEST_LOG("all scenes but very-far: found %d/%d (%.3f%%)", found_all, total,
                 100.0 * found_all / total);
}

SFM_TEST(relpose_5pt_degenerate)
{
    sfm_mat3 E[SFM_RELPOSE_5PT_MAX_SOLUTIONS];
    /* identical points */
    double x1[15], x2[15];
    for (int i = 0; i < 5; i++) {
        x1[3 * i] = 0.1; x1[3 * i + 1] = 0.2; x1[3 * i + 2] = 1.0;
        x2[3 * i] = 0.3; x2[3 * i + 1] = -0.1; x2[3 * i + 2] = 1.0;
    }
    SFM_CHECK_EQ_INT(sfm_relpose_5pt(x1, x2, E), 0);
    /* zero baseline (pure rotation): a continuum of essential matrices; the
     * solver returns 0 or finite matrices, never NaN */
    for (int it = 0; it < SFM_TEST_ITERS(200); it++) {
        double R[9];
        sfm_test_random_rotation(t, R);
        for (int i = 0; i < 5; i++) {
            double X[3] = {sfm_test_uniform(t, -1, 1), sfm_test_uniform(t, -1, 1), 1.0}, X2[3];
            for (int r = 0; r < 3; r++)
                X2[r] = R[3 * r] * X[0] + R[3 * r + 1] * X[1] + R[3 * r + 2] * X[2];
            bearing(X, x1 + 3 * i);
            bearing(X2, x2 + 3 * i);
        }
        int n = sfm_relpose_5pt(x1, x2, E);
        SFM_CHECK(n >= 0 && n <= SFM_RELPOSE_5PT_MAX_SOLUTIONS);
        SFM_CHECK(all_finite(E, n > 0 ? n : 0));
    }
    /* points on one 3D line */
    for (int it = 0; it < SFM_TEST_ITERS(200); it++) {
        scene s;
        make_scene(t, SC_GENERAL, &s);
        double P[3] = {0.0, 0.0, 5.0}, D[3];
        sfm_test_random_unit(t, D);
        for (int i = 0; i < 5; i++) {
            double X[3], X2[3], l = sfm_test_uniform(t, -1, 1);
            for (int r = 0; r < 3; r++)
                X[r] = P[r] + l * D[r];
            for (int r = 0; r < 3; r++)
                X2[r] = s.R[3 * r] * X[0] + s.R[3 * r + 1] * X[1] + s.R[3 * r + 2] * X[2] + s.t[r];
            bearing(X, x1 + 3 * i);
            bearing(X2, x2 + 3 * i);
        }
        int n = sfm_relpose_5pt(x1, x2, E);
        SFM_CHECK(n >= 0 && n <= SFM_RELPOSE_5PT_MAX_SOLUTIONS);
        SFM_CHECK(all_finite(E, n > 0 ? n : 0));
    }
}

SFM_TEST(relpose_5pt_contract)
{
    double x1[15], x2[15];
    scene s;
    make_scene(t, SC_GENERAL, &s);
    make_bearings(t, SC_GENERAL, &s, 5, x1, x2);
    sfm_mat3 E[SFM_RELPOSE_5PT_MAX_SOLUTIONS];
    sfm_test_fill_canary(E, sizeof E);
    SFM_CHECK_EQ_INT(sfm_relpose_5pt(NULL, x2, E), SFM_E_ARGUMENT);
    SFM_CHECK_EQ_INT(sfm_relpose_5pt(x1, NULL, E), SFM_E_ARGUMENT);
    SFM_CHECK_EQ_INT(sfm_relpose_5pt(x1, x2, NULL), SFM_E_ARGUMENT);
    x1[7] = (double)NAN;
    SFM_CHECK_EQ_INT(sfm_relpose_5pt(x1, x2, E), SFM_E_NONFINITE);
    x1[7] = 0.1;
    x2[14] = HUGE_VAL;
    SFM_CHECK_EQ_INT(sfm_relpose_5pt(x1, x2, E), SFM_E_NONFINITE);
    SFM_CHECK(sfm_test_canary_intact(E, sizeof E));
}

/* ---- 7-point ---------------------------------------------------------- */

SFM_TEST(fundamental_7pt_ground_truth_rate)
{
    const int iters = SFM_TEST_ITERS(3000);
    for (int kind = 0; kind < SC_COUNT; kind++) {
        int found = 0;
        long nsol = 0;
        for (int it = 0; it < iters; it++) {
            scene s;
            double p1[14], p2[14];
            sfm_mat3 F[SFM_FUNDAMENTAL_7PT_MAX_SOLUTIONS];
            make_scene(t, kind, &s);
            make_pixels(t, kind, &s, 7, p1, p2);
            int n = sfm_fundamental_7pt(p1, p2, F);
            SFM_CHECK(n >= 0 && n <= SFM_FUNDAMENTAL_7PT_MAX_SOLUTIONS);
            if (n < 0)
                continue;
            SFM_CHECK(all_finite(F, n));
            nsol += n;
            if (best_dist(F, n, s.F) < 1e-6)
                found++;
        }
        rate_report(t, "7pt", 7, kind, found, nsol, iters, 1);
    }
}

SFM_TEST(fundamental_7pt_degenerate_and_contract)
{
    double p1[14], p2[14];
    sfm_mat3 F[SFM_FUNDAMENTAL_7PT_MAX_SOLUTIONS];
    for (int i = 0; i < 7; i++) {
        p1[2 * i] = 100.0; p1[2 * i + 1] = 200.0;
        p2[2 * i] = 110.0; p2[2 * i + 1] = 190.0;
    }
    SFM_CHECK_EQ_INT(sfm_fundamental_7pt(p1, p2, F), 0);
    /* collinear in both images */
    for (int i = 0; i < 7; i++) {
        p1[2 * i] = 10.0 * i; p1[2 * i + 1] = 5.0 * i + 3.0;
        p2[2 * i] = 7.0 * i * i; p2[2 * i + 1] = 2.0 * i;
    }
    int n = sfm_fundamental_7pt(p1, p2, F);
    SFM_CHECK(n >= 0 && n <= SFM_FUNDAMENTAL_7PT_MAX_SOLUTIONS);
    SFM_CHECK(all_finite(F, n > 0 ? n : 0));

    scene s;
    make_scene(t, SC_GENERAL, &s);
    make_pixels(t, SC_GENERAL, &s, 7, p1, p2);
    sfm_test_fill_canary(F, sizeof F);
    SFM_CHECK_EQ_INT(sfm_fundamental_7pt(NULL, p2, F), SFM_E_ARGUMENT);
    SFM_CHECK_EQ_INT(sfm_fundamental_7pt(p1, NULL, F), SFM_E_ARGUMENT);
    SFM_CHECK_EQ_INT(sfm_fundamental_7pt(p1, p2, NULL), SFM_E_ARGUMENT);
    p2[3] = (double)NAN;
    SFM_CHECK_EQ_INT(sfm_fundamental_7pt(p1, p2, F), SFM_E_NONFINITE);
    SFM_CHECK(sfm_test_canary_intact(F, sizeof F));
}

/* ---- 8-point (essential and fundamental) ------------------------------ */

/* One 8-point sample on a fresh scene: 1 when it recovers the truth. */
typedef int (*trial_8pt)(sfm_test_ctx *t, int kind, int n);

static int trial_essential_8pt(sfm_test_ctx *t, int kind, int n)
{
    scene s;
    double x1[90], x2[90];
    sfm_mat3 E;
    make_scene(t, kind, &s);
    make_bearings(t, kind, &s, n, x1, x2);
    int ns = sfm_relpose_8pt(x1, x2, n, &E);
    SFM_CHECK(ns == 0 || ns == 1);
    if (ns != 1)
        return 0;
    SFM_CHECK(all_finite(&E, 1));
    return best_dist(&E, 1, s.E) < 1e-6;
}

static int trial_fundamental_8pt(sfm_test_ctx *t, int kind, int n)
{
    scene s;
    double p1[60], p2[60];
    sfm_mat3 F;
    make_scene(t, kind, &s);
    make_pixels(t, kind, &s, n, p1, p2);
    int ns = sfm_fundamental_8pt(p1, p2, n, &F);
    SFM_CHECK(ns == 0 || ns == 1);
    if (ns != 1)
        return 0;
    SFM_CHECK(all_finite(&F, 1));
    double d = F.m[0] * (F.m[4] * F.m[8] - F.m[5] * F.m[7]) -
               F.m[1] * (F.m[3] * F.m[8] - F.m[5] * F.m[6]) +
               F.m[2] * (F.m[3] * F.m[7] - F.m[4] * F.m[6]);
    SFM_CHECK(fabs(d) < 1e-12); /* rank 2 */
    return best_dist(&F, 1, s.F) < 1e-6;
}

static void rate_8pt(sfm_test_ctx *t, const char *solver, trial_8pt trial)
{
    const int iters = SFM_TEST_ITERS(2000);
    static const int sizes[2] = {8, 30};
    for (int si = 0; si < 2; si++) {
        const int n = sizes[si];
        for (int kind = 0; kind < SC_COUNT; kind++) {
            if (kind == SC_NEAR_PLANAR)
                continue; /* the linear 8-point is degenerate for planar scenes */
            int found = 0;
            for (int it = 0; it < iters; it++)
                found += trial(t, kind, n);
            rate_report(t, solver, n, kind, found, -1, iters, 1);
        }
    }
}

SFM_TEST(relpose_8pt_ground_truth_rate)
{
    rate_8pt(t, "8pt", trial_essential_8pt);
}

SFM_TEST(fundamental_8pt_ground_truth_rate)
{
    rate_8pt(t, "F8pt", trial_fundamental_8pt);
}

SFM_TEST(relpose_8pt_essential_manifold)
{
    /* With noise the least-squares E is projected: singular values (1,1,0)/sqrt2,
     * i.e. E E^T E = 0.5 E for a unit-Frobenius essential matrix. */
    for (int it = 0; it < SFM_TEST_ITERS(200); it++) {
        scene s;
        double x1[60], x2[60];
        sfm_mat3 E;
        make_scene(t, SC_GENERAL, &s);
        make_bearings(t, SC_GENERAL, &s, 20, x1, x2);
        for (int i = 0; i < 60; i++)
            x2[i] += sfm_test_normal(t, 1e-3);
        SFM_CHECK_EQ_INT(sfm_relpose_8pt(x1, x2, 20, &E), 1);
        double EEt[9], EEtE[9], Et[9];
        for (int r = 0; r < 3; r++)
            for (int c = 0; c < 3; c++)
                Et[3 * r + c] = E.m[3 * c + r];
        matmul3(E.m, Et, EEt);
        matmul3(EEt, E.m, EEtE);
        for (int i = 0; i < 9; i++)
            SFM_CHECK_NEAR(EEtE[i], 0.5 * E.m[i], 1e-12);
    }
}

SFM_TEST(relpose_8pt_degenerate_and_contract)
{
    double x1[30], x2[30], p1[20], p2[20];
    sfm_mat3 E, F;
    for (int i = 0; i < 10; i++) {
        x1[3 * i] = 0.1; x1[3 * i + 1] = 0.2; x1[3 * i + 2] = 1.0;
        x2[3 * i] = 0.2; x2[3 * i + 1] = 0.1; x2[3 * i + 2] = 1.0;
        p1[2 * i] = 5.0; p1[2 * i + 1] = 6.0;
        p2[2 * i] = 7.0; p2[2 * i + 1] = 8.0;
    }
    SFM_CHECK_EQ_INT(sfm_relpose_8pt(x1, x2, 8, &E), 0);
    SFM_CHECK_EQ_INT(sfm_relpose_8pt(x1, x2, 10, &E), 0);
    SFM_CHECK_EQ_INT(sfm_fundamental_8pt(p1, p2, 8, &F), 0);
    SFM_CHECK_EQ_INT(sfm_fundamental_8pt(p1, p2, 10, &F), 0);

    sfm_test_fill_canary(&E, sizeof E);
    sfm_test_fill_canary(&F, sizeof F);
    SFM_CHECK_EQ_INT(sfm_relpose_8pt(x1, x2, 7, &E), SFM_E_ARGUMENT);
    SFM_CHECK_EQ_INT(sfm_relpose_8pt(NULL, x2, 8, &E), SFM_E_ARGUMENT);
    SFM_CHECK_EQ_INT(sfm_relpose_8pt(x1, NULL, 8, &E), SFM_E_ARGUMENT);
    SFM_CHECK_EQ_INT(sfm_relpose_8pt(x1, x2, 8, NULL), SFM_E_ARGUMENT);
    SFM_CHECK_EQ_INT(sfm_fundamental_8pt(p1, p2, 7, &F), SFM_E_ARGUMENT);
    SFM_CHECK_EQ_INT(sfm_fundamental_8pt(NULL, p2, 8, &F), SFM_E_ARGUMENT);
    SFM_CHECK_EQ_INT(sfm_fundamental_8pt(p1, p2, -1, &F), SFM_E_ARGUMENT);
    x1[29] = (double)NAN;
    p2[19] = -HUGE_VAL;
    SFM_CHECK_EQ_INT(sfm_relpose_8pt(x1, x2, 10, &E), SFM_E_NONFINITE);
    SFM_CHECK_EQ_INT(sfm_fundamental_8pt(p1, p2, 10, &F), SFM_E_NONFINITE);
    SFM_CHECK(sfm_test_canary_intact(&E, sizeof E));
    SFM_CHECK(sfm_test_canary_intact(&F, sizeof F));
}
