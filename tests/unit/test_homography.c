/*
 * Homography solvers against synthetic planes with known answers:
 * sfm_homography_4pt and sfm_homography_dlt. Convention: p2h ~ H p1h with
 * H = K2 (R + t n^T / d) K1^-1 for the plane n^T X = d in camera 1.
 */
#include <math.h>
#include <string.h>

#include "sfm/sfm_solvers.h"
#include "sfm_test.h"

static void mm3(const double *A, const double *B, double *C)
{
    for (int r = 0; r < 3; r++)
        for (int c = 0; c < 3; c++)
            C[3 * r + c] = A[3 * r] * B[c] + A[3 * r + 1] * B[3 + c] + A[3 * r + 2] * B[6 + c];
}

static double det3(const double *M)
{
    return M[0] * (M[4] * M[8] - M[5] * M[7]) - M[1] * (M[3] * M[8] - M[5] * M[6]) +
           M[2] * (M[3] * M[7] - M[4] * M[6]);
}

static void unit9(double *M)
{
    double s = 0.0;
    for (int i = 0; i < 9; i++)
        s += M[i] * M[i];
    s = 1.0 / sqrt(s);
    if (det3(M) < 0.0)
        s = -s;
    for (int i = 0; i < 9; i++)
        M[i] *= s;
}

static double dist9(const double *A, const double *B)
{
    double d = 0.0;
    for (int i = 0; i < 9; i++)
        d += (A[i] - B[i]) * (A[i] - B[i]);
    return sqrt(d);
}

/* A random plane seen by two cameras; kind 0 general, 1 small motion,
 * 2 strong perspective (oblique plane), 3 far plane. Writes n pixel pairs
 * and the true homography (unit Frobenius, det > 0). */
