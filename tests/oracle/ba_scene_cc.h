// The synthetic scenes of tests/unit/ba_scene.h, for C++ programs: owns the
// arrays and seeds the generator from a name, as the test harness does.
#ifndef SFM_ORACLE_BA_SCENE_CC_H
#define SFM_ORACLE_BA_SCENE_CC_H

#include <cmath>
#include <cstdint>
#include <cstdio>
#include <cstring>
#include <vector>

extern "C" {
#include "sfm_test.h"
#include "../unit/ba_scene.h"
}

namespace sfm_oracle {

struct Scene {
    std::vector<double> R, t, K, X, R0, t0, K0, X0, xy, wgt;
    std::vector<int> oc, op;
    ba_scene s;
    sfm_test_ctx ctx;

    Scene(const char *name, int m, int n, double sigma, double rot_deg, double trans, double pt)
    {
        uint64_t h = 0xcbf29ce484222325ULL;
        for (const char *c = name; *c; c++) {
            h ^= (unsigned char)*c;
            h *= 0x100000001b3ULL;
        }
        ctx.name = name;
        ctx.failures = 0;
        sfm_rng_seed(&ctx.rng, h);
        R.resize(9 * m); t.resize(3 * m); K.resize(6 * m); X.resize(3 * n);
        R0.resize(9 * m); t0.resize(3 * m); K0.resize(6 * m); X0.resize(3 * n);
        oc.resize(m * n); op.resize(m * n); xy.resize(2 * m * n);
        s.R = R.data(); s.t = t.data(); s.K = K.data(); s.X = X.data();
        s.R0 = R0.data(); s.t0 = t0.data(); s.K0 = K0.data(); s.X0 = X0.data();
        s.oc = oc.data(); s.op = op.data(); s.xy = xy.data();
        bas_make(&ctx, &s, m, n, sigma, rot_deg, trans, pt);
    }
    // outliers on every `every`-th observation
    void add_outliers(int every, double lo, double hi)
    {
        for (int k = 0; k < s.nobs; k += every) {
            xy[2 * k] += sfm_test_uniform(&ctx, lo, hi) * ((k / every) % 2 ? 1 : -1);
            xy[2 * k + 1] += sfm_test_uniform(&ctx, -hi, hi);
        }
    }
};

// A problem over copies of the start.
struct Work {
    std::vector<double> R, t, K, X;
    sfm_ba_problem p;
    explicit Work(Scene &sc)
    {
        R = sc.R0; t = sc.t0; K = sc.K0; X = sc.X0;
        std::memset(&p, 0, sizeof p);
        p.n_cameras = sc.s.m;
        p.n_points = sc.s.n;
        p.n_observations = sc.s.nobs;
        p.rotations = R.data();
        p.translations = t.data();
        p.intrinsics = K.data();
        p.points = X.data();
        p.obs_camera = sc.oc.data();
        p.obs_point = sc.op.data();
        p.obs_xy = sc.xy.data();
        p.obs_weight = sc.wgt.empty() ? nullptr : sc.wgt.data();
    }
    void reset(const Scene &sc)
    {
        R = sc.R0; t = sc.t0; K = sc.K0; X = sc.X0;
        p.rotations = R.data(); p.translations = t.data(); p.intrinsics = K.data(); p.points = X.data();
    }
};

} // namespace sfm_oracle
#endif
