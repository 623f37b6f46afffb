"""libsfm.r2r_refine / r2r_ransac against a world model of two robots (numpy)
and against scipy.optimize.least_squares minimising the same whitened cost
(an independent optimiser: the two maximum-likelihood answers and their
Gauss-Newton covariances must agree)."""
import numpy as np
import pytest
from scipy.optimize import least_squares
from scipy.spatial.transform import Rotation

import libsfm
from libsfm import SfmError


def world_steps(rng, n, sd=0.0, sb=0.0):
    W1 = Rotation.random(n, random_state=rng).as_matrix()
    W2 = Rotation.random(n, random_state=rng).as_matrix()
    P1 = rng.uniform(-3, 3, (n, 3))
    P2 = rng.uniform(-3, 3, (n, 3))
    for k in range(n):
        while np.linalg.norm(P2[k] - P1[k]) < 1.0:
            P2[k] = rng.uniform(-3, 3, 3)
    C = W1[0].T @ W2[0]
    p = W1[0].T @ (P2[0] - P1[0])
    steps = []
    for k in range(n):
        v = P2[k] - P1[k]
        dist = np.linalg.norm(v)
        b1 = W1[k].T @ v / dist
        b2 = -W2[k].T @ v / dist
        if sb > 0:
            b1 = Rotation.from_rotvec(rng.normal(0, sb, 3)).apply(b1)
            b2 = Rotation.from_rotvec(rng.normal(0, sb, 3)).apply(b2)
        steps.append({"R1": W1[0].T @ W1[k], "t1": W1[0].T @ (P1[k] - P1[0]),
                      "R2": W2[0].T @ W2[k], "t2": W2[0].T @ (P2[k] - P2[0]),
                      "d": dist + (rng.normal(0, sd) if sd > 0 else 0.0), "b1": b1, "b2": b2})
    return steps, C, p


def tangent(m):
    """The library's documented tangent basis choice does not matter for the
    cost (|r|^2 per bearing is basis-free); any orthonormal pair will do."""
    a = np.zeros(3)
    a[np.argmin(np.abs(m))] = 1.0
    e1 = np.cross(m, a)
    e1 /= np.linalg.norm(e1)
    return e1, np.cross(m, e1)


def residuals(x, steps, C0, sd, sb):
    C = Rotation.from_rotvec(x[:3]).as_matrix() @ C0
    p = x[3:]
    r = []
    for s in steps:
        w = C @ s["t2"] + p - s["t1"]
        r.append((np.linalg.norm(w) - s["d"]) / sd)
        for key, v in (("b1", s["R1"].T @ w), ("b2", -s["R2"].T @ C.T @ w)):
            m = s[key] / np.linalg.norm(s[key])
            u = v / np.linalg.norm(v)
            e1, e2 = tangent(m)
            r += [e1 @ u / sb, e2 @ u / sb]
    return np.array(r)


def rot_err(C, Ct):
    return np.linalg.norm(Rotation.from_matrix(Ct @ C.T).as_rotvec())


def test_refine_converges_from_perturbed_truth():
    rng = np.random.default_rng(5)
    for _ in range(20):
        steps, C, p = world_steps(rng, 5)
        C0 = Rotation.from_rotvec(rng.normal(0, 0.08, 3)).as_matrix() @ C
        p0 = p + rng.normal(0, 0.2, 3)
        Cr, pr, cov = libsfm.r2r_refine(steps, C0, p0, 0.01, 0.01)
        assert rot_err(Cr, C) < 1e-9 and np.linalg.norm(pr - p) < 1e-9
        assert cov.shape == (6, 6) and np.allclose(cov, cov.T)
        assert np.all(np.linalg.eigvalsh(cov) > 0)


