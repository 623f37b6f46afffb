/*
 * Minimal pose solvers against synthetic problems with known answers:
 * sfm_p3p, sfm_relpose_upright_3pt, sfm_essential_to_poses.
 */
#include <math.h>
#include <string.h>

#include "sfm/sfm.h"
#include "sfm_test.h"

#define PI 3.14159265358979323846

/* ---- small helpers written out here (independent of the code under test) */

static void mat_mul(const double A[9], const double B[9], double C[9])
{
    for (int r = 0; r < 3; r++)
        for (int c = 0; c < 3; c++)
            C[3 * r + c] = A[3 * r] * B[c] + A[3 * r + 1] * B[3 + c] + A[3 * r + 2] * B[6 + c];
}

static void mat_vec(const double A[9], const double x[3], double y[3])
{
    for (int r = 0; r < 3; r++)
        y[r] = A[3 * r] * x[0] + A[3 * r + 1] * x[1] + A[3 * r + 2] * x[2];
}

static void mat_tvec(const double A[9], const double x[3], double y[3])
{
    for (int r = 0; r < 3; r++)
        y[r] = A[r] * x[0] + A[3 + r] * x[1] + A[6 + r] * x[2];
}

static double norm3(const double v[3])
{
    return sqrt(v[0] * v[0] + v[1] * v[1] + v[2] * v[2]);
}

static void normalize3(double v[3])
{
    double n = norm3(v);
    v[0] /= n;
    v[1] /= n;
    v[2] /= n;
}

/* Rodrigues, for building test rotations about chosen axes. */
static void axis_angle(const double axis[3], double angle, double R[9])
{
    double a[3] = {axis[0], axis[1], axis[2]};
    normalize3(a);
    double c = cos(angle), s = sin(angle), v = 1.0 - c;
    R[0] = c + a[0] * a[0] * v;
    R[1] = a[0] * a[1] * v - a[2] * s;
    R[2] = a[0] * a[2] * v + a[1] * s;
    R[3] = a[1] * a[0] * v + a[2] * s;
    R[4] = c + a[1] * a[1] * v;
    R[5] = a[1] * a[2] * v - a[0] * s;
    R[6] = a[2] * a[0] * v - a[1] * s;
    R[7] = a[2] * a[1] * v + a[0] * s;
    R[8] = c + a[2] * a[2] * v;
}

static double pose_dist(const sfm_pose *p, const double R[9], const double t[3])
{
    double e = 0.0;
    for (int i = 0; i < 9; i++)
        e = fmax(e, fabs(p->R[i] - R[i]));
    for (int i = 0; i < 3; i++)
        e = fmax(e, fabs(p->t[i] - t[i]));
    return e;
}

static int pose_finite(const sfm_pose *p)
{
    for (int i = 0; i < 9; i++)
        if (!isfinite(p->R[i]))
            return 0;
    for (int i = 0; i < 3; i++)
        if (!isfinite(p->t[i]))
            return 0;
    return 1;
}

/* ---- P3P ---------------------------------------------------------------- */

enum { P3P_GENERAL, P3P_FAR, P3P_NARROW, P3P_SMALLROT, P3P_NEAR180, P3P_NEARCOLLINEAR, P3P_NCASES };
/* One case of a minimal pose solver's ground-truth test: no out-of-range
 * count, no non-finite pose, the truth among the solutions in 99.9 % of the
 * samples. The log holds integers only: formatting a double needs a heap
 * under newlib. */
static void rate_report(sfm_test_ctx *t, const char *solver, int width, const char *case_name, int found,
                        int iters, int sols, int bad, int nonfinite)
{
    double rate = (double)found / iters;
    SFM_TEST_LOG("%s %-*s truth found in %d of %d, %d solutions", solver, width, case_name, found, iters,
                 sols);
    SFM_CHECK_EQ_INT(bad, 0);
    SFM_CHECK_EQ_INT(nonfinite, 0);
    SFM_CHECK_MSG(rate >= 0.999, "%s %s: ground truth found in %d of %d (< 99.9%%)", solver, case_name,
                  found, iters);
}

static const char *p3p_case_names[] = {"general", "far", "narrow-fov", "small-rot", "near-180",
                                       "near-collinear"};

