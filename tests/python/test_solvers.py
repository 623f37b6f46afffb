"""Solvers through the binding, against truth, PoseLib and OpenCV on the same inputs."""
import cv2
import numpy as np
import poselib
import pytest

import libsfm
from libsfm._ffi import SfmError


def _rot(rng, max_angle=np.pi):
    axis = rng.normal(size=3)
    axis /= np.linalg.norm(axis)
    a = rng.uniform(0, max_angle)
    K = np.array([[0, -axis[2], axis[1]], [axis[2], 0, -axis[0]], [-axis[1], axis[0], 0]])
    return np.eye(3) + np.sin(a) * K + (1 - np.cos(a)) * K @ K


def _skew(v):
    return np.array([[0, -v[2], v[1]], [v[2], 0, -v[0]], [-v[1], v[0], 0]])


def _unit(M):
    return M / np.linalg.norm(M)


def _dist(A, B):
    """Distance up to scale and sign."""
    A, B = _unit(A), _unit(B)
    return min(np.linalg.norm(A - B), np.linalg.norm(A + B))


def _problem(rng, n, sigma_px=0.0):
    """Two cameras, n points in front of both; pixel noise sigma_px on both images."""
    R = _rot(rng, 0.5)
    C2 = rng.normal(size=3)
    C2 /= np.linalg.norm(C2)
    t = -R @ C2
    K = np.array([[800.0, 0, 320], [0, 800.0, 240], [0, 0, 1]])
    X = np.column_stack([rng.uniform(-0.6, 0.6, n), rng.uniform(-0.45, 0.45, n), np.ones(n)])
    X *= rng.uniform(2, 10, n)[:, None]
    X2 = X @ R.T + t
    p1 = (X / X[:, 2:]) @ K.T
    p2 = (X2 / X2[:, 2:]) @ K.T
    p1 = p1[:, :2] + rng.normal(scale=sigma_px, size=(n, 2))
    p2 = p2[:, :2] + rng.normal(scale=sigma_px, size=(n, 2))
    Ki = np.linalg.inv(K)
    x1 = np.column_stack([p1, np.ones(n)]) @ Ki.T
    x2 = np.column_stack([p2, np.ones(n)]) @ Ki.T
    x1 /= np.linalg.norm(x1, axis=1)[:, None]
    x2 /= np.linalg.norm(x2, axis=1)[:, None]
    E = _unit(_skew(t) @ R)
    F = _unit(Ki.T @ E @ Ki)
    return x1, x2, p1, p2, E, F


def _plane_problem(rng, n, sigma_px=0.0):
    R = _rot(rng, 0.3)
    t = rng.normal(size=3) * 0.3
    nrm = np.array([rng.normal(0, 0.3), rng.normal(0, 0.3), 1.0])
    nrm /= np.linalg.norm(nrm)
    d = rng.uniform(3, 8)
    K = np.array([[700.0, 0, 320], [0, 700.0, 240], [0, 0, 1]])
    H = K @ (R + np.outer(t, nrm) / d) @ np.linalg.inv(K)
    uv = np.column_stack([rng.uniform(-0.5, 0.5, n), rng.uniform(-0.4, 0.4, n), np.ones(n)])
    X = uv * (d / (uv @ nrm))[:, None]
    X2 = X @ R.T + t
    p1 = ((X / X[:, 2:]) @ K.T)[:, :2] + rng.normal(scale=sigma_px, size=(n, 2))
    p2 = ((X2 / X2[:, 2:]) @ K.T)[:, :2] + rng.normal(scale=sigma_px, size=(n, 2))
    H = _unit(H) * np.sign(np.linalg.det(H))
    return p1, p2, H


def _best(sols, truth):
    return min((_dist(S, truth) for S in sols), default=np.inf)


# ---- against truth, noise-free ---------------------------------------------

