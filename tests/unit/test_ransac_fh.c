/* Nonlinear refinement of the fundamental matrix (Sampson error, orthonormal
 * representation) and of the homography (Sampson error) against the linear
 * fits they start from, on noisy synthetic scenes with known truth; and
 * DEGENSAC on a dominant plane; the two-view block residual against the
 * point-by-point one. */
#include <math.h>
#include <string.h>

#include "ransac_scene.h"
#include "robust/fundamental_lm.h"
#include "robust/homography_lm.h"
#include "robust/twoview.h"
#include "sfm/sfm.h"
#include "sfm_test.h"

#ifdef SFM_TEST_REDUCED
#define FH_LOG(...) ((void)0)
#else
#define FH_LOG(...) SFM_TEST_LOG(__VA_ARGS__)
#endif

#define NF 100
#define SEEDS 40

static double A1[2 * NF], A2[2 * NF], C1[2 * NF], C2[2 * NF];
static unsigned char TR[NF];

static const double KI[9] = {1.0 / 500, 0, -320.0 / 500, 0, 1.0 / 500, -240.0 / 500, 0, 0, 1};

/* Noise-free and noisy copies of one scene (same motion and points). */
static void scene_pair(sfm_test_ctx *t, int mode, double sigma, double R[9], double tr[3])
{
    sfm_camera cam = scene_pinhole();
    sfm_rng keep = t->rng;
    scene_twoview(t, &cam, NF, 0.0, 0.0, mode, C1, C2, TR, R, tr);
    t->rng = keep;
    scene_twoview(t, &cam, NF, 0.0, sigma, mode, A1, A2, TR, R, tr);
}

/* Symmetric epipolar distance of a noise-free pair (pixels). */
static double sym_epi(const double *F, const double *a, const double *b)
{
    double l[3], m[3];
    for (int r = 0; r < 3; r++) {
        l[r] = F[3 * r] * a[0] + F[3 * r + 1] * a[1] + F[3 * r + 2];
        m[r] = F[r] * b[0] + F[3 + r] * b[1] + F[6 + r];
    }
    double C = l[0] * b[0] + l[1] * b[1] + l[2];
    return 0.5 * fabs(C) * (1.0 / sqrt(l[0] * l[0] + l[1] * l[1]) +
                            1.0 / sqrt(m[0] * m[0] + m[1] * m[1]));
}

static double median_epi(const double *F)
{
    double d[NF];
    for (int i = 0; i < NF; i++)
        d[i] = sym_epi(F, C1 + 2 * i, C2 + 2 * i);
    return scene_median(d, NF);
}

/* Angle (degrees) between the rays of the epipoles of F (right null vector,
 * first image) and of the truth e1 ~ -R^T t, sign-free. */
static double epipole_err_deg(const double *F, const double *R, const double *tr)
{
    double e[3] = {0.0, 0.0, 0.0};
    double r0[3] = {F[0], F[1], F[2]}, r1[3] = {F[3], F[4], F[5]}, r2[3] = {F[6], F[7], F[8]};
    double best = -1.0;
    const double *rows[3] = {r0, r1, r2};
    for (int a = 0; a < 3; a++)
        for (int b = a + 1; b < 3; b++) {
            double x[3];
            x[0] = rows[a][1] * rows[b][2] - rows[a][2] * rows[b][1];
            x[1] = rows[a][2] * rows[b][0] - rows[a][0] * rows[b][2];
            x[2] = rows[a][0] * rows[b][1] - rows[a][1] * rows[b][0];
            double l = x[0] * x[0] + x[1] * x[1] + x[2] * x[2];
            if (l > best) {
                best = l;
                memcpy(e, x, sizeof x);
            }
        }
    double ray[3], truth[3];
    scene_matvec(KI, e, ray);
    for (int k = 0; k < 3; k++)
        truth[k] = -(R[k] * tr[0] + R[3 + k] * tr[1] + R[6 + k] * tr[2]);
    double a = scene_dir_err_deg(ray, truth);
    return a > 90.0 ? 180.0 - a : a;
}

/* One error measure of the linear fit against its LM refinement, summed
 * over scenes, with the number of scenes where LM came closer. */
typedef struct lin_vs_lm {
    double lin, lm;
    int wins;
} lin_vs_lm;

static void tally(lin_vs_lm *a, double lin, double lm)
{
    a->lin += lin;
    a->lm += lm;
    a->wins += lm < lin;
}