/* A random P3P problem: camera pose (R, t), three points in front. */
static void p3p_problem(sfm_test_ctx *t, int kind, double R[9], double tr[3], double x[9],
                        double X[9])
{
    if (kind == P3P_SMALLROT) {
        double ax[3];
        sfm_test_random_unit(t, ax);
        axis_angle(ax, sfm_test_uniform(t, 1e-6, 1e-2), R);
    } else if (kind == P3P_NEAR180) {
        double ax[3];
        sfm_test_random_unit(t, ax);
        axis_angle(ax, PI - sfm_test_uniform(t, 0.0, 1e-3), R);
    } else {
        sfm_test_random_rotation(t, R);
    }
    for (int k = 0; k < 3; k++)
        tr[k] = sfm_test_uniform(t, -2.0, 2.0);
    double fov = kind == P3P_NARROW ? 0.05 : 0.8;
    double dmin = kind == P3P_FAR ? 50.0 : 1.0, dmax = kind == P3P_FAR ? 500.0 : 10.0;
    for (int i = 0; i < 3; i++) {
        double xc[3];
        if (kind == P3P_NEARCOLLINEAR && i == 2) {
            /* close to the line through the first two points */
            double a = sfm_test_uniform(t, 0.2, 0.8);
            double Xc0[3], Xc1[3];
            mat_vec(R, X, Xc0);
            mat_vec(R, X + 3, Xc1);
            for (int k = 0; k < 3; k++)
                xc[k] = a * (Xc0[k] + tr[k]) + (1 - a) * (Xc1[k] + tr[k]) +
                        sfm_test_uniform(t, -0.01, 0.01);
        } else {
            double d = sfm_test_uniform(t, dmin, dmax);
            xc[0] = sfm_test_uniform(t, -fov, fov) * d;
            xc[1] = sfm_test_uniform(t, -fov, fov) * d;
            xc[2] = d;
        }
        double b[3] = {xc[0], xc[1], xc[2]};
        normalize3(b);
        memcpy(x + 3 * i, b, sizeof b);
        double v[3] = {xc[0] - tr[0], xc[1] - tr[1], xc[2] - tr[2]};
        mat_tvec(R, v, X + 3 * i);
    }
}

SFM_TEST(p3p_recovers_truth)
{
    const int iters = SFM_TEST_ITERS(20000);
    for (int kind = 0; kind < P3P_NCASES; kind++) {
        int found = 0, sols = 0, nonfinite = 0, bad = 0;
        for (int it = 0; it < iters; it++) {
            double R[9], tr[3], x[9], X[9];
            p3p_problem(t, kind, R, tr, x, X);
            sfm_pose poses[SFM_P3P_MAX_SOLUTIONS];
            int n = sfm_p3p(x, X, poses);
            if (n < 0 || n > SFM_P3P_MAX_SOLUTIONS) {
                bad++;
                continue;
            }
            sols += n;
            double scale = 1.0 + norm3(tr);
            int ok = 0;
            for (int s = 0; s < n; s++) {
                if (!pose_finite(&poses[s]))
                    nonfinite++;
                double e = 0.0;
                for (int i = 0; i < 9; i++)
                    e = fmax(e, fabs(poses[s].R[i] - R[i]));
                for (int i = 0; i < 3; i++)
                    e = fmax(e, fabs(poses[s].t[i] - tr[i]) / scale);
                if (e < 1e-6)
                    ok = 1;
            }
            found += ok;
        }
        rate_report(t, "p3p", 14, p3p_case_names[kind], found, iters, sols, bad, nonfinite);
    }
}

