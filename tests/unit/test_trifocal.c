#include <math.h>
#include <string.h>

#include "sfm/sfm.h"
#include "sfm_test.h"
#include "solvers/trifocal_internal.h"

/* Random camera P = K [R | t] looking at the origin region. */
static void random_camera(sfm_test_ctx *t, double P[12], double center_scale)
{
    double R[9], c[3], K[9] = {500 + sfm_test_uniform(t, -50, 50), 0, 320, 0, 520, 240, 0, 0, 1};
    sfm_test_random_rotation(t, R);
    for (int k = 0; k < 3; k++)
        c[k] = sfm_test_normal(t, center_scale);
    /* Camera on the -z side of the scene: centre = -4 * (third row of R) + c */
    double C[3];
    for (int k = 0; k < 3; k++)
        C[k] = -4.0 * R[6 + k] + c[k];
    double tt[3];
    for (int r = 0; r < 3; r++)
        tt[r] = -(R[r * 3] * C[0] + R[r * 3 + 1] * C[1] + R[r * 3 + 2] * C[2]);
    for (int r = 0; r < 3; r++)
        for (int col = 0; col < 4; col++) {
            double s = 0;
            for (int k = 0; k < 3; k++)
                s += K[r * 3 + k] * (col < 3 ? R[k * 3 + col] : tt[k]);
            P[r * 4 + col] = s;
        }
}

static int project(const double P[12], const double X[3], double x[2])
{
    double p[3];
    for (int r = 0; r < 3; r++)
        p[r] = P[r * 4] * X[0] + P[r * 4 + 1] * X[1] + P[r * 4 + 2] * X[2] + P[r * 4 + 3];
    if (!(p[2] > 1e-9))
        return 0;
    x[0] = p[0] / p[2];
    x[1] = p[1] / p[2];
    return 1;
}

static double dist_up_to_sign(const double *a, const double *b, int n)
{
    double na = 0, nb = 0;
    for (int i = 0; i < n; i++) {
        na += a[i] * a[i];
        nb += b[i] * b[i];
    }
    na = sqrt(na);
    nb = sqrt(nb);
    double dp = 0, dm = 0;
    for (int i = 0; i < n; i++) {
        dp += (a[i] / na - b[i] / nb) * (a[i] / na - b[i] / nb);
        dm += (a[i] / na + b[i] / nb) * (a[i] / na + b[i] / nb);
    }
    return sqrt(dp < dm ? dp : dm);
}

/* Three cameras, the first one arbitrary (not [I | 0]). */
static void three_cameras(sfm_test_ctx *t, double P[3][12])
{
    for (int v = 0; v < 3; v++)
        random_camera(t, P[v], 1.0);
}

static void random_point(sfm_test_ctx *t, double X[3])
{
    for (int k = 0; k < 3; k++)
        X[k] = sfm_test_uniform(t, -1, 1);
}

SFM_TEST(trifocal_from_canonical_cameras_matches_closed_form)
{
    for (int it = 0; it < SFM_TEST_ITERS(200); it++) {
        double P1[12] = {1, 0, 0, 0, 0, 1, 0, 0, 0, 0, 1, 0}, P2[12], P3[12], T[27], Tc[27];
        for (int k = 0; k < 12; k++) {
            P2[k] = sfm_test_normal(t, 1);
            P3[k] = sfm_test_normal(t, 1);
        }
        /* T_i = a_i b4^T - a4 b_i^T (H&Z eq. 15.1) */
        for (int i = 0; i < 3; i++)
            for (int j = 0; j < 3; j++)
                for (int k = 0; k < 3; k++)
                    Tc[i * 9 + j * 3 + k] = P2[j * 4 + i] * P3[k * 4 + 3] - P2[j * 4 + 3] * P3[k * 4 + i];
        SFM_CHECK_EQ_INT(sfm_trifocal_from_cameras(P1, P2, P3, T), SFM_OK);
        double n = 0, nc = 0;
        for (int k = 0; k < 27; k++) {
            n += T[k] * T[k];
            nc += Tc[k] * Tc[k];
        }
        SFM_CHECK_NEAR(n, 1.0, 1e-12);
        /* same sign, not only up to sign: the determinant formula is exact */
        double d = 0;
        for (int k = 0; k < 27; k++)
            d += (T[k] - Tc[k] / sqrt(nc)) * (T[k] - Tc[k] / sqrt(nc));
        SFM_CHECK_NEAR(sqrt(d), 0.0, 1e-10);
    }
}

