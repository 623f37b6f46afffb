"""libsfm.bundle_adjust against truth and against scipy.optimize.least_squares."""
import numpy as np
import pytest
from scipy.optimize import least_squares
from scipy.spatial.transform import Rotation

import libsfm
from libsfm._ffi import SfmError


def _scene(rng, m=4, n=30, sigma=0.0):
    Rs, ts = [], []
    for i in range(m):
        ang = -0.6 + 1.2 * i / (m - 1)
        C = np.array([6 * np.sin(ang), rng.uniform(-0.5, 0.5), -6 * np.cos(ang)])
        z = -C / np.linalg.norm(C)
        x = np.cross([0, 1, 0], z)
        x /= np.linalg.norm(x)
        y = np.cross(z, x)
        R = np.stack([x, y, z])
        Rs.append(R)
        ts.append(-R @ C)
    R = np.array(Rs)
    t = np.array(ts)
    K = np.tile([800.0, 800.0, 320.0, 240.0, 0.0, 0.0], (m, 1))
    X = rng.uniform(-1.5, 1.5, (n, 3))
    obs = []
    for j in range(n):
        for i in range(m):
            xc = R[i] @ X[j] + t[i]
            uv = K[i, :2] * xc[:2] / xc[2] + K[i, 2:4] + rng.normal(0, sigma, 2) if sigma else \
                K[i, :2] * xc[:2] / xc[2] + K[i, 2:4]
            obs.append([i, j, uv[0], uv[1]])
    return R, t, K, X, np.array(obs)


def _perturb(rng, R, t, X, deg=2.0, dt=0.05, dx=0.03):
    R0 = R.copy()
    t0 = t.copy()
    for i in range(1, len(R)):
        R0[i] = Rotation.from_rotvec(np.deg2rad(deg) * Rotation.random(random_state=rng.integers(1 << 31)).as_rotvec()
                                     / np.pi).as_matrix() @ R[i]
        t0[i] = t[i] + rng.normal(0, dt, 3)
    return R0, t0, X + rng.normal(0, dx, X.shape)


def test_noise_free_recovers_truth():
    rng = np.random.default_rng(1)
    R, t, K, X, obs = _scene(rng)
    R0, t0, X0 = _perturb(rng, R, t, X)
    t0[1, 0] = t[1, 0]
    out = libsfm.bundle_adjust({"rotations": R0, "translations": t0, "intrinsics": K}, X0, obs,
                               {"scale_gauge": "coordinate", "scale_camera": 1, "scale_coordinate": 0,
                                "function_tolerance": 1e-14, "parameter_tolerance": 1e-14})
    assert out["cost"] < 1e-12 < out["initial_cost"]
    np.testing.assert_allclose(out["cameras"]["rotations"], R, atol=1e-8)
    np.testing.assert_allclose(out["cameras"]["translations"], t, atol=1e-8)
    np.testing.assert_allclose(out["points"], X, atol=1e-8)
    assert out["cameras"]["intrinsics"].shape == (4, 6)
    assert out["workspace_bytes"] > 0
    # inputs are not modified
    assert not np.array_equal(R0, R)


def test_cost_matches_scipy_least_squares():
    rng = np.random.default_rng(2)
    R, t, K, X, obs = _scene(rng, m=3, n=20, sigma=0.5)
    R0, t0, X0 = _perturb(rng, R, t, X)
    m, n = len(R), len(X)
    ci = obs[:, 0].astype(int)
    pj = obs[:, 1].astype(int)

    def resid(v):
        rv = v[:3 * (m - 1)].reshape(-1, 3)
        tv = v[3 * (m - 1):6 * (m - 1)].reshape(-1, 3)
        Xv = v[6 * (m - 1):].reshape(-1, 3)
        Rm = np.concatenate([R0[:1], Rotation.from_rotvec(rv).as_matrix()])
        tm = np.concatenate([t0[:1], tv])
        xc = np.einsum("kij,kj->ki", Rm[ci], Xv[pj]) + tm[ci]
        uv = 800.0 * xc[:, :2] / xc[:, 2:3] + np.array([320.0, 240.0])
        return (uv - obs[:, 2:]).ravel()

    v0 = np.concatenate([Rotation.from_matrix(R0[1:]).as_rotvec().ravel(), t0[1:].ravel(), X0.ravel()])
    ref = least_squares(resid, v0, method="lm", xtol=1e-15, ftol=1e-15, gtol=1e-15, max_nfev=20000)
    out = libsfm.bundle_adjust({"rotations": R0, "translations": t0, "intrinsics": K}, X0, obs,
                               {"function_tolerance": 1e-14, "gradient_tolerance": 1e-14,
                                "parameter_tolerance": 1e-14, "max_iterations": 200})
    assert out["cost"] == pytest.approx(ref.cost, rel=1e-6)
    assert out["initial_cost"] == pytest.approx(0.5 * np.sum(resid(v0) ** 2), rel=1e-12)


