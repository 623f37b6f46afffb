/* Bundle adjustment: small problems, checked against synthetic truth,
 * finite differences and an explicit normal-matrix inverse. Static memory
 * stays well under 1 MB. */
#include <math.h>
#include <string.h>

#include "ba_scene.h"
#include "refine/ba_internal.h"
#include "jacobian_check.h"
#include "sfm/sfm.h"
#include "sfm_test.h"

/* Figures are logged on hosts only: on the Cortex-M7 target newlib's
 * floating-point printf allocates (dtoa's Balloc) and fails under rdimon. */
#ifdef SFM_TEST_REDUCED
#define BA_LOG(...) ((void)0)
#else
#define BA_LOG(...) SFM_TEST_LOG(__VA_ARGS__)
#endif

#define MAXM 5
#define MAXN 60
#define MAXO (MAXM * MAXN)
#define WS_BYTES (256 * 1024)

static unsigned char g_ws[WS_BYTES];
static double sR[9 * MAXM], st[3 * MAXM], sK[6 * MAXM], sX[3 * MAXN];
static double sR0[9 * MAXM], st0[3 * MAXM], sK0[6 * MAXM], sX0[3 * MAXN];
static int soc[MAXO], sop[MAXO];
static double sxy[2 * MAXO];
static double pR[9 * MAXM], pt[3 * MAXM], pK[6 * MAXM], pX[3 * MAXN];
static sfm_camera pC[MAXM];

static void scene(sfm_test_ctx *t, ba_scene *s, int m, int n, double sigma, double rot, double tr,
                  double ptn)
{
    s->R = sR; s->t = st; s->K = sK; s->X = sX;
    s->R0 = sR0; s->t0 = st0; s->K0 = sK0; s->X0 = sX0;
    s->oc = soc; s->op = sop; s->xy = sxy;
    bas_make(t, s, m, n, sigma, rot, tr, ptn);
}

/* The problem over the scene's starting values in pR, pt, pC, pX and the
 * default options. */
static void ba_start(ba_scene *s, sfm_ba_problem *p, sfm_ba_options *o)
{
    bas_problem(s, p, pR, pt, pC, pX);
    sfm_ba_default_options(o);
}

/* A solve without covariance in the whole workspace. */
static int ba_run(sfm_ba_problem *p, const sfm_ba_options *o, sfm_ba_result *r)
{
    return sfm_ba_solve(p, o, r, NULL, 0, g_ws, sizeof g_ws);
}

static size_t ws_for(const sfm_ba_problem *p, const sfm_ba_options *o)
{
    sfm_ba_dims d = {p->n_cameras, p->n_points, p->n_observations, o->intrinsics, o->refine_intrinsics};
    return sfm_ba_workspace_size(&d);
}

/* One observation's residual for verify_jacobian: parameters in the
 * tangent space (w, dt, dfocal, dcx, dcy, ddist[5], dX) around a base. */
typedef struct obs_fn_data {
    double R[9], t[3], X[3];
    sfm_camera cam;
    double aspect;
} obs_fn_data;

static int obs_apply(const obs_fn_data *d, const double *delta, double *uv, double *J, double *Jp)
{
    double dR[9], R[9], tt[3], X[3];
    bas_rodrigues(delta, dR);
    bas_matmul3(dR, d->R, R);
    sfm_camera cam = d->cam;
    cam.fx += delta[6];
    cam.fy = cam.fx * d->aspect;
    cam.cx += delta[7];
    cam.cy += delta[8];
    for (int e = 0; e < SFMI_BA_NDIST; e++)
        cam.dist[e] += delta[9 + e];
    for (int k = 0; k < 3; k++) {
        tt[k] = d->t[k] + delta[3 + k];
        X[k] = d->X[k] + delta[SFMI_BA_NLOC + k];
    }
    return sfmi_ba_project(&cam, d->aspect, R, tt, X, uv, J, Jp);
}

static int obs_residual(const void *user, const double *delta, double *r)
{
    return obs_apply(user, delta, r, NULL, NULL);
}

/* The analytic camera-side Jacobian and d(px)/dX of every camera model
 * against central differences (jacobian_check.h), at points across the
 * field of view. */