SFM_TEST(p3p_every_solution_fits)
{
    /* Every returned pose maps the world points onto the bearings. */
    const int iters = SFM_TEST_ITERS(2000);
    int bad = 0;
    for (int it = 0; it < iters; it++) {
        double R[9], tr[3], x[9], X[9];
        p3p_problem(t, P3P_GENERAL, R, tr, x, X);
        sfm_pose poses[SFM_P3P_MAX_SOLUTIONS];
        int n = sfm_p3p(x, X, poses);
        for (int s = 0; s < n; s++) {
            double RtR[9], Rt[9];
            for (int r = 0; r < 3; r++)
                for (int c = 0; c < 3; c++)
                    Rt[3 * r + c] = poses[s].R[3 * c + r];
            mat_mul(Rt, poses[s].R, RtR);
            for (int i = 0; i < 9; i++)
                if (fabs(RtR[i] - (i % 4 == 0)) > 1e-8)
                    bad++;
            for (int i = 0; i < 3; i++) {
                double xc[3];
                mat_vec(poses[s].R, X + 3 * i, xc);
                for (int k = 0; k < 3; k++)
                    xc[k] += poses[s].t[k];
                if (xc[0] * x[3 * i] + xc[1] * x[3 * i + 1] + xc[2] * x[3 * i + 2] <= 0.0)
                    bad++; /* behind the camera */
                double d = norm3(xc);
                for (int k = 0; k < 3; k++)
                    if (fabs(xc[k] / d - x[3 * i + k]) > 1e-8)
                        bad++;
            }
        }
    }
    SFM_CHECK_EQ_INT(bad, 0);
}

SFM_TEST(p3p_degenerate_gives_zero)
{
    double R[9], tr[3], x[9], X[9];
    sfm_pose poses[SFM_P3P_MAX_SOLUTIONS];
    for (int it = 0; it < SFM_TEST_ITERS(200); it++) {
        p3p_problem(t, P3P_GENERAL, R, tr, x, X);
        /* collinear world points */
        double Xc[9];
        memcpy(Xc, X, sizeof Xc);
        for (int k = 0; k < 3; k++)
            Xc[6 + k] = 0.3 * X[k] + 0.7 * X[3 + k];
        sfm_test_fill_canary(poses, sizeof poses);
        SFM_CHECK_EQ_INT(sfm_p3p(x, Xc, poses), 0);
        SFM_CHECK(sfm_test_canary_intact(poses, sizeof poses));
        /* identical world points */
        memcpy(Xc, X, sizeof Xc);
        memcpy(Xc + 3, X, 3 * sizeof(double));
        SFM_CHECK_EQ_INT(sfm_p3p(x, Xc, poses), 0);
        memcpy(Xc + 6, X, 3 * sizeof(double));
        SFM_CHECK_EQ_INT(sfm_p3p(x, Xc, poses), 0);
        /* identical bearings */
        double xc[9];
        memcpy(xc, x, sizeof xc);
        memcpy(xc + 3, x, 3 * sizeof(double));
        SFM_CHECK_EQ_INT(sfm_p3p(xc, X, poses), 0);
        /* zero bearing */
        memset(xc + 3, 0, 3 * sizeof(double));
        SFM_CHECK_EQ_INT(sfm_p3p(xc, X, poses), 0);
        SFM_CHECK(sfm_test_canary_intact(poses, sizeof poses));
    }
}

SFM_TEST(p3p_contract)
{
    double R[9], tr[3], x[9], X[9];
    p3p_problem(t, P3P_GENERAL, R, tr, x, X);
    sfm_pose poses[SFM_P3P_MAX_SOLUTIONS];
    sfm_test_fill_canary(poses, sizeof poses);
    SFM_CHECK_EQ_INT(sfm_p3p(NULL, X, poses), SFM_E_ARGUMENT);
    SFM_CHECK_EQ_INT(sfm_p3p(x, NULL, poses), SFM_E_ARGUMENT);
    SFM_CHECK_EQ_INT(sfm_p3p(x, X, NULL), SFM_E_ARGUMENT);
    for (int i = 0; i < 9; i++) {
        double xb[9], Xb[9];
        memcpy(xb, x, sizeof xb);
        memcpy(Xb, X, sizeof Xb);
        xb[i] = (double)NAN;
        SFM_CHECK_EQ_INT(sfm_p3p(xb, X, poses), SFM_E_NONFINITE);
        Xb[i] = HUGE_VAL;
        SFM_CHECK_EQ_INT(sfm_p3p(x, Xb, poses), SFM_E_NONFINITE);
    }
    SFM_CHECK(sfm_test_canary_intact(poses, sizeof poses));
}

/* ---- Upright 3-point ---------------------------------------------------- */

