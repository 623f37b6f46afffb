"""Polynomials, rotations and camera models (sfm_poly.h, sfm_rotation.h,
sfm_camera.h).

Polynomial coefficients are in descending order of power, as numpy.roots.
Rotations are 3x3 matrices acting as y = R x; axis-angle vectors are
angle * unit axis; quaternions are w-first (w, x, y, z) -- scipy's Rotation
stores them scalar-last. Cameras map points in the camera frame (z forward,
x right, y down) to pixels; distortion coefficients follow OpenCV: Brown
(k1, k2, p1, p2, k3) as cv2.projectPoints, fisheye (k1, k2, k3, k4) as
cv2.fisheye.
"""
import math

import numpy as np

from ._ffi import as_array, check, dptr, ffi, lib

__all__ = ["poly_roots", "rot_from_axis_angle", "rot_to_axis_angle", "rot_from_quat",
           "rot_to_quat", "rot_nearest", "skew", "rot_angle_between", "Camera",
           "POLY_MAX_DEGREE"]

POLY_MAX_DEGREE = lib.SFM_POLY_MAX_DEGREE


def poly_roots(c, lo=-math.inf, hi=math.inf, method="sturm"):
    """Real roots of the polynomial c[0] x^d + ... + c[d], ascending, each
    distinct root once.

    method "sturm": all real roots in the open interval (lo, hi), degree 1..20
    (sfm_poly_real_roots). method "closed": the closed forms for degree 2, 3, 4
    (sfm_poly_roots2/3/4; lo and hi must be left at their defaults)."""
    c = as_array(c, (None,), "c")
    d = c.shape[0] - 1
    out = np.empty(max(d, 1), dtype=np.float64)
    if method == "closed":
        fns = {2: lib.sfm_poly_roots2, 3: lib.sfm_poly_roots3, 4: lib.sfm_poly_roots4}
        if d not in fns:
            raise ValueError("closed forms take 3, 4 or 5 coefficients, got %d" % (d + 1))
        if lo != -math.inf or hi != math.inf:
            raise ValueError("the closed forms return all real roots: no lo/hi")
        n = check(fns[d](dptr(c), dptr(out)), "sfm_poly_roots%d" % d)
    elif method == "sturm":
        if d < 1:
            raise ValueError("need at least 2 coefficients (degree >= 1)")
        n = check(lib.sfm_poly_real_roots(dptr(c), d, float(lo), float(hi), dptr(out)),
                  "sfm_poly_real_roots")
    else:
        raise ValueError("method must be 'sturm' or 'closed'")
    return out[:n].copy()


def _unary(fn, a, shape_in, shape_out, name, where):
    a = as_array(a, shape_in, name)
    out = np.empty(shape_out, dtype=np.float64)
    check(fn(dptr(a), dptr(out)), where)
    return out


def rot_from_axis_angle(aa):
    """3x3 rotation of the axis-angle vector aa (3,)."""
    return _unary(lib.sfm_rot_from_axis_angle, aa, (3,), (3, 3), "aa", "sfm_rot_from_axis_angle")


def rot_to_axis_angle(R):
    """Axis-angle vector (3,) of rotation R, angle in [0, pi]."""
    return _unary(lib.sfm_rot_to_axis_angle, R, (3, 3), (3,), "R", "sfm_rot_to_axis_angle")


def rot_from_quat(q):
    """Rotation of the quaternion q = (w, x, y, z) (normalised first)."""
    return _unary(lib.sfm_rot_from_quat, q, (4,), (3, 3), "q", "sfm_rot_from_quat")


def rot_to_quat(R):
    """Unit quaternion (w, x, y, z), w >= 0, of rotation R."""
    return _unary(lib.sfm_rot_to_quat, R, (3, 3), (4,), "R", "sfm_rot_to_quat")


def rot_nearest(M):
    """Rotation closest to the 3x3 matrix M in Frobenius norm."""
    return _unary(lib.sfm_rot_nearest, M, (3, 3), (3, 3), "M", "sfm_rot_nearest")


def skew(v):
    """[v]_x: skew(v) @ w == cross(v, w)."""
    return _unary(lib.sfm_skew, v, (3,), (3, 3), "v", "sfm_skew")


