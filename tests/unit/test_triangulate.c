/*
 * Triangulation (DLT, midpoint, optimal two-view) against synthetic scenes
 * with known points, including points behind a camera and at infinity.
 */
#include <math.h>
#include <string.h>

#include "sfm/sfm.h"
#include "sfm_test.h"

#define TV_MAX 6
#define TP_MAX 64

static const double Kpix[9] = {800, 0, 320, 0, 780, 240, 0, 0, 1};

typedef struct scene {
    int nv, np;
    sfm_pose pose[TV_MAX];
    double Pn[TV_MAX * 12]; /* [R | t] */
    double Pp[TV_MAX * 12]; /* K [R | t] */
    double X[TP_MAX * 3];
    double xn[TV_MAX * TP_MAX * 2]; /* normalized observations */
    double xp[TV_MAX * TP_MAX * 2]; /* pixel observations */
    double f[TV_MAX * TP_MAX * 3];  /* bearings */
} scene;

static void look_at(sfm_test_ctx *t, const double c[3], double R[9])
{
    /* z axis towards the origin (plus a little jitter), x, y completing */
    double z[3] = {-c[0], -c[1], -c[2]};
    for (int k = 0; k < 3; k++)
        z[k] += sfm_test_uniform(t, -0.3, 0.3);
    double n = sqrt(z[0] * z[0] + z[1] * z[1] + z[2] * z[2]);
    for (int k = 0; k < 3; k++)
        z[k] /= n;
    double up[3];
    sfm_test_random_unit(t, up);
    double x[3] = {up[1] * z[2] - up[2] * z[1], up[2] * z[0] - up[0] * z[2], up[0] * z[1] - up[1] * z[0]};
    n = sqrt(x[0] * x[0] + x[1] * x[1] + x[2] * x[2]);
    for (int k = 0; k < 3; k++)
        x[k] /= n;
    double y[3] = {z[1] * x[2] - z[2] * x[1], z[2] * x[0] - z[0] * x[2], z[0] * x[1] - z[1] * x[0]};
    for (int k = 0; k < 3; k++) {
        R[k] = x[k];
        R[3 + k] = y[k];
        R[6 + k] = z[k];
    }
}

static void project_all(scene *s, double sigma_px, sfm_test_ctx *t)
{
    for (int v = 0; v < s->nv; v++) {
        const double *R = s->pose[v].R, *tr = s->pose[v].t;
        for (int j = 0; j < s->np; j++) {
            const double *X = s->X + 3 * j;
            double xc[3];
            for (int r = 0; r < 3; r++)
                xc[r] = R[3 * r] * X[0] + R[3 * r + 1] * X[1] + R[3 * r + 2] * X[2] + tr[r];
            double u = xc[0] / xc[2], w = xc[1] / xc[2];
            double pu = Kpix[0] * u + Kpix[2] + sfm_test_normal(t, sigma_px);
            double pv = Kpix[4] * w + Kpix[5] + sfm_test_normal(t, sigma_px);
            long o = (long)v * s->np + j;
            s->xp[2 * o] = pu;
            s->xp[2 * o + 1] = pv;
            s->xn[2 * o] = (pu - Kpix[2]) / Kpix[0];
            s->xn[2 * o + 1] = (pv - Kpix[5]) / Kpix[4];
            /* bearing: the (noisy) normalized ray through the pixel */
            s->f[3 * o] = s->xn[2 * o];
            s->f[3 * o + 1] = s->xn[2 * o + 1];
            s->f[3 * o + 2] = 1.0;
        }
    }
}