SFM_TEST(fundamental_lm_beats_linear_against_truth)
{
    int seeds = SFM_TEST_ITERS(SEEDS);
    lin_vs_lm d = {0.0, 0.0, 0}, e = {0.0, 0.0, 0}; /* epipolar distance, epipole */
    for (int k = 0; k < seeds; k++) {
        double R[9], tr[3];
        scene_pair(t, 0, 1.0, R, tr);
        sfm_mat3 L;
        SFM_CHECK_EQ_INT(sfm_fundamental_8pt(A1, A2, NF, &L), 1);
        double F[9];
        memcpy(F, L.m, sizeof F);
        double c0 = sfmi_robust_fundamental_cost(A1, A2, NF, 0.0, F);
        SFM_CHECK(sfmi_robust_fundamental_lm(A1, A2, NF, 0.0, 10, F) >= 0);
        double c1 = sfmi_robust_fundamental_cost(A1, A2, NF, 0.0, F);
        SFM_CHECK(c1 <= c0);
        /* rank 2 and unit norm by construction */
        double det = F[0] * (F[4] * F[8] - F[5] * F[7]) - F[1] * (F[3] * F[8] - F[5] * F[6]) +
                     F[2] * (F[3] * F[7] - F[4] * F[6]);
        double nrm = 0.0;
        for (int j = 0; j < 9; j++)
            nrm += F[j] * F[j];
        SFM_CHECK(fabs(det) < 1e-12);
        SFM_CHECK_NEAR(nrm, 1.0, 1e-12);
        double dl = median_epi(L.m), dm = median_epi(F);
        double el = epipole_err_deg(L.m, R, tr), em = epipole_err_deg(F, R, tr);
        tally(&d, dl, dm);
        tally(&e, el, em);
    }
    FH_LOG("median sym. epipolar distance to noise-free pairs, mean over %d scenes: linear %.4f "
           "px, LM %.4f px (LM closer in %d); epipole error linear %.3f deg, LM %.3f deg "
           "(LM closer in %d)",
           seeds, d.lin / seeds, d.lm / seeds, d.wins, e.lin / seeds, e.lm / seeds, e.wins);
    /* Statistics need the host's scene count; under emulation the point is
     * that the code runs (the checks above). Over 200 scenes: 17 % closer
     * in epipolar distance (LM closer in 62 %), epipoles 6 % closer. */
    if (seeds >= SEEDS) {
        SFM_CHECK(d.lm < 0.9 * d.lin);
        SFM_CHECK(e.lm <= e.lin);
        SFM_CHECK(2 * d.wins > seeds);
    }
}

/* |y - H x| in pixels. */
static double transfer(const double *H, const double *x, const double *y)
{
    double w = H[6] * x[0] + H[7] * x[1] + H[8];
    double u = (H[0] * x[0] + H[1] * x[1] + H[2]) / w - y[0];
    double v = (H[3] * x[0] + H[4] * x[1] + H[5]) / w - y[1];
    return sqrt(u * u + v * v);
}

static void mat3_mul(const double *A, const double *B, double *C)
{
    for (int r = 0; r < 3; r++)
        for (int c = 0; c < 3; c++)
            C[3 * r + c] = A[3 * r] * B[c] + A[3 * r + 1] * B[3 + c] + A[3 * r + 2] * B[6 + c];
}

/*
 * A ground plane seen at a grazing angle, where perspective is strong: the
 * normalised DLT weights its algebraic error by the projective depth, which
 * then varies across the image, and the Sampson error does not (for a plane
 * facing the camera the two agree to well within the noise). Plane
 * n . X1 = 1 with n about (0, 1, 0.25); noise-free pairs in C1/C2, noisy in
 * A1/A2; the true homography K (R + t n^T) K^-1 in Ht.
 */
