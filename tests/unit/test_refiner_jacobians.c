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
