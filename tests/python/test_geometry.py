"""Polynomials, rotations and cameras against numpy, scipy and OpenCV on the
same inputs (and against the known roots / points the inputs were built
from)."""
import math

import cv2
import numpy as np
import pytest
from scipy.spatial.transform import Rotation

import libsfm
from libsfm import Camera, SfmError
from libsfm._ffi import lib

RNG = np.random.default_rng(20261122)
EPS = np.finfo(float).eps


# ---- polynomials ----------------------------------------------------------

def _numpy_real_roots(c, tol=1e-7):
    r = np.roots(c)
    return np.sort(r[np.abs(r.imag) <= tol * np.maximum(1.0, np.abs(r))].real)


@pytest.mark.parametrize("deg", [2, 3, 4, 6, 10, 15, 20])
def test_poly_roots_vs_numpy_and_truth(deg):
    worst_sfm = worst_np = 0.0
    for _ in range(200):
        # real roots of mixed scale plus a complex pair, so the count matters
        k = max(deg - 2, 1) if deg > 2 else deg
        r = np.sort(RNG.choice([-1, 1], k) * 10 ** RNG.uniform(-1, 1, k))
        if np.min(np.diff(r), initial=np.inf) < 1e-2:
            continue
        c = np.poly(r)
        if k < deg:
            a, b = RNG.uniform(-2, 2), RNG.uniform(0.5, 2)
            c = np.polymul(c, [1.0, -2 * a, a * a + b * b])
        got = libsfm.poly_roots(c)
        ref = _numpy_real_roots(c)
        assert got.shape == r.shape == ref.shape
        worst_sfm = max(worst_sfm, np.max(np.abs(got - r) / np.maximum(1, np.abs(r))))
        worst_np = max(worst_np, np.max(np.abs(ref - r) / np.maximum(1, np.abs(r))))
        if deg <= 4:
            closed = libsfm.poly_roots(c, method="closed")
            assert closed.shape == r.shape
            assert np.allclose(closed, r, rtol=1e-9, atol=1e-12)
    # no worse than numpy's companion-matrix eigenvalues, to a small factor
    assert worst_sfm <= max(10 * worst_np, 1e-12)


def test_poly_clustered_pair_degree10():
    # the shape the 5-point solver needs: two of ten roots 1e-5 apart (closer
    # pairs stop being real once the coefficients are rounded to doubles)
    r = np.array([-2.5, -1.2, -0.4, 0.3, 0.7, 0.7 * (1 + 1e-5), 1.1, 1.9, 3.2, 6.0])
    c = np.poly(r)
    got = libsfm.poly_roots(c)
    assert got.shape == (10,)
    assert np.allclose(got, r, rtol=0, atol=1e-9)
    ref = _numpy_real_roots(c)
    assert ref.shape == (10,)
    assert np.max(np.abs(got - r)) <= max(np.max(np.abs(ref - r)), 1e-12)


def test_poly_interval_double_root_and_errors():
    c = np.poly([1, 2, 2, 5])
    got = libsfm.poly_roots(c)
    assert got.shape == (3,)
    assert np.allclose(got, [1, 2, 5], atol=1e-7)
    assert np.allclose(libsfm.poly_roots(c, 1.5, 10), [2, 5], atol=1e-7)
    assert libsfm.poly_roots([1, 0, 1]).size == 0
    with pytest.raises(ValueError):
        libsfm.poly_roots([[1, 2], [3, 4]])
    with pytest.raises(ValueError):
        libsfm.poly_roots([1, 2, 3, 4, 5, 6], method="closed")
    with pytest.raises(SfmError) as e:
        libsfm.poly_roots(np.ones(22))
    assert e.value.status == lib.SFM_E_CAPACITY
    with pytest.raises(SfmError) as e:
        libsfm.poly_roots([1, np.nan, 2])
    assert e.value.status == lib.SFM_E_NONFINITE


# ---- rotations ------------------------------------------------------------