enum {
    UP_GENERAL, UP_SMALLROT, UP_NEAR180_D, UP_EXACT180_D, UP_NEAR180_OTHER, UP_FORWARD,
    UP_SIDEWAYS, UP_PLANAR, UP_FAR, UP_AXIS_Y, UP_NCASES
};
static const char *up_case_names[] = {"general",  "small-rot", "near-180-d", "180-d",
                                      "180-other", "forward",  "sideways",  "near-planar",
                                      "far",       "d=y"};

/* A relative pose problem with a known direction d1 (frame 1), d2 = R d1. */
static void up_problem(sfm_test_ctx *t, int kind, double R[9], double tr[3], double d1[3],
                       double d2[3], double x1[9], double x2[9])
{
    double ax[3];
    sfm_test_random_unit(t, d1);
    if (kind == UP_AXIS_Y) {
        d1[0] = 0.0;
        d1[1] = 1.0;
        d1[2] = 0.0;
    }
    switch (kind) {
    case UP_SMALLROT:
        sfm_test_random_unit(t, ax);
        axis_angle(ax, sfm_test_uniform(t, 1e-7, 1e-3), R);
        break;
    case UP_NEAR180_D:
        axis_angle(d1, PI - sfm_test_uniform(t, 1e-9, 1e-3), R);
        break;
    case UP_EXACT180_D:
        axis_angle(d1, PI, R);
        break;
    case UP_NEAR180_OTHER:
        sfm_test_random_unit(t, ax);
        axis_angle(ax, PI - sfm_test_uniform(t, 0.0, 1e-3), R);
        break;
    default:
        sfm_test_random_rotation(t, R);
    }
    mat_vec(R, d1, d2);
    if (kind == UP_FORWARD) {
        tr[0] = sfm_test_uniform(t, -1e-3, 1e-3);
        tr[1] = sfm_test_uniform(t, -1e-3, 1e-3);
        tr[2] = -1.0;
    } else if (kind == UP_SIDEWAYS) {
        tr[0] = 1.0;
        tr[1] = sfm_test_uniform(t, -1e-3, 1e-3);
        tr[2] = sfm_test_uniform(t, -1e-3, 1e-3);
    } else {
        sfm_test_random_unit(t, tr);
    }
    normalize3(tr);
    double pn[3];
    sfm_test_random_unit(t, pn);
    for (int i = 0; i < 3; i++) {
        /* bearings in both frames point at the point: positive depths */
        double X[3], Xc2[3];
        {
            double d = kind == UP_FAR ? sfm_test_uniform(t, 100.0, 1000.0)
                                      : sfm_test_uniform(t, 2.0, 10.0);
            X[0] = sfm_test_uniform(t, -0.8, 0.8) * d;
            X[1] = sfm_test_uniform(t, -0.8, 0.8) * d;
            X[2] = d;
            if (kind == UP_PLANAR) {
                /* push towards the plane through (0,0,5) with normal pn */
                double off = (X[0] * pn[0] + X[1] * pn[1] + (X[2] - 5.0) * pn[2]);
                double keep = 1e-3;
                for (int k = 0; k < 3; k++)
                    X[k] -= (1.0 - keep) * off * pn[k];
            }
            mat_vec(R, X, Xc2);
            for (int k = 0; k < 3; k++)
                Xc2[k] += tr[k];
        }
        double b1[3] = {X[0], X[1], X[2]}, b2[3] = {Xc2[0], Xc2[1], Xc2[2]};
        normalize3(b1);
        normalize3(b2);
        memcpy(x1 + 3 * i, b1, sizeof b1);
        memcpy(x2 + 3 * i, b2, sizeof b2);
    }
}