static void ground_scene(sfm_test_ctx *t, double sigma, double *Ht)
{
    sfm_camera cam = scene_pinhole();
    double R[9], tr[3], nv[3];
    for (;;) {
        scene_rotation(t, 20.0, R);
        sfm_test_random_unit(t, tr);
        nv[0] = sfm_test_normal(t, 0.1);
        nv[1] = 1.0 + sfm_test_normal(t, 0.1);
        nv[2] = 0.25 + sfm_test_normal(t, 0.1);
        double l = sqrt(nv[0] * nv[0] + nv[1] * nv[1] + nv[2] * nv[2]);
        for (int k = 0; k < 3; k++)
            nv[k] /= l;
        int got = 0;
        for (int tries = 0; tries < 100 * NF && got < NF; tries++) {
            double px[2] = {sfm_test_uniform(t, 0, SCENE_W), sfm_test_uniform(t, 0, SCENE_H)};
            double b[3], X[3], q[2];
            sfm_camera_unproject(&cam, px, b);
            double nb = nv[0] * b[0] + nv[1] * b[1] + nv[2] * b[2];
            if (nb < 0.05)
                continue;
            scene_matvec(R, b, X);
            for (int k = 0; k < 3; k++)
                X[k] = X[k] / nb + tr[k];
            if (X[2] < 0.1 || sfm_camera_project(&cam, X, q, NULL) != SFM_OK)
                continue;
            if (q[0] < 0 || q[0] >= SCENE_W || q[1] < 0 || q[1] >= SCENE_H)
                continue;
            C1[2 * got] = px[0];
            C1[2 * got + 1] = px[1];
            C2[2 * got] = q[0];
            C2[2 * got + 1] = q[1];
            got++;
        }
        if (got == NF)
            break;
    }
    for (int i = 0; i < 2 * NF; i++) {
        A1[i] = C1[i] + sfm_test_normal(t, sigma);
        A2[i] = C2[i] + sfm_test_normal(t, sigma);
    }
    static const double KM[9] = {500, 0, 320, 0, 500, 240, 0, 0, 1};
    double M[9], tmp[9];
    for (int r = 0; r < 3; r++)
        for (int c = 0; c < 3; c++)
            M[3 * r + c] = R[3 * r + c] + tr[r] * nv[c];
    mat3_mul(KM, M, tmp);
    mat3_mul(tmp, KI, Ht);
}

/* Mean transfer error against the truth Ht over a 16 x 12 grid of the first
 * image, at the grid points whose true transfer lands in the second image
 * (the part of the plane both views see). */
static double grid_err(const double *H, const double *Ht)
{
    double s = 0.0;
    int m = 0;
    for (int gy = 0; gy < 12; gy++)
        for (int gx = 0; gx < 16; gx++) {
            const double x[2] = {20.0 + 40.0 * gx, 20.0 + 40.0 * gy};
            double w = Ht[6] * x[0] + Ht[7] * x[1] + Ht[8];
            double y[2] = {(Ht[0] * x[0] + Ht[1] * x[1] + Ht[2]) / w,
                           (Ht[3] * x[0] + Ht[4] * x[1] + Ht[5]) / w};
            if (!(w > 0.0) || y[0] < 0 || y[0] >= SCENE_W || y[1] < 0 || y[1] >= SCENE_H)
                continue;
            s += transfer(H, x, y);
            m++;
        }
    return m > 0 ? s / m : 0.0;
}

SFM_TEST(homography_lm_beats_linear_against_truth)
{
    int seeds = SFM_TEST_ITERS(SEEDS);
    lin_vs_lm d = {0.0, 0.0, 0}, g = {0.0, 0.0, 0}; /* median transfer, common-view grid */
    for (int k = 0; k < seeds; k++) {
        double Ht[9];
        ground_scene(t, 1.0, Ht);
        /* the truth maps the noise-free pairs */
        SFM_CHECK(transfer(Ht, C1, C2) < 1e-6);
        sfm_mat3 L;
        SFM_CHECK_EQ_INT(sfm_homography_dlt(A1, A2, NF, &L), 1);
        double H[9];
        memcpy(H, L.m, sizeof H);
        double c0 = sfmi_robust_homography_cost(A1, A2, NF, 0.0, H);
        SFM_CHECK(sfmi_robust_homography_lm(A1, A2, NF, 0.0, 10, H) >= 0);
        SFM_CHECK(sfmi_robust_homography_cost(A1, A2, NF, 0.0, H) <= c0);
        double dl[NF], dm[NF];
        for (int i = 0; i < NF; i++) {
            dl[i] = transfer(L.m, C1 + 2 * i, C2 + 2 * i);
            dm[i] = transfer(H, C1 + 2 * i, C2 + 2 * i);
        }
        double ml = scene_median(dl, NF), mm = scene_median(dm, NF);
        double gl = grid_err(L.m, Ht), gm = grid_err(H, Ht);
        tally(&d, ml, mm);
        tally(&g, gl, gm);
    }
    FH_LOG("grazing plane, mean over %d scenes: median transfer error of noise-free pairs "
           "linear %.4f px, LM %.4f px (LM closer in %d); transfer error over the common "
           "view linear %.4f px, LM %.4f px (LM closer in %d)",
           seeds, d.lin / seeds, d.lm / seeds, d.wins, g.lin / seeds, g.lm / seeds, g.wins);
    if (seeds >= SEEDS) {
        SFM_CHECK(d.lm < d.lin);
        SFM_CHECK(g.lm < g.lin);
        SFM_CHECK(2 * d.wins > seeds);
    }
}