static void make_scene(sfm_test_ctx *t, scene *s, int nv, int np, double radius, double sigma_px)
{
    s->nv = nv;
    s->np = np;
    for (int v = 0; v < nv; v++) {
        double c[3];
        sfm_test_random_unit(t, c);
        for (int k = 0; k < 3; k++)
            c[k] *= radius;
        look_at(t, c, s->pose[v].R);
        const double *R = s->pose[v].R;
        for (int r = 0; r < 3; r++)
            s->pose[v].t[r] = -(R[3 * r] * c[0] + R[3 * r + 1] * c[1] + R[3 * r + 2] * c[2]);
        for (int r = 0; r < 3; r++) {
            for (int k = 0; k < 3; k++)
                s->Pn[12 * v + 4 * r + k] = R[3 * r + k];
            s->Pn[12 * v + 4 * r + 3] = s->pose[v].t[r];
        }
        for (int r = 0; r < 3; r++)
            for (int k = 0; k < 4; k++)
                s->Pp[12 * v + 4 * r + k] = Kpix[3 * r] * s->Pn[12 * v + k] +
                                            Kpix[3 * r + 1] * s->Pn[12 * v + 4 + k] +
                                            Kpix[3 * r + 2] * s->Pn[12 * v + 8 + k];
    }
    for (int j = 0; j < np; j++)
        for (int k = 0; k < 3; k++)
            s->X[3 * j + k] = sfm_test_uniform(t, -1.0, 1.0);
    project_all(s, sigma_px, t);
}

static double point_err(const double *a, const double *b)
{
    double e = 0.0;
    for (int k = 0; k < 3; k++)
        e = fmax(e, fabs(a[k] - b[k]));
    return e;
}

/* d with x < 10^-d (0 for x >= 1) */
static int digits(double x)
{
    int d = 0;
    while (x < 1.0 && x > 0.0 && d < 30) {
        x *= 10.0;
        d++;
    }
    return d > 0 ? d - 1 : 0;
}

static double reproj_sq(const double P[12], const double X[3], const double x[2])
{
    double p[3];
    for (int r = 0; r < 3; r++)
        p[r] = P[4 * r] * X[0] + P[4 * r + 1] * X[1] + P[4 * r + 2] * X[2] + P[4 * r + 3];
    double du = p[0] / p[2] - x[0], dv = p[1] / p[2] - x[1];
    return du * du + dv * dv;
}

SFM_TEST(triangulate_noise_free_all_methods)
{
    static scene s;
    static double X[TP_MAX * 3];
    static int fl[TP_MAX];
    const int iters = SFM_TEST_ITERS(500);
    double worst[4] = {0, 0, 0, 0};
    int flagged = 0;
    for (int it = 0; it < iters; it++) {
        int nv = 2 + it % (TV_MAX - 1);
        make_scene(t, &s, nv, 32, sfm_test_uniform(t, 3.0, 20.0), 0.0);
        int n = sfm_triangulate_dlt(nv, s.Pp, s.np, s.xp, X, fl);
        SFM_CHECK_EQ_INT(n, s.np);
        for (int j = 0; j < s.np; j++) {
            worst[0] = fmax(worst[0], point_err(X + 3 * j, s.X + 3 * j));
            flagged += fl[j] != 0;
        }
        n = sfm_triangulate_dlt(nv, s.Pn, s.np, s.xn, X, fl);
        SFM_CHECK_EQ_INT(n, s.np);
        for (int j = 0; j < s.np; j++)
            worst[1] = fmax(worst[1], point_err(X + 3 * j, s.X + 3 * j));
        n = sfm_triangulate_midpoint(nv, s.pose, s.np, s.f, X, fl);
        SFM_CHECK_EQ_INT(n, s.np);
        for (int j = 0; j < s.np; j++)
            worst[2] = fmax(worst[2], point_err(X + 3 * j, s.X + 3 * j));
        n = sfm_triangulate_optimal2(s.Pp, s.Pp + 12, s.np, s.xp, s.xp + 2 * s.np, X, fl);
        SFM_CHECK_EQ_INT(n, s.np);
        for (int j = 0; j < s.np; j++)
            worst[3] = fmax(worst[3], point_err(X + 3 * j, s.X + 3 * j));
    }
    /* integers only: formatting a double needs a heap under newlib */
    SFM_TEST_LOG("worst error below 1e-%d (dlt-pixel), 1e-%d (dlt-normalized), 1e-%d "
                 "(midpoint), 1e-%d (optimal)",
                 digits(worst[0]), digits(worst[1]), digits(worst[2]), digits(worst[3]));
    SFM_CHECK_EQ_INT(flagged, 0);
    for (int m = 0; m < 4; m++)
        SFM_CHECK(worst[m] < 1e-8);
}