def test_rotations_vs_scipy():
    rots = Rotation.random(500, random_state=7)
    for rot in rots:
        R = rot.as_matrix()
        rv = rot.as_rotvec()
        assert np.allclose(libsfm.rot_from_axis_angle(rv), R, atol=1e-14)
        assert np.allclose(libsfm.rot_to_axis_angle(R), rv, atol=1e-12)
        qs = rot.as_quat()  # scalar-last
        q = np.r_[qs[3], qs[:3]]
        q = q if q[0] >= 0 else -q
        assert np.allclose(libsfm.rot_from_quat(q), R, atol=1e-14)
        assert np.allclose(libsfm.rot_to_quat(R), q, atol=1e-14)


@pytest.mark.parametrize("angle", [0.0, 1e-12, 1e-6, 1.0, math.pi - 1e-9, math.pi])
def test_rotation_special_angles_vs_scipy(angle):
    n = RNG.normal(size=3)
    n /= np.linalg.norm(n)
    rot = Rotation.from_rotvec(angle * n)
    R = rot.as_matrix()
    aa = libsfm.rot_to_axis_angle(R)
    ref = rot.as_rotvec()
    if angle == math.pi:  # the axis sign is free at exactly pi
        aa = aa if aa @ ref >= 0 else -aa
    assert np.allclose(aa, ref, rtol=1e-9, atol=1e-15 + 1e-7 * (angle > 3))
    R1 = Rotation.random(random_state=3)
    R2 = R1 * rot
    ang = libsfm.rot_angle_between(R1.as_matrix(), R2.as_matrix())
    assert ang == pytest.approx((R1.inv() * R2).magnitude(), abs=2e-14)
    assert ang == pytest.approx(angle, abs=2e-14)


def test_nearest_rotation_vs_scipy_and_svd():
    for _ in range(200):
        M = RNG.normal(size=(3, 3))
        R = libsfm.rot_nearest(M)
        U, _, Vt = np.linalg.svd(M)
        D = np.diag([1, 1, np.linalg.det(U @ Vt)])
        assert np.allclose(R, U @ D @ Vt, atol=1e-12)
        if np.linalg.det(M) > 0:  # scipy orthogonalises only proper matrices the same way
            assert np.allclose(R, Rotation.from_matrix(M).as_matrix(), atol=1e-9)
    with pytest.raises(SfmError) as e:
        libsfm.rot_nearest(np.outer([1, 2, 3], [1, 0, 1]))
    assert e.value.status == lib.SFM_E_SINGULAR


def test_skew_and_shape_errors():
    v, w = RNG.normal(size=3), RNG.normal(size=3)
    assert np.allclose(libsfm.skew(v) @ w, np.cross(v, w), atol=1e-14)
    with pytest.raises(ValueError):
        libsfm.rot_from_axis_angle([1, 2])
    with pytest.raises(ValueError):
        libsfm.rot_to_quat(np.eye(4))
    with pytest.raises(SfmError):
        libsfm.rot_from_quat([0, 0, 0, 0])


# ---- cameras --------------------------------------------------------------

K = np.array([[500.0, 0, 320.0], [0, 480.0, 240.0], [0, 0, 1]])
BROWN = np.array([-0.28, 0.07, 1e-3, -5e-4, 0.01])
FISH = np.array([-0.01, 0.02, -0.005, 0.001])


def _points(n, max_theta):
    th = RNG.uniform(0, max_theta, n)
    ph = RNG.uniform(-np.pi, np.pi, n)
    d = RNG.uniform(0.5, 10, n)
    return np.c_[d * np.sin(th) * np.cos(ph), d * np.sin(th) * np.sin(ph), d * np.cos(th)]


def test_brown_vs_opencv():
    cam = Camera.from_K(K, BROWN)
    X = _points(500, 0.75)
    px = cam.project(X)
    ref, jac = cv2.projectPoints(X.reshape(-1, 1, 3), np.zeros(3), np.zeros(3), K, BROWN)
    assert np.allclose(px, ref.reshape(-1, 2), atol=1e-9)
    # with rvec = 0 the derivative by tvec is the derivative by X
    for i in range(0, 500, 25):
        _, J = cam.project_jacobian(X[i])
        assert np.allclose(J, jac[2 * i:2 * i + 2, 3:6], rtol=1e-9, atol=1e-9)
    # undistortion: OpenCV iterates a fixed count; ask it for many
    und = cv2.undistortPoints(px.reshape(-1, 1, 2), K, BROWN,
                              criteria=(cv2.TERM_CRITERIA_COUNT | cv2.TERM_CRITERIA_EPS, 200, 1e-15))
    b = cam.unproject(px)
    assert np.allclose(b[:, :2] / b[:, 2:], und.reshape(-1, 2), atol=1e-9)
    assert np.allclose(b, X / np.linalg.norm(X, axis=1, keepdims=True), atol=1e-12)