def test_refine_agrees_with_scipy_least_squares():
    rng = np.random.default_rng(11)
    sd, sb = 0.05, 0.01
    for _ in range(10):
        steps, C, p = world_steps(rng, 6, sd, sb)
        Cr, pr, cov, st = libsfm.r2r_refine(steps, C, p, sd, sb, return_stats=True)
        sol = least_squares(residuals, np.r_[np.zeros(3), p], args=(steps, C, sd, sb),
                            method="lm", xtol=1e-15, ftol=1e-15, gtol=1e-15)
        Cs = Rotation.from_rotvec(sol.x[:3]).as_matrix() @ C
        assert rot_err(Cr, Cs) < 1e-7
        assert np.linalg.norm(pr - sol.x[3:]) < 1e-7
        assert st["final_cost"] == pytest.approx(0.5 * np.sum(sol.fun ** 2), rel=1e-7)
        assert st["n_equations"] == 30
        # covariance from scipy's Jacobian at the solution, re-expressed on
        # the left increment at the solution (the tangent at Cs, not at C)
        J = least_squares(residuals, np.r_[np.zeros(3), sol.x[3:]], args=(steps, Cs, sd, sb),
                          max_nfev=1, method="trf").jac
        covs = np.linalg.inv(J.T @ J)
        assert np.allclose(cov, covs, rtol=1e-4, atol=1e-12 + 1e-4 * np.abs(covs).max())


def test_refine_nees_and_error_reduction():
    rng = np.random.default_rng(3)
    sd, sb = 0.05, 0.01
    nees, before, after = [], [], []
    for _ in range(200):
        steps, C, p = world_steps(rng, 8, sd, sb)
        C0 = Rotation.from_rotvec(rng.normal(0, 0.03, 3)).as_matrix() @ C
        p0 = p + rng.normal(0, 0.1, 3)
        Cr, pr, cov = libsfm.r2r_refine(steps, C0, p0, sd, sb)
        e = np.r_[Rotation.from_matrix(C @ Cr.T).as_rotvec(), p - pr]
        nees.append(e @ np.linalg.solve(cov, e))
        before.append(np.linalg.norm(p0 - p))
        after.append(np.linalg.norm(pr - p))
    assert abs(np.mean(nees) - 6.0) < 5 * np.sqrt(12 / len(nees))
    assert np.mean(after) < 0.5 * np.mean(before)


def test_ransac_with_outliers():
    rng = np.random.default_rng(17)
    sd, sb = 0.02, 0.01
    for trial in range(5):
        steps, C, p = world_steps(rng, 10, sd, sb)
        bad = np.zeros((10, 3), bool)
        for k, j in rng.permutation([(k, j) for k in range(10) for j in range(3)])[:9]:
            bad[k, j] = True
            if j == 0:
                steps[k]["d"] += rng.uniform(1, 3)
            else:
                steps[k]["b%d" % j] = Rotation.random(random_state=rng).apply([1.0, 0, 0])
        r = libsfm.r2r_ransac(steps, sd, sb, seed=trial)
        assert rot_err(r.C, C) < 0.03 and np.linalg.norm(r.p - p) < 0.1
        assert r.inliers.shape == (10, 3)
        assert not np.any(r.inliers & bad)
        assert r.num_inliers == r.inliers.sum() >= 19
        assert r.covariance.shape == (6, 6)
        again = libsfm.r2r_ransac(steps, sd, sb, seed=trial)
        assert np.array_equal(again.C, r.C) and np.array_equal(again.inliers, r.inliers)


def test_bad_inputs():
    rng = np.random.default_rng(1)
    steps, C, p = world_steps(rng, 3)
    with pytest.raises(SfmError):
        libsfm.r2r_refine(steps, C, p, 0.0, 0.01)
    with pytest.raises(SfmError):
        libsfm.r2r_refine(steps, -C, p, 0.01, 0.01)  # a reflection
    with pytest.raises(SfmError):
        libsfm.r2r_refine([{"d": 1.0, "b1": [1, 0, 0]}], C, p, 0.01, 0.01)  # three equations
    with pytest.raises(ValueError):
        libsfm.r2r_refine(steps, C, p, 0.01, 0.01, loss="l1")
    with pytest.raises(ValueError):
        libsfm.r2r_refine(steps, C[:2], p, 0.01, 0.01)
    with pytest.raises(SfmError):
        libsfm.r2r_ransac(steps, 0.01, 0.01, threshold=-1.0)
    still = [dict(steps[0], d=steps[0]["d"]) for _ in range(6)]
    for s in still:
        s.pop("b1"), s.pop("b2")
    with pytest.raises(SfmError):
        libsfm.r2r_refine(still, C, p, 0.01, 0.01)
