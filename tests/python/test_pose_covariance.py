"""The pose covariance on request (covariance=True) against an independent
computation: s2 (J^T J)^-1 with J by central differences in numpy over the
returned inliers, the residuals written out here (bearing Sampson error for
the relative pose, tangent-plane reprojection error for the absolute pose),
s2 their variance; the tangent of t on the unit sphere in a basis of this
file's own choosing (the 6 x 6 (w, t) covariance does not depend on it)."""
import numpy as np
from scipy.spatial.transform import Rotation

import libsfm

K = np.array([[500.0, 0, 320], [0, 500, 240], [0, 0, 1]])


def bearings(px):
    x = np.column_stack([px, np.ones(len(px))]) @ np.linalg.inv(K).T
    return x / np.linalg.norm(x, axis=1, keepdims=True)


def skew(v):
    return np.array([[0, -v[2], v[1]], [v[2], 0, -v[0]], [-v[1], v[0], 0]])


def sampson(R, t, b1, b2):
    E = skew(t) @ R
    Eb1 = b1 @ E.T
    Etb2 = b2 @ E
    C = np.sum(b2 * Eb1, 1)
    D = np.sum(Eb1**2, 1) + np.sum(Etb2**2, 1) - 2 * C**2
    return C / np.sqrt(D)


def relpose_scene(rng, n=300):
    R = Rotation.from_rotvec(rng.normal(size=3) * 0.1).as_matrix()
    c = np.array([1.0, 0.2, 0.1])
    t = -R @ c
    X = np.column_stack([rng.uniform(-3, 3, n), rng.uniform(-2, 2, n), rng.uniform(4, 9, n)])
    x1 = X[:, :2] / X[:, 2:] * 500 + [320, 240]
    Xc = X @ R.T + t
    x2 = Xc[:, :2] / Xc[:, 2:] * 500 + [320, 240]
    x1 += rng.normal(scale=0.5, size=x1.shape)
    x2 += rng.normal(scale=0.5, size=x2.shape)
    return x1, x2


def numeric_cov(res, R, t, sphere, h=1e-6):
    """s2 G (J^T J)^-1 G^T with J of res(R, t) along (w, dt) by central
    differences; sphere: t moves in its tangent plane (2 parameters)."""
    if sphere:
        u, _, _ = np.linalg.svd(t.reshape(3, 1))
        B = u[:, 1:]  # an orthonormal basis of the tangent plane of t
    else:
        B = np.eye(3)

    def at(p):
        Rp = Rotation.from_rotvec(p[:3]).as_matrix() @ R
        tp = t + B @ p[3:]
        if sphere:
            tp = tp / np.linalg.norm(tp)
        return res(Rp, tp)

    npar = 3 + B.shape[1]
    r0 = at(np.zeros(npar))
    J = np.column_stack([(at(h * e) - at(-h * e)) / (2 * h) for e in np.eye(npar)])
    s2 = r0 @ r0 / (r0.size - npar)
    G = np.zeros((6, npar))
    G[:3, :3] = np.eye(3)
    G[3:, 3:] = B
    return s2 * G @ np.linalg.inv(J.T @ J) @ G.T


def test_relative_pose_covariance_matches_finite_differences():
    rng = np.random.default_rng(11)
    for _ in range(3):
        x1, x2 = relpose_scene(rng)
        r = libsfm.estimate_relative_pose(x1, x2, K, K, covariance=True)
        inl = r["inliers"]
        b1, b2 = bearings(x1)[inl], bearings(x2)[inl]
        ref = numeric_cov(lambda R, t: sampson(R, t, b1, b2), r["R"], r["t"], sphere=True)
        C = r["covariance"]
        assert np.abs(C - ref).max() < 1e-3 * np.abs(ref).max()
        assert libsfm.estimate_relative_pose(x1, x2, K, K)["covariance"] is None


def test_absolute_pose_covariance_matches_finite_differences():
    rng = np.random.default_rng(12)
    n = 200
    for _ in range(3):
        R = Rotation.from_rotvec(rng.normal(size=3)).as_matrix()
        t = rng.normal(size=3)
        px = np.column_stack([rng.uniform(0, 640, n), rng.uniform(0, 480, n)])
        Xc = bearings(px) * rng.uniform(3, 9, (n, 1))
        X = (Xc - t) @ R
        p = px + rng.normal(scale=0.5, size=px.shape)
        r = libsfm.estimate_absolute_pose(p, X, K, covariance=True)
        inl = r["inliers"]
        b = bearings(p)[inl]
        Xi = X[inl]
        # tangent-plane residuals at each bearing: (e_k . Xc) / (b . Xc)
        E1 = np.cross(b, np.where(np.abs(b[:, :1]) < 0.9, [[1.0, 0, 0]], [[0, 1.0, 0]]))
        E1 /= np.linalg.norm(E1, axis=1, keepdims=True)
        E2 = np.cross(b, E1)

        def res(Rp, tp):
            Y = Xi @ Rp.T + tp
            d = np.sum(b * Y, 1)
            return np.concatenate([np.sum(E1 * Y, 1) / d, np.sum(E2 * Y, 1) / d])

        ref = numeric_cov(res, r["R"], r["t"], sphere=False)
        C = r["covariance"]
        assert np.abs(C - ref).max() < 1e-3 * np.abs(ref).max()
        assert libsfm.estimate_absolute_pose(p, X, K)["covariance"] is None
