"""Linear algebra binding against numpy.linalg / scipy.linalg on the same inputs."""
import numpy as np
import pytest
import scipy.linalg

import libsfm
from libsfm import SfmError
from libsfm import linalg as la

SHAPES = [(1, 1), (3, 3), (9, 9), (27, 27), (100, 9), (5, 9), (8, 9), (12, 7)]


@pytest.mark.parametrize("shape", SHAPES)
def test_svd_matches_numpy(shape):
    rng = np.random.default_rng(sum(shape))
    for _ in range(20):
        A = rng.uniform(-1, 1, size=shape)
        U, S, V = la.svd(A)
        Sn = np.linalg.svd(A, compute_uv=False)
        assert np.allclose(S, Sn, rtol=0, atol=1e-13 * Sn[0])
        p = min(shape)
        assert np.allclose(U[:, :p] * S @ V[:, :p].T, A, atol=1e-13)
        assert np.allclose(U.T @ U, np.eye(shape[0]), atol=1e-13)
        assert np.allclose(V.T @ V, np.eye(shape[1]), atol=1e-13)
        assert np.array_equal(la.svd(A, compute_uv=False), S)


def test_svd_rank_deficient_and_ill_conditioned():
    rng = np.random.default_rng(3)
    A = rng.normal(size=(9, 4)) @ rng.normal(size=(4, 9))
    S = la.svd(A, compute_uv=False)
    Sn = np.linalg.svd(A, compute_uv=False)
    assert np.allclose(S, Sn, atol=1e-13 * Sn[0])
    assert np.all(S[4:] < 1e-13 * S[0])
    Q1, _ = np.linalg.qr(rng.normal(size=(9, 9)))
    Q2, _ = np.linalg.qr(rng.normal(size=(9, 9)))
    s = np.logspace(0, -10, 9)
    A = Q1 * s @ Q2.T
    assert np.allclose(la.svd(A, compute_uv=False), s, rtol=0, atol=1e-14)


@pytest.mark.parametrize("n", [1, 2, 3, 9, 27])
def test_sym_eig_matches_scipy(n):
    rng = np.random.default_rng(n)
    B = rng.normal(size=(n, n))
    A = B + B.T
    w, V = la.sym_eig(A)
    we = scipy.linalg.eigh(A, eigvals_only=True)
    assert np.allclose(w, we, atol=1e-13 * max(1, abs(we).max()))
    assert np.allclose(A @ V, V * w, atol=1e-12)
    assert np.allclose(V.T @ V, np.eye(n), atol=1e-13)
    # only the lower triangle is read
    Al = np.tril(A) + np.triu(np.full((n, n), np.nan), 1)
    assert np.array_equal(la.sym_eig(Al, eigvals_only=True), w)


@pytest.mark.parametrize("n", [1, 2, 3, 6, 10, 20])
def test_eig_matches_numpy(n):
    rng = np.random.default_rng(100 + n)
    for _ in range(10):
        A = rng.normal(size=(n, n))
        w, V = la.eig(A)
        wn = np.linalg.eigvals(A)
        # same multiset of eigenvalues
        for z in wn:
            assert np.min(np.abs(w - z)) < 1e-10 * max(1, np.abs(wn).max())
        assert np.allclose(A @ V, V * w, atol=1e-12 * np.linalg.norm(A))
        assert np.allclose(np.linalg.norm(V, axis=0), 1, atol=1e-13)
        # ordering: descending real part; conjugate pairs adjacent, +imag first
        assert np.all(np.diff(w.real) <= 1e-15)
        k = 0
        while k < n:
            if w[k].imag > 0:
                assert w[k + 1] == np.conj(w[k])
                k += 2
            else:
                assert w[k].imag == 0
                k += 1
        # the same eigenvectors as LAPACK's dgeev up to a unit complex factor
        wl, Vl = np.linalg.eig(A)
        for j in range(n):
            i = np.argmin(np.abs(w - wl[j]))
            gap = np.sort(np.abs(w - w[i]))[1] if n > 1 else 1.0
            if gap > 1e-3:
                assert abs(abs(np.vdot(V[:, i], Vl[:, j])) - 1) < 1e-9


