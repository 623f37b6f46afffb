// Oracle for the dense linear algebra: every libsfm routine against Eigen 3.4
// (JacobiSVD/BDCSVD, SelfAdjointEigenSolver, EigenSolver, HouseholderQR, LLT,
// PartialPivLU) on the same random matrices, at the sizes the solvers, the
// bundle adjustment and the rotations use: 3x3 to 27x27 square, tall 100x9
// and 400x27, wide 5x9/8x9; well-conditioned, condition 1e10, rank-deficient
// and repeated-singular-value inputs.
//
// Each row of the report is one check: the worst residual, the worst
// orthogonality error and the worst difference from Eigen over all matrices
// of that case, against the bounds stated in the row. Differences are
// relative: singular values and eigenvalues to the largest in magnitude,
// factors (R, L, LU) to their norm, eigenvalues of nonsymmetric matrices to
// |A|_F, null spaces as the largest entry of N N^T - Ne Ne^T, and solutions
// of linear systems as the relative forward error divided by the condition
// number (its square for least squares). The "vs" column takes the worst of
// the factor and solve comparisons. The run ends with
// "N passed, N failed".
#include <Eigen/Dense>
#include <Eigen/Eigenvalues>
#include <Eigen/SVD>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <cstring>
#include <random>
#include <string>
#include <vector>

#include "sfm/sfm.h"

using Eigen::MatrixXd;
using Eigen::VectorXd;
using RowMat = Eigen::Matrix<double, Eigen::Dynamic, Eigen::Dynamic, Eigen::RowMajor>;