SFM_TEST(triangulate_fundamental_from_projections)
{
    static scene s;
    for (int it = 0; it < SFM_TEST_ITERS(200); it++) {
        make_scene(t, &s, 2, 16, 5.0, 0.0);
        sfm_mat3 F;
        SFM_CHECK_EQ_INT(sfm_fundamental_from_projections(s.Pp, s.Pp + 12, &F), SFM_OK);
        for (int j = 0; j < s.np; j++) {
            const double *a = s.xp + 2 * j, *b = s.xp + 2 * (s.np + j);
            double Fa[3];
            for (int r = 0; r < 3; r++)
                Fa[r] = F.m[3 * r] * a[0] + F.m[3 * r + 1] * a[1] + F.m[3 * r + 2];
            double e = b[0] * Fa[0] + b[1] * Fa[1] + Fa[2];
            /* distance of b to the epipolar line, pixels */
            SFM_CHECK(fabs(e) / hypot(Fa[0], Fa[1]) < 1e-8);
        }
    }
    sfm_mat3 F;
    static scene s2;
    make_scene(t, &s2, 2, 1, 5.0, 0.0);
    double P2[12];
    memcpy(P2, s2.Pp, sizeof P2);
    /* same centre: F = 0 */
    SFM_CHECK_EQ_INT(sfm_fundamental_from_projections(s2.Pp, P2, &F), SFM_E_ARGUMENT);
}

SFM_TEST(triangulate_optimal_beats_dlt_with_noise)
{
    static scene s;
    static double Xd[TP_MAX * 3], Xo[TP_MAX * 3];
    const int iters = SFM_TEST_ITERS(300);
    long better = 0, total = 0;
    double err1 = 0.0, err2 = 0.0;
    for (int it = 0; it < iters; it++) {
        make_scene(t, &s, 2, 32, 6.0, 1.0);
        sfm_triangulate_dlt(2, s.Pp, s.np, s.xp, Xd, NULL);
        sfm_triangulate_optimal2(s.Pp, s.Pp + 12, s.np, s.xp, s.xp + 2 * s.np, Xo, NULL);
        for (int j = 0; j < s.np; j++) {
            double ed = reproj_sq(s.Pp, Xd + 3 * j, s.xp + 2 * j) +
                        reproj_sq(s.Pp + 12, Xd + 3 * j, s.xp + 2 * (s.np + j));
            double eo = reproj_sq(s.Pp, Xo + 3 * j, s.xp + 2 * j) +
                        reproj_sq(s.Pp + 12, Xo + 3 * j, s.xp + 2 * (s.np + j));
            better += eo <= ed * (1.0 + 1e-9) + 1e-18;
            total++;
            err1 += point_err(Xo + 3 * j, s.X + 3 * j);
        }
        /* same scene, twice the noise: errors about double */
        project_all(&s, 2.0, t);
        sfm_triangulate_optimal2(s.Pp, s.Pp + 12, s.np, s.xp, s.xp + 2 * s.np, Xo, NULL);
        for (int j = 0; j < s.np; j++)
            err2 += point_err(Xo + 3 * j, s.X + 3 * j);
    }
    double rate = (double)better / total;
    SFM_TEST_LOG("optimal reprojection <= DLT for %ld of %ld points; error ratio at 2x noise "
                 "%d/1000",
                 better, total, (int)(1000.0 * err2 / err1));
    SFM_CHECK(rate >= 0.999);
    SFM_CHECK(err2 / err1 > 1.7 && err2 / err1 < 2.3);
}

