/*
 * libsfm <-> Eigen interop for C++ robot code. Header-only; needs Eigen 3.4
 * and C++17. Nothing here is compiled into libsfm.
 *
 *  - Views (no copies): sfm::eigen::map(x) gives an Eigen::Map onto an sfm
 *    struct (vec2/vec3 as column vectors; mat3, mat34 and a pose's R as
 *    row-major matrices, the layout libsfm uses), map_rows(p, n) views an
 *    array of n sfm_vec2/sfm_vec3 as an n x 2 / n x 3 row-major matrix, and
 *    map_matrix(data, rows, cols) views any row-major double buffer.
 *    Writing through a view writes the sfm struct.
 *  - Conversions by value: to_sfm_* from Eigen types, to_isometry/from_isometry
 *    for poses (x_cam = R * X_world + t, world-to-camera).
 *  - Thin wrappers around the linear algebra returning Eigen types: svd,
 *    sym_eig, eig, nullspace, lu_solve, cholesky, qr. They allocate the
 *    workspace on the heap (std::vector) and report the libsfm status in
 *    the result's `status` (SFM_OK on success; the other members are then
 *    empty), so they work with exceptions disabled.
 */
#ifndef SFM_EIGEN_HPP
#define SFM_EIGEN_HPP

#include <Eigen/Core>
#include <Eigen/Geometry>

#include <complex>
#include <cstddef>
#include <vector>

#include "sfm/sfm.h"

