// The libsfm bundle adjustment problem stated for Ceres: the same projection
// models (pinhole, Brown-Conrady, Kannala-Brandt; fy = fx * aspect), the same cost
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

// camera block: angle-axis (3), t (3); intrinsics block: f, cx, cy and the
// five distortion entries of sfm_camera.dist. The camera models are written
// out here from their definitions (OpenCV's Brown-Conrady 5-vector and
// fisheye model), independently of the library.
struct Reprojection {
    double u, v, sw, aspect;
    int model;
    template <typename T>
    bool operator()(const T *cam, const T *intr, const T *X, T *res) const
    {
        T p[3];
        ceres::AngleAxisRotatePoint(cam, X, p);
        p[0] += cam[3];
        p[1] += cam[4];
        p[2] += cam[5];
        const T *k = intr + 3;
        T xd, yd;
        if (model == SFM_CAMERA_FISHEYE) {
            T rho = ceres::sqrt(p[0] * p[0] + p[1] * p[1]);
            T th = ceres::atan2(rho, p[2]);
            T t2 = th * th;
            T thd = th * (T(1.0) + t2 * (k[0] + t2 * (k[1] + t2 * (k[2] + t2 * k[3]))));
            xd = thd * p[0] / rho;
            yd = thd * p[1] / rho;
        } else {
            T xn = p[0] / p[2], yn = p[1] / p[2];
            T r2 = xn * xn + yn * yn;
            T d = T(1.0) + r2 * (k[0] + r2 * (k[1] + r2 * k[4]));
            if (model == SFM_CAMERA_PINHOLE)
                d = T(1.0);
            xd = xn * d;
            yd = yn * d;
            if (model == SFM_CAMERA_BROWN) {
                xd += T(2.0) * k[2] * xn * yn + k[3] * (r2 + T(2.0) * xn * xn);
                yd += k[2] * (r2 + T(2.0) * yn * yn) + T(2.0) * k[3] * xn * yn;
            }
        }
        res[0] = T(sw) * (intr[0] * xd + intr[1] - T(u));
        res[1] = T(sw) * (intr[0] * T(aspect) * yd + intr[2] - T(v));
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
    static constexpr int NI = 8;
    std::vector<double> cams, intr, pts;
    std::unique_ptr<ceres::Problem> problem;
    int m = 0, n = 0;

    void build(const sfm_ba_problem &p, const sfm_ba_options &o)
    {
        m = p.n_cameras;
        n = p.n_points;
        cams.assign(6 * m, 0.0);
        intr.assign(NI * m, 0.0);
        pts.assign(p.points, p.points + 3 * n);
        for (int i = 0; i < m; i++) {
            ceres::RotationMatrixToAngleAxis(ceres::RowMajorAdapter3x3(static_cast<const double *>(p.rotations + 9 * i)), &cams[6 * i]);
            for (int k = 0; k < 3; k++)
                cams[6 * i + 3 + k] = p.translations[3 * i + k];
            const sfm_camera &K = p.cameras[i];
            double *b = &intr[NI * i];
            b[0] = K.fx; b[1] = K.cx; b[2] = K.cy;
            for (int e = 0; e < 5; e++)
                b[3 + e] = K.dist[e];
        }
        const bool shared = o.intrinsics == SFM_BA_INTRINSICS_SHARED && o.refine_intrinsics != 0;
        if (shared) { // one block (camera 0's); every camera reads it
            for (int i = 1; i < m; i++)
                for (int k = 0; k < NI; k++)
                    intr[NI * i + k] = intr[k];
        }
        ceres::Problem::Options po;
        po.loss_function_ownership = ceres::TAKE_OWNERSHIP;
        problem.reset(new ceres::Problem(po));
        for (int k = 0; k < p.n_observations; k++) {
            int c = p.obs_camera[k], j = p.obs_point[k];
            double w = p.obs_weight ? p.obs_weight[k] : 1.0;
            const sfm_camera &K = p.cameras[c];
            auto *cf = new ceres::AutoDiffCostFunction<Reprojection, 2, 6, NI, 3>(
                new Reprojection{p.obs_xy[2 * k], p.obs_xy[2 * k + 1], std::sqrt(w), K.fy / K.fx, K.model});
            problem->AddResidualBlock(cf, make_loss(o.loss, o.loss_scale), &cams[6 * c],
                                      shared ? &intr[0] : &intr[NI * c], &pts[3 * j]);
        }
        if (o.gauge == SFM_BA_GAUGE_FIRST_CAMERA)
            problem->SetParameterBlockConstant(&cams[0]);
        if (shared) {
            std::vector<int> held;
            if (!(o.refine_intrinsics & SFM_BA_REFINE_FOCAL)) held.push_back(0);
            if (!(o.refine_intrinsics & SFM_BA_REFINE_PRINCIPAL)) { held.push_back(1); held.push_back(2); }
            const int model = p.cameras[0].model;
            const int nd = model == SFM_CAMERA_BROWN ? 5 : model == SFM_CAMERA_FISHEYE ? 4 : 0;
            const int free_d = (o.refine_intrinsics & SFM_BA_REFINE_DISTORTION) ? nd
                               : (o.refine_intrinsics & SFM_BA_REFINE_RADIAL) ? (nd < 2 ? nd : 2)
                               : (o.refine_intrinsics & SFM_BA_REFINE_K1) ? (nd < 1 ? nd : 1) : 0;
            for (int e = free_d; e < 5; e++)
                held.push_back(3 + e);
            if (!held.empty())
                problem->SetManifold(&intr[0], new ceres::SubsetManifold(NI, held));
        } else {
            for (int i = 0; i < m; i++)
                problem->SetParameterBlockConstant(&intr[NI * i]);
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
