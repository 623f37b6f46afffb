"""Small dense linear algebra (sfm_linalg.h): numpy in, numpy out.

Matrices are float64, row-major as numpy holds them. Shapes are checked
before any C call (ValueError); a negative C status raises SfmError.
"""
import numpy as np

from ._ffi import as_array, check, dptr, ffi, iptr, lib, to_int, workspace

__all__ = ["svd", "sym_eig", "eig", "nullspace", "lu_factor", "lu_solve", "cholesky",
           "cholesky_solve", "qr", "lstsq"]


def _matrix(A, name="A", square=False):
    A = as_array(A, (None, None), name)
    m, n = A.shape
    if m < 1 or n < 1:
        raise ValueError("%s must be non-empty, got shape %s" % (name, A.shape))
    if square and m != n:
        raise ValueError("%s must be square, got shape %s" % (name, A.shape))
    return A


def svd(A, compute_uv=True):
    """A = U @ diag(S) @ V.T with full U (m,m) and V (n,n), S descending.

    Returns (U, S, V) (note V, not V.T as numpy returns), or S alone when
    compute_uv is False."""
    A = _matrix(A)
    m, n = A.shape
    S = np.empty(min(m, n))
    U = np.empty((m, m)) if compute_uv else None
    V = np.empty((n, n)) if compute_uv else None
    buf, ws, size = workspace(lib.sfm_svd_workspace_size(m, n))
    check(lib.sfm_svd(dptr(A), m, n, dptr(U) if compute_uv else ffi.NULL, dptr(S),
                      dptr(V) if compute_uv else ffi.NULL, ws, size), "sfm_svd", {"A": A})
    return (U, S, V) if compute_uv else S


def sym_eig(A, eigvals_only=False):
    """Symmetric eigendecomposition from the lower triangle of A.

    Returns (w ascending, V with orthonormal eigenvectors as columns), or w."""
    A = _matrix(A, square=True)
    n = A.shape[0]
    w = np.empty(n)
    V = None if eigvals_only else np.empty((n, n))
    buf, ws, size = workspace(lib.sfm_sym_eig_workspace_size(n))
    check(lib.sfm_sym_eig(dptr(A), n, dptr(w), ffi.NULL if V is None else dptr(V), ws, size),
          "sfm_sym_eig", {"A": A})
    return w if eigvals_only else (w, V)


def eig(A, eigvals_only=False, raw=False):
    """Eigenvalues and eigenvectors of a real square matrix.

    Returns (w complex (n,), V complex (n,n)) with A @ V[:, k] = w[k] V[:, k],
    unit-norm columns, ordered by descending real part then imaginary part.
    With raw=True returns libsfm's real layout (wr, wi, V): a conjugate pair
    (k, k+1) stores the real and imaginary parts of the eigenvector of
    wr[k] + i wi[k] in columns k and k+1."""
    A = _matrix(A, square=True)
    n = A.shape[0]
    wr = np.empty(n)
    wi = np.empty(n)
    want_v = not eigvals_only
    V = np.empty((n, n)) if want_v else None
    buf, ws, size = workspace(lib.sfm_eig_workspace_size(n))
    check(lib.sfm_eig(dptr(A), n, dptr(wr), dptr(wi), dptr(V) if want_v else ffi.NULL, ws, size),
          "sfm_eig", {"A": A})
    if raw:
        return (wr, wi, V) if want_v else (wr, wi)
    w = wr + 1j * wi
    if not want_v:
        return w
    Vc = V.astype(np.complex128)
    k = 0
    while k < n:
        if wi[k] > 0 and k + 1 < n:
            Vc[:, k] = V[:, k] + 1j * V[:, k + 1]
            Vc[:, k + 1] = V[:, k] - 1j * V[:, k + 1]
            k += 2
        else:
            k += 1
    return w, Vc