def test_held_parameters_and_covariance():
    rng = np.random.default_rng(3)
    R, t, K, X, obs = _scene(rng, m=4, n=25, sigma=0.5)
    R0, t0, X0 = _perturb(rng, R, t, X)
    out = libsfm.bundle_adjust({"rotations": R0, "translations": t0, "intrinsics": K}, X0, obs,
                               {"fixed_cameras": [2], "fixed_points": [0, 5], "covariance": True})
    np.testing.assert_array_equal(out["cameras"]["rotations"][[0, 2]], R0[[0, 2]])
    np.testing.assert_array_equal(out["points"][[0, 5]], X0[[0, 5]])
    assert out["cost"] < out["initial_cost"]
    cov = out["covariance"]
    assert cov.shape == (4, 6, 6)
    assert np.all(cov[[0, 2]] == 0)
    # the distance gauge needs every other camera and point free
    with pytest.raises(SfmError):
        libsfm.bundle_adjust({"rotations": R0, "translations": t0, "intrinsics": K}, X0, obs,
                             {"fixed_cameras": [2], "scale_gauge": "distance", "scale_camera": 1})


def test_distance_gauge_and_covariance_shape():
    rng = np.random.default_rng(4)
    R, t, K, X, obs = _scene(rng, m=3, n=20, sigma=0.5)
    R0, t0, X0 = _perturb(rng, R, t, X)
    out = libsfm.bundle_adjust({"rotations": R0, "translations": t0, "intrinsics": K[:, :4]}, X0, obs,
                               {"scale_gauge": "distance", "scale_camera": 2, "scale_distance": 4.0,
                                "covariance": True, "loss": "huber", "loss_scale": 3.0})
    Rr, tr = out["cameras"]["rotations"], out["cameras"]["translations"]
    C = -np.einsum("kji,kj->ki", Rr, tr)
    assert np.linalg.norm(C[2] - C[0]) == pytest.approx(4.0, rel=1e-12)
    cov = out["covariance"]
    assert cov.shape == (3, 6, 6)
    assert np.all(cov[0] == 0)
    assert np.all(np.linalg.eigvalsh(cov[1]) > 0)
    np.testing.assert_allclose(cov[1], cov[1].T, atol=1e-15)


def test_bad_inputs():
    rng = np.random.default_rng(5)
    R, t, K, X, obs = _scene(rng, m=3, n=10)
    cams = {"rotations": R, "translations": t, "intrinsics": K}
    with pytest.raises(ValueError):
        libsfm.bundle_adjust({"rotations": R[:, :2], "translations": t, "intrinsics": K}, X, obs)
    with pytest.raises(ValueError):
        libsfm.bundle_adjust(cams, X[:, :2], obs)
    with pytest.raises(ValueError):
        libsfm.bundle_adjust(cams, X, obs[:, :3])
    with pytest.raises(ValueError):
        libsfm.bundle_adjust(cams, X, obs, {"loss": "bogus"})
    with pytest.raises(ValueError):
        libsfm.bundle_adjust(cams, X, obs, {"nonsense": 1})
    bad = obs.copy()
    bad[0, 0] = 0.5
    with pytest.raises(ValueError):
        libsfm.bundle_adjust(cams, X, bad)
    bad = obs.copy()
    bad[3, 1] = 10  # point index out of range
    with pytest.raises(SfmError) as e:
        libsfm.bundle_adjust(cams, X, bad)
    assert e.value.status == -1
    Xn = X.copy()
    Xn[2, 1] = np.nan
    with pytest.raises(SfmError) as e:
        libsfm.bundle_adjust(cams, Xn, obs)
    assert e.value.status == -2


