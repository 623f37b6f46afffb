/* The two poses of a plane-induced homography: H = R + t n^T / d built from
 * a random pose and plane, the decomposition must return that (R, t/|t|)
 * as one of its two, each a rotation with a unit t, and the other must
 * also map the plane's points (H up to scale). A rotation alone (t = 0)
 * has no translation to recover: 0. */
#include <math.h>
#include <string.h>

#include "sfm/sfm_rotation.h"
#include "solvers/homography_decompose.h"
#include "solvers/small_math.h"
#include "sfm_test.h"

static double rot_gap(const double *A, const double *B)
{
    double d = 0.0;
    for (int k = 0; k < 9; k++)
        d += (A[k] - B[k]) * (A[k] - B[k]);
    return sqrt(d);
}

/* a random pose (centre 0.3..1.3 away), a plane 4..8 deep tilted up to
 * ~30 deg, H, and 20 points of the plane seen by both cameras */
static void problem(sfm_test_ctx *t, double scale, double *R, double *tt, double *H, double *p1,
                    double *p2, int *m)
{
    double w[3] = {0.2 * sfm_rng_normal(&t->rng), 0.2 * sfm_rng_normal(&t->rng),
                   0.2 * sfm_rng_normal(&t->rng)};
    sfm_rot_from_axis_angle(w, R);
    for (int k = 0; k < 3; k++)
        tt[k] = scale * sfm_rng_normal(&t->rng);
    double n[3] = {0.5 * (sfm_rng_uniform(&t->rng) - 0.5), 0.5 * (sfm_rng_uniform(&t->rng) - 0.5),
                   1.0};
    double ln = sqrt(sfmi_dot3(n, n));
    for (int k = 0; k < 3; k++)
        n[k] /= ln;
    double d = 4.0 + 4.0 * sfm_rng_uniform(&t->rng);
    for (int r = 0; r < 3; r++)
        for (int c = 0; c < 3; c++)
            H[3 * r + c] = R[3 * r + c] + tt[r] * n[c] / d;
    *m = 0;
    for (int i = 0; i < 200 && *m < 20; i++) {
        double x[3] = {sfm_rng_uniform(&t->rng) - 0.5, sfm_rng_uniform(&t->rng) - 0.5, 1.0};
        double lam = d / sfmi_dot3(n, x), X2[3];
        if (!(lam > 0.0))
            continue;
        sfmi_matvec3(R, x, X2);
        for (int k = 0; k < 3; k++)
            X2[k] = lam * X2[k] + tt[k];
        if (!(X2[2] > 0.1))
            continue;
        p1[2 * *m] = x[0];
        p1[2 * *m + 1] = x[1];
        p2[2 * *m] = X2[0] / X2[2];
        p2[2 * *m + 1] = X2[1] / X2[2];
        (*m)++;
    }
}

SFM_TEST(homography_decompose_returns_the_truth_and_a_twin)
{
    const int iters = SFM_TEST_ITERS(500);
    int found = 0, runs = 0;
    for (int it = 0; it < iters; it++) {
        double R[9], tt[3], H[9], p1[40], p2[40], Rs[2][9], ts[2][3];
        int m;
        problem(t, 1.0, R, tt, H, p1, p2, &m);
        if (m < 4)
            continue;
        runs++;
        /* any scale and sign of H */
        double s = (it & 1 ? -1.0 : 1.0) * (0.1 + 10.0 * sfm_rng_uniform(&t->rng));
        for (int k = 0; k < 9; k++)
            H[k] *= s;
        int k = sfmi_homography_decompose(H, p1, p2, m, Rs, ts);
        SFM_CHECK_EQ_INT(k, 2);
        if (k != 2)
            continue;
        double lt = sqrt(sfmi_dot3(tt, tt)), tu[3] = {tt[0] / lt, tt[1] / lt, tt[2] / lt};
        int hit = 0;
        for (int j = 0; j < 2; j++) {
            double RtR[9];
            for (int a = 0; a < 3; a++)
                for (int b = 0; b < 3; b++)
                    RtR[3 * a + b] = Rs[j][a] * Rs[j][b] + Rs[j][3 + a] * Rs[j][3 + b] +
                                     Rs[j][6 + a] * Rs[j][6 + b];
            const double I[9] = {1, 0, 0, 0, 1, 0, 0, 0, 1};
            SFM_CHECK(rot_gap(RtR, I) < 1e-9);
            SFM_CHECK(fabs(sqrt(sfmi_dot3(ts[j], ts[j])) - 1.0) < 1e-12);
            double dt[3] = {ts[j][0] - tu[0], ts[j][1] - tu[1], ts[j][2] - tu[2]};
            hit |= rot_gap(Rs[j], R) < 1e-7 && sqrt(sfmi_dot3(dt, dt)) < 1e-7;
        }
        found += hit;
    }
    SFM_TEST_LOG("truth among the two in %d of %d", found, runs);
    SFM_CHECK(runs > iters / 2);
    SFM_CHECK_EQ_INT(found, runs);
}

SFM_TEST(homography_decompose_rotation_and_bad_input)
{
    double R[9], tt[3], H[9], p1[40], p2[40], Rs[2][9], ts[2][3];
    int m;
    problem(t, 0.0, R, tt, H, p1, p2, &m);
    SFM_CHECK(m >= 4);
    SFM_CHECK_EQ_INT(sfmi_homography_decompose(H, p1, p2, m, Rs, ts), 0);
    problem(t, 1.0, R, tt, H, p1, p2, &m);
    H[4] = (double)NAN;
    SFM_CHECK_EQ_INT(sfmi_homography_decompose(H, p1, p2, m, Rs, ts), 0);
    SFM_CHECK_EQ_INT(sfmi_homography_decompose(R, p1, p2, 0, Rs, ts), 0);
}