SFM_TEST(upright_3pt_recovers_truth)
{
    const int iters = SFM_TEST_ITERS(20000);
    for (int kind = 0; kind < UP_NCASES; kind++) {
        int found = 0, sols = 0, nonfinite = 0, bad = 0;
        for (int it = 0; it < iters; it++) {
            double R[9], tr[3], d1[3], d2[3], x1[9], x2[9];
            up_problem(t, kind, R, tr, d1, d2, x1, x2);
            sfm_pose poses[SFM_RELPOSE_UPRIGHT_3PT_MAX_SOLUTIONS];
            int n = sfm_relpose_upright_3pt(x1, x2, d1, d2, poses);
            if (n < 0 || n > SFM_RELPOSE_UPRIGHT_3PT_MAX_SOLUTIONS) {
                bad++;
                continue;
            }
            sols += n;
            int ok = 0;
            for (int s = 0; s < n; s++) {
                if (!pose_finite(&poses[s]))
                    nonfinite++;
                if (pose_dist(&poses[s], R, tr) < 1e-6)
                    ok = 1;
            }
            found += ok;
        }
        rate_report(t, "upright", 11, up_case_names[kind], found, iters, sols, bad, nonfinite);
    }
}

SFM_TEST(upright_3pt_solutions_are_consistent)
{
    /* Every solution: R proper rotation, R d1 = d2, |t| = 1, epipolar
     * constraints hold on the three pairs, the points lie in front. */
    const int iters = SFM_TEST_ITERS(2000);
    int bad = 0;
    for (int it = 0; it < iters; it++) {
        double R[9], tr[3], d1[3], d2[3], x1[9], x2[9];
        up_problem(t, UP_GENERAL, R, tr, d1, d2, x1, x2);
        sfm_pose poses[SFM_RELPOSE_UPRIGHT_3PT_MAX_SOLUTIONS];
        int n = sfm_relpose_upright_3pt(x1, x2, d1, d2, poses);
        for (int s = 0; s < n; s++) {
            const sfm_pose *p = &poses[s];
            double Rd[3];
            mat_vec(p->R, d1, Rd);
            for (int k = 0; k < 3; k++)
                if (fabs(Rd[k] - d2[k]) > 1e-9)
                    bad++;
            double det = p->R[0] * (p->R[4] * p->R[8] - p->R[5] * p->R[7]) -
                         p->R[1] * (p->R[3] * p->R[8] - p->R[5] * p->R[6]) +
                         p->R[2] * (p->R[3] * p->R[7] - p->R[4] * p->R[6]);
            if (fabs(det - 1.0) > 1e-9 || fabs(norm3(p->t) - 1.0) > 1e-9)
                bad++;
            for (int i = 0; i < 3; i++) {
                double v[3], w[3];
                mat_vec(p->R, x1 + 3 * i, v);
                /* x2 . (t x R x1) */
                w[0] = p->t[1] * v[2] - p->t[2] * v[1];
                w[1] = p->t[2] * v[0] - p->t[0] * v[2];
                w[2] = p->t[0] * v[1] - p->t[1] * v[0];
                double e = x2[3 * i] * w[0] + x2[3 * i + 1] * w[1] + x2[3 * i + 2] * w[2];
                if (fabs(e) > 1e-9)
                    bad++;
                /* in front of both cameras: l2 x2 = l1 R x1 + t with l1, l2 >= 0,
                 * from the 2x2 normal equations of [R x1, -x2] l = -t */
                double a11 = v[0] * v[0] + v[1] * v[1] + v[2] * v[2];
                double a12 = -(v[0] * x2[3 * i] + v[1] * x2[3 * i + 1] + v[2] * x2[3 * i + 2]);
                double a22 = x2[3 * i] * x2[3 * i] + x2[3 * i + 1] * x2[3 * i + 1] +
                             x2[3 * i + 2] * x2[3 * i + 2];
                double r1 = -(v[0] * p->t[0] + v[1] * p->t[1] + v[2] * p->t[2]);
                double r2 = x2[3 * i] * p->t[0] + x2[3 * i + 1] * p->t[1] + x2[3 * i + 2] * p->t[2];
                double dd = a11 * a22 - a12 * a12;
                double l1 = (r1 * a22 - a12 * r2) / dd, l2 = (a11 * r2 - a12 * r1) / dd;
                if (l1 < -1e-9 || l2 < -1e-9)
                    bad++;
            }
        }
    }
    SFM_CHECK_EQ_INT(bad, 0);
}