namespace {

std::mt19937_64 g_rng(20261122);
int g_pass = 0, g_fail = 0;
std::vector<unsigned char> g_ws;

void *ws(size_t n)
{
    if (g_ws.size() < n)
        g_ws.resize(n);
    return g_ws.data();
}

MatrixXd rand_mat(int m, int n)
{
    std::uniform_real_distribution<double> u(-1.0, 1.0);
    MatrixXd A(m, n);
    for (int j = 0; j < n; j++)
        for (int i = 0; i < m; i++)
            A(i, j) = u(g_rng);
    return A;
}

MatrixXd rand_orth(int n)
{
    std::normal_distribution<double> g(0.0, 1.0);
    MatrixXd G(n, n);
    for (int j = 0; j < n; j++)
        for (int i = 0; i < n; i++)
            G(i, j) = g(g_rng);
    Eigen::HouseholderQR<MatrixXd> qr(G);
    return qr.householderQ() * MatrixXd::Identity(n, n);
}

// m x n with the given singular values (p = min(m, n) of them)
MatrixXd with_singular_values(int m, int n, const VectorXd &s)
{
    int p = std::min(m, n);
    MatrixXd U = rand_orth(m), V = rand_orth(n);
    return U.leftCols(p) * s.asDiagonal() * V.leftCols(p).transpose();
}

struct Worst {
    double resid = 0, orth = 0, diff = 0;
    int count = 0, errors = 0, nonfinite = 0;
    void res(double v) { resid = std::max(resid, v); if (!std::isfinite(v)) nonfinite++; }
    void ort(double v) { orth = std::max(orth, v); if (!std::isfinite(v)) nonfinite++; }
    void dif(double v) { diff = std::max(diff, v); if (!std::isfinite(v)) nonfinite++; }
};

void report(const char *routine, const char *kase, const std::string &size, const Worst &w,
            double bres, double bort, double bdiff, const char *vs)
{
    bool ok = w.errors == 0 && w.nonfinite == 0 && w.resid <= bres && w.orth <= bort &&
              w.diff <= bdiff;
    std::printf("%-9s %-12s %-7s %5d  resid %8.2e (<= %.0e)  orth %8.2e (<= %.0e)  vs %-14s %8.2e (<= %.0e)  %s\n",
                routine, kase, size.c_str(), w.count, w.resid, bres, w.orth, bort, vs, w.diff,
                bdiff, ok ? "ok" : "FAIL");
    if (w.errors)
        std::printf("          %d calls returned an error status\n", w.errors);
    if (ok)
        g_pass++;
    else
        g_fail++;
}

std::string dims(int m, int n) { return std::to_string(m) + "x" + std::to_string(n); }

double orth_err(const MatrixXd &Q)
{
    return (Q.transpose() * Q - MatrixXd::Identity(Q.cols(), Q.cols())).cwiseAbs().maxCoeff();
}

// ------------------------------------------------------------------- SVD
enum SvdKind { WELL, COND1E10, RANKDEF, REPEATED };

void svd_case(SvdKind kind, int m, int n, int count, int full_u_checks)
{
    const int p = std::min(m, n);
    Worst w, wb;
    const size_t wsz = sfm_svd_workspace_size(m, n);
    RowMat U(m, m), V(n, n);
    VectorXd S(p);
    const bool use_bdc = p >= 20;
    for (int it = 0; it < count; it++) {
        MatrixXd A;
        VectorXd truth;
        switch (kind) {
        case WELL:
            A = rand_mat(m, n);
            break;
        case COND1E10:
            truth.resize(p);
            for (int k = 0; k < p; k++)
                truth[k] = std::pow(10.0, -10.0 * k / std::max(p - 1, 1));
            A = with_singular_values(m, n, truth);
            break;
        case RANKDEF: {
            int r = std::max(1, p - 1 - it % std::max(1, p / 2));
            A = rand_mat(m, r) * rand_mat(r, n);
            break;
        }
        case REPEATED:
            truth.resize(p);
            for (int k = 0; k < p; k++)
                truth[k] = k < p / 3 ? 2.0 : (k < 2 * p / 3 ? 1.0 : 0.25);
            A = with_singular_values(m, n, truth);
            break;
        }
        RowMat Ar = A;
        bool full = it < full_u_checks;
        int st = sfm_svd(Ar.data(), m, n, full ? U.data() : nullptr, S.data(), V.data(), ws(wsz), wsz);
        w.count++;
        if (st != SFM_OK) {
            w.errors++;
            continue;
        }
        Eigen::JacobiSVD<MatrixXd> ej(A, Eigen::ComputeThinU | Eigen::ComputeThinV);
        const VectorXd &se = ej.singularValues();
        if (full) {
            MatrixXd Um = U;
            w.ort(orth_err(Um));
            MatrixXd R = Um.leftCols(p) * S.asDiagonal() * MatrixXd(V).leftCols(p).transpose();
            double an = A.norm();
            w.res(an > 0 ? (R - A).norm() / an : (R - A).norm());
        } else {
            // thin check without U: A V = U S, columns of A V / S orthonormal
            MatrixXd AV = A * MatrixXd(V).leftCols(p);
            double an = A.norm();
            // |A - A V V^T| measures V's completeness, |AV| column norms S
            MatrixXd R = AV * MatrixXd(V).leftCols(p).transpose();
            w.res(an > 0 ? (R - A).norm() / an : 0.0);
            VectorXd cn = AV.colwise().norm();
            w.dif(std::fabs((cn - S).maxCoeff() / std::max(se[0], 1e-300)));
        }
        w.ort(orth_err(MatrixXd(V)));
        double s0 = std::max(se[0], 1e-300);
        w.dif((S - se).cwiseAbs().maxCoeff() / s0);
        if (truth.size())
            w.dif((S - truth).cwiseAbs().maxCoeff() / truth[0]);
        if (use_bdc) {
            Eigen::BDCSVD<MatrixXd> eb(A);
            wb.count++;
            if (kind == REPEATED) // BDCSVD's own error against the truth
                wb.dif((eb.singularValues() - truth).cwiseAbs().maxCoeff() / truth[0]);
            else
                wb.dif((S - eb.singularValues()).cwiseAbs().maxCoeff() / s0);
        }
    }
    static const char *names[] = {"random", "cond 1e10", "rank-def", "repeated"};
    const double bound_res = 1e-13, bound_orth = 1e-13;
    report("svd", names[kind], dims(m, n), w, bound_res, bound_orth, 1e-13,
           kind == WELL || kind == RANKDEF ? "JacobiSVD" : "JacobiSVD+true");
    if (use_bdc && kind == REPEATED)
        std::printf("%-9s %-12s %-7s %5d  (not counted) Eigen's BDCSVD vs truth: %8.2e; "
                    "libsfm vs truth is in the row above\n",
                    "svd", names[kind], dims(m, n).c_str(), wb.count, wb.diff);
    else if (use_bdc)
        report("svd", names[kind], dims(m, n), wb, 1, 1, 1e-13, "BDCSVD");
}

// ------------------------------------------------------- symmetric eig
void sym_case(int n, int count, bool repeated, bool ill)
{
    Worst w;
    const size_t wsz = sfm_sym_eig_workspace_size(n);
    RowMat V(n, n);
    VectorXd ev(n);
    for (int it = 0; it < count; it++) {
        MatrixXd A;
        VectorXd truth;
        if (repeated || ill) {
            truth.resize(n);
            for (int k = 0; k < n; k++)
                truth[k] = repeated ? (k < n / 2 ? -1.0 : 3.0)
                                    : std::pow(10.0, -10.0 * k / std::max(n - 1, 1)) * (k % 2 ? -1 : 1);
            MatrixXd Q = rand_orth(n);
            A = Q * truth.asDiagonal() * Q.transpose();
            A = 0.5 * (A + A.transpose());
            std::sort(truth.data(), truth.data() + n);
        } else {
            MatrixXd B = rand_mat(n, n);
            A = B + B.transpose();
        }
        RowMat Ar = A;
        int st = sfm_sym_eig(Ar.data(), n, ev.data(), V.data(), ws(wsz), wsz);
        w.count++;
        if (st != SFM_OK) {
            w.errors++;
            continue;
        }
        Eigen::SelfAdjointEigenSolver<MatrixXd> es(A);
        double scale = std::max(es.eigenvalues().cwiseAbs().maxCoeff(), 1e-300);
        MatrixXd Vm = V;
        w.res((A * Vm - Vm * ev.asDiagonal()).cwiseAbs().maxCoeff() / scale);
        w.ort(orth_err(Vm));
        w.dif((ev - es.eigenvalues()).cwiseAbs().maxCoeff() / scale);
        if (truth.size())
            w.dif((ev - truth).cwiseAbs().maxCoeff() / scale);
    }
    report("sym_eig", repeated ? "repeated" : (ill ? "cond 1e10" : "random"), dims(n, n), w,
           1e-13, 1e-13, 1e-13, "SelfAdjointES");
}

// ---------------------------------------------------- nonsymmetric eig
void eig_case(int n, int count, bool sparse_int)
{
    Worst w;
    const size_t wsz = sfm_eig_workspace_size(n);
    RowMat V(n, n);
    VectorXd wr(n), wi(n);
    std::uniform_int_distribution<int> d5(-2, 2), d2(0, 1);
    for (int it = 0; it < count; it++) {
        MatrixXd A = rand_mat(n, n);
        if (sparse_int)
            for (int j = 0; j < n; j++)
                for (int i = 0; i < n; i++)
                    A(i, j) = d2(g_rng) ? 0.0 : d5(g_rng);
        RowMat Ar = A;
        int st = sfm_eig(Ar.data(), n, wr.data(), wi.data(), V.data(), ws(wsz), wsz);
        w.count++;
        if (st != SFM_OK) {
            w.errors++;
            continue;
        }
        double an = std::max(A.norm(), 1e-300);
        Eigen::MatrixXcd Vc(n, n);
        Eigen::VectorXcd lc(n);
        for (int k = 0; k < n; k++) {
            if (wi[k] > 0) {
                for (int i = 0; i < n; i++) {
                    Vc(i, k) = {V(i, k), V(i, k + 1)};
                    Vc(i, k + 1) = {V(i, k), -V(i, k + 1)};
                }
                lc[k] = {wr[k], wi[k]};
                lc[k + 1] = {wr[k + 1], wi[k + 1]};
                k++;
            } else {
                for (int i = 0; i < n; i++)
                    Vc(i, k) = V(i, k);
                lc[k] = wr[k];
            }
        }
        Eigen::MatrixXcd Ac = A.cast<std::complex<double>>();
        w.res((Ac * Vc - Vc * lc.asDiagonal()).cwiseAbs().maxCoeff() / an);
        // unit norm per vector (complex norm)
        double nerr = 0;
        for (int k = 0; k < n; k++)
            nerr = std::max(nerr, std::fabs(Vc.col(k).norm() - 1.0));
        w.ort(nerr);
        if (sparse_int)
            continue; // defective spectra: eigenvalues are ill-conditioned by design
        Eigen::EigenSolver<MatrixXd> es(A, false);
        // match each Eigen eigenvalue to the nearest unused libsfm one
        std::vector<bool> used(n, false);
        double dmax = 0;
        for (int j = 0; j < n; j++) {
            std::complex<double> le = es.eigenvalues()[j];
            int best = -1;
            double bd = 1e300;
            for (int k = 0; k < n; k++)
                if (!used[k] && std::abs(lc[k] - le) < bd) {
                    bd = std::abs(lc[k] - le);
                    best = k;
                }
            used[best] = true;
            dmax = std::max(dmax, bd);
        }
        w.dif(dmax / an);
    }
    report("eig", sparse_int ? "sparse-int" : "random", dims(n, n), w, 1e-13, 1e-13,
           sparse_int ? 1.0 : 1e-10, sparse_int ? "(residual only)" : "EigenSolver");
}

// ------------------------------------------------------------------ QR
void qr_case(int m, int n, int count)
{
    Worst w;
    RowMat QR(m, n), Q(m, m);
    VectorXd tau(n);
    for (int it = 0; it < count; it++) {
        MatrixXd A = rand_mat(m, n);
        QR = A;
        int st = sfm_qr_factor(QR.data(), m, n, tau.data());
        if (st == SFM_OK)
            st = sfm_qr_form_q(QR.data(), tau.data(), m, n, Q.data());
        w.count++;
        if (st != SFM_OK) {
            w.errors++;
            continue;
        }
        MatrixXd R = MatrixXd(QR).topRows(n).triangularView<Eigen::Upper>();
        MatrixXd Qm = Q;
        w.res((Qm.leftCols(n) * R - A).norm() / A.norm());
        w.ort(orth_err(Qm));
        Eigen::HouseholderQR<MatrixXd> eq(A);
        MatrixXd Re = eq.matrixQR().topRows(n).triangularView<Eigen::Upper>();
        // R is unique up to the signs of its rows
        double d = 0;
        for (int i = 0; i < n; i++) {
            double sgn = (R(i, i) >= 0) == (Re(i, i) >= 0) ? 1.0 : -1.0;
            d = std::max(d, (R.row(i) - sgn * Re.row(i)).cwiseAbs().maxCoeff());
        }
        w.dif(d / A.norm());
        // least squares vs Eigen's solve
        VectorXd b = rand_mat(m, 1);
        VectorXd bx = b;
        if (sfm_qr_solve(QR.data(), tau.data(), m, n, bx.data()) != SFM_OK) {
            w.errors++;
            continue;
        }
        VectorXd xe = eq.solve(b);
        // least-squares forward error grows like cond^2: compare relative to it
        VectorXd sv = A.jacobiSvd().singularValues();
        double cond = sv[0] / sv[n - 1];
        w.dif((bx.head(n) - xe).norm() / xe.norm() / (cond * cond));
    }
    report("qr", "random", dims(m, n), w, 1e-13, 1e-13, 1e-12, "HouseholderQR");
}

// ------------------------------------------------------------- Cholesky
void llt_case(int n, int count)
{
    Worst w;
    RowMat L(n, n);
    for (int it = 0; it < count; it++) {
        MatrixXd B = rand_mat(n, n);
        MatrixXd A = B * B.transpose() + 0.1 * MatrixXd::Identity(n, n);
        L = A;
        int st = sfm_cholesky_factor(L.data(), n);
        w.count++;
        if (st != SFM_OK) {
            w.errors++;
            continue;
        }
        MatrixXd Lm = L;
        w.res((Lm * Lm.transpose() - A).norm() / A.norm());
        Eigen::LLT<MatrixXd> el(A);
        MatrixXd Le = el.matrixL();
        w.dif((Lm - Le).norm() / Le.norm());
        MatrixXd Bx = rand_mat(n, 2);
        RowMat X = Bx;
        sfm_cholesky_solve(L.data(), n, X.data(), 2);
        MatrixXd Xe = el.solve(Bx);
        VectorXd ev = Eigen::SelfAdjointEigenSolver<MatrixXd>(A, Eigen::EigenvaluesOnly).eigenvalues();
        w.dif((MatrixXd(X) - Xe).norm() / Xe.norm() / (ev[n - 1] / ev[0])); // forward error / cond
    }
    report("cholesky", "random spd", dims(n, n), w, 1e-13, 0, 1e-12, "LLT");
}

// ------------------------------------------------------------------ LU
void lu_case(int n, int count)
{
    Worst w;
    RowMat LU(n, n);
    std::vector<int> piv(n);
    for (int it = 0; it < count; it++) {
        MatrixXd A = rand_mat(n, n);
        LU = A;
        int st = sfm_lu_factor(LU.data(), n, piv.data());
        w.count++;
        if (st != SFM_OK) {
            w.errors++;
            continue;
        }
        MatrixXd L = MatrixXd(LU).triangularView<Eigen::UnitLower>();
        MatrixXd U = MatrixXd(LU).triangularView<Eigen::Upper>();
        MatrixXd PA = A;
        for (int k = 0; k < n; k++)
            PA.row(k).swap(PA.row(piv[k]));
        w.res((L * U - PA).norm() / A.norm());
        Eigen::PartialPivLU<MatrixXd> el(A);
        // same pivoting rule: identical factors up to rounding
        w.dif((MatrixXd(LU) - el.matrixLU()).norm() / el.matrixLU().norm());
        MatrixXd B = rand_mat(n, 3);
        RowMat X = B;
        sfm_lu_solve(LU.data(), piv.data(), n, X.data(), 3);
        MatrixXd Xe = el.solve(B);
        double rel = (MatrixXd(X) - Xe).norm() / Xe.norm();
        double cond = 1.0 / el.rcond();
        w.dif(rel / cond); // forward error relative to the condition number
    }
    report("lu", "random", dims(n, n), w, 1e-13, 0, 1e-12, "PartialPivLU");
}

// ------------------------------------------------------------ nullspace
void null_case(int m, int n, int k, int count)
{
    Worst w;
    const size_t wsz = sfm_nullspace_workspace_size(m, n);
    RowMat N(n, k);
    VectorXd S(k);
    for (int it = 0; it < count; it++) {
        int r = n - k; // rank
        MatrixXd A = rand_mat(m, std::min(r, m)) * rand_mat(std::min(r, m), n);
        RowMat Ar = A;
        int st = sfm_nullspace(Ar.data(), m, n, k, N.data(), S.data(), ws(wsz), wsz);
        w.count++;
        if (st != SFM_OK) {
            w.errors++;
            continue;
        }
        MatrixXd Nm = N;
        w.res((A * Nm).norm() / A.norm());
        w.ort(orth_err(Nm));
        Eigen::JacobiSVD<MatrixXd> es(A, Eigen::ComputeFullV);
        MatrixXd Ne = es.matrixV().rightCols(k);
        w.dif((Nm * Nm.transpose() - Ne * Ne.transpose()).cwiseAbs().maxCoeff());
    }
    report("nullspace", "rank n-k", dims(m, n) + "," + std::to_string(k), w, 1e-13, 1e-13, 1e-10,
           "JacobiSVD V");
}

} // namespace