SFM_TEST(trifocal_invariant_to_projective_frame)
{
    for (int it = 0; it < SFM_TEST_ITERS(100); it++) {
        double P[3][12], PH[3][12], H[16], T[27], TH[27];
        three_cameras(t, P);
        for (int k = 0; k < 16; k++)
            H[k] = sfm_test_normal(t, 1) + (k % 5 == 0 ? 3.0 : 0.0);
        for (int v = 0; v < 3; v++)
            for (int r = 0; r < 3; r++)
                for (int c = 0; c < 4; c++) {
                    double s = 0;
                    for (int k = 0; k < 4; k++)
                        s += P[v][r * 4 + k] * H[k * 4 + c];
                    PH[v][r * 4 + c] = s;
                }
        SFM_CHECK_EQ_INT(sfm_trifocal_from_cameras(P[0], P[1], P[2], T), SFM_OK);
        SFM_CHECK_EQ_INT(sfm_trifocal_from_cameras(PH[0], PH[1], PH[2], TH), SFM_OK);
        SFM_CHECK(dist_up_to_sign(T, TH, 27) < 1e-9);
    }
}

SFM_TEST(trifocal_incidence_epipoles_fundamentals_transfer)
{
    int bad = 0;
    for (int it = 0; it < SFM_TEST_ITERS(200); it++) {
        double P[3][12], T[27], e2[3], e3[3];
        sfm_mat3 F21, F31, F32;
        three_cameras(t, P);
        SFM_CHECK_EQ_INT(sfm_trifocal_from_cameras(P[0], P[1], P[2], T), SFM_OK);
        SFM_CHECK_EQ_INT(sfm_trifocal_epipoles(T, e2, e3), SFM_OK);
        SFM_CHECK_EQ_INT(sfm_trifocal_fundamentals(T, &F21, &F31, &F32), SFM_OK);
        /* Epipoles are the images of the first camera centre. */
        double A[12], S[3], V[16], C[4], ws_buf[1024];
        memcpy(A, P[0], sizeof A);
        SFM_CHECK_EQ_INT(sfm_svd(A, 3, 4, NULL, S, V, ws_buf, sizeof ws_buf), SFM_OK);
        for (int k = 0; k < 4; k++)
            C[k] = V[k * 4 + 3];
        double i2[3], i3[3];
        for (int r = 0; r < 3; r++) {
            i2[r] = i3[r] = 0;
            for (int k = 0; k < 4; k++) {
                i2[r] += P[1][r * 4 + k] * C[k];
                i3[r] += P[2][r * 4 + k] * C[k];
            }
        }
        SFM_CHECK(dist_up_to_sign(e2, i2, 3) < 1e-8);
        SFM_CHECK(dist_up_to_sign(e3, i3, 3) < 1e-8);
        for (int p = 0; p < 10; p++) {
            double X[3], x[3][2];
            random_point(t, X);
            if (!project(P[0], X, x[0]) || !project(P[1], X, x[1]) || !project(P[2], X, x[2]))
                continue;
            double h[3][3];
            for (int v = 0; v < 3; v++) {
                h[v][0] = x[v][0] / 500;
                h[v][1] = x[v][1] / 500;
                h[v][2] = 1.0 / 500;
            }
            /* [x2]_x (sum_i x1^i T_i) [x3]_x = 0 */
            double M[9] = {0}, worst = 0;
            for (int i = 0; i < 3; i++)
                for (int k = 0; k < 9; k++)
                    M[k] += h[0][i] * T[i * 9 + k];
            double S2[9] = {0, -h[1][2], h[1][1], h[1][2], 0, -h[1][0], -h[1][1], h[1][0], 0};
            double S3[9] = {0, -h[2][2], h[2][1], h[2][2], 0, -h[2][0], -h[2][1], h[2][0], 0};
            for (int r = 0; r < 3; r++)
                for (int c = 0; c < 3; c++) {
                    double s = 0;
                    for (int a = 0; a < 3; a++)
                        for (int b = 0; b < 3; b++)
                            s += S2[r * 3 + a] * M[a * 3 + b] * S3[b * 3 + c];
                    if (fabs(s) > worst)
                        worst = fabs(s);
                }
            SFM_CHECK(worst < 1e-12);
            /* Epipolar constraints, in pixel-normalized units. */
            double f21 = 0, f31 = 0, f32 = 0;
            for (int r = 0; r < 3; r++)
                for (int c = 0; c < 3; c++) {
                    f21 += h[1][r] * F21.m[r * 3 + c] * h[0][c];
                    f31 += h[2][r] * F31.m[r * 3 + c] * h[0][c];
                    f32 += h[2][r] * F32.m[r * 3 + c] * h[1][c];
                }
            SFM_CHECK(fabs(f21) < 1e-10 && fabs(f31) < 1e-10 && fabs(f32) < 1e-10);
            double x3[2];
            int st = sfm_trifocal_transfer(T, &F21, x[0], x[1], x3);
            if (st != SFM_OK || hypot(x3[0] - x[2][0], x3[1] - x[2][1]) > 1e-6)
                bad++;
        }
    }
    SFM_CHECK_EQ_INT(bad, 0);
}