SFM_TEST(triangulate_flags_behind_and_infinity)
{
    static scene s;
    double X[3 * 2];
    int fl[2];
    make_scene(t, &s, 2, 1, 5.0, 0.0);
    /* a point behind camera 1: mirror it through camera 1's centre */
    {
        const double *R = s.pose[0].R, *tr = s.pose[0].t;
        double c[3];
        for (int k = 0; k < 3; k++)
            c[k] = -(R[k] * tr[0] + R[3 + k] * tr[1] + R[6 + k] * tr[2]);
        for (int k = 0; k < 3; k++)
            s.X[k] = 2.0 * c[k] - s.X[k];
        project_all(&s, 0.0, t);
    }
    SFM_CHECK_EQ_INT(sfm_triangulate_dlt(2, s.Pp, 1, s.xp, X, fl), 0);
    SFM_CHECK_EQ_INT(fl[0], SFM_TRI_BEHIND);
    SFM_CHECK(point_err(X, s.X) < 1e-8);
    SFM_CHECK_EQ_INT(sfm_triangulate_optimal2(s.Pp, s.Pp + 12, 1, s.xp, s.xp + 2, X, fl), 0);
    SFM_CHECK_EQ_INT(fl[0], SFM_TRI_BEHIND);
    SFM_CHECK_EQ_INT(sfm_triangulate_midpoint(2, s.pose, 1, s.f, X, fl), 0);
    SFM_CHECK_EQ_INT(fl[0], SFM_TRI_BEHIND);
    SFM_CHECK(point_err(X, s.X) < 1e-8);
    /* a point projected with a negated P is still behind (sign of det M) */
    {
        double Pneg[24];
        for (int k = 0; k < 24; k++)
            Pneg[k] = -s.Pp[k];
        SFM_CHECK_EQ_INT(sfm_triangulate_dlt(2, Pneg, 1, s.xp, X, fl), 0);
        SFM_CHECK_EQ_INT(fl[0], SFM_TRI_BEHIND);
    }

    /* points at infinity: two cameras with the same rotation, a direction */
    sfm_pose poses[2];
    double P[24];
    sfm_test_random_rotation(t, poses[0].R);
    memcpy(poses[1].R, poses[0].R, sizeof poses[0].R);
    for (int k = 0; k < 3; k++) {
        poses[0].t[k] = 0.0;
        poses[1].t[k] = sfm_test_uniform(t, -1, 1);
    }
    for (int v = 0; v < 2; v++)
        for (int r = 0; r < 3; r++) {
            for (int k = 0; k < 3; k++)
                P[12 * v + 4 * r + k] = poses[v].R[3 * r + k];
            P[12 * v + 4 * r + 3] = poses[v].t[r];
        }
    /* direction d in front: camera z of d > 0 */
    double dcam[3] = {0.1, -0.2, 1.0}, d[3];
    for (int k = 0; k < 3; k++)
        d[k] = poses[0].R[k] * dcam[0] + poses[0].R[3 + k] * dcam[1] + poses[0].R[6 + k] * dcam[2];
    double nd = sqrt(d[0] * d[0] + d[1] * d[1] + d[2] * d[2]);
    for (int k = 0; k < 3; k++)
        d[k] /= nd;
    double x[4] = {0.1, -0.2, 0.1, -0.2}, f[6] = {0.1, -0.2, 1.0, 0.1, -0.2, 1.0};
    SFM_CHECK_EQ_INT(sfm_triangulate_dlt(2, P, 1, x, X, fl), 0);
    SFM_CHECK_EQ_INT(fl[0], SFM_TRI_INFINITY);
    SFM_CHECK(point_err(X, d) < 1e-9);
    SFM_CHECK_EQ_INT(sfm_triangulate_midpoint(2, poses, 1, f, X, fl), 0);
    SFM_CHECK_EQ_INT(fl[0], SFM_TRI_INFINITY);
    SFM_CHECK(point_err(X, d) < 1e-9);
    SFM_CHECK_EQ_INT(sfm_triangulate_optimal2(P, P + 12, 1, x, x + 2, X, fl), 0);
    SFM_CHECK(fl[0] & SFM_TRI_INFINITY);
    SFM_CHECK(point_err(X, d) < 1e-9);
    /* a far but finite point (1e4 baselines) is not at infinity */
    double Xf[3];
    for (int k = 0; k < 3; k++)
        Xf[k] = 1e4 * d[k];
    double xf[4];
    for (int v = 0; v < 2; v++) {
        double p[3];
        for (int r = 0; r < 3; r++)
            p[r] = P[12 * v + 4 * r] * Xf[0] + P[12 * v + 4 * r + 1] * Xf[1] +
                   P[12 * v + 4 * r + 2] * Xf[2] + P[12 * v + 4 * r + 3];
        xf[2 * v] = p[0] / p[2];
        xf[2 * v + 1] = p[1] / p[2];
    }
    SFM_CHECK_EQ_INT(sfm_triangulate_dlt(2, P, 1, xf, X, fl), 1);
    SFM_CHECK(point_err(X, Xf) < 1e-6 * 1e4);
}

