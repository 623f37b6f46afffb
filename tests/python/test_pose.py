"""Pose solvers and triangulation against PoseLib and OpenCV on the same inputs."""
import numpy as np
import pytest

import libsfm
from libsfm import SfmError
from pose_scenes import rand_rot, rot_y, unit_rows

poselib = pytest.importorskip("poselib")
cv2 = pytest.importorskip("cv2")


def perturb_bearings(x, rng, sigma):
    """Noise of about sigma radians on each bearing."""
    return unit_rows(x + rng.normal(scale=sigma, size=x.shape))


def match(sols_a, sols_b, tol, t_up_to_sign=False):
    """Fraction of the solutions in sols_a that have a partner in sols_b."""
    if not sols_a:
        return 1.0
    hit = 0
    for Ra, ta in sols_a:
        for Rb, tb in sols_b:
            if np.abs(Ra - Rb).max() > tol:
                continue
            if t_up_to_sign:
                na, nb = ta / np.linalg.norm(ta), tb / np.linalg.norm(tb)
                ok = min(np.abs(na - nb).max(), np.abs(na + nb).max()) < tol
            else:
                ok = np.abs(ta - tb).max() < tol * (1 + np.linalg.norm(ta))
            if ok:
                hit += 1
                break
    return hit / len(sols_a)


def test_p3p_matches_poselib_with_noise():
    rng = np.random.default_rng(1)
    rates, found, found_pl = [], 0, 0
    n = 2000
    for _ in range(n):
        R = rand_rot(rng)
        t = rng.uniform(-2, 2, size=3)
        Xc = np.column_stack([rng.uniform(-0.8, 0.8, (3, 2)), np.ones(3)]) * rng.uniform(1, 10, (3, 1))
        X = (Xc - t) @ R
        x = perturb_bearings(unit_rows(Xc), rng, 1e-4)
        ours = libsfm.p3p(x, X)
        theirs = [(p.R, p.t) for p in poselib.p3p(x, X)]
        rates.append(match(theirs, ours, 1e-6))
        found += any(np.abs(Ro - R).max() < 1e-2 for Ro, _ in ours)
        found_pl += any(np.abs(Rt - R).max() < 1e-2 for Rt, _ in theirs)
    # Same minimal problem, both exact: the same solutions where both succeed,
    # and the truth found (within the noise) as often as PoseLib finds it.
    assert np.mean(rates) > 0.995
    assert found >= found_pl - n // 200 and found / n > 0.95


def test_relpose_upright_matches_poselib_y_up_and_rotated():
    rng = np.random.default_rng(2)
    n = 2000
    rates_y, rates_g = [], []
    found = found_pl = 0
    ey = np.array([0.0, 1.0, 0.0])
    for _ in range(n):
        R = rot_y(rng.uniform(-np.pi, np.pi))
        t = unit_rows(rng.normal(size=(1, 3)))[0]
        X = np.column_stack([rng.uniform(-0.8, 0.8, (3, 2)), np.ones(3)]) * rng.uniform(2, 10, (3, 1))
        x1 = unit_rows(X)
        x2 = unit_rows(X @ R.T + t)
        x1n = perturb_bearings(x1, rng, 1e-3)
        x2n = perturb_bearings(x2, rng, 1e-3)
        theirs = [(p.R, p.t) for p in poselib.relpose_upright_3pt(x1n, x2n)]
        ours = libsfm.relpose_upright_3pt(x1n, x2n, ey, ey)
        # libsfm drops solutions that put a point behind a camera; each one
        # it keeps is one of PoseLib's.
        rates_y.append(match(ours, theirs, 1e-6, t_up_to_sign=True))
        # The same problem seen through arbitrary frame rotations A, B: the
        # known direction is then a general vector in each frame.
        A, B = rand_rot(rng), rand_rot(rng)
        ours_g = libsfm.relpose_upright_3pt(x1n @ A.T, x2n @ B.T, A @ ey, B @ ey)
        back = [(B.T @ Rg @ A, B.T @ tg) for Rg, tg in ours_g]
        rates_g.append(match(back, theirs, 1e-6, t_up_to_sign=True))
        # and the noise-free truth-like solution PoseLib finds, libsfm finds
        near_pl = [(Rt, tt) for Rt, tt in theirs if np.abs(Rt - R).max() < 1e-2]
        if near_pl:
            found_pl += 1
            found += match(near_pl, ours, 1e-6, t_up_to_sign=True) == 1.0
    assert np.mean(rates_y) > 0.995
    assert np.mean(rates_g) > 0.995
    assert found >= 0.99 * found_pl


