// The libsfm bundle adjustment problem stated for Ceres: the same projection
// model (pinhole with radial k1, k2; fy = fx * aspect), the same cost
// 1/2 sum rho(w |r|^2) (residual sqrt(w) r with the same loss), camera 0 held.
// Rotations are angle-axis blocks in Ceres; the minimum is the same as on
// libsfm's SO(3) parameterization. Shared by the oracle test and the benchmark.
#ifndef SFM_ORACLE_BA_CERES_PROBLEM_H
#define SFM_ORACLE_BA_CERES_PROBLEM_H

#include <ceres/ceres.h>
#include <ceres/rotation.h>

#include <cmath>
#include <memory>
#include <vector>

extern "C" {
#include "sfm/sfm.h"
}

namespace sfm_oracle {

// camera block: angle-axis (3), t (3); intrinsics block: f, cx, cy, k1, k2
struct Reprojection {
    double u, v, sw, aspect;
    template <typename T>
    bool operator()(const T *cam, const T *intr, const T *X, T *res) const
    {
        T p[3];
        ceres::AngleAxisRotatePoint(cam, X, p);
        p[0] += cam[3];
        p[1] += cam[4];
        p[2] += cam[5];
        T xn = p[0] / p[2], yn = p[1] / p[2];
        T r2 = xn * xn + yn * yn;
        T d = T(1.0) + r2 * (intr[3] + intr[4] * r2);
        res[0] = T(sw) * (intr[0] * d * xn + intr[1] - T(u));
        res[1] = T(sw) * (intr[0] * T(aspect) * d * yn + intr[2] - T(v));
        return true;
    }
};

// min(s, a^2)
class TruncatedLoss : public ceres::LossFunction {
  public:
    explicit TruncatedLoss(double a) : a2_(a * a) {}
    void Evaluate(double s, double rho[3]) const override
    {
        if (s <= a2_) {
            rho[0] = s;
            rho[1] = 1.0;
        } else {
            rho[0] = a2_;
            rho[1] = 0.0;
        }
        rho[2] = 0.0;
    }

  private:
    double a2_;
};

inline ceres::LossFunction *make_loss(int loss, double a)
{
    switch (loss) {
    case SFM_BA_LOSS_HUBER: return new ceres::HuberLoss(a);
    case SFM_BA_LOSS_CAUCHY: return new ceres::CauchyLoss(a);
    case SFM_BA_LOSS_TRUNCATED: return new TruncatedLoss(a);
    default: return nullptr;
    }
}

// Holds the Ceres parameter blocks for an sfm_ba_problem (fixed intrinsics,
// or SHARED intrinsics refining the entries in refine_mask).
struct CeresBA {
    std::vector<double> cams, intr, pts;
    std::unique_ptr<ceres::Problem> problem;
    int m = 0, n = 0;

    void build(const sfm_ba_problem &p, const sfm_ba_options &o)
    {
        m = p.n_cameras;
        n = p.n_points;
        cams.assign(6 * m, 0.0);
        intr.assign(5 * m, 0.0);
        pts.assign(p.points, p.points + 3 * n);
        for (int i = 0; i < m; i++) {
            ceres::RotationMatrixToAngleAxis(ceres::RowMajorAdapter3x3(static_cast<const double *>(p.rotations + 9 * i)), &cams[6 * i]);
            for (int k = 0; k < 3; k++)
                cams[6 * i + 3 + k] = p.translations[3 * i + k];
            const double *K = p.intrinsics + 6 * i;
            double *b = &intr[5 * i];
            b[0] = K[0]; b[1] = K[2]; b[2] = K[3]; b[3] = K[4]; b[4] = K[5];
        }
        const bool shared = o.intrinsics == SFM_BA_INTRINSICS_SHARED && o.refine_intrinsics != 0;
        if (shared) { // one block (camera 0's); every camera reads it
            for (int i = 1; i < m; i++)
                for (int k = 0; k < 5; k++)
                    intr[5 * i + k] = intr[k];
        }
        ceres::Problem::Options po;
        po.loss_function_ownership = ceres::TAKE_OWNERSHIP;
        problem.reset(new ceres::Problem(po));
        for (int k = 0; k < p.n_observations; k++) {
            int c = p.obs_camera[k], j = p.obs_point[k];
            double w = p.obs_weight ? p.obs_weight[k] : 1.0;
            const double *K = p.intrinsics + 6 * c;
            auto *cf = new ceres::AutoDiffCostFunction<Reprojection, 2, 6, 5, 3>(
                new Reprojection{p.obs_xy[2 * k], p.obs_xy[2 * k + 1], std::sqrt(w), K[1] / K[0]});
            problem->AddResidualBlock(cf, make_loss(o.loss, o.loss_scale), &cams[6 * c],
                                      shared ? &intr[0] : &intr[5 * c], &pts[3 * j]);
        }
        if (o.gauge == SFM_BA_GAUGE_FIRST_CAMERA)
            problem->SetParameterBlockConstant(&cams[0]);
        if (shared) {
            std::vector<int> held;
            if (!(o.refine_intrinsics & SFM_BA_REFINE_FOCAL)) held.push_back(0);
            if (!(o.refine_intrinsics & SFM_BA_REFINE_PRINCIPAL)) { held.push_back(1); held.push_back(2); }
            if (!(o.refine_intrinsics & SFM_BA_REFINE_RADIAL)) { held.push_back(3); held.push_back(4); }
            if (!held.empty())
                problem->SetManifold(&intr[0], new ceres::SubsetManifold(5, held));
        } else {
            for (int i = 0; i < m; i++)
                problem->SetParameterBlockConstant(&intr[5 * i]);
        }
    }

    // Ceres options matching sfm_ba_options' LM settings and tolerances.
    static ceres::Solver::Options solver_options(const sfm_ba_options &o)
    {
        ceres::Solver::Options so;
        so.linear_solver_type = ceres::DENSE_SCHUR;
        so.trust_region_strategy_type = ceres::LEVENBERG_MARQUARDT;
        so.num_threads = 1;
        so.max_num_iterations = o.max_iterations;
        so.function_tolerance = o.function_tolerance;
        so.gradient_tolerance = o.gradient_tolerance;
        so.parameter_tolerance = o.parameter_tolerance;
        so.initial_trust_region_radius = o.initial_trust_radius;
        so.minimizer_progress_to_stdout = false;
        so.logging_type = ceres::SILENT;
        return so;
    }
};

} // namespace sfm_oracle

#endif
