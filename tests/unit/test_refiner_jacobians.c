/* verify_jacobian (tests/harness/jacobian_check.h) on every refiner's
 * residual: the analytic Jacobians of the Sampson, reprojection,
 * fundamental-matrix and homography refinements and of the trifocal gold
 * standard against central differences along the manifolds the LM driver
 * updates on, at points away from the optimum. (Bundle adjustment's
 * projection through each camera model is checked in test_ba.c.) */
#include <math.h>
#include <string.h>

#include "core/lm.h"
#include "jacobian_check.h"
#include "robust/fundamental_lm.h"
#include "robust/homography_lm.h"
#include "robust/reproj_lm.h"
#include "robust/sampson_lm.h"
#include "robust/trifocal_refine.h"
#include "sfm/sfm.h"
#include "sfm_test.h"

/* Figures are logged on hosts only (newlib's floating-point printf
 * allocates on the Cortex-M7 target). */
#ifdef SFM_TEST_REDUCED
#define JLOG(...) ((void)0)
#else
#define JLOG(...) SFM_TEST_LOG(__VA_ARGS__)
#endif

#define NPT 20
#define TOL 1e-6

static void matvec(const double *M, const double *x, double *y)
{
    for (int r = 0; r < 3; r++)
        y[r] = M[3 * r] * x[0] + M[3 * r + 1] * x[1] + M[3 * r + 2] * x[2];
}

static void normalize3(double *v)
{
    double n = sqrt(v[0] * v[0] + v[1] * v[1] + v[2] * v[2]);
    for (int k = 0; k < 3; k++)
        v[k] /= n;
}

/* A rotation a few degrees from R. */
static void nudge_rotation(sfm_test_ctx *t, const double *R, double deg, double *out)
{
    double w[3], dR[9];
    sfm_test_random_unit(t, w);
    for (int k = 0; k < 3; k++)
        w[k] *= deg * 3.14159265358979323846 / 180.0;
    sfm_rot_from_axis_angle(w, dR);
    for (int r = 0; r < 3; r++)
        for (int c = 0; c < 3; c++)
            out[3 * r + c] = dR[3 * r] * R[c] + dR[3 * r + 1] * R[3 + c] + dR[3 * r + 2] * R[6 + c];
}

/* Two views of points 2..10 ahead: bearings b1, b2 (noisy), the truth R, t. */
static void two_view(sfm_test_ctx *t, double *b1, double *b2, double *X, double R[9], double tr[3])
{
    sfm_test_random_rotation(t, R);
    nudge_rotation(t, (const double[9]){1, 0, 0, 0, 1, 0, 0, 0, 1}, 15.0, R);
    sfm_test_random_unit(t, tr);
    for (int i = 0; i < NPT; i++) {
        double *x = X + 3 * i;
        x[0] = sfm_test_uniform(t, -2, 2);
        x[1] = sfm_test_uniform(t, -2, 2);
        x[2] = sfm_test_uniform(t, 4, 10);
        double y[3];
        matvec(R, x, y);
        for (int k = 0; k < 3; k++) {
            y[k] += tr[k] + sfm_test_normal(t, 0.01);
            b1[3 * i + k] = x[k];
            b2[3 * i + k] = y[k];
        }
        normalize3(b1 + 3 * i);
        normalize3(b2 + 3 * i);
    }
}