def nullspace(A, k=1):
    """The k right singular vectors of A with the smallest singular values.

    Returns (N (n,k), S (k,)), smallest first."""
    A = _matrix(A)
    m, n = A.shape
    k = to_int(k, "k", 1, n)
    N = np.empty((n, k))
    S = np.empty(k)
    buf, ws, size = workspace(lib.sfm_nullspace_workspace_size(m, n))
    check(lib.sfm_nullspace(dptr(A), m, n, k, dptr(N), dptr(S), ws, size), "sfm_nullspace", {"A": A})
    return N, S


def lu_factor(A):
    """LU with partial pivoting: returns (LU (n,n), piv (n,) int32), L unit
    lower below the diagonal, piv[i] = row swapped with row i at step i."""
    A = _matrix(A, square=True)
    n = A.shape[0]
    LU = A.copy()
    piv = np.empty(n, dtype=np.int32)
    check(lib.sfm_lu_factor(dptr(LU), n, iptr(piv)), "sfm_lu_factor", {"A": A})
    return LU, piv


def _rhs(B, n):
    """(X, vec): a writable (n, k) float64 copy of the right-hand side B, of
    shape (n,) or (n, k) with k >= 1, and whether B was a vector."""
    Barr = np.asarray(B, dtype=np.float64)
    vec = Barr.ndim == 1
    X = as_array(Barr.reshape(-1, 1) if vec else Barr, (n, None), "B").copy()
    if X.shape[1] < 1:
        raise ValueError("B must have at least one column")
    return X, vec


def lu_solve(A, B):
    """X with A X = B (B of shape (n,) or (n, k)) by LU with partial pivoting."""
    A = _matrix(A, square=True)
    n = A.shape[0]
    X, vec = _rhs(B, n)
    LU, piv = lu_factor(A)
    check(lib.sfm_lu_solve(dptr(LU), iptr(piv), n, dptr(X), X.shape[1]), "sfm_lu_solve", {"B": X})
    return X[:, 0] if vec else X


def cholesky(A):
    """Lower-triangular L (n, n) with A = L L^T for a symmetric positive
    definite A (n, n) (only its lower triangle is read)."""
    A = _matrix(A, square=True)
    L = A.copy()
    check(lib.sfm_cholesky_factor(dptr(L), A.shape[0]), "sfm_cholesky_factor", {"A": A})
    return L


def cholesky_solve(L, B):
    """X with L L^T X = B: L (n, n) from cholesky(), B (n,) or (n, k); X has
    B's shape."""
    L = _matrix(L, "L", square=True)
    n = L.shape[0]
    X, vec = _rhs(B, n)
    check(lib.sfm_cholesky_solve(dptr(L), n, dptr(X), X.shape[1]), "sfm_cholesky_solve", {"L": L, "B": X})
    return X[:, 0] if vec else X


def qr(A):
    """Householder QR of an (m, n) matrix with m >= n: returns (Q (m,m), R (m,n))."""
    A = _matrix(A)
    m, n = A.shape
    if m < n:
        raise ValueError("qr needs rows >= columns, got shape %s" % (A.shape,))
    F = A.copy()
    tau = np.empty(n)
    check(lib.sfm_qr_factor(dptr(F), m, n, dptr(tau)), "sfm_qr_factor", {"A": A})
    Q = np.empty((m, m))
    check(lib.sfm_qr_form_q(dptr(F), dptr(tau), m, n, dptr(Q)), "sfm_qr_form_q")
    return Q, np.triu(F)


def lstsq(A, b):
    """x minimizing |A x - b| for an (m, n) A with m >= n and full column rank."""
    A = _matrix(A)
    m, n = A.shape
    if m < n:
        raise ValueError("lstsq needs rows >= columns, got shape %s" % (A.shape,))
    x = as_array(b, (m,), "b").copy()
    F = A.copy()
    tau = np.empty(n)
    check(lib.sfm_qr_factor(dptr(F), m, n, dptr(tau)), "sfm_qr_factor", {"A": A})
    check(lib.sfm_qr_solve(dptr(F), dptr(tau), m, n, dptr(x)), "sfm_qr_solve", {"b": x})
    return x[:n].copy()