SFM_TEST(trifocal_cameras_reproduce_tensor)
{
    for (int it = 0; it < SFM_TEST_ITERS(200); it++) {
        double P[3][12], T[27], P2[12], P3[12], T2[27];
        const double I[12] = {1, 0, 0, 0, 0, 1, 0, 0, 0, 0, 1, 0};
        three_cameras(t, P);
        SFM_CHECK_EQ_INT(sfm_trifocal_from_cameras(P[0], P[1], P[2], T), SFM_OK);
        SFM_CHECK_EQ_INT(sfm_trifocal_cameras(T, P2, P3), SFM_OK);
        SFM_CHECK_EQ_INT(sfm_trifocal_from_cameras(I, P2, P3, T2), SFM_OK);
        SFM_CHECK(dist_up_to_sign(T, T2, 27) < 1e-8);
    }
}

/* Projections of n random points seen in front of all three cameras. */
static int make_triplets(sfm_test_ctx *t, double P[3][12], int n, double *x1, double *x2,
                         double *x3, double sigma)
{
    int got = 0, tries = 0;
    while (got < n && tries < 100 * n) {
        double X[3], a[2], b[2], c[2];
        tries++;
        random_point(t, X);
        if (!project(P[0], X, a) || !project(P[1], X, b) || !project(P[2], X, c))
            continue;
        x1[2 * got] = a[0] + sfm_test_normal(t, sigma);
        x1[2 * got + 1] = a[1] + sfm_test_normal(t, sigma);
        x2[2 * got] = b[0] + sfm_test_normal(t, sigma);
        x2[2 * got + 1] = b[1] + sfm_test_normal(t, sigma);
        x3[2 * got] = c[0] + sfm_test_normal(t, sigma);
        x3[2 * got + 1] = c[1] + sfm_test_normal(t, sigma);
        got++;
    }
    return got == n;
}

static unsigned char tf_ws[256 * 1024];

SFM_TEST(trifocal_7pt_exact_on_noise_free_triplets)
{
    SFM_CHECK(sfm_trifocal_7pt_workspace_size() <= sizeof tf_ws);
    int found = 0, total = 0;
    for (int it = 0; it < SFM_TEST_ITERS(300); it++) {
        double P[3][12], T[27], Te[27], x1[2 * 40], x2[2 * 40], x3[2 * 40];
        three_cameras(t, P);
        int n = it % 2 ? 7 : 40;
        if (!make_triplets(t, P, n, x1, x2, x3, 0.0))
            continue;
        SFM_CHECK_EQ_INT(sfm_trifocal_from_cameras(P[0], P[1], P[2], T), SFM_OK);
        int st = sfm_trifocal_7pt(x1, x2, x3, n, Te, tf_ws, sizeof tf_ws);
        total++;
        if (st == SFM_OK && dist_up_to_sign(T, Te, 27) < 1e-6)
            found++;
    }
    SFM_TEST_LOG("tensor recovered in %d of %d noise-free problems", found, total);
    SFM_CHECK(found >= total - total / 1000);
}