SFM_TEST(refiner_jacobian_sampson_free_and_upright)
{
    double b1[3 * NPT], b2[3 * NPT], X[3 * NPT], R[9], tr[3];
    int idx[NPT];
    for (int i = 0; i < NPT; i++)
        idx[i] = i;
    double worst = 0.0;
    for (int it = 0; it < SFM_TEST_ITERS(10); it++) {
        two_view(t, b1, b2, X, R, tr);
        double R0[9], t0[3] = {tr[0] + 0.05, tr[1] - 0.03, tr[2]};
        nudge_rotation(t, R, 2.0, R0);
        normalize3(t0);
        for (int up = 0; up < 2; up++) {
            double axis[3] = {0.0, 1.0, 0.0}, d2[3];
            matvec(R0, axis, d2);
            sfmi_sampson_problem sp;
            sfmi_sampson_lm_problem(b1, b2, idx, NPT, up ? d2 : NULL, 0.0, R0, t0, &sp);
            for (int i = 0; i < NPT; i += 3) {
                double e = sfm_test_verify_lm_residual(&sp.prob, i, 1e-6);
                worst = fmax(worst, e);
                SFM_CHECK_MSG(e < TOL, "upright %d pair %d: error %.3g", up, i, e);
            }
        }
    }
    JLOG("worst relative Jacobian error %.3g", worst);
}

SFM_TEST(refiner_jacobian_reprojection)
{
    double b1[3 * NPT], b2[3 * NPT], X[3 * NPT], R[9], tr[3];
    int idx[NPT];
    for (int i = 0; i < NPT; i++)
        idx[i] = i;
    double worst = 0.0;
    for (int it = 0; it < SFM_TEST_ITERS(10); it++) {
        two_view(t, b1, b2, X, R, tr);
        double R0[9], t0[3] = {tr[0] + 0.1, tr[1], tr[2] - 0.1};
        nudge_rotation(t, R, 2.0, R0);
        sfmi_reproj_problem rp;
        sfmi_reproj_lm_problem(b2, X, idx, NPT, 0.0, R0, t0, &rp);
        for (int i = 0; i < NPT; i += 3) {
            double e = sfm_test_verify_lm_residual(&rp.prob, i, 1e-6);
            worst = fmax(worst, e);
            SFM_CHECK_MSG(e < TOL, "point %d: error %.3g", i, e);
        }
    }
    JLOG("worst relative Jacobian error %.3g", worst);
}

/* Pixels of the two views through K = (500, 500, 320, 240). */
static void to_pixels(const double *b, double *p)
{
    for (int i = 0; i < NPT; i++) {
        p[2 * i] = 500.0 * b[3 * i] / b[3 * i + 2] + 320.0;
        p[2 * i + 1] = 500.0 * b[3 * i + 1] / b[3 * i + 2] + 240.0;
    }
}

SFM_TEST(refiner_jacobian_fundamental)
{
    double b1[3 * NPT], b2[3 * NPT], X[3 * NPT], R[9], tr[3], p1[2 * NPT], p2[2 * NPT];
    double worst = 0.0;
    for (int it = 0; it < SFM_TEST_ITERS(10); it++) {
        two_view(t, b1, b2, X, R, tr);
        to_pixels(b1, p1);
        to_pixels(b2, p2);
        /* F = K^-T [t]x R K^-1 of a nudged pose: rank 2, not the optimum */
        double R0[9], E[9], T[9], F[9];
        nudge_rotation(t, R, 1.0, R0);
        sfm_skew(tr, T);
        for (int r = 0; r < 3; r++)
            for (int c = 0; c < 3; c++)
                E[3 * r + c] = T[3 * r] * R0[c] + T[3 * r + 1] * R0[3 + c] + T[3 * r + 2] * R0[6 + c];
        const double Ki[9] = {1.0 / 500, 0, -320.0 / 500, 0, 1.0 / 500, -240.0 / 500, 0, 0, 1};
        double A[9];
        for (int r = 0; r < 3; r++)
            for (int c = 0; c < 3; c++)
                A[3 * r + c] = E[3 * r] * Ki[c] + E[3 * r + 1] * Ki[3 + c] + E[3 * r + 2] * Ki[6 + c];
        for (int r = 0; r < 3; r++)
            for (int c = 0; c < 3; c++)
                F[3 * r + c] = Ki[r] * A[c] + Ki[3 + r] * A[3 + c] + Ki[6 + r] * A[6 + c];
        sfmi_fundamental_problem fp;
        SFM_CHECK_EQ_INT(sfmi_fundamental_lm_problem(p1, p2, NPT, 0.0, F, &fp), 0);
        for (int i = 0; i < NPT; i += 3) {
            double e = sfm_test_verify_lm_residual(&fp.prob, i, 1e-6);
            worst = fmax(worst, e);
            SFM_CHECK_MSG(e < TOL, "pair %d: error %.3g", i, e);
        }
    }
    JLOG("worst relative Jacobian error %.3g", worst);
}

