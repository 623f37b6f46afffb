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
    std::vector<sfm_camera> cams, cams0; // truth and start when set_model was called
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
    // Every camera of one model with these distortion coefficients (truth);
    // the observations re-rendered through sfm_camera_project with noise
    // sigma; the start's focal scaled by focal_scale.
    void set_model(int model, const double dist[5], double sigma, double focal_scale)
    {
        cams.resize(s.m);
        for (int i = 0; i < s.m; i++) {
            sfm_camera &c = cams[i];
            std::memset(&c, 0, sizeof c);
            c.model = model;
            c.fx = K[6 * i]; c.fy = K[6 * i + 1]; c.cx = K[6 * i + 2]; c.cy = K[6 * i + 3];
            for (int e = 0; e < 5; e++)
                c.dist[e] = dist[e];
        }
        cams0 = cams;
        for (int i = 0; i < s.m; i++) {
            cams0[i].fx *= focal_scale;
            cams0[i].fy *= focal_scale;
        }
        for (int k = 0; k < s.nobs; k++) {
            const double *Rv = &R[9 * s.oc[k]], *tv = &t[3 * s.oc[k]], *Xj = &X[3 * s.op[k]];
            double xc[3];
            for (int r = 0; r < 3; r++)
                xc[r] = Rv[3 * r] * Xj[0] + Rv[3 * r + 1] * Xj[1] + Rv[3 * r + 2] * Xj[2] + tv[r];
            sfm_camera_project(&cams[s.oc[k]], xc, &xy[2 * k], nullptr);
            xy[2 * k] += sfm_test_normal(&ctx, sigma);
            xy[2 * k + 1] += sfm_test_normal(&ctx, sigma);
        }
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
    std::vector<sfm_camera> cams;
    sfm_ba_problem p;
    void start_cameras(const Scene &sc)
    {
        if (!sc.cams0.empty()) {
            cams = sc.cams0;
        } else {
            cams.resize(sc.s.m);
            bas_cameras_from_rows(sc.K0.data(), sc.s.m, cams.data());
        }
    }
    explicit Work(Scene &sc)
    {
        R = sc.R0; t = sc.t0; K = sc.K0; X = sc.X0;
        start_cameras(sc);
        std::memset(&p, 0, sizeof p);
        p.n_cameras = sc.s.m;
        p.n_points = sc.s.n;
        p.n_observations = sc.s.nobs;
        p.rotations = R.data();
        p.translations = t.data();
        p.cameras = cams.data();
        p.points = X.data();
        p.obs_camera = sc.oc.data();
        p.obs_point = sc.op.data();
        p.obs_xy = sc.xy.data();
        p.obs_weight = sc.wgt.empty() ? nullptr : sc.wgt.data();
    }
    void reset(const Scene &sc)
    {
        R = sc.R0; t = sc.t0; K = sc.K0; X = sc.X0;
        start_cameras(sc);
        p.rotations = R.data(); p.translations = t.data(); p.cameras = cams.data(); p.points = X.data();
    }
};

} // namespace sfm_oracle
#endif