SFM_TEST(trifocal_7pt_transfer_error_near_noise_floor)
{
    double sum = 0;
    int cnt = 0;
    for (int it = 0; it < SFM_TEST_ITERS(50); it++) {
        double P[3][12], Te[27], x1[2 * 100], x2[2 * 100], x3[2 * 100];
        sfm_mat3 F21;
        double y1[2 * 100], y2[2 * 100], y3[2 * 100];
        three_cameras(t, P);
        if (!make_triplets(t, P, 100, x1, x2, x3, 0.0))
            continue;
        memcpy(y1, x1, sizeof y1);
        memcpy(y2, x2, sizeof y2);
        memcpy(y3, x3, sizeof y3);
        for (int k = 0; k < 200; k++) {
            y1[k] += sfm_test_normal(t, 0.5);
            y2[k] += sfm_test_normal(t, 0.5);
            y3[k] += sfm_test_normal(t, 0.5);
        }
        SFM_CHECK_EQ_INT(sfm_trifocal_7pt(y1, y2, y3, 100, Te, tf_ws, sizeof tf_ws), SFM_OK);
        SFM_CHECK_EQ_INT(sfm_trifocal_fundamentals(Te, &F21, NULL, NULL), SFM_OK);
        /* transfer noise-free x1, x2 through the estimated tensor */
        for (int p = 0; p < 100; p++) {
            double x3p[2];
            if (sfm_trifocal_transfer(Te, &F21, &x1[2 * p], &x2[2 * p], x3p) != SFM_OK)
                continue;
            sum += hypot(x3p[0] - x3[2 * p], x3p[1] - x3[2 * p + 1]);
            cnt++;
        }
    }
    double mean = sum / cnt;
    SFM_TEST_LOG("mean transfer error %.3f px with 0.5 px noise, 100 triplets", mean);
    SFM_CHECK(cnt > 0);
    SFM_CHECK(mean < 1.0);
}

/* Collinear camera centres (a robot driving straight): all epipolar lines of
 * a point coincide, so a wrong match slid along that line passes every
 * pairwise epipolar test; the trifocal error sees it. */
SFM_TEST(trifocal_rejects_match_on_shared_epipolar_line)
{
    double K[9] = {500, 0, 320, 0, 500, 240, 0, 0, 1}, P[3][12];
    for (int v = 0; v < 3; v++) {
        double C[3] = {0.3 * v, 0.05 * v, 0.0};
        for (int r = 0; r < 3; r++)
            for (int c = 0; c < 4; c++)
                P[v][r * 4 + c] = c < 3 ? K[r * 3 + c] : -(K[r * 3] * C[0] + K[r * 3 + 1] * C[1] + K[r * 3 + 2] * C[2]);
    }
    double T[27];
    sfm_mat3 F21, F31, F32;
    SFM_CHECK_EQ_INT(sfm_trifocal_from_cameras(P[0], P[1], P[2], T), SFM_OK);
    SFM_CHECK_EQ_INT(sfm_trifocal_fundamentals(T, &F21, &F31, &F32), SFM_OK);
    int caught = 0;
    for (int it = 0; it < 20; it++) {
        double X[3] = {sfm_test_uniform(t, -1, 1), sfm_test_uniform(t, -1, 1), sfm_test_uniform(t, 3, 6)};
        double x[3][2];
        SFM_CHECK(project(P[0], X, x[0]) && project(P[1], X, x[1]) && project(P[2], X, x[2]));
        /* wrong match in view 3: the same epipolar line, 15 px away */
        double l[3];
        const double h1[3] = {x[0][0], x[0][1], 1};
        for (int r = 0; r < 3; r++)
            l[r] = F31.m[r * 3] * h1[0] + F31.m[r * 3 + 1] * h1[1] + F31.m[r * 3 + 2] * h1[2];
        double dn = hypot(l[0], l[1]);
        double w[2] = {x[2][0] + 15.0 * l[1] / dn, x[2][1] - 15.0 * l[0] / dn};
        /* pairwise epipolar distances of the wrong triplet stay tiny */
        const double h2[3] = {x[1][0], x[1][1], 1}, hw[3] = {w[0], w[1], 1};
        double d31 = 0, d32 = 0, l32[3];
        for (int r = 0; r < 3; r++) {
            d31 += hw[r] * l[r];
            l32[r] = F32.m[r * 3] * h2[0] + F32.m[r * 3 + 1] * h2[1] + F32.m[r * 3 + 2] * h2[2];
            d32 += hw[r] * l32[r];
        }
        d31 = fabs(d31) / dn;
        d32 = fabs(d32) / hypot(l32[0], l32[1]);
        SFM_CHECK(d31 < 1e-6 && d32 < 1e-6);
        double e_true, e_wrong;
        SFM_CHECK_EQ_INT(sfm_trifocal_point_error(P[0], P[1], P[2], x[0], x[1], x[2], &e_true, NULL), SFM_OK);
        SFM_CHECK_EQ_INT(sfm_trifocal_point_error(P[0], P[1], P[2], x[0], x[1], w, &e_wrong, NULL), SFM_OK);
        SFM_CHECK(e_true < 1e-12);
        if (e_wrong > 4.0 * 4.0)
            caught++;
    }
    SFM_CHECK_EQ_INT(caught, 20);
}