SFM_TEST(refiner_jacobian_homography)
{
    double worst = 0.0;
    for (int it = 0; it < SFM_TEST_ITERS(10); it++) {
        double H[9], p1[2 * NPT], p2[2 * NPT];
        for (int k = 0; k < 9; k++)
            H[k] = (k % 4 == 0 ? 1.0 : 0.0) + sfm_test_normal(t, k >= 6 ? 1e-4 : 0.05);
        H[2] += 20.0;
        H[5] -= 10.0;
        for (int i = 0; i < NPT; i++) {
            double x[3] = {sfm_test_uniform(t, 0, 640), sfm_test_uniform(t, 0, 480), 1.0}, y[3];
            matvec(H, x, y);
            p1[2 * i] = x[0];
            p1[2 * i + 1] = x[1];
            p2[2 * i] = y[0] / y[2] + sfm_test_normal(t, 1.0);
            p2[2 * i + 1] = y[1] / y[2] + sfm_test_normal(t, 1.0);
        }
        sfmi_homography_problem hp;
        SFM_CHECK_EQ_INT(sfmi_homography_lm_problem(p1, p2, NPT, 0.0, H, &hp), 0);
        for (int i = 0; i < NPT; i += 3) {
            double e = sfm_test_verify_lm_residual(&hp.prob, i, 1e-6);
            worst = fmax(worst, e);
            SFM_CHECK_MSG(e < TOL, "pair %d: error %.3g", i, e);
        }
    }
    JLOG("worst relative Jacobian error %.3g", worst);
}

/* The trifocal refinement's residual of one point as a function of the
 * tangent step (dP2 (12), dP3 (12), dX (3) along sfmi_lm_sphere_basis). */
typedef struct tf_probe {
    const double *xs[3];
    double P2[12], P3[12], X[4];
} tf_probe;

static int tf_residual(const void *user, const double *d, double *r)
{
    const tf_probe *q = user;
    double P2[12], P3[12], X[4];
    for (int k = 0; k < 12; k++) {
        P2[k] = q->P2[k] + d[k];
        P3[k] = q->P3[k] + d[12 + k];
    }
    const sfmi_lm_block blk = {(double *)q->X, 4, SFMI_LM_SPHERE, 0, NULL, NULL};
    if (!sfmi_lm_block_plus(&blk, q->X, d + 24, X))
        return 0;
    sfmi_tf_point_blocks b;
    if (!sfmi_tf_point_jacobians(q->xs, 0, P2, P3, X, &b))
        return 0;
    memcpy(r, b.r, sizeof b.r);
    return 1;
}

