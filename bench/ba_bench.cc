// Bundle adjustment: time per solve, libsfm beside Ceres 2.1 (DENSE_SCHUR,
// Levenberg-Marquardt, one thread, the same tolerances, initial trust region
// and iteration limit, the same start) on synthetic scenes of 3x200, 5x500 and
// 10x2000 (cameras x points, every point in every view, 0.5 px noise, start
// perturbed by 3 degrees, 0.1 and 0.05 units). Ceres' problem is built
// outside the timed region; its Solve() (which includes its preprocessing) is
// timed. libsfm's time is one sfm_ba_solve call on a preallocated workspace.
#include <algorithm>
#include <chrono>
#include <cstdio>
#include <cstdlib>
#include <string>
#include <vector>

#include "ba_ceres_problem.h"
#include "ba_scene_cc.h"

using namespace sfm_oracle;
using clk = std::chrono::steady_clock;

static double minimum(const std::vector<double> &v)
{
    return *std::min_element(v.begin(), v.end());
}

static double median(std::vector<double> v)
{
    std::sort(v.begin(), v.end());
    return v[v.size() / 2];
}

int main(int argc, char **argv)
{
    google::InitGoogleLogging(argv[0]);
    FLAGS_minloglevel = 2;
    /* "once": one solve of each per size (for valgrind --tool=callgrind with
     * --toggle-collect=sfm_ba_solve or --toggle-collect='ceres::Solve*') */
    bool once = argc > 1 && std::string(argv[1]) == "once";
    int reps_scale = (argc > 1 && !once) ? std::atoi(argv[1]) : 1;
    int only = (once && argc > 2) ? std::atoi(argv[2]) : -1; /* one size: 0, 1, 2 */
    const int sizes[3][2] = {{3, 200}, {5, 500}, {10, 2000}};
    sfm_ba_options o;
    sfm_ba_default_options(&o);
    std::printf("%-8s %6s %10s %10s %6s %10s %10s %6s %7s %7s %10s %9s\n", "size", "obs", "libsfm_min",
                "libsfm_med", "steps", "ceres_min", "ceres_med", "steps", "r_min", "r_med", "ws_bytes",
                "cost_diff");
    for (int si = 0; si < 3; si++) {
        if (only >= 0 && si != only)
            continue;
        int m = sizes[si][0], n = sizes[si][1];
        char name[64];
        std::snprintf(name, sizeof name, "bench_%dx%d", m, n);
        Scene sc(name, m, n, 0.5, 3.0, 0.1, 0.05);
        int reps = once ? 1 : std::max(3, (si == 2 ? 7 : 21) * reps_scale);
        Work w(sc);
        sfm_ba_dims d = {m, n, sc.s.nobs, o.intrinsics, o.refine_intrinsics};
        size_t wsb = sfm_ba_workspace_size(&d);
        std::vector<unsigned char> ws(wsb);
        std::vector<double> tl, tc;
        sfm_ba_result r{};
        ceres::Solver::Summary sum;
        for (int rep = 0; rep < reps; rep++) {
            w.reset(sc);
            auto t0 = clk::now();
            int st = sfm_ba_solve(&w.p, &o, &r, nullptr, 0, ws.data(), ws.size());
            auto t1 = clk::now();
            if (st != SFM_OK) {
                std::printf("libsfm failed: %d\n", st);
                return 1;
            }
            tl.push_back(std::chrono::duration<double, std::milli>(t1 - t0).count());

            Work w2(sc);
            CeresBA cb;
            cb.build(w2.p, o);
            auto so = CeresBA::solver_options(o);
            auto t2 = clk::now();
            ceres::Solve(so, cb.problem.get(), &sum);
            auto t3 = clk::now();
            tc.push_back(std::chrono::duration<double, std::milli>(t3 - t2).count());
        }
        double ml = median(tl), mc = median(tc), nl = minimum(tl), nc = minimum(tc);
        char sz[32];
        std::snprintf(sz, sizeof sz, "%dx%d", m, n);
        /* Ceres does not list the final step it computes and rejects on the
         * function tolerance; count it so both columns count linear solves */
        int csteps = (int)sum.iterations.size() - 1 +
                     (sum.message.find("Function tolerance") != std::string::npos ? 1 : 0);
        std::printf("%-8s %6d %10.3f %10.3f %6d %10.3f %10.3f %6d %6.2fx %6.2fx %10zu %9.1e\n", sz,
                    sc.s.nobs, nl, ml, r.iterations, nc, mc, csteps, nc / nl, mc / ml, wsb,
                    std::fabs(r.final_cost - sum.final_cost) / sum.final_cost);
    }
    std::printf("ms per solve (min and median of interleaved repeats); r = ceres / libsfm (target >= 3x);\n"
                "cost_diff = |libsfm - ceres| / ceres final cost (both stop on function_tolerance 1e-6)\n");
    return 0;
}