SFM_TEST(ba_jacobian_matches_finite_differences)
{
    const int models[3] = {SFM_CAMERA_PINHOLE, SFM_CAMERA_BROWN, SFM_CAMERA_FISHEYE};
    for (int mi = 0; mi < 3; mi++) {
        double worst = 0.0;
        for (int it = 0; it < SFM_TEST_ITERS(20); it++) {
            obs_fn_data d;
            sfm_test_random_rotation(t, d.R);
            for (int k = 0; k < 3; k++) {
                d.t[k] = sfm_test_uniform(t, -1, 1);
                d.X[k] = sfm_test_uniform(t, -1, 1);
            }
            d.t[2] += 5.0;
            /* make sure the point is in front */
            double z = d.R[6] * d.X[0] + d.R[7] * d.X[1] + d.R[8] * d.X[2] + d.t[2];
            if (z < 1.0)
                d.t[2] += 2.0 - z;
            memset(&d.cam, 0, sizeof d.cam);
            d.cam.model = models[mi];
            d.cam.fx = sfm_test_uniform(t, 300, 900);
            d.cam.fy = d.cam.fx * sfm_test_uniform(t, 0.9, 1.1);
            d.cam.cx = 320;
            d.cam.cy = 240;
            d.aspect = d.cam.fy / d.cam.fx;
            if (models[mi] == SFM_CAMERA_BROWN) {
                d.cam.dist[0] = sfm_test_uniform(t, -0.3, 0.3);
                d.cam.dist[1] = sfm_test_uniform(t, -0.1, 0.1);
                d.cam.dist[2] = sfm_test_uniform(t, -0.01, 0.01);
                d.cam.dist[3] = sfm_test_uniform(t, -0.01, 0.01);
                d.cam.dist[4] = sfm_test_uniform(t, -0.05, 0.05);
            } else if (models[mi] == SFM_CAMERA_FISHEYE) {
                for (int e = 0; e < 4; e++)
                    d.cam.dist[e] = sfm_test_uniform(t, -0.05, 0.05);
            }
            double uv[2], J[2 * SFMI_BA_NLOC], Jp[6];
            const double zero[SFMI_BA_NLOC + 3] = {0};
            SFM_CHECK(obs_apply(&d, zero, uv, J, Jp));
            if (models[mi] != SFM_CAMERA_FISHEYE) {
                /* the projection itself against the scene's own model */
                double ref[2], K[6] = {d.cam.fx, d.cam.fy, d.cam.cx, d.cam.cy, d.cam.dist[0], d.cam.dist[1]};
                if (models[mi] == SFM_CAMERA_PINHOLE || (d.cam.dist[2] == 0 && d.cam.dist[3] == 0 && d.cam.dist[4] == 0)) {
                    SFM_CHECK(bas_project(d.R, d.t, K, d.X, ref));
                    SFM_CHECK_NEAR(uv[0], ref[0], 1e-9);
                    SFM_CHECK_NEAR(uv[1], ref[1], 1e-9);
                }
            }
            /* the full analytic Jacobian: camera-side columns, then the point */
            enum { NC = SFMI_BA_NLOC + 3 };
            double Ja[2 * NC];
            for (int r = 0; r < 2; r++) {
                for (int c = 0; c < SFMI_BA_NLOC; c++)
                    Ja[r * NC + c] = J[r * SFMI_BA_NLOC + c];
                for (int c = 0; c < 3; c++)
                    Ja[r * NC + SFMI_BA_NLOC + c] = Jp[r * 3 + c];
            }
            double err = sfm_test_verify_jacobian(obs_residual, &d, NC, 2, Ja, 1e-6);
            worst = fmax(worst, err);
            SFM_CHECK_MSG(err < 1e-5, "model %d: relative Jacobian error %.3g", models[mi], err);
        }
        BA_LOG("camera model %d: worst relative Jacobian error %.3g", models[mi], worst);
    }
}

/* Noise-free scene, perturbed start, first camera and one coordinate of the
 * second camera held (the true values): the solve lands on the truth. */
SFM_TEST(ba_noise_free_recovers_truth)
{
    ba_scene s;
    scene(t, &s, 4, 40, 0.0, 3.0, 0.1, 0.05);
    st0[3 + 0] = st[3 + 0];
    sfm_ba_problem p;
    sfm_ba_options o;
    ba_start(&s, &p, &o);
    o.scale_gauge = SFM_BA_SCALE_COORDINATE;
    o.scale_camera = 1;
    o.scale_coordinate = 0;
    o.function_tolerance = 1e-14;
    o.parameter_tolerance = 1e-14;
    size_t need = ws_for(&p, &o);
    SFM_CHECK(need > 0 && need <= WS_BYTES);
    sfm_ba_result r;
    SFM_CHECK_EQ_INT(sfm_ba_solve(&p, &o, &r, NULL, 0, g_ws, need), SFM_OK);
    BA_LOG("initial %.3g final %.3g iters %d reason %d", r.initial_cost, r.final_cost, r.iterations, r.stop_reason);
    SFM_CHECK(r.initial_cost > 1e3);
    SFM_CHECK(r.final_cost < 1e-12);
    SFM_CHECK(bas_max_abs_diff(pR, sR, 9 * s.m) < 1e-8);
    SFM_CHECK(bas_max_abs_diff(pt, st, 3 * s.m) < 1e-8);
    SFM_CHECK(bas_max_abs_diff(pX, sX, 3 * s.n) < 1e-8);
    SFM_CHECK_EQ_INT(r.n_camera_params, 6 * 3 - 1);
    SFM_CHECK_EQ_INT(r.n_point_params, 3 * 40);
}

/* Noisy scene: the result is a minimum (the gradient vanishes, a restart does
 * not move it) and its cost is near the chi-square expectation. */