namespace sfm {
namespace eigen {

static_assert(sizeof(sfm_vec2) == 2 * sizeof(double), "sfm_vec2 must be two packed doubles");
static_assert(sizeof(sfm_vec3) == 3 * sizeof(double), "sfm_vec3 must be three packed doubles");
static_assert(sizeof(sfm_mat3) == 9 * sizeof(double), "sfm_mat3 must be nine packed doubles");
static_assert(sizeof(sfm_mat34) == 12 * sizeof(double), "sfm_mat34 must be twelve packed doubles");

using RowMatrix3d = Eigen::Matrix<double, 3, 3, Eigen::RowMajor>;
using RowMatrix34d = Eigen::Matrix<double, 3, 4, Eigen::RowMajor>;
using RowMatrixXd = Eigen::Matrix<double, Eigen::Dynamic, Eigen::Dynamic, Eigen::RowMajor>;
using RowMatrixX2d = Eigen::Matrix<double, Eigen::Dynamic, 2, Eigen::RowMajor>;
using RowMatrixX3d = Eigen::Matrix<double, Eigen::Dynamic, 3, Eigen::RowMajor>;

// ---- views ---------------------------------------------------------------
inline Eigen::Map<Eigen::Vector2d> map(sfm_vec2 &v) { return Eigen::Map<Eigen::Vector2d>(v.v); }
inline Eigen::Map<const Eigen::Vector2d> map(const sfm_vec2 &v)
{
    return Eigen::Map<const Eigen::Vector2d>(v.v);
}
inline Eigen::Map<Eigen::Vector3d> map(sfm_vec3 &v) { return Eigen::Map<Eigen::Vector3d>(v.v); }
inline Eigen::Map<const Eigen::Vector3d> map(const sfm_vec3 &v)
{
    return Eigen::Map<const Eigen::Vector3d>(v.v);
}
inline Eigen::Map<RowMatrix3d> map(sfm_mat3 &m) { return Eigen::Map<RowMatrix3d>(m.m); }
inline Eigen::Map<const RowMatrix3d> map(const sfm_mat3 &m)
{
    return Eigen::Map<const RowMatrix3d>(m.m);
}
inline Eigen::Map<RowMatrix34d> map(sfm_mat34 &m) { return Eigen::Map<RowMatrix34d>(m.m); }
inline Eigen::Map<const RowMatrix34d> map(const sfm_mat34 &m)
{
    return Eigen::Map<const RowMatrix34d>(m.m);
}
/* A pose's rotation and translation (x_cam = R * X_world + t). */
inline Eigen::Map<RowMatrix3d> map_R(sfm_pose &p) { return Eigen::Map<RowMatrix3d>(p.R); }
inline Eigen::Map<const RowMatrix3d> map_R(const sfm_pose &p)
{
    return Eigen::Map<const RowMatrix3d>(p.R);
}
inline Eigen::Map<Eigen::Vector3d> map_t(sfm_pose &p) { return Eigen::Map<Eigen::Vector3d>(p.t); }
inline Eigen::Map<const Eigen::Vector3d> map_t(const sfm_pose &p)
{
    return Eigen::Map<const Eigen::Vector3d>(p.t);
}

/* n points as the rows of an n x 2 / n x 3 matrix. */
inline Eigen::Map<RowMatrixX2d> map_rows(sfm_vec2 *p, Eigen::Index n)
{
    return Eigen::Map<RowMatrixX2d>(p[0].v, n, 2);
}
inline Eigen::Map<const RowMatrixX2d> map_rows(const sfm_vec2 *p, Eigen::Index n)
{
    return Eigen::Map<const RowMatrixX2d>(p[0].v, n, 2);
}
inline Eigen::Map<RowMatrixX3d> map_rows(sfm_vec3 *p, Eigen::Index n)
{
    return Eigen::Map<RowMatrixX3d>(p[0].v, n, 3);
}
inline Eigen::Map<const RowMatrixX3d> map_rows(const sfm_vec3 *p, Eigen::Index n)
{
    return Eigen::Map<const RowMatrixX3d>(p[0].v, n, 3);
}

/* Any row-major buffer, as libsfm's functions take them. */
inline Eigen::Map<RowMatrixXd> map_matrix(double *data, Eigen::Index rows, Eigen::Index cols)
{
    return Eigen::Map<RowMatrixXd>(data, rows, cols);
}
inline Eigen::Map<const RowMatrixXd> map_matrix(const double *data, Eigen::Index rows,
                                                Eigen::Index cols)
{
    return Eigen::Map<const RowMatrixXd>(data, rows, cols);
}

// ---- conversions ---------------------------------------------------------
inline sfm_vec2 to_sfm_vec2(const Eigen::Vector2d &v) { return sfm_vec2{{v[0], v[1]}}; }
inline sfm_vec3 to_sfm_vec3(const Eigen::Vector3d &v) { return sfm_vec3{{v[0], v[1], v[2]}}; }
inline sfm_mat3 to_sfm_mat3(const Eigen::Matrix3d &m)
{
    sfm_mat3 r;
    map(r) = m;
    return r;
}
inline sfm_mat34 to_sfm_mat34(const Eigen::Matrix<double, 3, 4> &m)
{
    sfm_mat34 r;
    map(r) = m;
    return r;
}
/* World-to-camera pose as an isometry: x_cam = T * X_world. */
inline Eigen::Isometry3d to_isometry(const sfm_pose &p)
{
    Eigen::Isometry3d T = Eigen::Isometry3d::Identity();
    T.linear() = map_R(p);
    T.translation() = map_t(p);
    return T;
}
inline sfm_pose from_isometry(const Eigen::Isometry3d &T)
{
    sfm_pose p;
    map_R(p) = T.linear();
    map_t(p) = T.translation();
    return p;
}

// ---- linear algebra wrappers ---------------------------------------------
namespace detail {
inline RowMatrixXd row_major(const Eigen::Ref<const Eigen::MatrixXd> &A) { return RowMatrixXd(A); }
inline int dim(Eigen::Index n) { return n > SFM_LINALG_MAX_DIM ? -1 : static_cast<int>(n); }
} // namespace detail

struct SVD {
    int status = SFM_E_ARGUMENT;
    Eigen::MatrixXd U;  // m x m (empty when not requested)
    Eigen::VectorXd S;  // min(m, n), descending
    Eigen::MatrixXd V;  // n x n (empty when not requested)
    bool ok() const { return status == SFM_OK; }
};

/* A = U diag(S) V^T (full U and V). */
inline SVD svd(const Eigen::Ref<const Eigen::MatrixXd> &A, bool want_u = true, bool want_v = true)
{
    SVD r;
    const int m = detail::dim(A.rows()), n = detail::dim(A.cols());
    const size_t wsz = sfm_svd_workspace_size(m, n);
    if (wsz == 0)
        return r;
    RowMatrixXd a = detail::row_major(A), u(want_u ? m : 0, want_u ? m : 0),
                v(want_v ? n : 0, want_v ? n : 0);
    Eigen::VectorXd s(m < n ? m : n);
    std::vector<unsigned char> ws(wsz);
    r.status = sfm_svd(a.data(), m, n, want_u ? u.data() : nullptr, s.data(),
                       want_v ? v.data() : nullptr, ws.data(), ws.size());
    if (r.status == SFM_OK) {
        r.U = u;
        r.S = s;
        r.V = v;
    }
    return r;
}

struct SymEig {
    int status = SFM_E_ARGUMENT;
    Eigen::VectorXd values;   // ascending
    Eigen::MatrixXd vectors;  // orthonormal columns
    bool ok() const { return status == SFM_OK; }
};

/* Symmetric eigendecomposition; only the lower triangle of A is read. */
inline SymEig sym_eig(const Eigen::Ref<const Eigen::MatrixXd> &A, bool want_vectors = true)
{
    SymEig r;
    const int n = detail::dim(A.rows());
    if (A.rows() != A.cols())
        return r;
    const size_t wsz = sfm_sym_eig_workspace_size(n);
    if (wsz == 0)
        return r;
    RowMatrixXd a = detail::row_major(A), v(want_vectors ? n : 0, want_vectors ? n : 0);
    Eigen::VectorXd w(n);
    std::vector<unsigned char> ws(wsz);
    r.status = sfm_sym_eig(a.data(), n, w.data(), want_vectors ? v.data() : nullptr, ws.data(),
                           ws.size());
    if (r.status == SFM_OK) {
        r.values = w;
        r.vectors = v;
    }
    return r;
}

struct Eig {
    int status = SFM_E_ARGUMENT;
    Eigen::VectorXcd values;   // descending real part, then imaginary part
    Eigen::MatrixXcd vectors;  // unit-norm complex eigenvectors as columns
    bool ok() const { return status == SFM_OK; }
};

/* Real nonsymmetric eigenproblem, unpacked from libsfm's LAPACK-style layout
 * into complex eigenvectors (column k belongs to values[k]). */
inline Eig eig(const Eigen::Ref<const Eigen::MatrixXd> &A, bool want_vectors = true)
{
    Eig r;
    const int n = detail::dim(A.rows());
    if (A.rows() != A.cols())
        return r;
    const size_t wsz = sfm_eig_workspace_size(n);
    if (wsz == 0)
        return r;
    RowMatrixXd a = detail::row_major(A), v(want_vectors ? n : 0, want_vectors ? n : 0);
    Eigen::VectorXd wr(n), wi(n);
    std::vector<unsigned char> ws(wsz);
    r.status = sfm_eig(a.data(), n, wr.data(), wi.data(), want_vectors ? v.data() : nullptr,
                       ws.data(), ws.size());
    if (r.status != SFM_OK)
        return r;
    r.values.resize(n);
    for (int k = 0; k < n; k++)
        r.values[k] = std::complex<double>(wr[k], wi[k]);
    if (!want_vectors)
        return r;
    r.vectors.resize(n, n);
    for (int k = 0; k < n; k++) {
        if (wi[k] > 0.0 && k + 1 < n) {
            for (int i = 0; i < n; i++) {
                r.vectors(i, k) = std::complex<double>(v(i, k), v(i, k + 1));
                r.vectors(i, k + 1) = std::complex<double>(v(i, k), -v(i, k + 1));
            }
            k++;
        } else {
            for (int i = 0; i < n; i++)
                r.vectors(i, k) = v(i, k);
        }
    }
    return r;
}

struct Nullspace {
    int status = SFM_E_ARGUMENT;
    Eigen::MatrixXd N;  // n x k, smallest singular value first
    Eigen::VectorXd S;  // the k singular values
    bool ok() const { return status == SFM_OK; }
};

inline Nullspace nullspace(const Eigen::Ref<const Eigen::MatrixXd> &A, int k)
{
    Nullspace r;
    const int m = detail::dim(A.rows()), n = detail::dim(A.cols());
    const size_t wsz = sfm_nullspace_workspace_size(m, n);
    if (wsz == 0 || k < 1 || k > n)
        return r;
    RowMatrixXd a = detail::row_major(A), N(n, k);
    Eigen::VectorXd s(k);
    std::vector<unsigned char> ws(wsz);
    r.status = sfm_nullspace(a.data(), m, n, k, N.data(), s.data(), ws.data(), ws.size());
    if (r.status == SFM_OK) {
        r.N = N;
        r.S = s;
    }
    return r;
}

struct Solve {
    int status = SFM_E_ARGUMENT;
    Eigen::MatrixXd X;
    bool ok() const { return status == SFM_OK; }
};

/* X = A^-1 B by LU with partial pivoting. */
inline Solve lu_solve(const Eigen::Ref<const Eigen::MatrixXd> &A,
                      const Eigen::Ref<const Eigen::MatrixXd> &B)
{
    Solve r;
    const int n = detail::dim(A.rows()), nrhs = detail::dim(B.cols());
    if (A.rows() != A.cols() || B.rows() != A.rows() || n < 1 || nrhs < 1)
        return r;
    RowMatrixXd lu = detail::row_major(A), x = detail::row_major(B);
    std::vector<int> piv(static_cast<size_t>(n));
    r.status = sfm_lu_factor(lu.data(), n, piv.data());
    if (r.status == SFM_OK)
        r.status = sfm_lu_solve(lu.data(), piv.data(), n, x.data(), nrhs);
    if (r.status == SFM_OK)
        r.X = x;
    return r;
}

struct Cholesky {
    int status = SFM_E_ARGUMENT;
    Eigen::MatrixXd L;  // lower triangular, A = L L^T
    bool ok() const { return status == SFM_OK; }
};

inline Cholesky cholesky(const Eigen::Ref<const Eigen::MatrixXd> &A)
{
    Cholesky r;
    const int n = detail::dim(A.rows());
    if (A.rows() != A.cols() || n < 1)
        return r;
    RowMatrixXd l = detail::row_major(A);
    r.status = sfm_cholesky_factor(l.data(), n);
    if (r.status == SFM_OK)
        r.L = l;
    return r;
}

struct QR {
    int status = SFM_E_ARGUMENT;
    Eigen::MatrixXd Q;  // m x m orthogonal
    Eigen::MatrixXd R;  // m x n upper triangular
    bool ok() const { return status == SFM_OK; }
};

/* Householder QR of an m x n matrix, m >= n. */
inline QR qr(const Eigen::Ref<const Eigen::MatrixXd> &A)
{
    QR r;
    const int m = detail::dim(A.rows()), n = detail::dim(A.cols());
    if (m < 1 || n < 1 || m < n)
        return r;
    RowMatrixXd f = detail::row_major(A), q(m, m);
    Eigen::VectorXd tau(n);
    r.status = sfm_qr_factor(f.data(), m, n, tau.data());
    if (r.status == SFM_OK)
        r.status = sfm_qr_form_q(f.data(), tau.data(), m, n, q.data());
    if (r.status == SFM_OK) {
        r.Q = q;
        r.R = Eigen::MatrixXd(f).triangularView<Eigen::Upper>();
    }
    return r;
}

} // namespace eigen
} // namespace sfm

#endif