SFM_TEST(trifocal_point_error_is_geometric)
{
    for (int it = 0; it < SFM_TEST_ITERS(200); it++) {
        double P[3][12], X[3], x[3][2], y[3][2], e, Xh[4];
        three_cameras(t, P);
        random_point(t, X);
        if (!project(P[0], X, x[0]) || !project(P[1], X, x[1]) || !project(P[2], X, x[2]))
            continue;
        SFM_CHECK_EQ_INT(sfm_trifocal_point_error(P[0], P[1], P[2], x[0], x[1], x[2], &e, Xh), SFM_OK);
        SFM_CHECK(e < 1e-14);
        SFM_CHECK_NEAR(Xh[0] / Xh[3], X[0], 1e-8);
        double d2 = 0;
        for (int v = 0; v < 3; v++)
            for (int k = 0; k < 2; k++) {
                double n = sfm_test_normal(t, 1.0);
                y[v][k] = x[v][k] + n;
                d2 += n * n;
            }
        SFM_CHECK_EQ_INT(sfm_trifocal_point_error(P[0], P[1], P[2], y[0], y[1], y[2], &e, NULL), SFM_OK);
        /* optimal error can only be below the error at the true point, and
         * removes about 3 of the 6 degrees of freedom of the noise */
        SFM_CHECK(e <= d2 * (1 + 1e-9));
    }
}

SFM_TEST(trifocal_contracts)
{
    double P[12] = {1, 0, 0, 0, 0, 1, 0, 0, 0, 0, 1, 0}, T[27], x[14] = {0}, out[27];
    SFM_CHECK_EQ_INT(sfm_trifocal_from_cameras(NULL, P, P, T), SFM_E_ARGUMENT);
    /* identical cameras: the tensor vanishes */
    sfm_test_fill_canary(out, sizeof out);
    SFM_CHECK_EQ_INT(sfm_trifocal_from_cameras(P, P, P, out), SFM_E_SINGULAR);
    SFM_CHECK(sfm_test_canary_intact(out, sizeof out));
    double Pn[12];
    memcpy(Pn, P, sizeof Pn);
    Pn[5] = (double)NAN;
    SFM_CHECK_EQ_INT(sfm_trifocal_from_cameras(P, Pn, P, out), SFM_E_NONFINITE);
    SFM_CHECK_EQ_INT(sfm_trifocal_7pt(x, x, x, 6, out, tf_ws, sizeof tf_ws), SFM_E_ARGUMENT);
    /* all points identical: normalization is singular, nothing written */
    SFM_CHECK_EQ_INT(sfm_trifocal_7pt(x, x, x, 7, out, tf_ws, sizeof tf_ws), SFM_E_SINGULAR);
    SFM_CHECK(sfm_test_canary_intact(out, sizeof out));
    double xs[14];
    for (int k = 0; k < 14; k++)
        xs[k] = sfm_test_uniform(t, 0, 100);
    SFM_CHECK_EQ_INT(sfm_trifocal_7pt(xs, xs, xs, 7, out, tf_ws, sfm_trifocal_7pt_workspace_size() - 1),
                     SFM_E_WORKSPACE);
    SFM_CHECK(sfm_test_canary_intact(out, sizeof out));
    xs[3] = HUGE_VAL;
    SFM_CHECK_EQ_INT(sfm_trifocal_7pt(xs, xs, xs, 7, out, tf_ws, sizeof tf_ws), SFM_E_NONFINITE);
    double e;
    SFM_CHECK_EQ_INT(sfm_trifocal_point_error(P, P, P, x, x, x, NULL, NULL), SFM_E_ARGUMENT);
    SFM_CHECK_EQ_INT(sfm_trifocal_point_error(P, P, Pn, x, x, x, &e, NULL), SFM_E_NONFINITE);
    double l[3] = {1, 2, 3};
    SFM_CHECK_EQ_INT(sfm_trifocal_transfer_line(NULL, l, l, l), SFM_E_ARGUMENT);
    SFM_CHECK_EQ_INT(sfm_trifocal_epipoles(T, NULL, l), SFM_E_ARGUMENT);
}