#define ND 200
static double D1[2 * ND], D2[2 * ND], E1[2 * ND], E2[2 * ND], G1[2 * ND], G2[2 * ND];
static unsigned char DT[ND];
static unsigned char DWS[SFM_RANSAC_FUNDAMENTAL_WS_SIZE(ND)];

/* True F = K^-T [t]x R K^-1 (unit Frobenius norm). */
static void true_f(const double *R, const double *tr, double *F)
{
    double E[9], tmp[9];
    for (int c = 0; c < 3; c++) {
        E[c] = tr[1] * R[6 + c] - tr[2] * R[3 + c];
        E[3 + c] = tr[2] * R[c] - tr[0] * R[6 + c];
        E[6 + c] = tr[0] * R[3 + c] - tr[1] * R[c];
    }
    for (int r = 0; r < 3; r++)
        for (int c = 0; c < 3; c++) {
            tmp[3 * r + c] = 0.0;
            for (int k = 0; k < 3; k++)
                tmp[3 * r + c] += KI[3 * k + r] * E[3 * k + c];
        }
    double n = 0.0;
    for (int r = 0; r < 3; r++)
        for (int c = 0; c < 3; c++) {
            F[3 * r + c] = 0.0;
            for (int k = 0; k < 3; k++)
                F[3 * r + c] += tmp[3 * r + k] * KI[3 * k + c];
            n += F[3 * r + c] * F[3 * r + c];
        }
    for (int k = 0; k < 9; k++)
        F[k] /= sqrt(n);
}

/*
 * A dominant plane: of ND matches, noff general-position inliers, nout
 * outliers and the rest on one plane, with 0.5 px noise. Noise-free copies in
 * E1/E2 (the outliers' second pixels are replaced in both).
 */
static void dominant_plane(sfm_test_ctx *t, int noff, int nout, double R[9], double tr[3])
{
    sfm_camera cam = scene_pinhole();
    double R2[9], t2[3];
    sfm_rng keep = t->rng;
    scene_twoview(t, &cam, ND, 0.0, 0.0, 1, E1, E2, DT, R, tr);
    sfm_rng after = t->rng;
    t->rng = keep;
    /* the same stream start gives the same motion, general points */
    scene_twoview(t, &cam, ND, 0.0, 0.0, 0, G1, G2, DT, R2, t2);
    t->rng = after;
    memcpy(E1, G1, 2 * sizeof(double) * (size_t)noff);
    memcpy(E2, G2, 2 * sizeof(double) * (size_t)noff);
    for (int i = 0; i < 2 * ND; i++) {
        D1[i] = E1[i] + sfm_test_normal(t, 0.5);
        D2[i] = E2[i] + sfm_test_normal(t, 0.5);
    }
    for (int i = ND - nout; i < ND; i++) {
        D2[2 * i] = E2[2 * i] = sfm_test_uniform(t, 0, SCENE_W);
        D2[2 * i + 1] = E2[2 * i + 1] = sfm_test_uniform(t, 0, SCENE_H);
    }
}

SFM_TEST(fundamental_degensac_flag_dominant_plane)
{
    int trials = SFM_TEST_ITERS(12), flagged = 0, good = 0;
    double worst = 0.0, worst_e = 0.0;
    for (int k = 0; k < trials; k++) {
        double R[9], tr[3], Ft[9];
        sfm_mat3 F;
        const int noff = ND / 10, nout = ND / 5;
        dominant_plane(t, noff, nout, R, tr);
        sfm_ransac_options opt;
        sfm_ransac_default_options(&opt);
        opt.threshold = 1.5;
        sfm_ransac_stats st;
        int ni = sfm_ransac_fundamental(D1, D2, ND, NULL, NULL, &opt, &F, NULL, &st, DWS,
                                        sizeof DWS);
        SFM_CHECK(ni >= 8);
        if (ni < 8)
            continue;
        flagged += (st.flags & SFM_RANSAC_FLAG_DEGENSAC) != 0;
        /* against the truth: the off-plane points (noise-free) lie on the
         * epipolar lines of F, and the epipoles agree */
        double d[ND];
        for (int i = 0; i < noff; i++)
            d[i] = sym_epi(F.m, E1 + 2 * i, E2 + 2 * i);
        double med = scene_median(d, noff), ee = epipole_err_deg(F.m, R, tr);
        true_f(R, tr, Ft);
        double et = epipole_err_deg(Ft, R, tr);
        SFM_CHECK(et < 1e-6);
        good += med < 1.0 && ee < 5.0;
        worst = med > worst ? med : worst;
        worst_e = ee > worst_e ? ee : worst_e;
    }
    FH_LOG("dominant plane: DEGENSAC flag in %d of %d runs; %d runs fit the off-plane points "
           "(worst median %.3f px, worst epipole %.2f deg)",
           flagged, trials, good, worst, worst_e);
    SFM_CHECK_MSG(flagged == trials, "flag raised in %d of %d", flagged, trials);
    SFM_CHECK_MSG(good == trials, "%d of %d runs fit the off-plane points", good, trials);
}