SFM_TEST(triangulate_contract)
{
    static scene s;
    make_scene(t, &s, 3, 4, 5.0, 0.0);
    double X[3 * 4];
    int fl[4];
    sfm_test_fill_canary(X, sizeof X);
    sfm_test_fill_canary(fl, sizeof fl);
    SFM_CHECK_EQ_INT(sfm_triangulate_dlt(3, NULL, 4, s.xp, X, fl), SFM_E_ARGUMENT);
    SFM_CHECK_EQ_INT(sfm_triangulate_dlt(3, s.Pp, 4, NULL, X, fl), SFM_E_ARGUMENT);
    SFM_CHECK_EQ_INT(sfm_triangulate_dlt(3, s.Pp, 4, s.xp, NULL, fl), SFM_E_ARGUMENT);
    SFM_CHECK_EQ_INT(sfm_triangulate_dlt(1, s.Pp, 4, s.xp, X, fl), SFM_E_ARGUMENT);
    SFM_CHECK_EQ_INT(sfm_triangulate_dlt(3, s.Pp, -1, s.xp, X, fl), SFM_E_ARGUMENT);
    SFM_CHECK_EQ_INT(sfm_triangulate_midpoint(3, NULL, 4, s.f, X, fl), SFM_E_ARGUMENT);
    SFM_CHECK_EQ_INT(sfm_triangulate_midpoint(1, s.pose, 4, s.f, X, fl), SFM_E_ARGUMENT);
    SFM_CHECK_EQ_INT(sfm_triangulate_midpoint(3, s.pose, 4, NULL, X, fl), SFM_E_ARGUMENT);
    SFM_CHECK_EQ_INT(sfm_triangulate_optimal2(NULL, s.Pp + 12, 4, s.xp, s.xp + 8, X, fl),
                     SFM_E_ARGUMENT);
    SFM_CHECK_EQ_INT(sfm_triangulate_optimal2(s.Pp, s.Pp + 12, 4, s.xp, NULL, X, fl),
                     SFM_E_ARGUMENT);
    SFM_CHECK_EQ_INT(sfm_triangulate_optimal2(s.Pp, s.Pp + 12, -2, s.xp, s.xp + 8, X, fl),
                     SFM_E_ARGUMENT);
    /* cameras with a common centre */
    SFM_CHECK_EQ_INT(sfm_triangulate_optimal2(s.Pp, s.Pp, 4, s.xp, s.xp + 8, X, fl),
                     SFM_E_ARGUMENT);
    /* a zero bearing */
    double fz[3 * 3 * 4];
    memcpy(fz, s.f, sizeof fz);
    fz[3] = fz[4] = fz[5] = 0.0;
    SFM_CHECK_EQ_INT(sfm_triangulate_midpoint(3, s.pose, 4, fz, X, fl), SFM_E_ARGUMENT);
    /* NaN anywhere */
    double xb[3 * 4 * 2];
    memcpy(xb, s.xp, sizeof xb);
    xb[9] = (double)NAN;
    SFM_CHECK_EQ_INT(sfm_triangulate_dlt(3, s.Pp, 4, xb, X, fl), SFM_E_NONFINITE);
    SFM_CHECK_EQ_INT(sfm_triangulate_optimal2(s.Pp, s.Pp + 12, 4, s.xp, xb + 8, X, fl),
                     SFM_E_NONFINITE);
    double Pb[36];
    memcpy(Pb, s.Pp, sizeof Pb);
    Pb[20] = HUGE_VAL;
    SFM_CHECK_EQ_INT(sfm_triangulate_dlt(3, Pb, 4, s.xp, X, fl), SFM_E_NONFINITE);
    SFM_CHECK_EQ_INT(sfm_triangulate_optimal2(s.Pp, Pb + 12, 4, s.xp, s.xp + 8, X, fl),
                     SFM_E_NONFINITE);
    sfm_pose pb[3];
    memcpy(pb, s.pose, sizeof pb);
    pb[2].t[1] = (double)NAN;
    SFM_CHECK_EQ_INT(sfm_triangulate_midpoint(3, pb, 4, s.f, X, fl), SFM_E_NONFINITE);
    fz[3] = (double)NAN;
    SFM_CHECK_EQ_INT(sfm_triangulate_midpoint(3, s.pose, 4, fz, X, fl), SFM_E_NONFINITE);
    SFM_CHECK(sfm_test_canary_intact(X, sizeof X));
    SFM_CHECK(sfm_test_canary_intact(fl, sizeof fl));
    /* zero points is fine and writes nothing */
    SFM_CHECK_EQ_INT(sfm_triangulate_dlt(3, s.Pp, 0, NULL, X, fl), 0);
    SFM_CHECK(sfm_test_canary_intact(X, sizeof X));
}