SFM_TEST(ba_noisy_converges_to_minimum)
{
    ba_scene s;
    const double sigma = 0.5;
    scene(t, &s, 5, 50, sigma, 2.0, 0.05, 0.05);
    st0[3] = st[3]; /* the held gauge coordinate starts at its true value in both runs */
    sfm_ba_problem p;
    sfm_ba_options o;
    ba_start(&s, &p, &o);
    o.scale_gauge = SFM_BA_SCALE_COORDINATE;
    o.function_tolerance = 1e-12;
    sfm_ba_result r, r2;
    SFM_CHECK_EQ_INT(ba_run(&p, &o, &r), SFM_OK);
    /* restart from the truth: same minimum */
    sfm_ba_problem p2;
    static double qR[9 * MAXM], qt[3 * MAXM], qX[3 * MAXN];
    static sfm_camera qK[MAXM];
    memcpy(s.R0, s.R, sizeof(double) * 9 * s.m);
    memcpy(s.t0, s.t, sizeof(double) * 3 * s.m);
    memcpy(s.X0, s.X, sizeof(double) * 3 * s.n);
    bas_problem(&s, &p2, qR, qt, qK, qX);
    SFM_CHECK_EQ_INT(ba_run(&p2, &o, &r2), SFM_OK);
    BA_LOG("cost %.10g vs from truth %.10g, iters %d", r.final_cost, r2.final_cost, r.iterations);
    SFM_CHECK_NEAR(r.final_cost, r2.final_cost, 1e-8 * r2.final_cost);
    BA_LOG("point difference between the two starts %.3g", bas_max_abs_diff(pX, qX, 3 * s.n));
    SFM_CHECK(bas_max_abs_diff(pX, qX, 3 * s.n) < 1e-5);
    /* 2 nobs - params degrees of freedom, cost = chi2 sigma^2 / 2 */
    double dof = 2.0 * s.nobs - (6 * 4 - 1) - 3 * s.n;
    double expect = 0.5 * sigma * sigma * dof;
    SFM_CHECK(r.final_cost > 0.6 * expect && r.final_cost < 1.4 * expect);
    /* close to the truth at the noise level */
    SFM_CHECK(bas_max_abs_diff(pX, sX, 3 * s.n) < 0.05);
}

SFM_TEST(ba_held_parameters_do_not_move)
{
    ba_scene s;
    scene(t, &s, 4, 30, 0.5, 2.0, 0.05, 0.05);
    sfm_ba_problem p;
    bas_problem(&s, &p, pR, pt, pC, pX);
    static unsigned char cflags[MAXM], pfix[MAXN];
    memset(cflags, 0, sizeof cflags);
    memset(pfix, 0, sizeof pfix);
    cflags[2] = SFM_BA_FIX_POSE;
    cflags[3] = SFM_BA_FIX_INTRINSICS;
    pfix[3] = pfix[7] = 1;
    p.camera_flags = cflags;
    p.point_fixed = pfix;
    sfm_ba_options o;
    sfm_ba_default_options(&o);
    o.intrinsics = SFM_BA_INTRINSICS_PER_CAMERA;
    o.refine_intrinsics = SFM_BA_REFINE_FOCAL;
    o.scale_gauge = SFM_BA_SCALE_COORDINATE;
    o.scale_coordinate = 2;
    for (int i = 0; i < s.m; i++)
        pC[i].fx = pC[i].fy = 790.0; /* perturbed focal */
    double K0[6 * MAXM];
    bas_rows_from_cameras(pC, s.m, K0);
    sfm_ba_result r;
    SFM_CHECK_EQ_INT(ba_run(&p, &o, &r), SFM_OK);
    bas_rows_from_cameras(pC, s.m, pK);
    SFM_CHECK(memcmp(pR, sR0, 9 * sizeof(double)) == 0);
    SFM_CHECK(memcmp(pt, st0, 3 * sizeof(double)) == 0);
    SFM_CHECK(memcmp(pR + 18, sR0 + 18, 9 * sizeof(double)) == 0);
    SFM_CHECK(memcmp(pt + 6, st0 + 6, 3 * sizeof(double)) == 0);
    SFM_CHECK(pt[5] == st0[5]);
    SFM_CHECK(memcmp(pK + 18, K0 + 18, 6 * sizeof(double)) == 0);
    SFM_CHECK(memcmp(pX + 9, sX0 + 9, 3 * sizeof(double)) == 0);
    SFM_CHECK(memcmp(pX + 21, sX0 + 21, 3 * sizeof(double)) == 0);
    /* the free ones did move */
    SFM_CHECK(pK[6] != K0[6]);
    SFM_CHECK(pt[3] != st0[3]);
    SFM_CHECK(r.final_cost < r.initial_cost);
}

/* Transforming the world by a rigid motion and a scale gives the same
 * solution, transformed. */