SFM_TEST(refiner_jacobian_trifocal_point_and_cameras)
{
    double worst = 0.0;
    for (int it = 0; it < SFM_TEST_ITERS(20); it++) {
        tf_probe q;
        double x[3][2];
        for (int v = 0; v < 3; v++) {
            x[v][0] = sfm_test_uniform(t, -0.3, 0.3);
            x[v][1] = sfm_test_uniform(t, -0.3, 0.3);
            q.xs[v] = x[v];
        }
        /* cameras near [I | c] with a random point in front of all three */
        for (int k = 0; k < 12; k++) {
            q.P2[k] = (k % 5 == 0 ? 1.0 : 0.0) + sfm_test_normal(t, 0.05);
            q.P3[k] = (k % 5 == 0 ? 1.0 : 0.0) + sfm_test_normal(t, 0.05);
        }
        q.P2[3] += 0.5;
        q.P3[7] -= 0.5;
        double Xe[4] = {sfm_test_uniform(t, -1, 1), sfm_test_uniform(t, -1, 1), sfm_test_uniform(t, 4, 6), 1.0};
        double nn = sqrt(Xe[0] * Xe[0] + Xe[1] * Xe[1] + Xe[2] * Xe[2] + 1.0);
        for (int k = 0; k < 4; k++)
            q.X[k] = Xe[k] / nn;
        sfmi_tf_point_blocks b;
        SFM_CHECK(sfmi_tf_point_jacobians(q.xs, 0, q.P2, q.P3, q.X, &b));
        enum { NC = 27 };
        double J[6 * NC];
        memset(J, 0, sizeof J);
        /* the camera blocks from their factors: iw [X^T 0 -u X^T; 0 X^T -v X^T] */
        for (int w = 0; w < 2; w++) {
            const double iw = b.cam[3 * w], uv[2] = {b.cam[3 * w + 1], b.cam[3 * w + 2]};
            for (int h = 0; h < 2; h++)
                for (int k = 0; k < 4; k++) {
                    J[(2 + 2 * w + h) * NC + 12 * w + 4 * h + k] = iw * q.X[k];
                    J[(2 + 2 * w + h) * NC + 12 * w + 8 + k] = -iw * uv[h] * q.X[k];
                }
        }
        for (int r = 0; r < 6; r++)
            for (int c = 0; c < 3; c++)
                J[r * NC + 24 + c] = b.Jp[r * 3 + c];
        double e = sfm_test_verify_jacobian(tf_residual, &q, NC, 6, J, 1e-7);
        worst = fmax(worst, e);
        SFM_CHECK_MSG(e < TOL, "trial %d: error %.3g", it, e);
    }
    JLOG("worst relative Jacobian error %.3g", worst);
}

/* The batch callback of the Sampson problem gives the per-pair callback's
 * values bit for bit: every count from 1 to SFMI_LM_BATCH (the lanes past
 * count repeat a pair and are dropped), free and upright rotation, t free
 * and held, with and without the Jacobian, and a pair at the epipole (D = 0:
 * left out). */
SFM_TEST(refiner_sampson_batch_matches_per_pair)
{
#if SFMI_LM_HAVE_BATCH
    double b1[3 * NPT], b2[3 * NPT], X[3 * NPT], R[9], tr[3];
    int idx[NPT];
    int compared = 0;
    for (int it = 0; it < SFM_TEST_ITERS(10); it++) {
        two_view(t, b1, b2, X, R, tr);
        for (int i = 0; i < NPT; i++)
            idx[i] = (7 * i + it) % NPT;
        double R0[9], t0[3] = {tr[0] + 0.05, tr[1] - 0.03, tr[2]};
        nudge_rotation(t, R, 2.0, R0);
        normalize3(t0);
        /* pair 3 at the epipoles of (R0, t0): b1 = R0^T t0, b2 = t0 */
        double e1[3] = {R0[0] * t0[0] + R0[3] * t0[1] + R0[6] * t0[2],
                        R0[1] * t0[0] + R0[4] * t0[1] + R0[7] * t0[2],
                        R0[2] * t0[0] + R0[5] * t0[1] + R0[8] * t0[2]};
        memcpy(b1 + 3 * 3, e1, sizeof e1);
        memcpy(b2 + 3 * 3, t0, sizeof t0);
        for (int mode = 0; mode < 4; mode++) {
            const int up = mode & 1, held = mode >> 1;
            double axis[3] = {0.0, 1.0, 0.0}, d2[3];
            matvec(R0, axis, d2);
            sfmi_sampson_problem sp;
            sfmi_sampson_lm_problem(b1, b2, idx, NPT, up ? d2 : NULL, 0.0, R0, t0, &sp);
            if (held)
                sp.blocks[1].manifold = SFMI_LM_CONSTANT;
            SFM_CHECK(sp.prob.batch != NULL);
            const int nt = (up ? 1 : 3) + (held ? 0 : 2);
            const double *xp[2] = {R0, t0};
            for (int count = 1; count <= SFMI_LM_BATCH; count++) {
                for (int i0 = 0; i0 + count <= NPT; i0 += count) {
                    int okb[SFMI_LM_BATCH];
                    double rb[SFMI_LM_BATCH], Jb[SFMI_LM_BATCH * SFMI_LM_BATCH_TANGENT];
                    double rn[SFMI_LM_BATCH];
                    sp.prob.batch(&sp, xp, i0, count, okb, rb, Jb);
                    sp.prob.batch(&sp, xp, i0, count, okb, rn, NULL);
                    for (int k = 0; k < count; k++) {
                        double r1 = 0.0, J1[5] = {0};
                        int ok = sp.prob.residual(&sp, xp, i0 + k, &r1, J1);
                        SFM_CHECK_EQ_INT(okb[k], ok);
                        if (ok != 1)
                            continue;
                        SFM_CHECK(memcmp(&rb[k], &r1, sizeof r1) == 0);
                        SFM_CHECK(memcmp(&rn[k], &r1, sizeof r1) == 0);
                        for (int c = 0; c < nt; c++) {
                            const double *jb = &Jb[c * SFMI_LM_BATCH + k];
                            SFM_CHECK(memcmp(jb, &J1[c], sizeof(double)) == 0);
                        }
                        compared++;
                    }
                }
            }
        }
    }
    SFM_CHECK(compared > 0);
#else
    SFM_CHECK(1);
#endif
}