def rot_angle_between(R1, R2):
    """Geodesic angle (radians, [0, pi]) between rotations R1 and R2."""
    R1 = as_array(R1, (3, 3), "R1")
    R2 = as_array(R2, (3, 3), "R2")
    ang = ffi.new("double *")
    check(lib.sfm_rot_angle_between(dptr(R1), dptr(R2), ang), "sfm_rot_angle_between")
    return float(ang[0])


class Camera:
    """A camera model: "pinhole", "brown" (dist = k1, k2, p1, p2, k3) or
    "fisheye" (dist = k1, k2, k3, k4), focal lengths fx, fy and principal
    point cx, cy in pixels."""

    MODELS = {"pinhole": lib.SFM_CAMERA_PINHOLE, "brown": lib.SFM_CAMERA_BROWN,
              "fisheye": lib.SFM_CAMERA_FISHEYE}
    NDIST = {"pinhole": 0, "brown": 5, "fisheye": 4}

    def __init__(self, model, fx, fy, cx, cy, dist=()):
        if model not in self.MODELS:
            raise ValueError("model must be one of %s" % ", ".join(self.MODELS))
        dist = np.asarray(dist, dtype=np.float64).ravel()
        if dist.shape[0] > self.NDIST[model]:
            raise ValueError("%s takes at most %d distortion coefficients"
                             % (model, self.NDIST[model]))
        self.model = model
        self.fx, self.fy, self.cx, self.cy = float(fx), float(fy), float(cx), float(cy)
        self.dist = np.zeros(self.NDIST[model])
        self.dist[:dist.shape[0]] = dist
        self._c = ffi.new("sfm_camera *")
        self._c.model = self.MODELS[model]
        self._c.fx, self._c.fy, self._c.cx, self._c.cy = self.fx, self.fy, self.cx, self.cy
        for i, v in enumerate(self.dist):
            self._c.dist[i] = float(v)
        check(lib.sfm_camera_validate(self._c), "sfm_camera_validate")

    @classmethod
    def from_K(cls, K, dist=(), model=None):
        """From a 3x3 intrinsic matrix (zero skew) and OpenCV distortion
        coefficients; model defaults to "brown" with coefficients, else
        "pinhole". OpenCV's 4-coefficient form (k1, k2, p1, p2) is accepted."""
        K = as_array(K, (3, 3), "K")
        dist = np.asarray(dist, dtype=np.float64).ravel()
        if model is None:
            model = "brown" if dist.size else "pinhole"
        return cls(model, K[0, 0], K[1, 1], K[0, 2], K[1, 2], dist)

    @property
    def K(self):
        return np.array([[self.fx, 0.0, self.cx], [0.0, self.fy, self.cy], [0.0, 0.0, 1.0]])

    def __repr__(self):
        return "Camera(%r, fx=%g, fy=%g, cx=%g, cy=%g, dist=%s)" % (
            self.model, self.fx, self.fy, self.cx, self.cy, [float(v) for v in self.dist])

    def project(self, X):
        """Pixels of points X (3,) or (n, 3) in the camera frame."""
        X = np.asarray(X, dtype=np.float64)
        single = X.ndim == 1
        X = as_array(X.reshape(1, -1) if single else X, (None, 3), "X")
        px = np.empty((X.shape[0], 2), dtype=np.float64)
        check(lib.sfm_camera_project_many(self._c, dptr(X), X.shape[0], dptr(px)),
              "sfm_camera_project_many")
        return px[0] if single else px

    def project_jacobian(self, X):
        """(px (2,), J (2, 3)) for one point X (3,): J = d(px)/dX."""
        X = as_array(X, (3,), "X")
        px = np.empty(2, dtype=np.float64)
        J = np.empty((2, 3), dtype=np.float64)
        check(lib.sfm_camera_project(self._c, dptr(X), dptr(px), dptr(J)), "sfm_camera_project")
        return px, J

    def unproject(self, px):
        """Unit bearings of pixels px (2,) or (n, 2). Raises SfmError with
        status SFM_E_NO_CONVERGENCE for a pixel outside the region where the
        distortion can be inverted."""
        px = np.asarray(px, dtype=np.float64)
        single = px.ndim == 1
        px = as_array(px.reshape(1, -1) if single else px, (None, 2), "px")
        b = np.empty((px.shape[0], 3), dtype=np.float64)
        check(lib.sfm_camera_unproject_many(self._c, dptr(px), px.shape[0], dptr(b)),
              "sfm_camera_unproject_many")
        return b[0] if single else b