def test_modes_and_shared_focal():
    rng = np.random.default_rng(6)
    R, t, K, X, obs = _scene(rng, m=4, n=40)
    R0, t0, X0 = _perturb(rng, R, t, X)
    out = libsfm.bundle_adjust({"rotations": R0, "translations": t0, "intrinsics": K}, X, obs,
                               {"mode": "pose_only", "function_tolerance": 1e-14})
    np.testing.assert_array_equal(out["points"], X)
    np.testing.assert_allclose(out["cameras"]["translations"], t, atol=1e-8)
    out = libsfm.bundle_adjust({"rotations": R, "translations": t, "intrinsics": K}, X0, obs,
                               {"mode": "points_only", "function_tolerance": 1e-14})
    np.testing.assert_allclose(out["points"], X, atol=1e-8)
    t0[1, 2] = t[1, 2]
    K0 = K.copy()
    K0[:, :2] *= 1.02
    out = libsfm.bundle_adjust({"rotations": R0, "translations": t0, "intrinsics": K0}, X0, obs,
                               {"intrinsics": "shared", "refine": ["focal"], "scale_gauge": "coordinate",
                                "scale_camera": 1, "scale_coordinate": 2,
                                "function_tolerance": 1e-15, "parameter_tolerance": 1e-15})
    np.testing.assert_allclose(out["cameras"]["intrinsics"], K, atol=1e-6)
    assert out["stop_reason"] in ("function_tolerance", "parameter_tolerance", "gradient")


@pytest.mark.parametrize("model", ["brown", "fisheye"])
def test_distorted_cameras_recover_truth_rendered_by_opencv(model):
    """Observations rendered by OpenCV's own projection (cv2.projectPoints /
    cv2.fisheye.projectPoints), noise-free; the start has a 2 % focal error and
    no distortion: the shared focal and every distortion coefficient come
    back, with the poses and points."""
    cv2 = pytest.importorskip("cv2")
    rng = np.random.default_rng(7)
    R, t, _, X, obs = _scene(rng, m=5, n=60)
    fx, fy, cx, cy = 500.0, 505.0, 320.0, 240.0
    Kcv = np.array([[fx, 0, cx], [0, fy, cy], [0, 0, 1.0]])
    dist = (np.array([-0.12, 0.05, 0.001, -0.0015, -0.01]) if model == "brown"
            else np.array([0.02, -0.01, 0.004, -0.001]))
    for row in obs:
        i, j = int(row[0]), int(row[1])
        rv = cv2.Rodrigues(R[i])[0]
        if model == "brown":
            uv, _ = cv2.projectPoints(X[j].reshape(1, 1, 3), rv, t[i], Kcv, dist)
        else:
            uv, _ = cv2.fisheye.projectPoints(X[j].reshape(1, 1, 3), rv, t[i].reshape(3, 1), Kcv, dist)
        row[2:4] = uv.ravel()
    R0, t0, X0 = _perturb(rng, R, t, X, deg=1.0, dt=0.02, dx=0.02)
    t0[1, 0] = t[1, 0]
    start = [libsfm.Camera(model, 1.02 * fx, 1.02 * fy, cx, cy) for _ in range(5)]
    out = libsfm.bundle_adjust({"rotations": R0, "translations": t0, "models": start}, X0, obs,
                               {"intrinsics": "shared", "refine": ["focal", "distortion"],
                                "scale_gauge": "coordinate", "scale_camera": 1, "scale_coordinate": 0,
                                "max_iterations": 200, "function_tolerance": 1e-15,
                                "parameter_tolerance": 1e-15, "gradient_tolerance": 1e-14})
    assert out["cost"] < 1e-12 < out["initial_cost"]
    for c in out["cameras"]["models"]:
        assert c.model == model
        assert abs(c.fx - fx) < 1e-6 and abs(c.fy / c.fx - fy / fx) < 1e-12
        np.testing.assert_allclose(c.dist, dist, atol=1e-8)
    np.testing.assert_allclose(out["points"], X, atol=1e-7)
    # the start objects are untouched
    assert start[0].fx == 1.02 * fx and not np.any(start[0].dist)
