// Final costs of libsfm's bundle adjustment against Ceres 2.1 (DENSE_SCHUR,
// Levenberg-Marquardt) on the same problems from the same starts, both run to
// tight tolerances: the two minima must agree to 1e-6 relative.
#include <cmath>
#include <cstdio>
#include <vector>

#include "ba_ceres_problem.h"
#include "ba_scene_cc.h"

using namespace sfm_oracle;

static int g_pass = 0, g_fail = 0;

static void run(const char *name, Scene &sc, sfm_ba_options o)
{
    o.max_iterations = 200;
    o.function_tolerance = 1e-14;
    o.gradient_tolerance = 1e-14;
    o.parameter_tolerance = 1e-14;
    Work w(sc);
    sfm_ba_dims d = {w.p.n_cameras, w.p.n_points, w.p.n_observations, o.intrinsics, o.refine_intrinsics};
    std::vector<unsigned char> ws(sfm_ba_workspace_size(&d));
    sfm_ba_result r;
    int st = sfm_ba_solve(&w.p, &o, &r, nullptr, 0, ws.data(), ws.size());

    Work w2(sc);
    CeresBA cb;
    cb.build(w2.p, o);
    ceres::Solver::Summary sum;
    ceres::Solve(CeresBA::solver_options(o), cb.problem.get(), &sum);

    double rel = std::fabs(r.final_cost - sum.final_cost) / sum.final_cost;
    double rel0 = std::fabs(r.initial_cost - sum.initial_cost) / sum.initial_cost;
    bool ok = st == SFM_OK && rel <= 1e-6 && rel0 <= 1e-12;
    std::printf("%s %s: %dx%d, %d obs: libsfm %.12g (%d it, stop %d)  ceres %.12g (%d it, %s)  rel %.2e  initial rel %.1e\n",
                ok ? "ok  " : "FAIL", name, sc.s.m, sc.s.n, sc.s.nobs, r.final_cost, r.iterations,
                r.stop_reason, sum.final_cost, (int)sum.iterations.size() - 1,
                ceres::TerminationTypeToString(sum.termination_type), rel, rel0);
    (ok ? g_pass : g_fail)++;
}

int main(int, char **argv)
{
    google::InitGoogleLogging(argv[0]);
    FLAGS_minloglevel = 2; /* Ceres logs a failed Cholesky on the free scale gauge; the step is retried */
    sfm_ba_options o;
    sfm_ba_default_options(&o);
    {
        Scene sc("ceres_3x100", 3, 100, 0.5, 3.0, 0.1, 0.05);
        run("squared", sc, o);
    }
    {
        Scene sc("ceres_5x500", 5, 500, 0.5, 3.0, 0.1, 0.05);
        run("squared", sc, o);
    }
    {
        Scene sc("ceres_10x2000", 10, 2000, 0.5, 3.0, 0.1, 0.05);
        run("squared", sc, o);
    }
    {
        Scene sc("ceres_weights", 5, 300, 0.5, 2.0, 0.05, 0.05);
        sc.wgt.resize(sc.s.nobs);
        for (int k = 0; k < sc.s.nobs; k++)
            sc.wgt[k] = 0.5 + sfm_test_uniform(&sc.ctx, 0.0, 2.0);
        run("weighted", sc, o);
    }
    const sfm_ba_loss losses[3] = {SFM_BA_LOSS_HUBER, SFM_BA_LOSS_CAUCHY, SFM_BA_LOSS_TRUNCATED};
    const char *names[3] = {"huber+outliers", "cauchy+outliers", "truncated+outliers"};
    for (int l = 0; l < 3; l++) {
        Scene sc("ceres_robust", 5, 300, 0.5, l == 2 ? 0.5 : 2.0, l == 2 ? 0.01 : 0.05, 0.02);
        sc.add_outliers(20, 20, 60);
        sfm_ba_options ro = o;
        ro.loss = losses[l];
        ro.loss_scale = 2.0;
        run(names[l], sc, ro);
    }
    {
        Scene sc("ceres_focal_radial", 5, 300, 0.5, 2.0, 0.05, 0.05);
        for (int i = 0; i < sc.s.m; i++) {
            sc.K0[6 * i] *= 1.02;
            sc.K0[6 * i + 1] *= 1.02;
        }
        sfm_ba_options io = o;
        io.intrinsics = SFM_BA_INTRINSICS_SHARED;
        io.refine_intrinsics = SFM_BA_REFINE_FOCAL | SFM_BA_REFINE_RADIAL;
        run("shared focal+k1k2", sc, io);
    }
    {
        /* k1 alone free, k2 held at its non-zero value (the
         * self-calibration's one-term model) */
        Scene sc("ceres_focal_k1", 5, 300, 0.5, 2.0, 0.05, 0.05);
        const double dist[5] = {-0.2, 0.08, 0.0, 0.0, 0.0};
        sc.set_model(SFM_CAMERA_BROWN, dist, 0.5, 1.02);
        for (int i = 0; i < sc.s.m; i++)
            sc.cams0[i].dist[0] = -0.15;
        sfm_ba_options io = o;
        io.intrinsics = SFM_BA_INTRINSICS_SHARED;
        io.refine_intrinsics = SFM_BA_REFINE_FOCAL | SFM_BA_REFINE_K1;
        run("brown shared focal+k1", sc, io);
    }
    {
        /* Brown-Conrady: radial, tangential and k3 refined with the focal */
        Scene sc("ceres_brown", 5, 300, 0.5, 2.0, 0.05, 0.05);
        const double dist[5] = {-0.12, 0.05, 0.001, -0.0015, -0.01};
        sc.set_model(SFM_CAMERA_BROWN, dist, 0.5, 1.02);
        sfm_ba_options io = o;
        io.intrinsics = SFM_BA_INTRINSICS_SHARED;
        io.refine_intrinsics = SFM_BA_REFINE_FOCAL | SFM_BA_REFINE_PRINCIPAL | SFM_BA_REFINE_DISTORTION;
        run("brown shared all", sc, io);
    }
    {
        /* Kannala-Brandt fisheye, k1..k4 refined with the focal */
        Scene sc("ceres_fisheye", 5, 300, 0.5, 2.0, 0.05, 0.05);
        const double dist[5] = {0.02, -0.01, 0.004, -0.001, 0.0};
        sc.set_model(SFM_CAMERA_FISHEYE, dist, 0.5, 1.02);
        sfm_ba_options io = o;
        io.intrinsics = SFM_BA_INTRINSICS_SHARED;
        io.refine_intrinsics = SFM_BA_REFINE_FOCAL | SFM_BA_REFINE_DISTORTION;
        run("fisheye shared focal+k1..k4", sc, io);
    }
    std::printf("%d passed, %d failed\n", g_pass, g_fail);
    return g_fail == 0 ? 0 : 1;
}