def test_eig_raw_layout_and_known_values():
    R = np.array([[0.0, -1.0], [1.0, 0.0]])
    wr, wi, V = la.eig(R, raw=True)
    assert np.allclose(wr, 0) and np.allclose(wi, [1, -1])
    v = V[:, 0] + 1j * V[:, 1]
    assert np.allclose(R @ v, 1j * v)
    C = np.array([[6.0, -11.0, 6.0], [1, 0, 0], [0, 1, 0]])  # roots 3, 2, 1
    assert np.allclose(la.eig(C, eigvals_only=True), [3, 2, 1], atol=1e-13)


@pytest.mark.parametrize("shape,k", [((8, 9), 1), ((7, 9), 2), ((5, 9), 4), ((100, 9), 1)])
def test_nullspace_matches_scipy(shape, k):
    rng = np.random.default_rng(k)
    m, n = shape
    r = n - k
    A = rng.normal(size=(m, min(r, m))) @ rng.normal(size=(min(r, m), n))
    N, S = la.nullspace(A, k)
    Ns = scipy.linalg.null_space(A, rcond=1e-10)
    assert Ns.shape[1] == k
    assert np.allclose(N @ N.T, Ns @ Ns.T, atol=1e-10)
    assert np.allclose(A @ N, 0, atol=1e-12)
    assert np.all(S < 1e-12 * np.linalg.norm(A))


@pytest.mark.parametrize("n", [1, 3, 9, 27])
def test_lu_cholesky_qr_match_scipy(n):
    rng = np.random.default_rng(7 * n)
    A = rng.normal(size=(n, n)) + n * np.eye(n)
    B = rng.normal(size=(n, 3))
    assert np.allclose(la.lu_solve(A, B), scipy.linalg.solve(A, B), atol=1e-12)
    assert np.allclose(la.lu_solve(A, B[:, 0]), np.linalg.solve(A, B[:, 0]), atol=1e-12)
    LU, piv = la.lu_factor(A)
    lu_s, piv_s = scipy.linalg.lu_factor(A)
    assert np.allclose(LU, lu_s, atol=1e-13) and np.array_equal(piv, piv_s)
    S = A @ A.T
    L = la.cholesky(S)
    assert np.allclose(L, np.linalg.cholesky(S), atol=1e-12 * np.abs(S).max())
    assert np.allclose(la.cholesky_solve(L, B), scipy.linalg.solve(S, B, assume_a="pos"), atol=1e-10)
    M = rng.normal(size=(n + 4, n))
    Q, R = la.qr(M)
    Qn, Rn = np.linalg.qr(M, mode="complete")
    assert np.allclose(np.abs(R), np.abs(Rn), atol=1e-13)
    assert np.allclose(Q @ R, M, atol=1e-13)
    b = rng.normal(size=n + 4)
    assert np.allclose(la.lstsq(M, b), np.linalg.lstsq(M, b, rcond=None)[0], atol=1e-12)


def test_errors():
    with pytest.raises(ValueError):
        la.svd(np.zeros(3))
    with pytest.raises(ValueError):
        la.eig(np.zeros((2, 3)))
    with pytest.raises(ValueError):
        la.nullspace(np.eye(3), 4)
    with pytest.raises(ValueError):
        la.qr(np.zeros((2, 3)))
    with pytest.raises(ValueError):
        la.lu_solve(np.eye(3), np.zeros(4))
    A = np.eye(3)
    A[1, 1] = np.nan
    with pytest.raises(SfmError) as e:
        la.svd(A)
    assert e.value.status == libsfm.lib.SFM_E_NONFINITE
    with pytest.raises(SfmError) as e:
        la.cholesky(-np.eye(2))
    assert e.value.status == libsfm.lib.SFM_E_SINGULAR
    with pytest.raises(SfmError):
        la.lu_factor(np.zeros((2, 2)))
    assert libsfm.linalg is la