/* The six-point minimal solver (solvers/trifocal_6pt.c): on noise-free
 * triplets every solution reproduces its six triplets (three-view
 * reprojection error after optimal triangulation under the solution's
 * cameras), one of them is the true tensor, and a seventh triplet, which
 * the solver never sees, fits that one. A sample with three of its first
 * four points collinear in a view gives no solution. */
SFM_TEST(trifocal_6pt_minimal_solutions_contain_truth)
{
    static const double I34[12] = {1, 0, 0, 0, 0, 1, 0, 0, 0, 0, 1, 0};
    int found = 0, total = 0, sols = 0, worst_fit_bad = 0;
    double worst_fit = 0.0;
    for (int it = 0; it < SFM_TEST_ITERS(500); it++) {
        double P[3][12], T[27], x1[14], x2[14], x3[14];
        three_cameras(t, P);
        if (!make_triplets(t, P, 7, x1, x2, x3, 0.0))
            continue;
        SFM_CHECK_EQ_INT(sfm_trifocal_from_cameras(P[0], P[1], P[2], T), SFM_OK);
        double P2[3][12], P3[3][12];
        int k = sfmi_trifocal_6pt(x1, x2, x3, NULL, P2, P3);
        SFM_CHECK(k >= 0 && k <= 3);
        {   /* the same sample through an index list: the same bits */
            static const int idx[6] = {0, 1, 2, 3, 4, 5};
            double Q2[3][12], Q3[3][12];
            SFM_CHECK_EQ_INT(sfmi_trifocal_6pt(x1, x2, x3, idx, Q2, Q3), k);
            SFM_CHECK(k == 0 || (memcmp(P2, Q2, sizeof(double) * 12 * (size_t)k) == 0 &&
                                 memcmp(P3, Q3, sizeof(double) * 12 * (size_t)k) == 0));
        }
        total++;
        sols += k;
        int hit = 0;
        for (int s = 0; s < k; s++) {
            double Ts[27], e, X[4];
            if (sfm_trifocal_from_cameras(I34, P2[s], P3[s], Ts) != SFM_OK)
                continue;
            for (int p = 0; p < 6; p++) {
                if (sfm_trifocal_point_error(I34, P2[s], P3[s], &x1[2 * p], &x2[2 * p], &x3[2 * p],
                                             &e, X) != SFM_OK)
                    e = HUGE_VAL;
                if (!(e < 1e-12))
                    worst_fit_bad++;
                else if (e > worst_fit)
                    worst_fit = e;
            }
            if (dist_up_to_sign(T, Ts, 27) < 1e-6 &&
                sfm_trifocal_point_error(I34, P2[s], P3[s], &x1[12], &x2[12], &x3[12], &e, X) ==
                    SFM_OK &&
                e < 1e-12)
                hit = 1;
        }
        found += hit;
    }
    SFM_TEST_LOG("6-point: truth in %d of %d problems, %.2f solutions each, worst fit %.1e px2, "
                 "%d triplets not reproduced",
                 found, total, (double)sols / (total > 0 ? total : 1), worst_fit, worst_fit_bad);
    SFM_CHECK(found >= total - total / 200);
    SFM_CHECK(worst_fit_bad <= total / 200);

    double P[3][12], x1[14], x2[14], x3[14], P2[3][12], P3[3][12];
    three_cameras(t, P);
    SFM_CHECK(make_triplets(t, P, 7, x1, x2, x3, 0.0));
    x1[4] = 0.5 * (x1[0] + x1[2]);
    x1[5] = 0.5 * (x1[1] + x1[3]);
    SFM_CHECK_EQ_INT(sfmi_trifocal_6pt(x1, x2, x3, NULL, P2, P3), 0);
}
