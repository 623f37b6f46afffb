// Linear algebra benchmark: libsfm beside Eigen on the same matrices, in one
// process run. Microseconds per call (best of 5 timed batches) and, when run
// with --callgrind CASE IMPL under valgrind --tool=callgrind, the instruction
// count of exactly CALLS calls of one implementation (the make target divides).
//
// Cases: SVD 3x3, 9x9, 27x27 (full U, S, V; Eigen JacobiSVD with full U and
// V, fixed-size types where Eigen has them; BDCSVD for 27x27 too) and the
// 10x10 real nonsymmetric eigenproblem with vectors (Eigen EigenSolver).
#include <Eigen/Dense>
#include <Eigen/Eigenvalues>
#include <Eigen/SVD>

#include <chrono>
#include <cstdio>
#include <cstring>
#include <functional>
#include <memory>
#include <random>
#include <string>
#include <vector>

#if defined(__has_include)
#if __has_include(<valgrind/callgrind.h>)
#include <valgrind/callgrind.h>
#define HAVE_CALLGRIND 1
#endif
#endif
#ifndef HAVE_CALLGRIND
#define CALLGRIND_TOGGLE_COLLECT
#endif

#include "sfm/sfm.h"

namespace {

constexpr int kMatrices = 64;    // distinct inputs, cycled
constexpr int kCgCalls = 1000;   // calls measured under callgrind

volatile double g_sink;

template <int M, int N>
std::vector<Eigen::Matrix<double, M, N, Eigen::RowMajor>> inputs(int m, int n, unsigned seed)
{
    std::mt19937_64 rng(seed);
    std::uniform_real_distribution<double> u(-1, 1);
    std::vector<Eigen::Matrix<double, M, N, Eigen::RowMajor>> v(kMatrices);
    for (auto &A : v) {
        A.resize(m, n);
        for (int i = 0; i < m; i++)
            for (int j = 0; j < n; j++)
                A(i, j) = u(rng);
    }
    return v;
}

template <class F>
double usec_per_call(F &&f)
{
    using clk = std::chrono::steady_clock;
    // calibrate: enough calls for ~40 ms per batch
    long calls = 16;
    for (;;) {
        auto t0 = clk::now();
        for (long i = 0; i < calls; i++)
            f(static_cast<int>(i % kMatrices));
        double s = std::chrono::duration<double>(clk::now() - t0).count();
        if (s > 0.04)
            break;
        calls *= 2;
    }
    double best = 1e300;
    for (int rep = 0; rep < 5; rep++) {
        auto t0 = clk::now();
        for (long i = 0; i < calls; i++)
            f(static_cast<int>(i % kMatrices));
        double s = std::chrono::duration<double>(clk::now() - t0).count();
        best = std::min(best, s / calls * 1e6);
    }
    return best;
}

struct Case {
    std::string name, impl;
    std::function<void(int)> fn;
};

std::vector<unsigned char> g_ws(1 << 20);

template <int N>
void add_svd(std::vector<Case> &cases, const char *name)
{
    using Fixed = Eigen::Matrix<double, N, N>;
    auto A = std::make_shared<std::vector<Eigen::Matrix<double, N, N, Eigen::RowMajor>>>(
        inputs<N, N>(N, N, 1000 + N));
    auto out = std::make_shared<std::vector<double>>(3 * N * N);
    const size_t wsz = sfm_svd_workspace_size(N, N);
    cases.push_back({name, "libsfm", [A, out, wsz](int i) {
                         double *U = out->data(), *S = U + N * N, *V = S + N * N;
                         sfm_svd((*A)[i].data(), N, N, U, S, V, g_ws.data(), wsz);
                         g_sink = S[N - 1] + U[0] + V[0];
                     }});
    cases.push_back({name, "Eigen JacobiSVD", [A](int i) {
                         Fixed M = (*A)[i];
                         Eigen::JacobiSVD<Fixed> svd(M, Eigen::ComputeFullU | Eigen::ComputeFullV);
                         g_sink = svd.singularValues()[N - 1] + svd.matrixU()(0, 0) + svd.matrixV()(0, 0);
                     }});
    if (N >= 27)
        cases.push_back({name, "Eigen BDCSVD", [A](int i) {
                             Eigen::MatrixXd M = (*A)[i];
                             Eigen::BDCSVD<Eigen::MatrixXd> svd(M, Eigen::ComputeFullU | Eigen::ComputeFullV);
                             g_sink = svd.singularValues()[N - 1] + svd.matrixU()(0, 0) + svd.matrixV()(0, 0);
                         }});
}

void add_eig10(std::vector<Case> &cases)
{
    constexpr int N = 10;
    using Fixed = Eigen::Matrix<double, N, N>;
    auto A = std::make_shared<std::vector<Eigen::Matrix<double, N, N, Eigen::RowMajor>>>(
        inputs<N, N>(N, N, 77));
    auto out = std::make_shared<std::vector<double>>(N * N + 2 * N);
    const size_t wsz = sfm_eig_workspace_size(N);
    cases.push_back({"eig 10x10", "libsfm", [A, out, wsz](int i) {
                         double *V = out->data(), *wr = V + N * N, *wi = wr + N;
                         sfm_eig((*A)[i].data(), N, wr, wi, V, g_ws.data(), wsz);
                         g_sink = wr[0] + V[0];
                     }});
    cases.push_back({"eig 10x10", "Eigen EigenSolver", [A](int i) {
                         Fixed M = (*A)[i];
                         Eigen::EigenSolver<Fixed> es(M, true);
                         g_sink = es.eigenvalues()[0].real() + es.eigenvectors()(0, 0).real();
                     }});
}

} // namespace

int main(int argc, char **argv)
{
    std::vector<Case> cases;
    add_svd<3>(cases, "svd 3x3");
    add_svd<9>(cases, "svd 9x9");
    add_svd<27>(cases, "svd 27x27");
    add_eig10(cases);

    if (argc == 4 && std::strcmp(argv[1], "--callgrind") == 0) {
        for (auto &c : cases)
            if (c.name == argv[2] && c.impl == argv[3]) {
                c.fn(0); // warm up outside the measured region
                CALLGRIND_TOGGLE_COLLECT;
                for (int i = 0; i < kCgCalls; i++)
                    c.fn(i % kMatrices);
                CALLGRIND_TOGGLE_COLLECT;
                std::printf("%d\n", kCgCalls);
                return 0;
            }
        std::fprintf(stderr, "no case %s / %s\n", argv[2], argv[3]);
        return 2;
    }
    if (argc == 2 && std::strcmp(argv[1], "--list") == 0) {
        for (auto &c : cases)
            std::printf("%s|%s\n", c.name.c_str(), c.impl.c_str());
        return 0;
    }

    std::printf("linalg bench: us per call, best of 5 batches, %d distinct random inputs cycled\n",
                kMatrices);
    std::printf("ratio = this row / libsfm on the same inputs (above 1: libsfm is faster)\n");
    std::printf("%-10s %-18s %10s %10s\n", "case", "impl", "us/call", "ratio");
    double base = 0;
    for (auto &c : cases) {
        double us = usec_per_call(c.fn);
        if (c.impl == "libsfm")
            base = us;
        std::printf("%-10s %-18s %10.3f %10.2f\n", c.name.c_str(), c.impl.c_str(), us,
                    c.impl == "libsfm" ? 1.0 : us / base);
    }
    return 0;
}