def test_fisheye_vs_opencv():
    cam = Camera("fisheye", 500, 480, 320, 240, FISH)
    X = _points(500, 1.4)  # OpenCV's fisheye works in x/z: stay in front
    px = cam.project(X)
    ref, jac = cv2.fisheye.projectPoints(X.reshape(-1, 1, 3), np.zeros(3), np.zeros(3), K, FISH)
    assert np.allclose(px, ref.reshape(-1, 2), atol=1e-9)
    # jacobian columns: f(2), c(2), k(4), om(3), T(3), alpha
    for i in range(0, 500, 25):
        _, J = cam.project_jacobian(X[i])
        assert np.allclose(J, jac[2 * i:2 * i + 2, 11:14], rtol=1e-7, atol=1e-7)
    und = cv2.fisheye.undistortPoints(px.reshape(-1, 1, 2), K, FISH,
                                      criteria=(cv2.TERM_CRITERIA_COUNT | cv2.TERM_CRITERIA_EPS,
                                                200, 1e-15))
    b = cam.unproject(px)
    assert np.allclose(b[:, :2] / b[:, 2:], und.reshape(-1, 2), atol=1e-8)
    assert np.allclose(b, X / np.linalg.norm(X, axis=1, keepdims=True), atol=1e-12)


def test_pinhole_vs_opencv_and_jacobian_fd():
    cam = Camera("pinhole", 500, 480, 320, 240)
    X = _points(100, 1.0)
    ref, _ = cv2.projectPoints(X.reshape(-1, 1, 3), np.zeros(3), np.zeros(3), K, None)
    assert np.allclose(cam.project(X), ref.reshape(-1, 2), atol=1e-10)
    for c in (cam, Camera.from_K(K, BROWN), Camera("fisheye", 500, 480, 320, 240, FISH)):
        x = X[3]
        _, J = c.project_jacobian(x)
        h = 1e-6
        fd = np.array([(c.project(x + h * e) - c.project(x - h * e)) / (2 * h)
                       for e in np.eye(3)]).T
        assert np.allclose(J, fd, rtol=1e-6, atol=1e-6)


def test_non_invertible_distortion_raises():
    cam = Camera("brown", 500, 480, 320, 240, [-0.5, 0, 0, 0, 0])
    peak = math.sqrt(2 / 3) * 2 / 3  # largest distorted radius reachable
    b = cam.unproject([320 + 500 * 0.5, 240])
    assert b[0] / b[2] < math.sqrt(2 / 3)
    with pytest.raises(SfmError) as e:
        cam.unproject([320 + 500 * (peak + 0.01), 240])
    assert e.value.status == lib.SFM_E_NO_CONVERGENCE
    fish = Camera("fisheye", 500, 480, 320, 240, [-0.3, 0, 0, 0])
    with pytest.raises(SfmError) as e:
        fish.unproject([320, 240 + 480 * 0.75])
    assert e.value.status == lib.SFM_E_NO_CONVERGENCE


def test_camera_errors():
    with pytest.raises(ValueError):
        Camera("kannala", 1, 1, 0, 0)
    with pytest.raises(ValueError):
        Camera("fisheye", 1, 1, 0, 0, [0.1] * 5)
    with pytest.raises(SfmError) as e:
        Camera("pinhole", 0, 1, 0, 0)
    assert e.value.status == lib.SFM_E_ARGUMENT
    cam = Camera("pinhole", 500, 500, 320, 240)
    with pytest.raises(ValueError):
        cam.project(np.ones((4, 2)))
    with pytest.raises(ValueError):
        cam.unproject(np.ones((4, 3)))
    with pytest.raises(SfmError) as e:
        cam.project([0.0, 0.0, -1.0])
    assert e.value.status == lib.SFM_E_SINGULAR