static void make_problem(sfm_test_ctx *t, int kind, int n, double *p1, double *p2, double Ht[9])
{
    double R[9], C2[3], nrm[3], d;
    sfm_test_random_unit(t, nrm);
    if (nrm[2] < 0.0)
        for (int i = 0; i < 3; i++)
            nrm[i] = -nrm[i];
    if (kind == 2) { /* oblique: normal nearly perpendicular to the view */
        nrm[2] = sfm_test_uniform(t, 0.05, 0.2);
        double s = sqrt(nrm[0] * nrm[0] + nrm[1] * nrm[1]);
        double k = sqrt(1.0 - nrm[2] * nrm[2]) / s;
        nrm[0] *= k;
        nrm[1] *= k;
    } else if (nrm[2] < 0.5) {
        nrm[2] += 0.5;
        double s = sqrt(nrm[0] * nrm[0] + nrm[1] * nrm[1] + nrm[2] * nrm[2]);
        for (int i = 0; i < 3; i++)
            nrm[i] /= s;
    }
    d = kind == 3 ? sfm_test_uniform(t, 50.0, 200.0) : sfm_test_uniform(t, 2.0, 10.0);
    /* small rotation of camera 2 so the plane stays in view */
    double ax[3];
    sfm_test_random_unit(t, ax);
    double ang = kind == 1 ? sfm_test_uniform(t, 1e-4, 1e-2) : sfm_test_uniform(t, 0.0, 0.5);
    double c = cos(ang), s = sin(ang), C = 1.0 - c;
    R[0] = c + ax[0] * ax[0] * C;         R[1] = ax[0] * ax[1] * C - ax[2] * s; R[2] = ax[0] * ax[2] * C + ax[1] * s;
    R[3] = ax[1] * ax[0] * C + ax[2] * s; R[4] = c + ax[1] * ax[1] * C;         R[5] = ax[1] * ax[2] * C - ax[0] * s;
    R[6] = ax[2] * ax[0] * C - ax[1] * s; R[7] = ax[2] * ax[1] * C + ax[0] * s; R[8] = c + ax[2] * ax[2] * C;
    sfm_test_random_unit(t, C2);
    double b = kind == 1 ? sfm_test_uniform(t, 0.01, 0.1) : sfm_test_uniform(t, 0.2, 1.0);
    for (int i = 0; i < 3; i++)
        C2[i] *= b;
    double tv[3];
    for (int i = 0; i < 3; i++)
        tv[i] = -(R[3 * i] * C2[0] + R[3 * i + 1] * C2[1] + R[3 * i + 2] * C2[2]);
    double f1 = sfm_test_uniform(t, 400, 1500), f2 = sfm_test_uniform(t, 400, 1500);
    double K1[9] = {f1, 0, 320, 0, f1, 240, 0, 0, 1}, K2[9] = {f2, 0, 330, 0, f2, 250, 0, 0, 1};
    double K1i[9] = {1 / f1, 0, -320 / f1, 0, 1 / f1, -240 / f1, 0, 0, 1};
    double A[9], M[9];
    for (int r = 0; r < 3; r++)
        for (int cc = 0; cc < 3; cc++)
            A[3 * r + cc] = R[3 * r + cc] + tv[r] * nrm[cc] / d;
    mm3(K2, A, M);
    mm3(M, K1i, Ht);
    unit9(Ht);
    for (int i = 0; i < n; i++) {
        double X[3], X2[3];
        int tries = 0;
        do {
            /* a ray through a random pixel, cut with the plane */
            double u = sfm_test_uniform(t, -0.5, 0.5), v = sfm_test_uniform(t, -0.4, 0.4);
            double den = nrm[0] * u + nrm[1] * v + nrm[2];
            double z = d / den;
            X[0] = u * z; X[1] = v * z; X[2] = z;
            for (int r = 0; r < 3; r++)
                X2[r] = R[3 * r] * X[0] + R[3 * r + 1] * X[1] + R[3 * r + 2] * X[2] + tv[r];
        } while ((X[2] <= 0.1 || X2[2] <= 0.1 || X[2] > 1e4) && ++tries < 1000);
        p1[2 * i] = K1[0] * X[0] / X[2] + K1[2];
        p1[2 * i + 1] = K1[4] * X[1] / X[2] + K1[5];
        p2[2 * i] = K2[0] * X2[0] / X2[2] + K2[2];
        p2[2 * i + 1] = K2[4] * X2[1] / X2[2] + K2[5];
    }
}

static const char *const KIND[4] = {"general", "small-motion", "oblique", "far"};

static int finite9(const double *m)
{
    for (int i = 0; i < 9; i++)
        if (!isfinite(m[i]))
            return 0;
    return 1;
}

SFM_TEST(homography_4pt_ground_truth_rate)
{
    const int iters = SFM_TEST_ITERS(5000);
    for (int kind = 0; kind < 4; kind++) {
        int found = 0;
        for (int it = 0; it < iters; it++) {
            double p1[8], p2[8], Ht[9];
            sfm_mat3 H;
            make_problem(t, kind, 4, p1, p2, Ht);
            int n = sfm_homography_4pt(p1, p2, &H);
            SFM_CHECK(n == 0 || n == 1);
            if (n == 1) {
                SFM_CHECK(finite9(H.m));
                SFM_CHECK(det3(H.m) > 0.0);
                if (dist9(H.m, Ht) < 1e-6)
                    found++;
            }
        }
        SFM_TEST_LOG("%-12s found %d/%d (%.3f%%)", KIND[kind], found, iters, 100.0 * found / iters);
        SFM_CHECK_MSG(found >= 0.999 * iters, "H4pt %s: %d of %d", KIND[kind], found, iters);
    }
}