SFM_TEST(triangulate_dlt_matches_svd_of_stacked_rows)
{
    /* With noise, the DLT point is the smallest right singular vector of the
     * stacked unit-norm rows: compare with sfm_nullspace on that matrix. */
    static scene s;
    static double X[TP_MAX * 3];
    static unsigned char ws[16384];
    int bad = 0, checked = 0;
    for (int it = 0; it < SFM_TEST_ITERS(200); it++) {
        int nv = 2 + it % (TV_MAX - 1);
        make_scene(t, &s, nv, 8, sfm_test_uniform(t, 3.0, 30.0), 2.0);
        SFM_CHECK(sfm_triangulate_dlt(nv, s.Pp, s.np, s.xp, X, NULL) >= 0);
        SFM_CHECK(sfm_nullspace_workspace_size(2 * nv, 4) <= sizeof ws);
        for (int j = 0; j < s.np; j++) {
            double A[2 * TV_MAX * 4], N[4];
            for (int v = 0; v < nv; v++) {
                const double *P = s.Pp + 12 * v, *o = s.xp + 2 * (v * s.np + j);
                for (int r = 0; r < 2; r++) {
                    double n = 0.0;
                    for (int k = 0; k < 4; k++) {
                        A[(2 * v + r) * 4 + k] = o[r] * P[8 + k] - P[4 * r + k];
                        n += A[(2 * v + r) * 4 + k] * A[(2 * v + r) * 4 + k];
                    }
                    for (int k = 0; k < 4; k++)
                        A[(2 * v + r) * 4 + k] /= sqrt(n);
                }
            }
            if (sfm_nullspace(A, 2 * nv, 4, 1, N, NULL, ws, sizeof ws) != SFM_OK) {
                bad++;
                continue;
            }
            double Xr[3] = {N[0] / N[3], N[1] / N[3], N[2] / N[3]};
            double scale = 1.0 + sqrt(Xr[0] * Xr[0] + Xr[1] * Xr[1] + Xr[2] * Xr[2]);
            if (point_err(X + 3 * j, Xr) > 1e-9 * scale)
                bad++;
            checked++;
        }
    }
    SFM_TEST_LOG("DLT against the SVD of the stacked rows: %d of %d differ", bad, checked);
    SFM_CHECK_EQ_INT(bad, 0);
}