int main()
{
    std::printf("libsfm linear algebra vs Eigen %d.%d.%d (relative errors; worst over all matrices)\n",
                EIGEN_WORLD_VERSION, EIGEN_MAJOR_VERSION, EIGEN_MINOR_VERSION);
    const int square[] = {3, 4, 5, 6, 7, 8, 9, 10, 12, 15, 20, 27};
    for (int n : square)
        svd_case(WELL, n, n, n <= 10 ? 3000 : 1000, 1000000);
    svd_case(WELL, 100, 9, 1000, 1000000);
    svd_case(WELL, 400, 27, 200, 20);
    svd_case(WELL, 5, 9, 2000, 1000000);
    svd_case(WELL, 8, 9, 2000, 1000000);
    svd_case(WELL, 9, 27, 500, 1000000);
    for (int n : {3, 9, 27})
        svd_case(COND1E10, n, n, n <= 9 ? 2000 : 500, 1000000);
    svd_case(COND1E10, 100, 9, 500, 1000000);
    svd_case(COND1E10, 400, 27, 100, 10);
    for (int n : {3, 9, 27})
        svd_case(RANKDEF, n, n, n <= 9 ? 2000 : 500, 1000000);
    svd_case(RANKDEF, 100, 9, 500, 1000000);
    svd_case(RANKDEF, 400, 27, 100, 10);
    for (int n : {3, 9, 27})
        svd_case(REPEATED, n, n, n <= 9 ? 2000 : 500, 1000000);
    svd_case(REPEATED, 100, 9, 500, 1000000);

    for (int n : square)
        sym_case(n, n <= 10 ? 2000 : 1000, false, false);
    for (int n : {3, 9, 27}) {
        sym_case(n, 1000, true, false);
        sym_case(n, 1000, false, true);
    }
    for (int n : square)
        eig_case(n, n <= 10 ? 2000 : 1000, false);
    for (int n : {3, 6, 10})
        eig_case(n, 2000, true);
    for (int n : square)
        qr_case(n, n, 1000);
    qr_case(100, 9, 1000);
    qr_case(400, 27, 100);
    for (int n : square)
        llt_case(n, 1000);
    for (int n : square)
        lu_case(n, 1000);
    null_case(8, 9, 1, 2000);
    null_case(7, 9, 2, 2000);
    null_case(5, 9, 4, 2000);
    null_case(100, 9, 1, 1000);
    null_case(9, 9, 3, 2000);
    std::printf("%d passed, %d failed\n", g_pass, g_fail);
    return g_fail ? 1 : 0;
}