SFM_TEST(homography_dlt_ground_truth_rate)
{
    const int iters = SFM_TEST_ITERS(2000);
    static const int sizes[3] = {4, 5, 40};
    for (int si = 0; si < 3; si++)
        for (int kind = 0; kind < 4; kind++) {
            int found = 0;
            for (int it = 0; it < iters; it++) {
                double p1[80], p2[80], Ht[9];
                sfm_mat3 H;
                make_problem(t, kind, sizes[si], p1, p2, Ht);
                int n = sfm_homography_dlt(p1, p2, sizes[si], &H);
                SFM_CHECK(n == 0 || n == 1);
                if (n == 1) {
                    SFM_CHECK(finite9(H.m));
                    if (dist9(H.m, Ht) < 1e-6)
                        found++;
                }
            }
            SFM_TEST_LOG("n=%d %-12s found %d/%d (%.3f%%)", sizes[si], KIND[kind], found, iters,
                         100.0 * found / iters);
            SFM_CHECK_MSG(found >= 0.999 * iters, "H dlt n=%d %s: %d of %d", sizes[si], KIND[kind],
                          found, iters);
        }
}

SFM_TEST(homography_maps_points)
{
    /* The 4-point homography maps its own four points exactly. */
    for (int it = 0; it < SFM_TEST_ITERS(500); it++) {
        double p1[8], p2[8], Ht[9];
        sfm_mat3 H;
        make_problem(t, 0, 4, p1, p2, Ht);
        SFM_CHECK_EQ_INT(sfm_homography_4pt(p1, p2, &H), 1);
        for (int i = 0; i < 4; i++) {
            const double *h = H.m, *a = p1 + 2 * i;
            double w = h[6] * a[0] + h[7] * a[1] + h[8];
            SFM_CHECK_NEAR((h[0] * a[0] + h[1] * a[1] + h[2]) / w, p2[2 * i], 1e-8);
            SFM_CHECK_NEAR((h[3] * a[0] + h[4] * a[1] + h[5]) / w, p2[2 * i + 1], 1e-8);
        }
    }
}

SFM_TEST(homography_degenerate)
{
    sfm_mat3 H;
    /* three collinear points in image 1 */
    double a[8] = {0, 0, 1, 1, 2, 2, 0, 5};
    double b[8] = {0, 0, 1, 0, 0, 1, 1, 1};
    SFM_CHECK_EQ_INT(sfm_homography_4pt(a, b, &H), 0);
    SFM_CHECK_EQ_INT(sfm_homography_4pt(b, a, &H), 0);
    /* identical points */
    double c[8] = {3, 4, 3, 4, 3, 4, 3, 4};
    SFM_CHECK_EQ_INT(sfm_homography_4pt(c, b, &H), 0);
    SFM_CHECK_EQ_INT(sfm_homography_dlt(c, b, 4, &H), 0);
    /* all points on one line: rank-deficient DLT */
    double l1[20], l2[20];
    for (int i = 0; i < 10; i++) {
        l1[2 * i] = i; l1[2 * i + 1] = 2.0 * i + 1.0;
        l2[2 * i] = 3.0 * i; l2[2 * i + 1] = -i;
    }
    SFM_CHECK_EQ_INT(sfm_homography_dlt(l1, l2, 10, &H), 0);
    SFM_CHECK_EQ_INT(sfm_homography_dlt(l1, l2, 4, &H), 0);
    /* nearly collinear (1e-13 off the line, relative): 0, never NaN */
    double e[8] = {0, 0, 1000, 1000, 2000, 2000 + 1e-10, 0, 500};
    int n = sfm_homography_4pt(e, b, &H);
    SFM_CHECK(n == 0 || (n == 1 && finite9(H.m)));
}

/* Every triple of the four points made collinear (the fourth point of the
 * triple moved onto the line of the other two), in image 1 or image 2 only,
 * at scales from 1e-3 to 1e3 and offsets up to 1e4 times the scale (larger
 * offsets round the moved point off the line by more than the tolerance, so
 * the points are no longer collinear as doubles): 0 solutions and
 * H untouched. Each case vanishes a different triple product of one image,
 * and the test must not depend on the scale or position of the points. */