/* The influence test of the relative-pose polish (sfmi_sampson_prune)
 * against an oracle written here: each pair's Sampson error from its own
 * formula, the Jacobian by central differences along a tangent basis of its
 * own (leverages do not depend on the basis), the leverages h from a
 * Gauss-Jordan inverse of J^T J, Cook's distance r^2 h / (p sigma^2
 * (1 - h)^2). Also the truth: pairs planted with a residual of 12 sigma are
 * dropped, and nearly all true pairs kept. */
#define PRUNE_N 120
#define PRUNE_PLANT 4

static double sampson_of(const double *R, const double *tv, const double *x1, const double *x2)
{
    double u[3], a[3], v[3];
    matvec(R, x1, u);
    a[0] = tv[1] * u[2] - tv[2] * u[1];
    a[1] = tv[2] * u[0] - tv[0] * u[2];
    a[2] = tv[0] * u[1] - tv[1] * u[0];
    v[0] = x2[1] * tv[2] - x2[2] * tv[1];
    v[1] = x2[2] * tv[0] - x2[0] * tv[2];
    v[2] = x2[0] * tv[1] - x2[1] * tv[0];
    const double C = u[0] * v[0] + u[1] * v[1] + u[2] * v[2];
    const double D = a[0] * a[0] + a[1] * a[1] + a[2] * a[2] + v[0] * v[0] + v[1] * v[1] +
                     v[2] * v[2] - 2.0 * C * C;
    return C / sqrt(D);
}

/* (R, t) moved by the tangent vector d: R <- exp([w]x) R with w = d[0..2]
 * (or d[0] axis when axis is given), t <- normalise(t + d e1 + d e2). */
static void moved(const double *R, const double *tv, const double *axis, const double *d,
                  double *Rm, double *tm)
{
    const int nr = axis ? 1 : 3;
    double w[3] = {d[0], axis ? 0.0 : d[1], axis ? 0.0 : d[2]}, dR[9];
    if (axis)
        for (int k = 0; k < 3; k++)
            w[k] = d[0] * axis[k];
    sfm_rot_from_axis_angle(w, dR);
    for (int r = 0; r < 3; r++)
        for (int c = 0; c < 3; c++)
            Rm[3 * r + c] = dR[3 * r] * R[c] + dR[3 * r + 1] * R[3 + c] + dR[3 * r + 2] * R[6 + c];
    /* a tangent basis at t: e1 = normalise(t x z or t x x), e2 = t x e1 */
    double e1[3], e2[3], z[3] = {0.0, 0.0, 1.0};
    if (fabs(tv[2]) > 0.9) {
        z[0] = 1.0;
        z[2] = 0.0;
    }
    e1[0] = tv[1] * z[2] - tv[2] * z[1];
    e1[1] = tv[2] * z[0] - tv[0] * z[2];
    e1[2] = tv[0] * z[1] - tv[1] * z[0];
    normalize3(e1);
    e2[0] = tv[1] * e1[2] - tv[2] * e1[1];
    e2[1] = tv[2] * e1[0] - tv[0] * e1[2];
    e2[2] = tv[0] * e1[1] - tv[1] * e1[0];
    for (int k = 0; k < 3; k++)
        tm[k] = tv[k] + d[nr] * e1[k] + d[nr + 1] * e2[k];
    normalize3(tm);
}

