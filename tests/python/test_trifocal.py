"""Trifocal tensor bindings against an independent numpy construction."""
import numpy as np
import pytest

import libsfm


def random_cameras(rng):
    Ps = []
    for _ in range(3):
        q = rng.normal(size=4)
        q /= np.linalg.norm(q)
        w, x, y, z = q
        R = np.array([[1 - 2 * (y * y + z * z), 2 * (x * y - w * z), 2 * (x * z + w * y)],
                      [2 * (x * y + w * z), 1 - 2 * (x * x + z * z), 2 * (y * z - w * x)],
                      [2 * (x * z - w * y), 2 * (y * z + w * x), 1 - 2 * (x * x + y * y)]])
        C = -4 * R[2] + rng.normal(size=3)
        K = np.array([[500, 0, 320], [0, 500, 240], [0, 0, 1.0]])
        Ps.append(K @ np.hstack([R, (-R @ C)[:, None]]))
    return Ps


def tensor_numpy(P1, P2, P3):
    """H&Z eq. 17.12 written independently: 4x4 determinants."""
    T = np.empty((3, 3, 3))
    for i in range(3):
        rows = np.delete(P1, i, axis=0)
        for j in range(3):
            for k in range(3):
                T[i, j, k] = (-1) ** i * np.linalg.det(np.vstack([rows, P2[j], P3[k]]))
    return T / np.linalg.norm(T)


def project(P, X):
    x = (P @ np.hstack([X, np.ones((len(X), 1))]).T).T
    return x[:, :2] / x[:, 2:]


def same_up_to_sign(a, b):
    a = a / np.linalg.norm(a)
    b = b / np.linalg.norm(b)
    return min(np.linalg.norm(a - b), np.linalg.norm(a + b))


def test_from_cameras_matches_numpy():
    rng = np.random.default_rng(1)
    for _ in range(20):
        Ps = random_cameras(rng)
        assert same_up_to_sign(libsfm.trifocal_from_cameras(*Ps), tensor_numpy(*Ps)) < 1e-10


def test_7pt_transfer_and_cameras():
    rng = np.random.default_rng(2)
    Ps = random_cameras(rng)
    X = rng.uniform(-1, 1, size=(30, 3))
    xs = [project(P, X) for P in Ps]
    T = libsfm.trifocal_7pt(*xs)
    assert same_up_to_sign(T, tensor_numpy(*Ps)) < 1e-7
    x3 = libsfm.trifocal_transfer(T, xs[0], xs[1])
    assert np.max(np.abs(x3 - xs[2])) < 1e-5
    P = libsfm.cameras_from_trifocal(T)
    assert P.shape == (3, 3, 4)
    assert same_up_to_sign(libsfm.trifocal_from_cameras(*P), T) < 1e-8
    err, Xh = libsfm.trifocal_point_error(*Ps, xs[0][0], xs[1][0], xs[2][0])
    assert err < 1e-12
    assert np.allclose(Xh[:3] / Xh[3], X[0], atol=1e-8)


def test_bad_shapes_and_status():
    with pytest.raises(ValueError):
        libsfm.trifocal_7pt(np.zeros((7, 3)), np.zeros((7, 2)), np.zeros((7, 2)))
    with pytest.raises(libsfm.SfmError) as e:
        libsfm.trifocal_7pt(np.zeros((6, 2)), np.zeros((6, 2)), np.zeros((6, 2)))
    assert e.value.status == -1
    P = np.hstack([np.eye(3), np.zeros((3, 1))])
    with pytest.raises(libsfm.SfmError):
        libsfm.trifocal_from_cameras(P, P, P)


def test_estimate_trifocal_with_outliers():
    rng = np.random.default_rng(3)
    Ps = random_cameras(rng)
    X = rng.uniform(-1, 1, size=(150, 3))
    xs = [project(P, X) + rng.normal(scale=0.5, size=(150, 2)) for P in Ps]
    bad = rng.random(150) < 0.3
    xs[2][bad] = rng.uniform(0, 640, size=(bad.sum(), 2))
    r = libsfm.estimate_trifocal(*xs, threshold_px=2.0, seed=7)
    assert r["inliers"].dtype == bool
    assert np.sum(r["inliers"] & ~bad) >= 0.95 * np.sum(~bad)
    assert np.sum(r["inliers"] & bad) <= 3
    assert same_up_to_sign(r["T"], libsfm.trifocal_from_cameras(*r["P"])) < 1e-8
    clean = [project(P, X) for P in Ps]
    x3 = libsfm.trifocal_transfer(r["T"], clean[0], clean[1])
    assert np.median(np.linalg.norm(x3 - clean[2], axis=1)) < 0.5
    again = libsfm.estimate_trifocal(*xs, threshold_px=2.0, seed=7)
    assert np.array_equal(again["inliers"], r["inliers"]) and np.array_equal(again["T"], r["T"])