def test_noise_free_truth():
    rng = np.random.default_rng(1)
    for _ in range(200):
        x1, x2, p1, p2, E, F = _problem(rng, 30)
        assert _best(libsfm.relpose_5pt(x1[:5], x2[:5]), E) < 1e-8
        assert _best(libsfm.fundamental_7pt(p1[:7], p2[:7]), F) < 1e-8
        assert _dist(libsfm.essential_8pt(x1[:8], x2[:8]), E) < 1e-8
        assert _dist(libsfm.essential_8pt(x1, x2), E) < 1e-8
        assert _dist(libsfm.fundamental_8pt(p1, p2), F) < 1e-8
        q1, q2, H = _plane_problem(rng, 20)
        H4 = libsfm.homography_4pt(q1[:4], q2[:4])
        assert np.linalg.det(H4) > 0 and np.linalg.norm(H4 - H) < 1e-8
        assert np.linalg.norm(libsfm.homography_dlt(q1, q2) - H) < 1e-8


# ---- against PoseLib, same noisy inputs ------------------------------------

def _essential_residual(E, x1, x2):
    E = _unit(E)
    epi = np.abs(np.einsum("ij,jk,ik->i", x2, E, x1)).max()
    return max(epi, np.linalg.norm(2 * E @ E.T @ E - np.trace(E @ E.T) * E))


def _fundamental_residual(F, p1, p2):
    F = _unit(F)
    a = np.column_stack([p1, np.ones(len(p1))])
    b = np.column_stack([p2, np.ones(len(p2))])
    a /= np.linalg.norm(a, axis=1)[:, None]
    b /= np.linalg.norm(b, axis=1)[:, None]
    return max(np.abs(np.einsum("ij,jk,ik->i", b, F, a)).max(), abs(np.linalg.det(F)))


def _covered(ours, theirs, residual):
    """Per oracle solution: ours has it within 1e-6, or ours has a nearby
    (within 1e-2) solution that satisfies the equations better (the two
    differ by rounding and ours is the more accurate)."""
    flags = []
    for T in theirs:
        if len(ours) == 0:
            flags.append(False)
            continue
        d = [_dist(O, T) for O in ours]
        k = int(np.argmin(d))
        flags.append(d[k] < 1e-6 or (d[k] < 1e-2 and residual(ours[k]) < residual(T)))
    return flags


def _same_solution_sets(rng, trials, n, solve):
    """Minimal problems of n points with 0.5 px noise; solve(x1, x2, p1, p2)
    gives our solutions, the reference's and the residual of a matrix on
    that sample. Both solve the same polynomial system: the same solutions
    (99.5 % covered) and the same number of them (within 2 %)."""
    flags, counts = [], [0, 0]
    for _ in range(trials):
        x1, x2, p1, p2, _, _ = _problem(rng, n, sigma_px=0.5)
        ours, theirs, residual = solve(x1, x2, p1, p2)
        counts[0] += len(ours)
        counts[1] += len(theirs)
        flags += _covered(ours, theirs, residual)
    assert np.mean(flags) > 0.995, np.mean(flags)
    assert abs(counts[0] - counts[1]) <= 0.02 * counts[1], counts


def test_relpose_5pt_same_as_poselib_with_noise():
    def solve(x1, x2, p1, p2):
        return (libsfm.relpose_5pt(x1, x2), poselib.essential_matrix_5pt(x1, x2),
                lambda M: _essential_residual(M, x1, x2))

    _same_solution_sets(np.random.default_rng(2), 500, 5, solve)


def test_essential_8pt_same_as_poselib_with_noise():
    rng = np.random.default_rng(3)
    for n in (8, 50):
        d = []
        for _ in range(200):
            x1, x2, _, _, E, _ = _problem(rng, n, sigma_px=0.5)
            ours = libsfm.essential_8pt(x1, x2)
            theirs = poselib.essential_matrix_8pt(x1, x2)
            d.append(_dist(ours, theirs))
        assert np.median(d) < 1e-8, (n, np.median(d))