SFM_TEST(upright_3pt_degenerate_gives_zero)
{
    for (int it = 0; it < SFM_TEST_ITERS(200); it++) {
        double R[9], tr[3], d1[3], d2[3], x1[9], x2[9];
        up_problem(t, UP_GENERAL, R, tr, d1, d2, x1, x2);
        sfm_pose poses[SFM_RELPOSE_UPRIGHT_3PT_MAX_SOLUTIONS];
        /* three identical pairs */
        double y1[9], y2[9];
        for (int i = 0; i < 3; i++) {
            memcpy(y1 + 3 * i, x1, 3 * sizeof(double));
            memcpy(y2 + 3 * i, x2, 3 * sizeof(double));
        }
        sfm_test_fill_canary(poses, sizeof poses);
        SFM_CHECK_EQ_INT(sfm_relpose_upright_3pt(y1, y2, d1, d2, poses), 0);
        SFM_CHECK(sfm_test_canary_intact(poses, sizeof poses));
        /* zero bearings */
        memset(y1, 0, sizeof y1);
        SFM_CHECK_EQ_INT(sfm_relpose_upright_3pt(y1, x2, d1, d2, poses), 0);
        SFM_CHECK(sfm_test_canary_intact(poses, sizeof poses));
        /* two identical pairs: no NaN, whatever the count */
        memcpy(y1, x1, sizeof y1);
        memcpy(y2, x2, sizeof y2);
        memcpy(y1 + 3, x1, 3 * sizeof(double));
        memcpy(y2 + 3, x2, 3 * sizeof(double));
        int n = sfm_relpose_upright_3pt(y1, y2, d1, d2, poses);
        SFM_CHECK(n >= 0 && n <= 4);
        for (int s = 0; s < n; s++)
            SFM_CHECK(pose_finite(&poses[s]));
    }
}

SFM_TEST(upright_3pt_contract)
{
    double R[9], tr[3], d1[3], d2[3], x1[9], x2[9];
    up_problem(t, UP_GENERAL, R, tr, d1, d2, x1, x2);
    sfm_pose poses[SFM_RELPOSE_UPRIGHT_3PT_MAX_SOLUTIONS];
    sfm_test_fill_canary(poses, sizeof poses);
    SFM_CHECK_EQ_INT(sfm_relpose_upright_3pt(NULL, x2, d1, d2, poses), SFM_E_ARGUMENT);
    SFM_CHECK_EQ_INT(sfm_relpose_upright_3pt(x1, NULL, d1, d2, poses), SFM_E_ARGUMENT);
    SFM_CHECK_EQ_INT(sfm_relpose_upright_3pt(x1, x2, NULL, d2, poses), SFM_E_ARGUMENT);
    SFM_CHECK_EQ_INT(sfm_relpose_upright_3pt(x1, x2, d1, NULL, poses), SFM_E_ARGUMENT);
    SFM_CHECK_EQ_INT(sfm_relpose_upright_3pt(x1, x2, d1, d2, NULL), SFM_E_ARGUMENT);
    double z[3] = {0.0, 0.0, 0.0};
    SFM_CHECK_EQ_INT(sfm_relpose_upright_3pt(x1, x2, z, d2, poses), SFM_E_ARGUMENT);
    SFM_CHECK_EQ_INT(sfm_relpose_upright_3pt(x1, x2, d1, z, poses), SFM_E_ARGUMENT);
    for (int i = 0; i < 9; i++) {
        double b[9];
        memcpy(b, x1, sizeof b);
        b[i] = (double)NAN;
        SFM_CHECK_EQ_INT(sfm_relpose_upright_3pt(b, x2, d1, d2, poses), SFM_E_NONFINITE);
        memcpy(b, x2, sizeof b);
        b[i] = -HUGE_VAL;
        SFM_CHECK_EQ_INT(sfm_relpose_upright_3pt(x1, b, d1, d2, poses), SFM_E_NONFINITE);
    }
    for (int i = 0; i < 3; i++) {
        double b[3];
        memcpy(b, d1, sizeof b);
        b[i] = (double)NAN;
        SFM_CHECK_EQ_INT(sfm_relpose_upright_3pt(x1, x2, b, d2, poses), SFM_E_NONFINITE);
        memcpy(b, d2, sizeof b);
        b[i] = (double)NAN;
        SFM_CHECK_EQ_INT(sfm_relpose_upright_3pt(x1, x2, d1, b, poses), SFM_E_NONFINITE);
    }
    SFM_CHECK(sfm_test_canary_intact(poses, sizeof poses));
}