/* Cook's distance of every pair under (R, t) by the oracle above. */
static void oracle_cook(const double *b1, const double *b2, int n, const double *axis,
                        const double *R, const double *tv, double sigma2, double *r, double *cook)
{
    const int p = axis ? 3 : 5;
    static double J[PRUNE_N][5];
    double M[5][10] = {{0}};
    for (int i = 0; i < n; i++) {
        r[i] = sampson_of(R, tv, b1 + 3 * i, b2 + 3 * i);
        for (int c = 0; c < p; c++) {
            double d[5] = {0}, Rm[9], tm[3], f[2];
            for (int s = 0; s < 2; s++) {
                d[c] = s ? -1e-6 : 1e-6;
                moved(R, tv, axis, d, Rm, tm);
                f[s] = sampson_of(Rm, tm, b1 + 3 * i, b2 + 3 * i);
            }
            J[i][c] = (f[0] - f[1]) / 2e-6;
        }
        for (int a = 0; a < p; a++)
            for (int b = 0; b < p; b++)
                M[a][b] += J[i][a] * J[i][b];
    }
    /* Gauss-Jordan inverse of M into M[.][p..2p) */
    for (int a = 0; a < p; a++)
        M[a][p + a] = 1.0;
    for (int c = 0; c < p; c++) {
        int piv = c;
        for (int a = c + 1; a < p; a++)
            if (fabs(M[a][c]) > fabs(M[piv][c]))
                piv = a;
        for (int b = 0; b < 2 * p; b++) {
            double s = M[c][b];
            M[c][b] = M[piv][b];
            M[piv][b] = s;
        }
        const double inv = 1.0 / M[c][c];
        for (int b = 0; b < 2 * p; b++)
            M[c][b] *= inv;
        for (int a = 0; a < p; a++) {
            if (a == c)
                continue;
            const double f = M[a][c];
            for (int b = 0; b < 2 * p; b++)
                M[a][b] -= f * M[c][b];
        }
    }
    for (int i = 0; i < n; i++) {
        double h = 0.0;
        for (int a = 0; a < p; a++)
            for (int b = 0; b < p; b++)
                h += J[i][a] * M[a][p + b] * J[i][b];
        cook[i] = r[i] * r[i] * h / ((double)p * sigma2 * (1.0 - h) * (1.0 - h));
    }
}