SFM_TEST(ba_invariant_to_world_frame)
{
    ba_scene s;
    scene(t, &s, 4, 40, 0.5, 2.0, 0.05, 0.05);
    sfm_ba_problem p;
    sfm_ba_options o;
    ba_start(&s, &p, &o);
    o.scale_gauge = SFM_BA_SCALE_DISTANCE;
    o.scale_distance = 3.0;
    o.function_tolerance = 1e-12;
    sfm_ba_result r1, r2;
    SFM_CHECK_EQ_INT(ba_run(&p, &o, &r1), SFM_OK);
    /* X' = sc Q X + b; camera: R' = R Q^T, t' = sc t - R Q^T b */
    double Q[9], b[3] = {1.0, -2.0, 0.5}, sc = 2.5;
    sfm_test_random_rotation(t, Q);
    static double qR[9 * MAXM], qt[3 * MAXM], qX[3 * MAXN];
    static sfm_camera qK[MAXM];
    sfm_ba_problem p2;
    bas_problem(&s, &p2, qR, qt, qK, qX);
    for (int i = 0; i < s.m; i++) {
        double Rn[9], QT[9];
        for (int r = 0; r < 3; r++)
            for (int c = 0; c < 3; c++)
                QT[3 * r + c] = Q[3 * c + r];
        bas_matmul3(qR + 9 * i, QT, Rn);
        memcpy(qR + 9 * i, Rn, sizeof Rn);
        for (int r = 0; r < 3; r++)
            qt[3 * i + r] = sc * qt[3 * i + r] - (Rn[3 * r] * b[0] + Rn[3 * r + 1] * b[1] + Rn[3 * r + 2] * b[2]);
    }
    for (int j = 0; j < s.n; j++) {
        double x[3];
        for (int r = 0; r < 3; r++)
            x[r] = sc * (Q[3 * r] * qX[3 * j] + Q[3 * r + 1] * qX[3 * j + 1] + Q[3 * r + 2] * qX[3 * j + 2]) + b[r];
        memcpy(qX + 3 * j, x, sizeof x);
    }
    SFM_CHECK_EQ_INT(ba_run(&p2, &o, &r2), SFM_OK);
    SFM_CHECK_NEAR(r1.final_cost, r2.final_cost, 1e-7 * r1.final_cost);
    /* distance gauge: both have |C1 - C0| = 3 */
    double md = 0.0;
    for (int j = 0; j < s.n; j++) {
        /* map solution 2 back: X = Q^T (X' - C0') / ... compare via camera-0 frame coordinates */
        double a1[3], a2[3];
        for (int r = 0; r < 3; r++) {
            a1[r] = pR[3 * r] * pX[3 * j] + pR[3 * r + 1] * pX[3 * j + 1] + pR[3 * r + 2] * pX[3 * j + 2] + pt[r];
            a2[r] = qR[3 * r] * qX[3 * j] + qR[3 * r + 1] * qX[3 * j + 1] + qR[3 * r + 2] * qX[3 * j + 2] + qt[r];
        }
        md = fmax(md, bas_max_abs_diff(a1, a2, 3));
    }
    BA_LOG("max point difference in camera-0 frame %.3g", md);
    SFM_CHECK(md < 1e-6);
    for (int i = 0; i < s.m; i++) {
        double C[2][3];
        for (int r = 0; r < 3; r++) {
            C[0][r] = -(pR[9 * i + r] * pt[3 * i] + pR[9 * i + 3 + r] * pt[3 * i + 1] + pR[9 * i + 6 + r] * pt[3 * i + 2]);
            C[1][r] = -(pR[r] * pt[0] + pR[3 + r] * pt[1] + pR[6 + r] * pt[2]);
        }
        if (i == 1) {
            double d = sqrt((C[0][0] - C[1][0]) * (C[0][0] - C[1][0]) + (C[0][1] - C[1][1]) * (C[0][1] - C[1][1]) +
                            (C[0][2] - C[1][2]) * (C[0][2] - C[1][2]));
            SFM_CHECK_NEAR(d, 3.0, 1e-9);
        }
    }
}

SFM_TEST(ba_robust_loss_resists_outliers)
{
    ba_scene s;
    scene(t, &s, 4, 50, 0.5, 2.0, 0.05, 0.05);
    sfm_ba_options o;
    sfm_ba_default_options(&o);
    o.scale_gauge = SFM_BA_SCALE_COORDINATE;
    o.max_iterations = 100;
    o.loss_scale = 2.0; /* whitened pixels: 4 sigma */
    sfm_ba_problem p;
    sfm_ba_result r;
    /* the clean maximum-likelihood estimate, for scale */
    bas_problem(&s, &p, pR, pt, pC, pX);
    SFM_CHECK_EQ_INT(ba_run(&p, &o, &r), SFM_OK);
    double e_clean = bas_max_abs_diff(pX, sX, 3 * s.n);
    /* 10% gross outliers, 20 to 60 px */
    for (int k = 0; k < s.nobs; k += 10) {
        sxy[2 * k] += sfm_test_uniform(t, 20, 60);
        sxy[2 * k + 1] += sfm_test_uniform(t, -60, 60);
    }
    bas_problem(&s, &p, pR, pt, pC, pX);
    SFM_CHECK_EQ_INT(ba_run(&p, &o, &r), SFM_OK);
    double e_sq = bas_max_abs_diff(pX, sX, 3 * s.n);
    BA_LOG("max point error: clean %.4f, outliers with squared loss %.4f", e_clean, e_sq);
    const int losses[2] = {SFM_BA_LOSS_HUBER, SFM_BA_LOSS_CAUCHY};
    for (int l = 0; l < 3; l++) {
        if (l < 2)
            bas_problem(&s, &p, pR, pt, pC, pX); /* truncated continues from Cauchy's answer */
        o.loss = l < 2 ? losses[l] : SFM_BA_LOSS_TRUNCATED;
        SFM_CHECK_EQ_INT(ba_run(&p, &o, &r), SFM_OK);
        double e = bas_max_abs_diff(pX, sX, 3 * s.n);
        BA_LOG("loss %d: max point error %.4f (cost %.4g, %d iters)", o.loss, e, r.final_cost, r.iterations);
        /* Huber's influence is bounded, not zero: one-sided outliers bias it */
        SFM_CHECK(e < 0.3 * e_sq);
        if (o.loss != SFM_BA_LOSS_HUBER)
            SFM_CHECK(e < 2.0 * e_clean);
    }
}

/* Covariance from the reduced camera system equals the camera block of the
 * inverse of the full normal matrix built from finite differences. */