/* ---- Essential matrix to poses ------------------------------------------ */

static void essential_problem(sfm_test_ctx *t, int n, double R[9], double tr[3], double E[9],
                              double *x1, double *x2)
{
    sfm_test_random_rotation(t, R);
    sfm_test_random_unit(t, tr);
    /* E = [t]x R, random scale and sign */
    double S[9] = {0, -tr[2], tr[1], tr[2], 0, -tr[0], -tr[1], tr[0], 0};
    mat_mul(S, R, E);
    double sc = sfm_test_uniform(t, 0.1, 10.0) * (sfm_test_uniform(t, -1, 1) < 0 ? -1.0 : 1.0);
    for (int i = 0; i < 9; i++)
        E[i] *= sc;
    for (int i = 0; i < n; i++) {
        double X[3], Xc[3];
        double d = sfm_test_uniform(t, 2.0, 20.0);
        X[0] = sfm_test_uniform(t, -0.8, 0.8) * d;
        X[1] = sfm_test_uniform(t, -0.8, 0.8) * d;
        X[2] = d;
        mat_vec(R, X, Xc);
        for (int k = 0; k < 3; k++)
            Xc[k] += tr[k];
        normalize3(X);
        normalize3(Xc);
        memcpy(x1 + 3 * i, X, sizeof X);
        memcpy(x2 + 3 * i, Xc, sizeof Xc);
    }
}

SFM_TEST(essential_to_poses_recovers_truth)
{
    enum { N = 20 };
    const int iters = SFM_TEST_ITERS(20000);
    int found = 0, chosen = 0, bad = 0;
    for (int it = 0; it < iters; it++) {
        double R[9], tr[3], x1[3 * N], x2[3 * N];
        sfm_mat3 E;
        essential_problem(t, N, R, tr, E.m, x1, x2);
        sfm_pose poses[4];
        int cnt[4];
        int n = sfm_essential_to_poses(&E, x1, x2, N, poses, cnt);
        if (n != 4) {
            bad++;
            continue;
        }
        int ok = 0;
        for (int s = 0; s < 4; s++) {
            if (!pose_finite(&poses[s]))
                bad++;
            if (pose_dist(&poses[s], R, tr) < 1e-9)
                ok = 1;
        }
        found += ok;
        if (pose_dist(&poses[0], R, tr) < 1e-9 && cnt[0] == N && cnt[1] < N)
            chosen++;
        for (int s = 1; s < 4; s++)
            if (cnt[s] > cnt[s - 1])
                bad++;
    }
    SFM_TEST_LOG("essential: truth among the four in %d of %d, chosen in %d", found, iters,
                 chosen);
    SFM_CHECK_EQ_INT(bad, 0);
    SFM_CHECK(found == iters);
    SFM_CHECK((double)chosen / iters >= 0.999);
}

