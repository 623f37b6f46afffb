// The C++ interop header: views alias the sfm structs, conversions round-trip,
// and the wrappers return what Eigen's own decompositions say on the same
// inputs. Ends with "N passed, N failed".
#include "sfm/sfm_eigen.hpp"

#include <Eigen/Dense>

#include <cmath>
#include <cstdio>

namespace {

int g_pass = 0, g_fail = 0;

void check(bool ok, const char *what)
{
    std::printf("%-4s %s\n", ok ? "ok" : "FAIL", what);
    (ok ? g_pass : g_fail)++;
}

} // namespace

int main()
{
    using namespace sfm::eigen;

    // views write through to the structs, in libsfm's row-major layout
    sfm_mat3 m3 = {{1, 2, 3, 4, 5, 6, 7, 8, 9}};
    check(map(m3)(0, 1) == 2 && map(m3)(1, 0) == 4, "map(sfm_mat3) is row-major");
    map(m3)(2, 1) = -1;
    check(m3.m[7] == -1, "writing through map(sfm_mat3) writes the struct");
    sfm_mat34 P = {{1, 0, 0, 5, 0, 1, 0, 6, 0, 0, 1, 7}};
    check(map(P).col(3) == Eigen::Vector3d(5, 6, 7), "map(sfm_mat34) last column is t");
    sfm_vec3 pts[4] = {{{1, 2, 3}}, {{4, 5, 6}}, {{7, 8, 9}}, {{10, 11, 12}}};
    auto rows = map_rows(pts, 4);
    check(rows.rows() == 4 && rows(2, 1) == 8, "map_rows(sfm_vec3*) is n x 3");
    rows.col(2).setZero();
    check(pts[3].v[2] == 0 && pts[0].v[2] == 0, "writing through map_rows writes the points");
    const sfm_vec2 uv[2] = {{{0.5, 1.5}}, {{2.5, 3.5}}};
    check(map_rows(uv, 2)(1, 0) == 2.5, "map_rows(const sfm_vec2*)");
    sfm_vec3 v = to_sfm_vec3(Eigen::Vector3d(1, -2, 3));
    check(map(v).dot(Eigen::Vector3d(1, 1, 1)) == 2, "to_sfm_vec3 / map(sfm_vec3)");

    // poses: x_cam = R X + t both ways
    Eigen::Isometry3d T = Eigen::Isometry3d::Identity();
    T.linear() = Eigen::AngleAxisd(0.3, Eigen::Vector3d(1, 2, 3).normalized()).toRotationMatrix();
    T.translation() = Eigen::Vector3d(0.1, -0.2, 0.3);
    sfm_pose p = from_isometry(T);
    Eigen::Vector3d X(1, 2, 3);
    Eigen::Vector3d xc = map_R(p) * X + map_t(p);
    check((xc - T * X).norm() < 1e-15, "from_isometry: x_cam = R X + t");
    check(to_isometry(p).isApprox(T, 1e-15), "to_isometry round trip");
    check(map_R(p)(0, 1) == T.linear()(0, 1), "pose R is row-major in the struct");
    sfm_mat3 R3 = to_sfm_mat3(T.linear());
    check(R3.m[1] == T.linear()(0, 1) && R3.m[3] == T.linear()(1, 0), "to_sfm_mat3 row-major");

    // wrappers against Eigen on the same input
    Eigen::MatrixXd A = Eigen::MatrixXd::Random(9, 7);
    SVD s = svd(A);
    Eigen::JacobiSVD<Eigen::MatrixXd> ej(A);
    check(s.ok() && s.U.rows() == 9 && s.V.rows() == 7, "svd: full U and V");
    check(s.ok() && (s.S - ej.singularValues()).norm() < 1e-13, "svd: S matches JacobiSVD");
    check(s.ok() && (s.U.leftCols(7) * s.S.asDiagonal() * s.V.transpose() - A).norm() < 1e-13,
          "svd: A = U S V^T");
    SVD s2 = svd(A.transpose(), false, true);
    check(s2.ok() && s2.U.size() == 0 && (s2.S - s.S).norm() < 1e-13, "svd: wide input, no U");

    Eigen::MatrixXd B = Eigen::MatrixXd::Random(6, 6);
    Eigen::MatrixXd Sy = B + B.transpose();
    SymEig se = sym_eig(Sy);
    Eigen::SelfAdjointEigenSolver<Eigen::MatrixXd> es(Sy);
    check(se.ok() && (se.values - es.eigenvalues()).norm() < 1e-13, "sym_eig: values match");
    check(se.ok() && (Sy * se.vectors - se.vectors * se.values.asDiagonal()).norm() < 1e-13,
          "sym_eig: A V = V diag(w)");

    Eigen::MatrixXd C = Eigen::MatrixXd::Random(10, 10);
    Eig e = eig(C);
    Eigen::MatrixXcd Cc = C.cast<std::complex<double>>();
    check(e.ok() && (Cc * e.vectors - e.vectors * e.values.asDiagonal()).norm() < 1e-12,
          "eig: A v = lambda v (complex)");
    Eigen::EigenSolver<Eigen::MatrixXd> ees(C, false);
    double worst = 0;
    for (int j = 0; j < 10 && e.ok(); j++) {
        double best = 1e300;
        for (int k = 0; k < 10; k++)
            best = std::min(best, std::abs(e.values[k] - ees.eigenvalues()[j]));
        worst = std::max(worst, best);
    }
    check(e.ok() && worst < 1e-12, "eig: values match EigenSolver");
    check(e.ok() && e.values[0].real() >= e.values[9].real(), "eig: descending real part");

    Eigen::MatrixXd F = Eigen::MatrixXd::Random(8, 9);
    Nullspace ns = nullspace(F, 1);
    check(ns.ok() && (F * ns.N).norm() < 1e-13 && std::fabs(ns.N.norm() - 1) < 1e-14,
          "nullspace: F n = 0, |n| = 1");

    Eigen::MatrixXd M = Eigen::MatrixXd::Random(5, 5) + 5 * Eigen::MatrixXd::Identity(5, 5);
    Eigen::MatrixXd rhs = Eigen::MatrixXd::Random(5, 2);
    Solve so = lu_solve(M, rhs);
    check(so.ok() && (so.X - M.partialPivLu().solve(rhs)).norm() < 1e-13, "lu_solve vs PartialPivLU");
    Eigen::MatrixXd Spd = M * M.transpose();
    Cholesky ch = cholesky(Spd);
    check(ch.ok() && (ch.L - Eigen::MatrixXd(Spd.llt().matrixL())).norm() < 1e-12, "cholesky vs LLT");
    QR q = qr(F.transpose());
    check(q.ok() && (q.Q * q.R - F.transpose()).norm() < 1e-13, "qr: Q R = A");

    // failures are statuses, not exceptions
    Eigen::MatrixXd Bad = A;
    Bad(0, 0) = std::nan("");
    check(svd(Bad).status == SFM_E_NONFINITE && svd(Bad).S.size() == 0, "svd: NaN -> SFM_E_NONFINITE");
    check(cholesky(-Spd).status == SFM_E_SINGULAR, "cholesky: not SPD -> SFM_E_SINGULAR");
    check(eig(A).status == SFM_E_ARGUMENT, "eig: non-square -> SFM_E_ARGUMENT");

    std::printf("%d passed, %d failed\n", g_pass, g_fail);
    return g_fail ? 1 : 0;
}