SFM_TEST(sampson_prune_matches_cook_oracle_and_drops_planted_pairs)
{
    static double b1[3 * PRUNE_N], b2[3 * PRUNE_N], r[PRUNE_N], cook[PRUNE_N];
    int idx[PRUNE_N];
    const double noise = 1e-3, cut = 16.0 / PRUNE_N;
    int decided = 0;
    for (int it = 0; it < SFM_TEST_ITERS(10); it++) {
        for (int up = 0; up < 2; up++) {
            double R[9], tv[3];
            sfm_test_random_rotation(t, R);
            nudge_rotation(t, (const double[9]){1, 0, 0, 0, 1, 0, 0, 0, 1}, 15.0, R);
            sfm_test_random_unit(t, tv);
            for (int i = 0; i < PRUNE_N; i++) {
                double x[3] = {sfm_test_uniform(t, -2, 2), sfm_test_uniform(t, -2, 2),
                               sfm_test_uniform(t, 4, 10)}, y[3];
                matvec(R, x, y);
                for (int k = 0; k < 3; k++) {
                    b1[3 * i + k] = x[k];
                    b2[3 * i + k] = y[k] + tv[k];
                }
                normalize3(b1 + 3 * i);
                normalize3(b2 + 3 * i);
                /* noise (or a planted error of 12 sigma, for the last
                 * pairs) across the epipolar plane of camera 2 */
                double nrm[3], u[3];
                matvec(R, b1 + 3 * i, u);
                nrm[0] = tv[1] * u[2] - tv[2] * u[1];
                nrm[1] = tv[2] * u[0] - tv[0] * u[2];
                nrm[2] = tv[0] * u[1] - tv[1] * u[0];
                normalize3(nrm);
                const double e = i >= PRUNE_N - PRUNE_PLANT ? 12.0 * noise : sfm_test_normal(t, noise);
                for (int k = 0; k < 3; k++)
                    b2[3 * i + k] += e * nrm[k];
                normalize3(b2 + 3 * i);
                idx[i] = i;
            }
            double axis[3] = {0.0, 1.0, 0.0}, d2[3];
            matvec(R, axis, d2);
            const double *ax = up ? d2 : NULL;
            /* sigma from the true pairs' residuals at the truth */
            double s2 = 0.0;
            for (int i = 0; i < PRUNE_N - PRUNE_PLANT; i++) {
                const double ri = sampson_of(R, tv, b1 + 3 * i, b2 + 3 * i);
                s2 += ri * ri;
            }
            s2 /= PRUNE_N - PRUNE_PLANT;
            oracle_cook(b1, b2, PRUNE_N, ax, R, tv, s2, r, cook);
            const int kept = sfmi_sampson_prune(b1, b2, idx, PRUNE_N, ax, R, tv, s2, cut);
            SFM_CHECK(kept > 0 && kept <= PRUNE_N);
            /* kept in order, a subset; the oracle's verdict wherever the
             * distance is not within 2 % of the cut */
            int j = 0, true_dropped = 0;
            for (int i = 0; i < PRUNE_N; i++) {
                const int in = j < kept && idx[j] == i;
                j += in;
                if (i >= PRUNE_N - PRUNE_PLANT)
                    SFM_CHECK_MSG(!in, "planted pair %d kept (Cook %.3g, cut %.3g)", i, cook[i], cut);
                else
                    true_dropped += !in;
                if (fabs(cook[i] - cut) > 0.02 * cut) {
                    SFM_CHECK_MSG(in == (cook[i] < cut), "pair %d: kept %d, oracle Cook %.4g, cut %.4g",
                                  i, in, cook[i], cut);
                    decided++;
                }
            }
            SFM_CHECK_EQ_INT(j, kept);
            SFM_CHECK_MSG(true_dropped <= PRUNE_N / 20, "%d true pairs dropped", true_dropped);
            /* refused: no noise level, too few pairs (list untouched) */
            for (int i = 0; i < PRUNE_N; i++)
                idx[i] = PRUNE_N - 1 - i;
            SFM_CHECK_EQ_INT(sfmi_sampson_prune(b1, b2, idx, PRUNE_N, ax, R, tv, 0.0, cut), PRUNE_N);
            SFM_CHECK_EQ_INT(sfmi_sampson_prune(b1, b2, idx, PRUNE_N, ax, R, tv, (double)NAN, cut),
                             PRUNE_N);
            SFM_CHECK_EQ_INT(sfmi_sampson_prune(b1, b2, idx, up ? 4 : 6, ax, R, tv, s2, cut), up ? 4 : 6);
            for (int i = 0; i < PRUNE_N; i++)
                SFM_CHECK_EQ_INT(idx[i], PRUNE_N - 1 - i);
        }
    }
    SFM_CHECK(decided > 0);
    JLOG("%d verdicts compared with the oracle", decided);
}