SFM_TEST(ba_covariance_matches_full_inverse)
{
    ba_scene s;
    scene(t, &s, 3, 8, 0.5, 1.0, 0.02, 0.02);
    sfm_ba_problem p;
    sfm_ba_options o;
    ba_start(&s, &p, &o);
    o.scale_gauge = SFM_BA_SCALE_COORDINATE;
    o.scale_coordinate = 0;
    o.want_covariance = 1;
    o.function_tolerance = 1e-14;
    static double cov[36 * MAXM];
    sfm_ba_result r;
    SFM_CHECK_EQ_INT(sfm_ba_solve(&p, &o, &r, cov, 36 * MAXM, g_ws, sizeof g_ws), SFM_OK);
    SFM_CHECK_EQ_INT(r.covariance_status, SFM_OK);
    bas_rows_from_cameras(pC, s.m, pK);
    /* parameters: cam1 (w, t1, t2), cam2 (w, t), points */
    enum { NP = 5 + 6 + 3 * 8 };
    static double J[2 * 3 * 8 * NP], A[NP * NP], Ainv[NP * NP];
    int nr = 2 * s.nobs;
    memset(J, 0, sizeof J);
    const double h = 1e-6;
    for (int c = 0; c < NP; c++) {
        for (int sg = -1; sg <= 1; sg += 2) {
            double R[9 * MAXM], tt[3 * MAXM], X[3 * MAXN];
            memcpy(R, pR, sizeof R);
            memcpy(tt, pt, sizeof tt);
            memcpy(X, pX, sizeof X);
            int cam = -1, l = 0;
            if (c < 5) { cam = 1; l = c < 3 ? c : c + 1; }
            else if (c < 11) { cam = 2; l = c - 5; }
            if (cam >= 0) {
                if (l < 3) {
                    double w[3] = {0, 0, 0}, dR[9];
                    w[l] = sg * h;
                    bas_rodrigues(w, dR);
                    bas_matmul3(dR, R + 9 * cam, R + 9 * cam);
                } else {
                    tt[3 * cam + l - 3] += sg * h;
                }
            } else {
                X[c - 11] += sg * h;
            }
            for (int k = 0; k < s.nobs; k++) {
                double uv[2];
                bas_project(R + 9 * soc[k], tt + 3 * soc[k], pK + 6 * soc[k], X + 3 * sop[k], uv);
                J[(2 * k) * NP + c] += sg * uv[0] / (2 * h);
                J[(2 * k + 1) * NP + c] += sg * uv[1] / (2 * h);
            }
        }
    }
    for (int a = 0; a < NP; a++)
        for (int b = 0; b < NP; b++) {
            double v = 0;
            for (int k = 0; k < nr; k++)
                v += J[k * NP + a] * J[k * NP + b];
            A[a * NP + b] = v;
        }
    /* Gauss-Jordan inverse written out here, independent of the library */
    for (int i = 0; i < NP * NP; i++)
        Ainv[i] = (i % (NP + 1)) == 0 ? 1.0 : 0.0;
    for (int col = 0; col < NP; col++) {
        int piv = col;
        for (int r2 = col + 1; r2 < NP; r2++)
            if (fabs(A[r2 * NP + col]) > fabs(A[piv * NP + col]))
                piv = r2;
        for (int k = 0; k < NP; k++) {
            double tmp = A[col * NP + k]; A[col * NP + k] = A[piv * NP + k]; A[piv * NP + k] = tmp;
            tmp = Ainv[col * NP + k]; Ainv[col * NP + k] = Ainv[piv * NP + k]; Ainv[piv * NP + k] = tmp;
        }
        double d = A[col * NP + col];
        for (int k = 0; k < NP; k++) {
            A[col * NP + k] /= d;
            Ainv[col * NP + k] /= d;
        }
        for (int r2 = 0; r2 < NP; r2++) {
            if (r2 == col)
                continue;
            double f = A[r2 * NP + col];
            for (int k = 0; k < NP; k++) {
                A[r2 * NP + k] -= f * A[col * NP + k];
                Ainv[r2 * NP + k] -= f * Ainv[col * NP + k];
            }
        }
    }
    /* camera 0 held: zero block */
    double z0 = 0;
    for (int i = 0; i < 36; i++)
        z0 = fmax(z0, fabs(cov[i]));
    SFM_CHECK(z0 == 0.0);
    double maxrel = 0;
    for (int a = 0; a < 6; a++)
        for (int b = 0; b < 6; b++) {
            /* camera 2: params 5..10 */
            double ref = Ainv[(5 + a) * NP + 5 + b];
            double got = cov[72 + 6 * a + b];
            double scale = sqrt(Ainv[(5 + a) * NP + 5 + a] * Ainv[(5 + b) * NP + 5 + b]);
            maxrel = fmax(maxrel, fabs(got - ref) / scale);
        }
    for (int a = 0; a < 6; a++)
        for (int b = 0; b < 6; b++) {
            int ia = a < 3 ? a : (a == 3 ? -1 : a - 1), ib = b < 3 ? b : (b == 3 ? -1 : b - 1);
            double got = cov[36 + 6 * a + b];
            if (ia < 0 || ib < 0) {
                SFM_CHECK(got == 0.0);
                continue;
            }
            double ref = Ainv[ia * NP + ib];
            double scale = sqrt(Ainv[ia * NP + ia] * Ainv[ib * NP + ib]);
            maxrel = fmax(maxrel, fabs(got - ref) / scale);
        }
    BA_LOG("max relative covariance difference %.3g", maxrel);
    SFM_CHECK(maxrel < 1e-4);
}

