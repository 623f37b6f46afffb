"""Minimal and linear solvers for two-view geometry and homographies.

Bearings are (n, 3) direction vectors, pixels and plane points (n, 2).
Between two cameras x_cam2 = R x_cam1 + t; E = [t]x R with x2^T E x1 = 0;
F with p2h^T F p1h = 0; H with p2h ~ H p1h (h: homogeneous (u, v, 1)).
E and F have unit Frobenius norm (sign arbitrary); H unit Frobenius norm and
det(H) > 0. Solvers returning one matrix give None for a degenerate sample.
"""
import numpy as np

from ._ffi import as_array, check, dptr, ffi, lib


def _pair(a, b, cols, n, names):
    a = as_array(a, (n, cols), names[0])
    b = as_array(b, (n, cols), names[1])
    if a.shape != b.shape:
        raise ValueError("%s and %s must have the same shape, got %s and %s"
                         % (names[0], names[1], a.shape, b.shape))
    return a, b


def _at_least(a, k, name):
    if a.shape[0] < k:
        raise ValueError("%s needs at least %d rows, got %d" % (name, k, a.shape[0]))


def _many(fn, a, b, cap, where):
    out = ffi.new("sfm_mat3[%d]" % cap)
    n = check(fn(dptr(a), dptr(b), out), where)
    res = np.empty((n, 3, 3))
    for k in range(n):
        res[k] = np.frombuffer(ffi.buffer(out[k].m), dtype=np.float64).reshape(3, 3)
    return res


def _one(fn, a, b, where):
    out = ffi.new("sfm_mat3 *")
    n = check(fn(dptr(a), dptr(b), a.shape[0], out), where)
    if n == 0:
        return None
    return np.frombuffer(ffi.buffer(out.m), dtype=np.float64).reshape(3, 3).copy()


def relpose_5pt(x1, x2):
    """Essential matrices from 5 bearing pairs (Nister): array (n, 3, 3), n <= 10."""
    a, b = _pair(x1, x2, 3, 5, ("x1", "x2"))
    return _many(lib.sfm_relpose_5pt, a, b, lib.SFM_RELPOSE_5PT_MAX_SOLUTIONS, "relpose_5pt")


def fundamental_7pt(p1, p2):
    """Fundamental matrices from 7 pixel pairs: array (n, 3, 3), n <= 3."""
    a, b = _pair(p1, p2, 2, 7, ("p1", "p2"))
    return _many(lib.sfm_relpose_7pt, a, b, lib.SFM_RELPOSE_7PT_MAX_SOLUTIONS, "fundamental_7pt")


def essential_8pt(x1, x2):
    """Least-squares essential matrix from n >= 8 bearing pairs: (3, 3) or None."""
    a, b = _pair(x1, x2, 3, None, ("x1", "x2"))
    _at_least(a, 8, "x1")
    return _one(lib.sfm_relpose_8pt, a, b, "essential_8pt")


def fundamental_8pt(p1, p2):
    """Normalized eight-point fundamental matrix from n >= 8 pixel pairs: (3, 3) or None."""
    a, b = _pair(p1, p2, 2, None, ("p1", "p2"))
    _at_least(a, 8, "p1")
    return _one(lib.sfm_fundamental_8pt, a, b, "fundamental_8pt")


def homography_4pt(q1, q2):
    """Homography from exactly 4 point pairs: (3, 3) or None (collinear triple)."""
    a, b = _pair(q1, q2, 2, 4, ("q1", "q2"))
    out = ffi.new("sfm_mat3 *")
    n = check(lib.sfm_homography_4pt(dptr(a), dptr(b), out), "homography_4pt")
    if n == 0:
        return None
    return np.frombuffer(ffi.buffer(out.m), dtype=np.float64).reshape(3, 3).copy()


def homography_dlt(q1, q2):
    """Normalized DLT homography from n >= 4 point pairs: (3, 3) or None."""
    a, b = _pair(q1, q2, 2, None, ("q1", "q2"))
    _at_least(a, 4, "q1")
    return _one(lib.sfm_homography_dlt, a, b, "homography_dlt")