SFM_TEST(homography_4pt_collinear_triples)
{
    static const int tri[4][3] = {{0, 1, 2}, {0, 1, 3}, {0, 2, 3}, {1, 2, 3}};
    for (int it = 0; it < SFM_TEST_ITERS(200); it++) {
        double p1[8], p2[8], Ht[9];
        make_problem(t, it % 4, 4, p1, p2, Ht);
        const double scale = pow(10.0, sfm_test_uniform(t, -3.0, 3.0));
        const double off = scale * sfm_test_uniform(t, -1e4, 1e4);
        for (int i = 0; i < 8; i++) {
            p1[i] = p1[i] * scale + off;
            p2[i] = p2[i] * scale - off;
        }
        for (int img = 0; img < 2; img++)
            for (int k = 0; k < 4; k++) {
                double q[2][8];
                memcpy(q[0], p1, sizeof p1);
                memcpy(q[1], p2, sizeof p2);
                double *p = q[img];
                const int a = tri[k][0], b = tri[k][1], c = tri[k][2];
                const double s = sfm_test_uniform(t, -2.0, 2.0);
                p[2 * c] = p[2 * a] + s * (p[2 * b] - p[2 * a]);
                p[2 * c + 1] = p[2 * a + 1] + s * (p[2 * b + 1] - p[2 * a + 1]);
                sfm_mat3 H;
                sfm_test_fill_canary(&H, sizeof H);
                SFM_CHECK_EQ_INT(sfm_homography_4pt(q[0], q[1], &H), 0);
                SFM_CHECK(sfm_test_canary_intact(&H, sizeof H));
            }
        /* the unmodified scaled problem still solves exactly */
        sfm_mat3 H;
        SFM_CHECK_EQ_INT(sfm_homography_4pt(p1, p2, &H), 1);
        SFM_CHECK(finite9(H.m));
    }
    /* non-finite input in image 2 only (lane 1): status, nothing written */
    double p1[8], p2[8], Ht[9];
    make_problem(t, 0, 4, p1, p2, Ht);
    sfm_mat3 H;
    sfm_test_fill_canary(&H, sizeof H);
    p2[7] = HUGE_VAL;
    SFM_CHECK_EQ_INT(sfm_homography_4pt(p1, p2, &H), SFM_E_NONFINITE);
    p2[7] = (double)NAN;
    SFM_CHECK_EQ_INT(sfm_homography_4pt(p1, p2, &H), SFM_E_NONFINITE);
    SFM_CHECK(sfm_test_canary_intact(&H, sizeof H));
}

SFM_TEST(homography_contract)
{
    double p1[8], p2[8], Ht[9], q1[20], q2[20];
    make_problem(t, 0, 4, p1, p2, Ht);
    make_problem(t, 0, 10, q1, q2, Ht);
    sfm_mat3 H;
    sfm_test_fill_canary(&H, sizeof H);
    SFM_CHECK_EQ_INT(sfm_homography_4pt(NULL, p2, &H), SFM_E_ARGUMENT);
    SFM_CHECK_EQ_INT(sfm_homography_4pt(p1, NULL, &H), SFM_E_ARGUMENT);
    SFM_CHECK_EQ_INT(sfm_homography_4pt(p1, p2, NULL), SFM_E_ARGUMENT);
    SFM_CHECK_EQ_INT(sfm_homography_dlt(q1, q2, 3, &H), SFM_E_ARGUMENT);
    SFM_CHECK_EQ_INT(sfm_homography_dlt(NULL, q2, 10, &H), SFM_E_ARGUMENT);
    SFM_CHECK_EQ_INT(sfm_homography_dlt(q1, q2, 10, NULL), SFM_E_ARGUMENT);
    p1[5] = (double)NAN;
    q2[19] = HUGE_VAL;
    SFM_CHECK_EQ_INT(sfm_homography_4pt(p1, p2, &H), SFM_E_NONFINITE);
    SFM_CHECK_EQ_INT(sfm_homography_dlt(q1, q2, 10, &H), SFM_E_NONFINITE);
    SFM_CHECK(sfm_test_canary_intact(&H, sizeof H));
}