SFM_TEST(fundamental_degensac_flag_quiet_on_general_scene)
{
    sfm_camera cam = scene_pinhole();
    int trials = SFM_TEST_ITERS(12), flagged = 0;
    for (int k = 0; k < trials; k++) {
        double R[9], tr[3];
        sfm_mat3 F;
        scene_twoview(t, &cam, ND, 0.3, 0.5, 0, D1, D2, DT, R, tr);
        sfm_ransac_options opt;
        sfm_ransac_default_options(&opt);
        opt.threshold = 1.5;
        sfm_ransac_stats st;
        int ni = sfm_ransac_fundamental(D1, D2, ND, NULL, NULL, &opt, &F, NULL, &st, DWS,
                                        sizeof DWS);
        SFM_CHECK(ni >= 8);
        flagged += ni >= 8 && (st.flags & SFM_RANSAC_FLAG_DEGENSAC) != 0;
    }
    SFM_CHECK_MSG(flagged == 0, "flag raised in %d of %d general scenes", flagged, trials);
}

/* The two-view block residual gives the point-by-point Sampson error bit
 * for bit, for every block length (the odd tail included), indices in any
 * order and repeated, and the degenerate pairs (|E b1| = |E^T b2| = 0:
 * SFM_ROBUST_HUGE). Where the target has no block residual it is not
 * built and the engine calls the point-by-point one. */
SFM_TEST(twoview_block_residual_bit_identical)
{
#if SFMI_TWOVIEW_HAVE_BLOCK
    enum { NB = 24 };
    double b1[3 * NB], b2[3 * NB];
    twoview_model m;
    memset(&m, 0, sizeof m);
    int differ = 0, checked = 0;
    for (int trial = 0; trial < 50; trial++) {
        for (int i = 0; i < 3 * NB; i++) {
            b1[i] = 2.0 * sfm_rng_uniform(&t->rng) - 1.0;
            b2[i] = 2.0 * sfm_rng_uniform(&t->rng) - 1.0;
        }
        for (int k = 0; k < 9; k++)
            m.E[k] = 2.0 * sfm_rng_uniform(&t->rng) - 1.0;
        /* pair 0: b1 along the right null vector of E and b2 along the left
         * one, so that both gradients vanish */
        if (trial % 5 == 0) {
            memset(m.E, 0, sizeof m.E);
            m.E[1] = -1.0;
            m.E[3] = 1.0; /* [z]x: null vectors (0, 0, 1) */
            b1[0] = b1[1] = 0.0;
            b1[2] = 1.0;
            b2[0] = b2[1] = 0.0;
            b2[2] = -1.0;
        }
        twoview_ctx c = {b1, b2, NB, NULL, NULL, 1e-3};
        int idx[SFM_RANSAC_BLOCK];
        for (int count = 1; count <= SFM_RANSAC_BLOCK; count++) {
            for (int q = 0; q < count; q++)
                idx[q] = q == 0 && trial % 5 == 0 ? 0 : (int)sfm_rng_bounded(&t->rng, NB);
            double r[SFM_RANSAC_BLOCK];
            sfmi_twoview_residuals(&c, (const double *)&m, idx, count, r);
            for (int q = 0; q < count; q++) {
                double want = sfmi_twoview_residual(&c, (const double *)&m, idx[q]);
                differ += memcmp(&want, &r[q], sizeof want) != 0;
                checked++;
            }
        }
        if (trial % 5 == 0) {
            double r0;
            sfmi_twoview_residuals(&c, (const double *)&m, idx, 1, &r0);
            SFM_CHECK(r0 == 1e300);
        }
    }
    FH_LOG("%d of %d block residuals differ from the point-by-point ones", differ, checked);
    SFM_CHECK_EQ_INT(differ, 0);
#else
    SFM_CHECK(1);
#endif
}