def test_three_view_pose_synthetic_scale_and_accuracy():
    rng = np.random.default_rng(0)
    K = np.array([[800, 0, 320], [0, 800, 240], [0, 0, 1.0]])
    from scipy.spatial.transform import Rotation

    Rs = [np.eye(3)] + [Rotation.from_rotvec(rng.normal(scale=0.2, size=3)).as_matrix() for _ in range(2)]
    ts = [np.zeros(3)] + [rng.normal(size=3) for _ in range(2)]
    X = rng.uniform(-2, 2, size=(300, 3)) + [0, 0, 8]
    xs = []
    for R, t in zip(Rs, ts):
        p = (K @ (R @ X.T + t[:, None])).T
        xs.append(p[:, :2] / p[:, 2:] + rng.normal(scale=0.5, size=(300, 2)))
    bad = rng.random(300) < 0.25
    xs[1][bad] = rng.uniform(0, 640, size=(bad.sum(), 2))
    r = libsfm.estimate_three_view_pose(*xs, K, K, K, threshold_px=1.5, seed=1)
    s = np.linalg.norm(ts[1])
    for v in (1, 2):
        ang = np.degrees(np.arccos(np.clip((np.trace(r["R"][v].T @ Rs[v]) - 1) / 2, -1, 1)))
        assert ang < 0.3
        # one consistent scale: t3 relative to |t2| = 1
        assert np.linalg.norm(r["t"][v] * s - ts[v]) < 0.02 * np.linalg.norm(ts[v])
    assert np.sum(r["inliers"] & bad) <= 3 and np.sum(r["inliers"] & ~bad) >= 0.95 * np.sum(~bad)


def test_three_view_pose_zero_baseline_is_singular():
    rng = np.random.default_rng(1)
    x = rng.uniform(0, 1, size=(200, 2)) * [640, 480]
    K = np.array([[500, 0, 319.5], [0, 500, 239.5], [0, 0, 1.0]])
    with pytest.raises(libsfm.SfmError) as e:
        libsfm.estimate_three_view_pose(x, x, x, K, K, K)
    assert e.value.status == -5


def test_three_view_pose_dominant_plane():
    """80% of the points on one plane: the plane-induced tensor and the
    planar twin pose must not win over the true geometry."""
    from scipy.spatial.transform import Rotation

    K = np.array([[500, 0, 319.5], [0, 500, 239.5], [0, 0, 1.0]])
    Rs = [np.eye(3), Rotation.from_euler("y", -5.71, degrees=True).as_matrix(),
          Rotation.from_euler("y", -10, degrees=True).as_matrix()]
    ts = [np.zeros(3), np.array([0.45, 0.0, 0.05]), np.array([0.9, 0.05, 0.1])]
    for seed in range(1, 6):
        rng = np.random.default_rng(seed)
        plane = np.c_[rng.uniform(-2, 2, 80), rng.uniform(-1.5, 1.5, 80), np.full(80, 6.0)]
        off = np.c_[rng.uniform(-2, 2, 20), rng.uniform(-1.5, 1.5, 20), rng.uniform(3, 9, 20)]
        X = np.vstack([plane, off])
        xs = []
        for R, t in zip(Rs, ts):
            p = (K @ (R @ X.T + t[:, None])).T
            xs.append(p[:, :2] / p[:, 2:] + rng.normal(scale=0.3, size=(100, 2)))
        r = libsfm.estimate_three_view_pose(*xs, K, K, K, threshold_px=1.0, seed=seed)
        for v in (1, 2):
            ang = np.degrees(np.arccos(np.clip((np.trace(r["R"][v].T @ Rs[v]) - 1) / 2, -1, 1)))
            c = r["t"][v] @ ts[v] / np.linalg.norm(r["t"][v]) / np.linalg.norm(ts[v])
            assert ang < 0.5, (seed, v, ang)
            assert np.degrees(np.arccos(np.clip(c, -1, 1))) < 5, (seed, v)