SFM_TEST(essential_to_poses_noisy_and_degenerate)
{
    enum { N = 30 };
    int chosen = 0;
    const int iters = SFM_TEST_ITERS(2000);
    for (int it = 0; it < iters; it++) {
        double R[9], tr[3], x1[3 * N], x2[3 * N];
        sfm_mat3 E;
        essential_problem(t, N, R, tr, E.m, x1, x2);
        double mx = 0.0;
        sfm_mat3 En;
        for (int i = 0; i < 9; i++)
            mx = fmax(mx, fabs(E.m[i]));
        for (int i = 0; i < 9; i++)
            En.m[i] = E.m[i] + sfm_test_normal(t, 1e-4 * mx);
        sfm_pose poses[4];
        int cnt[4];
        SFM_CHECK_EQ_INT(sfm_essential_to_poses(&En, x1, x2, N, poses, cnt), 4);
        /* every R is a rotation even for a noisy E */
        for (int s = 0; s < 4; s++) {
            double Rt[9], RtR[9];
            for (int r = 0; r < 3; r++)
                for (int c = 0; c < 3; c++)
                    Rt[3 * r + c] = poses[s].R[3 * c + r];
            mat_mul(Rt, poses[s].R, RtR);
            for (int i = 0; i < 9; i++)
                SFM_CHECK(fabs(RtR[i] - (i % 4 == 0)) < 1e-12);
        }
        if (pose_dist(&poses[0], R, tr) < 1e-2)
            chosen++;
    }
    SFM_CHECK((double)chosen / iters >= 0.99);
    /* no points: fixed order, zero counts, no point arrays needed */
    double R[9], tr[3];
    sfm_mat3 E;
    essential_problem(t, 0, R, tr, E.m, NULL, NULL);
    sfm_pose poses[4];
    int cnt[4] = {7, 7, 7, 7};
    SFM_CHECK_EQ_INT(sfm_essential_to_poses(&E, NULL, NULL, 0, poses, cnt), 4);
    SFM_CHECK(cnt[0] == 0 && cnt[3] == 0);
    for (int k = 0; k < 3; k++) {
        SFM_CHECK_NEAR(poses[0].t[k], -poses[1].t[k], 0.0);
        SFM_CHECK_NEAR(poses[2].t[k], poses[0].t[k], 0.0);
    }
    SFM_CHECK_EQ_INT(sfm_essential_to_poses(&E, NULL, NULL, 0, poses, NULL), 4);
    /* zero and rank-1 E: 0, nothing written */
    sfm_mat3 Z = {{0}};
    sfm_test_fill_canary(poses, sizeof poses);
    SFM_CHECK_EQ_INT(sfm_essential_to_poses(&Z, NULL, NULL, 0, poses, NULL), 0);
    double a[3] = {1, 2, 3}, b[3] = {-1, 0.5, 2};
    for (int r = 0; r < 3; r++)
        for (int c = 0; c < 3; c++)
            Z.m[3 * r + c] = a[r] * b[c];
    SFM_CHECK_EQ_INT(sfm_essential_to_poses(&Z, NULL, NULL, 0, poses, NULL), 0);
    SFM_CHECK(sfm_test_canary_intact(poses, sizeof poses));
}

SFM_TEST(essential_to_poses_contract)
{
    enum { N = 5 };
    double R[9], tr[3], x1[3 * N], x2[3 * N];
    sfm_mat3 E;
    essential_problem(t, N, R, tr, E.m, x1, x2);
    sfm_pose poses[4];
    int cnt[4];
    sfm_test_fill_canary(poses, sizeof poses);
    sfm_test_fill_canary(cnt, sizeof cnt);
    SFM_CHECK_EQ_INT(sfm_essential_to_poses(NULL, x1, x2, N, poses, cnt), SFM_E_ARGUMENT);
    SFM_CHECK_EQ_INT(sfm_essential_to_poses(&E, x1, x2, N, NULL, cnt), SFM_E_ARGUMENT);
    SFM_CHECK_EQ_INT(sfm_essential_to_poses(&E, NULL, x2, N, poses, cnt), SFM_E_ARGUMENT);
    SFM_CHECK_EQ_INT(sfm_essential_to_poses(&E, x1, NULL, N, poses, cnt), SFM_E_ARGUMENT);
    SFM_CHECK_EQ_INT(sfm_essential_to_poses(&E, x1, x2, -1, poses, cnt), SFM_E_ARGUMENT);
    sfm_mat3 b;
    memcpy(b.m, E.m, sizeof b.m);
    b.m[4] = (double)NAN;
    SFM_CHECK_EQ_INT(sfm_essential_to_poses(&b, x1, x2, N, poses, cnt), SFM_E_NONFINITE);
    b.m[4] = HUGE_VAL;
    SFM_CHECK_EQ_INT(sfm_essential_to_poses(&b, x1, x2, N, poses, cnt), SFM_E_NONFINITE);
    double xb[3 * N];
    memcpy(xb, x2, sizeof xb);
    xb[3 * N - 1] = (double)NAN;
    SFM_CHECK_EQ_INT(sfm_essential_to_poses(&E, x1, xb, N, poses, cnt), SFM_E_NONFINITE);
    SFM_CHECK(sfm_test_canary_intact(poses, sizeof poses));
    SFM_CHECK(sfm_test_canary_intact(cnt, sizeof cnt));
}