SFM_TEST(ba_intrinsics_recovered)
{
    /* noise-free: shared focal, then per-camera focal + principal point +
     * radial, then shared focal + k1 alone (k2 held at a non-zero truth) */
    for (int mode = 0; mode < 3; mode++) {
        ba_scene s;
        scene(t, &s, 5, 60, 0.0, 1.0, 0.02, 0.02);
        st0[3] = st[3];
        for (int i = 0; i < s.m; i++) {
            double *K = sK + 6 * i;
            if (mode == 1) {
                K[0] = 780 + 10 * i; K[1] = K[0] * 1.01; K[2] = 315 + i; K[3] = 245 - i;
                K[4] = -0.1; K[5] = 0.02;
            } else if (mode == 2) {
                K[0] = 700; K[1] = 700; K[2] = 320; K[3] = 240;
                K[4] = -0.25; K[5] = 0.1;
            }
        }
        /* re-observe with these intrinsics */
        for (int k = 0; k < s.nobs; k++)
            bas_project(sR + 9 * soc[k], st + 3 * soc[k], sK + 6 * soc[k], sX + 3 * sop[k], sxy + 2 * k);
        memcpy(sK0, sK, sizeof sK0);
        for (int i = 0; i < s.m; i++) {
            sK0[6 * i] *= 1.03;
            sK0[6 * i + 1] *= 1.03;
            if (mode == 1) {
                sK0[6 * i + 2] += 3; sK0[6 * i + 3] -= 2; sK0[6 * i + 4] = 0; sK0[6 * i + 5] = 0;
            } else if (mode == 2) {
                sK0[6 * i + 4] = 0;
            }
        }
        sfm_ba_problem p;
        sfm_ba_options o;
        ba_start(&s, &p, &o);
        o.scale_gauge = SFM_BA_SCALE_COORDINATE;
        o.intrinsics = mode == 1 ? SFM_BA_INTRINSICS_PER_CAMERA : SFM_BA_INTRINSICS_SHARED;
        o.refine_intrinsics = mode == 0 ? SFM_BA_REFINE_FOCAL : mode == 1 ? 7 : SFM_BA_REFINE_FOCAL | SFM_BA_REFINE_K1;
        o.function_tolerance = 1e-15;
        o.parameter_tolerance = 1e-15;
        o.max_iterations = 200;
        sfm_ba_result r;
        SFM_CHECK(ws_for(&p, &o) <= sizeof g_ws);
        SFM_CHECK_EQ_INT(ba_run(&p, &o, &r), SFM_OK);
        if (mode == 2) /* f and k1 free, k2 held: 2 intrinsics after the 6 (m - 1) - 1 pose columns */
            SFM_CHECK_EQ_INT(r.n_camera_params, 6 * (s.m - 1) - 1 + 2);
        bas_rows_from_cameras(pC, s.m, pK);
        double ek = bas_max_abs_diff(pK, sK, 6 * s.m);
        BA_LOG("mode %d: K error %.3g, cost %.3g -> %.3g, %d iters, reason %d", mode, ek,
                     r.initial_cost, r.final_cost, r.iterations, r.stop_reason);
        SFM_CHECK(r.final_cost < 1e-10);
        SFM_CHECK(ek < 1e-4);
        SFM_CHECK(bas_max_abs_diff(pX, sX, 3 * s.n) < 1e-6);
        for (int i = 0; i < s.m; i++)
            SFM_CHECK_NEAR(pK[6 * i + 1] / pK[6 * i], sK[6 * i + 1] / sK[6 * i], 1e-12);
    }
}

SFM_TEST(ba_pose_only_and_points_only)
{
    ba_scene s;
    scene(t, &s, 3, 40, 0.0, 3.0, 0.1, 0.0);
    sfm_ba_problem p;
    sfm_ba_options o;
    ba_start(&s, &p, &o);
    o.mode = SFM_BA_MODE_POSE_ONLY;
    o.function_tolerance = 1e-14;
    sfm_ba_result r;
    SFM_CHECK_EQ_INT(ba_run(&p, &o, &r), SFM_OK);
    SFM_CHECK_EQ_INT(r.n_point_params, 0);
    SFM_CHECK(r.final_cost < 1e-12);
    SFM_CHECK(bas_max_abs_diff(pt, st, 3 * s.m) < 1e-8);
    SFM_CHECK(memcmp(pX, sX, sizeof(double) * 3 * s.n) == 0);

    /* one camera, pose only, as RANSAC refinement uses it: camera 0 is
     * refined (the gauge options apply to full solves only) */
    {
        sfm_ba_problem p1;
        int nobs1 = 0;
        static int oc1[MAXO], op1[MAXO];
        static double xy1[2 * MAXO];
        for (int k = 0; k < s.nobs; k++) {
            if (soc[k] != 1)
                continue;
            oc1[nobs1] = 0;
            op1[nobs1] = sop[k];
            xy1[2 * nobs1] = sxy[2 * k];
            xy1[2 * nobs1 + 1] = sxy[2 * k + 1];
            nobs1++;
        }
        bas_problem(&s, &p1, pR, pt, pC, pX);
        memcpy(pR, sR0 + 9, 9 * sizeof(double));
        memcpy(pt, st0 + 3, 3 * sizeof(double));
        p1.n_cameras = 1;
        p1.n_observations = nobs1;
        p1.obs_camera = oc1;
        p1.obs_point = op1;
        p1.obs_xy = xy1;
        sfm_ba_options o1;
        sfm_ba_default_options(&o1);
        o1.mode = SFM_BA_MODE_POSE_ONLY;
        o1.function_tolerance = 1e-14;
        SFM_CHECK_EQ_INT(ba_run(&p1, &o1, &r), SFM_OK);
        SFM_CHECK_EQ_INT(r.n_camera_params, 6);
        SFM_CHECK(r.final_cost < 1e-12);
        SFM_CHECK(bas_max_abs_diff(pR, sR + 9, 9) < 1e-8);
        SFM_CHECK(bas_max_abs_diff(pt, st + 3, 3) < 1e-8);
    }

    /* points only: true cameras, perturbed points */
    scene(t, &s, 3, 40, 0.0, 0.0, 0.0, 0.1);
    bas_problem(&s, &p, pR, pt, pC, pX);
    o.mode = SFM_BA_MODE_POINTS_ONLY;
    SFM_CHECK_EQ_INT(ba_run(&p, &o, &r), SFM_OK);
    SFM_CHECK_EQ_INT(r.n_camera_params, 0);
    SFM_CHECK(r.final_cost < 1e-12);
    SFM_CHECK(bas_max_abs_diff(pX, sX, 3 * s.n) < 1e-8);
    SFM_CHECK(memcmp(pR, sR0, sizeof(double) * 9 * s.m) == 0);
}