def test_relpose_upright_noise_free_truth():
    rng = np.random.default_rng(3)
    ok = 0
    n = 1000
    for _ in range(n):
        R = rand_rot(rng)
        d1 = unit_rows(rng.normal(size=(1, 3)))[0]
        t = unit_rows(rng.normal(size=(1, 3)))[0]
        X = np.column_stack([rng.uniform(-0.8, 0.8, (3, 2)), np.ones(3)]) * rng.uniform(2, 10, (3, 1))
        sols = libsfm.relpose_upright_3pt(unit_rows(X), unit_rows(X @ R.T + t), d1, R @ d1)
        ok += any(np.abs(Ro - R).max() < 1e-6 and np.abs(to - t).max() < 1e-6 for Ro, to in sols)
    assert ok / n >= 0.999


def test_essential_to_poses_matches_opencv_recover_pose():
    rng = np.random.default_rng(4)
    agree = n_used = 0
    for _ in range(300):
        A = rand_rot(rng)
        R = A @ rot_y(rng.uniform(-0.5, 0.5)) @ A.T  # camera 2 still sees the points
        t = unit_rows(rng.normal(size=(1, 3)))[0]
        X = np.column_stack([rng.uniform(-0.8, 0.8, (40, 2)), np.ones(40)]) * rng.uniform(2, 20, (40, 1))
        Xc2 = X @ R.T + t
        keep = Xc2[:, 2] > 0.1
        if keep.sum() < 10:
            continue
        X, Xc2 = X[keep], Xc2[keep]
        n_used += 1
        p1 = X[:, :2] / X[:, 2:] + rng.normal(scale=1e-3, size=(len(X), 2))
        p2 = Xc2[:, :2] / Xc2[:, 2:] + rng.normal(scale=1e-3, size=(len(X), 2))
        tx = np.array([[0, -t[2], t[1]], [t[2], 0, -t[0]], [-t[1], t[0], 0]])
        E = tx @ R
        poses, counts = libsfm.essential_to_poses(
            E, np.column_stack([p1, np.ones(len(p1))]), np.column_stack([p2, np.ones(len(p2))]))
        assert len(poses) == 4 and counts[0] >= counts[1] >= counts[2] >= counts[3]
        _, Rc, tc, _ = cv2.recoverPose(E, np.ascontiguousarray(p1), np.ascontiguousarray(p2),
                                       np.eye(3))
        Rb, tb = poses[0]
        if np.abs(Rb - Rc).max() < 1e-6 and np.abs(tb - tc.ravel()).max() < 1e-6:
            agree += 1
        assert np.abs(Rb - R).max() < 1e-9 and np.abs(tb - t).max() < 1e-9
    assert n_used > 250 and agree / n_used > 0.99


def make_views(rng, nv, m, K):
    P, Pn, poses = [], [], []
    for _ in range(nv):
        c = unit_rows(rng.normal(size=(1, 3)))[0] * rng.uniform(4, 8)
        z = -c / np.linalg.norm(c)
        x = np.cross(rng.normal(size=3), z)
        x /= np.linalg.norm(x)
        y = np.cross(z, x)
        R = np.array([x, y, z])
        t = -R @ c
        Rt = np.column_stack([R, t])
        Pn.append(Rt)
        P.append(K @ Rt)
        poses.append((R, t))
    X = rng.uniform(-1, 1, (m, 3))
    return P, Pn, X


def project(P, X):
    h = np.column_stack([X, np.ones(len(X))]) @ P.T
    return h[:, :2] / h[:, 2:]


K = np.array([[800.0, 0, 320], [0, 790, 240], [0, 0, 1]])


def test_triangulate_dlt_vs_opencv():
    rng = np.random.default_rng(5)
    P, Pn, X = make_views(rng, 2, 200, K)
    x = [project(p, X) for p in P]
    # noise-free: both exact
    Xo, fl = libsfm.triangulate(P, x, method="dlt")
    Xh = cv2.triangulatePoints(P[0], P[1], x[0].T.copy(), x[1].T.copy())
    Xcv = (Xh[:3] / Xh[3]).T
    assert np.all(fl == 0)
    assert np.abs(Xo - X).max() < 1e-9 and np.abs(Xcv - X).max() < 1e-6
    # with pixel noise: same accuracy as OpenCV's DLT, errors linear in noise
    errs = {}
    for sigma in (0.5, 1.0, 2.0):
        xn = [xi + rng.normal(scale=sigma, size=xi.shape) for xi in x]
        Xo, _ = libsfm.triangulate(P, xn, method="dlt")
        Xh = cv2.triangulatePoints(P[0], P[1], xn[0].T.copy(), xn[1].T.copy())
        Xcv = (Xh[:3] / Xh[3]).T
        eo = np.median(np.linalg.norm(Xo - X, axis=1))
        ec = np.median(np.linalg.norm(Xcv - X, axis=1))
        assert 0.7 < eo / ec < 1.4
        errs[sigma] = eo
    assert 1.5 < errs[1.0] / errs[0.5] < 2.6 and 1.5 < errs[2.0] / errs[1.0] < 2.6


