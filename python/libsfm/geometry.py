"""Polynomials, rotations and camera models (sfm_poly.h, sfm_rotation.h,
sfm_camera.h; the Camera class lives in libsfm.camera).

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
from .camera import Camera  # noqa: F401  (re-exported: libsfm.geometry.Camera)

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
    """Rotation matrix (3, 3) of the axis-angle vector aa (3,): angle in
    radians times the unit axis."""
    return _unary(lib.sfm_rot_from_axis_angle, aa, (3,), (3, 3), "aa", "sfm_rot_from_axis_angle")


def rot_to_axis_angle(R):
    """Axis-angle vector (3,) of the rotation R (3, 3): unit axis times the
    angle in radians, in [0, pi]."""
    return _unary(lib.sfm_rot_to_axis_angle, R, (3, 3), (3,), "R", "sfm_rot_to_axis_angle")


def rot_from_quat(q):
    """Rotation matrix (3, 3) of the quaternion q (4,) = (w, x, y, z),
    normalised first."""
    return _unary(lib.sfm_rot_from_quat, q, (4,), (3, 3), "q", "sfm_rot_from_quat")


def rot_to_quat(R):
    """Unit quaternion (4,) = (w, x, y, z), w >= 0, of the rotation R (3, 3)."""
    return _unary(lib.sfm_rot_to_quat, R, (3, 3), (4,), "R", "sfm_rot_to_quat")


def rot_nearest(M):
    """The rotation (3, 3) closest to the matrix M (3, 3) in Frobenius norm."""
    return _unary(lib.sfm_rot_nearest, M, (3, 3), (3, 3), "M", "sfm_rot_nearest")


def skew(v):
    """The cross-product matrix (3, 3) of v (3,): skew(v) @ w == cross(v, w)."""
    return _unary(lib.sfm_skew, v, (3,), (3, 3), "v", "sfm_skew")


def rot_angle_between(R1, R2):
    """Geodesic angle (radians, [0, pi]) between rotations R1 and R2."""
    R1 = as_array(R1, (3, 3), "R1")
    R2 = as_array(R2, (3, 3), "R2")
    ang = ffi.new("double *")
    check(lib.sfm_rot_angle_between(dptr(R1), dptr(R2), ang), "sfm_rot_angle_between")
    return float(ang[0])