# ---- against OpenCV, same noisy inputs -------------------------------------

def test_fundamental_7pt_same_as_opencv():
    def solve(x1, x2, p1, p2):
        ours = libsfm.fundamental_7pt(p1, p2)
        Fcv, _ = cv2.findFundamentalMat(p1, p2, cv2.FM_7POINT)
        theirs = [] if Fcv is None else [Fcv[3 * k:3 * k + 3] for k in range(Fcv.shape[0] // 3)]
        return ours, theirs, lambda M: _fundamental_residual(M, p1, p2)

    _same_solution_sets(np.random.default_rng(4), 300, 7, solve)


def test_fundamental_8pt_same_as_opencv():
    rng = np.random.default_rng(5)
    for n in (8, 40):
        d = []
        for _ in range(200):
            _, _, p1, p2, _, F = _problem(rng, n, sigma_px=0.5)
            Fcv, _ = cv2.findFundamentalMat(p1, p2, cv2.FM_8POINT)
            ours = libsfm.fundamental_8pt(p1, p2)
            d.append(_dist(ours, Fcv))
            assert _dist(ours, _f8_reference(p1, p2)) < 1e-9
        # OpenCV solves the normal equations (squared condition number), so
        # it agrees to ~1e-8 typically, less on ill-conditioned samples
        assert np.median(d) < 1e-7, (n, np.median(d))
        assert np.percentile(d, 90) < 1e-4, (n, np.percentile(d, 90))


def _hartley(p):
    c = p.mean(0)
    s = np.sqrt(2) / np.mean(np.linalg.norm(p - c, axis=1))
    return np.array([[s, 0, -s * c[0]], [0, s, -s * c[1]], [0, 0, 1]])


def _f8_reference(p1, p2):
    """Normalized eight-point written out in numpy (SVDs of the full system)."""
    T1, T2 = _hartley(p1), _hartley(p2)
    a = np.column_stack([p1, np.ones(len(p1))]) @ T1.T
    b = np.column_stack([p2, np.ones(len(p2))]) @ T2.T
    A = np.einsum("ni,nj->nij", b, a).reshape(-1, 9)
    F = np.linalg.svd(A)[2][-1].reshape(3, 3)
    U, S, Vt = np.linalg.svd(F)
    F = U @ np.diag([S[0], S[1], 0]) @ Vt
    return _unit(T2.T @ F @ T1)


def _dlt_reference(q1, q2):
    """Normalized DLT written out in numpy (SVD of the full 2n x 9 system)."""
    def T(p):
        c = p.mean(0)
        s = np.sqrt(2) / np.mean(np.linalg.norm(p - c, axis=1))
        return np.array([[s, 0, -s * c[0]], [0, s, -s * c[1]], [0, 0, 1]])
    T1, T2 = T(q1), T(q2)
    a = np.column_stack([q1, np.ones(len(q1))]) @ T1.T
    b = np.column_stack([q2, np.ones(len(q2))]) @ T2.T
    rows = []
    for (x, y, _), (u, v, _) in zip(a, b):
        rows.append([0, 0, 0, -x, -y, -1, v * x, v * y, v])
        rows.append([x, y, 1, 0, 0, 0, -u * x, -u * y, -u])
    h = np.linalg.svd(np.array(rows))[2][-1].reshape(3, 3)
    H = np.linalg.inv(T2) @ h @ T1
    return _unit(H) * np.sign(np.linalg.det(H))


def test_homography_same_as_opencv_and_numpy():
    rng = np.random.default_rng(6)
    d = []
    for _ in range(300):
        q1, q2, H = _plane_problem(rng, 30, sigma_px=0.5)
        H4 = libsfm.homography_4pt(q1[:4], q2[:4])
        Hcv, _ = cv2.findHomography(q1[:4], q2[:4], 0)
        d.append(_dist(H4, Hcv))
        assert np.linalg.norm(H4 - _dlt_reference(q1[:4], q2[:4])) < 1e-9
        assert np.linalg.norm(libsfm.homography_dlt(q1, q2) - _dlt_reference(q1, q2)) < 1e-9
    # OpenCV solves the normal equations in float64: agreement to its accuracy
    assert np.median(d) < 1e-5 and np.max(d) < 1e-2, (np.median(d), np.max(d))


# ---- errors grow linearly with pixel noise ---------------------------------

@pytest.mark.parametrize("solver", ["5pt", "7pt", "e8pt", "f8pt", "h4pt", "hdlt"])
def test_error_linear_in_noise(solver):
    sigmas = [0.05, 0.1, 0.2, 0.4, 0.8]
    med = []
    for s in sigmas:
        rng = np.random.default_rng(7)  # same problems and noise directions at every level
        errs = []
        for _ in range(300):
            if solver in ("h4pt", "hdlt"):
                q1, q2, H = _plane_problem(rng, 20, 0.0)
                n1 = rng.normal(size=q1.shape)
                q2 = q2 + s * n1
                est = libsfm.homography_4pt(q1[:4], q2[:4]) if solver == "h4pt" else libsfm.homography_dlt(q1, q2)
                errs.append(np.inf if est is None else _dist(est, H))
                continue
            x1, x2, p1, p2, E, F = _problem(rng, 20, 0.0)
            noise = rng.normal(size=p2.shape)
            p2n = p2 + s * noise
            Ki = np.linalg.inv(np.array([[800.0, 0, 320], [0, 800.0, 240], [0, 0, 1]]))
            x2n = np.column_stack([p2n, np.ones(len(p2n))]) @ Ki.T
            x2n /= np.linalg.norm(x2n, axis=1)[:, None]
            if solver == "5pt":
                errs.append(_best(libsfm.relpose_5pt(x1[:5], x2n[:5]), E))
            elif solver == "7pt":
                errs.append(_best(libsfm.fundamental_7pt(p1[:7], p2n[:7]), F))
            elif solver == "e8pt":
                errs.append(_dist(libsfm.essential_8pt(x1, x2n), E))
            else:
                errs.append(_dist(libsfm.fundamental_8pt(p1, p2n), F))
        med.append(np.median(errs))
    ratios = np.array(med[1:]) / np.array(med[:-1])
    # doubling the noise doubles the (median) error: linear, not worse
    assert np.all((ratios > 1.6) & (ratios < 2.5)), (solver, med, ratios)


# ---- contracts --------------------------------------------------------------

def test_shapes_and_statuses():
    x = np.ones((5, 3))
    with pytest.raises(ValueError):
        libsfm.relpose_5pt(np.ones((4, 3)), np.ones((4, 3)))
    with pytest.raises(ValueError):
        libsfm.relpose_5pt(x, np.ones((5, 2)))
    with pytest.raises(ValueError):
        libsfm.fundamental_7pt(np.ones((8, 2)), np.ones((8, 2)))
    with pytest.raises(ValueError):
        libsfm.essential_8pt(np.ones((7, 3)), np.ones((7, 3)))
    with pytest.raises(ValueError):
        libsfm.fundamental_8pt(np.ones((9, 2)), np.ones((8, 2)))
    with pytest.raises(ValueError):
        libsfm.homography_4pt(np.ones((5, 2)), np.ones((5, 2)))
    with pytest.raises(ValueError):
        libsfm.homography_dlt(np.ones((3, 2)), np.ones((3, 2)))
    bad = x.copy()
    bad[2, 1] = np.nan
    with pytest.raises(SfmError) as e:
        libsfm.relpose_5pt(bad, x)
    assert e.value.status == -2
    # degenerate samples: no solution, not an error
    assert libsfm.relpose_5pt(x, x).shape == (0, 3, 3)
    assert libsfm.homography_4pt(np.zeros((4, 2)), np.zeros((4, 2))) is None
    assert libsfm.essential_8pt(np.ones((8, 3)), np.ones((8, 3))) is None