SFM_TEST(ba_contract)
{
    ba_scene s;
    scene(t, &s, 3, 10, 0.5, 1.0, 0.01, 0.01);
    sfm_ba_problem p;
    sfm_ba_options o;
    ba_start(&s, &p, &o);
    sfm_ba_result r;
    size_t need = ws_for(&p, &o);
    SFM_CHECK(need > 0);
    SFM_CHECK_EQ_INT(sfm_ba_workspace_size(NULL), 0);
    SFM_CHECK_EQ_INT(sfm_ba_default_options(NULL), SFM_E_ARGUMENT);
    static double c0R[9 * MAXM], c0X[3 * MAXN];
    memcpy(c0R, pR, sizeof c0R);
    memcpy(c0X, pX, sizeof c0X);
#define UNTOUCHED() (memcmp(c0R, pR, sizeof c0R) == 0 && memcmp(c0X, pX, sizeof c0X) == 0 && sfm_test_canary_intact(&r, sizeof r))
    sfm_test_fill_canary(&r, sizeof r);
    SFM_CHECK_EQ_INT(sfm_ba_solve(NULL, &o, &r, NULL, 0, g_ws, need), SFM_E_ARGUMENT);
    SFM_CHECK_EQ_INT(sfm_ba_solve(&p, NULL, &r, NULL, 0, g_ws, need), SFM_E_ARGUMENT);
    SFM_CHECK_EQ_INT(sfm_ba_solve(&p, &o, NULL, NULL, 0, g_ws, need), SFM_E_ARGUMENT);
    SFM_CHECK_EQ_INT(sfm_ba_solve(&p, &o, &r, NULL, 0, NULL, need), SFM_E_WORKSPACE);
    /* one byte short, at several alignments */
    for (int off = 0; off < 16; off += 5)
        SFM_CHECK_EQ_INT(sfm_ba_solve(&p, &o, &r, NULL, 0, g_ws + off, need - 1), SFM_E_WORKSPACE);
    SFM_CHECK(UNTOUCHED());
    o.want_covariance = 1;
    SFM_CHECK_EQ_INT(sfm_ba_solve(&p, &o, &r, NULL, 0, g_ws, need), SFM_E_ARGUMENT);
    o.want_covariance = 0;
    /* NaN in points, observations, weights */
    pX[4] = (double)NAN;
    SFM_CHECK_EQ_INT(sfm_ba_solve(&p, &o, &r, NULL, 0, g_ws, need), SFM_E_NONFINITE);
    pX[4] = c0X[4];
    double keep = sxy[3];
    sxy[3] = HUGE_VAL;
    SFM_CHECK_EQ_INT(sfm_ba_solve(&p, &o, &r, NULL, 0, g_ws, need), SFM_E_NONFINITE);
    sxy[3] = keep;
    static double wts[MAXO];
    for (int k = 0; k < s.nobs; k++)
        wts[k] = 1.0;
    p.obs_weight = wts;
    wts[2] = (double)NAN;
    SFM_CHECK_EQ_INT(sfm_ba_solve(&p, &o, &r, NULL, 0, g_ws, need), SFM_E_NONFINITE);
    wts[2] = -1.0;
    SFM_CHECK_EQ_INT(sfm_ba_solve(&p, &o, &r, NULL, 0, g_ws, need), SFM_E_ARGUMENT);
    p.obs_weight = NULL;
    /* indices out of range */
    int kc = soc[5];
    soc[5] = 3;
    SFM_CHECK_EQ_INT(sfm_ba_solve(&p, &o, &r, NULL, 0, g_ws, need), SFM_E_ARGUMENT);
    soc[5] = -1;
    SFM_CHECK_EQ_INT(sfm_ba_solve(&p, &o, &r, NULL, 0, g_ws, need), SFM_E_ARGUMENT);
    soc[5] = kc;
    int kp = sop[5];
    sop[5] = 10;
    SFM_CHECK_EQ_INT(sfm_ba_solve(&p, &o, &r, NULL, 0, g_ws, need), SFM_E_ARGUMENT);
    sop[5] = kp;
    /* a camera with no observations: move camera 2's observations to camera 1 */
    static int oc2[MAXO];
    for (int k = 0; k < s.nobs; k++)
        oc2[k] = soc[k] == 2 ? 1 : soc[k];
    p.obs_camera = oc2;
    SFM_CHECK_EQ_INT(sfm_ba_solve(&p, &o, &r, NULL, 0, g_ws, need), SFM_E_ARGUMENT);
    p.obs_camera = soc;
    /* a free point nobody sees */
    p.n_points = 11;
    double keep3[3];
    memcpy(keep3, pX + 30, sizeof keep3);
    pX[30] = pX[31] = pX[32] = 0.0;
    {
        sfm_ba_dims d = {3, 11, p.n_observations, 0, 0};
        SFM_CHECK_EQ_INT(sfm_ba_solve(&p, &o, &r, NULL, 0, g_ws, sfm_ba_workspace_size(&d)), SFM_E_ARGUMENT);
    }
    p.n_points = 10;
    memcpy(pX + 30, keep3, sizeof keep3);
    /* bad counts and options */
    p.n_cameras = 0;
    SFM_CHECK_EQ_INT(sfm_ba_solve(&p, &o, &r, NULL, 0, g_ws, need), SFM_E_ARGUMENT);
    p.n_cameras = 3;
    o.loss = 9;
    SFM_CHECK_EQ_INT(sfm_ba_solve(&p, &o, &r, NULL, 0, g_ws, need), SFM_E_ARGUMENT);
    o.loss = SFM_BA_LOSS_HUBER;
    o.loss_scale = 0.0;
    SFM_CHECK_EQ_INT(sfm_ba_solve(&p, &o, &r, NULL, 0, g_ws, need), SFM_E_ARGUMENT);
    sfm_ba_default_options(&o);
    o.scale_gauge = SFM_BA_SCALE_COORDINATE;
    o.scale_camera = 3;
    SFM_CHECK_EQ_INT(sfm_ba_solve(&p, &o, &r, NULL, 0, g_ws, need), SFM_E_ARGUMENT);
    sfm_ba_default_options(&o);
    pC[0].fx = 0.0;
    SFM_CHECK_EQ_INT(sfm_ba_solve(&p, &o, &r, NULL, 0, g_ws, need), SFM_E_ARGUMENT);
    pC[0].fx = sK0[0];
    pC[1].model = 7; /* no such model */
    SFM_CHECK_EQ_INT(sfm_ba_solve(&p, &o, &r, NULL, 0, g_ws, need), SFM_E_ARGUMENT);
    pC[1].model = SFM_CAMERA_BROWN;
    pC[1].dist[3] = (double)NAN;
    SFM_CHECK_EQ_INT(sfm_ba_solve(&p, &o, &r, NULL, 0, g_ws, need), SFM_E_NONFINITE);
    pC[1].dist[3] = 0.0;
    /* shared intrinsics need one model */
    o.intrinsics = SFM_BA_INTRINSICS_SHARED;
    o.refine_intrinsics = SFM_BA_REFINE_FOCAL;
    pC[2].model = SFM_CAMERA_FISHEYE;
    {
        sfm_ba_dims d = {3, 10, p.n_observations, SFM_BA_INTRINSICS_SHARED, SFM_BA_REFINE_FOCAL};
        SFM_CHECK_EQ_INT(sfm_ba_solve(&p, &o, &r, NULL, 0, g_ws, sfm_ba_workspace_size(&d)), SFM_E_ARGUMENT);
    }
    pC[2].model = SFM_CAMERA_BROWN;
    sfm_ba_default_options(&o);
    /* NaN options are non-finite, not merely wrong */
    o.loss_scale = (double)NAN;
    SFM_CHECK_EQ_INT(sfm_ba_solve(&p, &o, &r, NULL, 0, g_ws, need), SFM_E_NONFINITE);
    sfm_ba_default_options(&o);
    o.function_tolerance = (double)NAN;
    SFM_CHECK_EQ_INT(sfm_ba_solve(&p, &o, &r, NULL, 0, g_ws, need), SFM_E_NONFINITE);
    sfm_ba_default_options(&o);
    /* a covariance buffer shorter than 36 m */
    {
        static double cov[36 * MAXM];
        o.want_covariance = 1;
        SFM_CHECK_EQ_INT(sfm_ba_solve(&p, &o, &r, cov, 36 * 3 - 1, g_ws, need), SFM_E_ARGUMENT);
        o.want_covariance = 0;
    }
    /* counts beyond the arrays are caught by the workspace before any array
     * is read (the workspace was sized for the real counts) */
    p.n_points = 1000;
    p.n_observations = 5000;
    SFM_CHECK_EQ_INT(sfm_ba_solve(&p, &o, &r, NULL, 0, g_ws, need), SFM_E_WORKSPACE);
    p.n_points = 10;
    p.n_observations = s.nobs;
    pR[0] = (double)NAN;
    SFM_CHECK_EQ_INT(sfm_ba_solve(&p, &o, &r, NULL, 0, g_ws, need), SFM_E_NONFINITE);
    pR[0] = c0R[0] * 1.001; /* not a rotation */
    SFM_CHECK_EQ_INT(sfm_ba_solve(&p, &o, &r, NULL, 0, g_ws, need), SFM_E_ARGUMENT);
    for (int e = 0; e < 3; e++) /* a reflection */
        pR[9 + e] = -c0R[9 + e];
    SFM_CHECK_EQ_INT(sfm_ba_solve(&p, &o, &r, NULL, 0, g_ws, need), SFM_E_ARGUMENT);
    memcpy(pR, c0R, sizeof c0R);
    SFM_CHECK(UNTOUCHED());
    /* and the exact size works */
    SFM_CHECK_EQ_INT(sfm_ba_solve(&p, &o, &r, NULL, 0, g_ws + 3, need), SFM_OK);
#undef UNTOUCHED
}