def test_triangulate_optimal_vs_opencv_correct_matches():
    rng = np.random.default_rng(6)
    P, Pn, X = make_views(rng, 2, 300, K)
    x = [project(p, X) + rng.normal(scale=1.0, size=(300, 2)) for p in P]
    Xo, fl = libsfm.triangulate(P, x, method="optimal")
    assert np.all(fl == 0)
    # OpenCV: Hartley-Sturm correction with F from the same cameras, then DLT
    C1 = np.linalg.svd(P[0])[2][-1]
    e2 = P[1] @ C1
    ex = np.array([[0, -e2[2], e2[1]], [e2[2], 0, -e2[0]], [-e2[1], e2[0], 0]])
    F = ex @ P[1] @ np.linalg.pinv(P[0])
    n1, n2 = cv2.correctMatches(F, x[0].reshape(1, -1, 2), x[1].reshape(1, -1, 2))
    Xh = cv2.triangulatePoints(P[0], P[1], n1.reshape(-1, 2).T.copy(), n2.reshape(-1, 2).T.copy())
    Xcv = (Xh[:3] / Xh[3]).T
    assert np.median(np.linalg.norm(Xo - Xcv, axis=1)) < 1e-6
    assert np.percentile(np.linalg.norm(Xo - Xcv, axis=1), 99) < 1e-4


def test_triangulate_midpoint_and_multiview():
    rng = np.random.default_rng(7)
    P, Pn, X = make_views(rng, 4, 50, K)
    xn = [project(p, X) for p in Pn]
    Xm, fl = libsfm.triangulate(Pn, xn, method="midpoint")
    assert np.all(fl == 0) and np.abs(Xm - X).max() < 1e-9
    Xd, fl = libsfm.triangulate(P, [project(p, X) for p in P], method="dlt")
    assert np.all(fl == 0) and np.abs(Xd - X).max() < 1e-9
    # a point behind the first camera is flagged, not dropped
    C = -Pn[0][:, :3].T @ Pn[0][:, 3]
    Xb = 2 * C - X[:1]
    Xo, fl = libsfm.triangulate(P[:2], [project(p, Xb) for p in P[:2]], method="dlt")
    assert fl[0] & libsfm.pose.BEHIND and np.abs(Xo - Xb).max() < 1e-8


def test_shapes_and_statuses():
    with pytest.raises(ValueError):
        libsfm.p3p(np.zeros((2, 3)), np.zeros((3, 3)))
    with pytest.raises(ValueError):
        libsfm.relpose_upright_3pt(np.zeros((3, 3)), np.zeros((3, 3)), np.zeros(2), np.zeros(3))
    with pytest.raises(ValueError):
        libsfm.triangulate([np.eye(3, 4)], [np.zeros((1, 2))])
    with pytest.raises(ValueError):
        libsfm.triangulate([np.eye(3, 4)] * 2, [np.zeros((1, 2))] * 2, method="nope")
    with pytest.raises(ValueError):
        libsfm.essential_to_poses(np.eye(3), np.zeros((3, 3)), None)
    x = np.eye(3)
    x[0, 0] = np.nan
    with pytest.raises(SfmError) as e:
        libsfm.p3p(x, np.eye(3))
    assert e.value.status == -2
    with pytest.raises(SfmError):
        libsfm.relpose_upright_3pt(np.eye(3), np.eye(3), np.zeros(3), np.array([0, 1.0, 0]))
    # degenerate: collinear world points give no solution, not an error
    X = np.array([[0, 0, 5.0], [1, 0, 5], [2, 0, 5]])
    assert libsfm.p3p(unit_rows(X), X) == []
    poses, counts = libsfm.essential_to_poses(np.zeros((3, 3)))
    assert poses == [] and not counts.any()
