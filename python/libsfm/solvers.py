"""Minimal and linear solvers for two-view geometry and homographies.

Bearings are (n, 3) direction vectors, pixels and plane points (n, 2).
Between two cameras x_cam2 = R x_cam1 + t; E = [t]x R with x2^T E x1 = 0;
F with p2h^T F p1h = 0; H with p2h ~ H p1h (h: homogeneous (u, v, 1)).
E and F have unit Frobenius norm (sign arbitrary); H unit Frobenius norm and
det(H) > 0. Solvers returning one matrix give None for a degenerate sample.
"""
import numpy as np

from ._ffi import as_array, check, dptr, ffi, lib

__all__ = ["relpose_5pt", "fundamental_7pt", "essential_8pt", "fundamental_8pt", "homography_4pt",
           "homography_dlt"]


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


def _many(fn, a, b, cap, where, names):
    out = ffi.new("sfm_mat3[%d]" % cap)
    n = check(fn(dptr(a), dptr(b), out), where, dict(zip(names, (a, b))))
    res = np.empty((n, 3, 3))
    for k in range(n):
        res[k] = np.frombuffer(ffi.buffer(out[k].m), dtype=np.float64).reshape(3, 3)
    return res


def _one(fn, a, b, where, names):
    out = ffi.new("sfm_mat3 *")
    n = check(fn(dptr(a), dptr(b), a.shape[0], out), where, dict(zip(names, (a, b))))
    if n == 0:
        return None
    return np.frombuffer(ffi.buffer(out.m), dtype=np.float64).reshape(3, 3).copy()


def relpose_5pt(x1, x2):
    """Essential matrices from 5 bearing pairs (Nister).

    x1, x2: (5, 3) bearings (directions; their scale does not matter) in
    cameras 1 and 2. Returns an (m, 3, 3) array, m <= 10, x2^T E x1 = 0."""
    a, b = _pair(x1, x2, 3, 5, ("x1", "x2"))
    return _many(lib.sfm_relpose_5pt, a, b, lib.SFM_RELPOSE_5PT_MAX_SOLUTIONS, "relpose_5pt",
                 ("x1", "x2"))


def fundamental_7pt(p1, p2):
    """Fundamental matrices from 7 pixel pairs.

    p1, p2: (7, 2) pixels. Returns an (m, 3, 3) array, m <= 3, p2h^T F p1h
    = 0."""
    a, b = _pair(p1, p2, 2, 7, ("p1", "p2"))
    return _many(lib.sfm_fundamental_7pt, a, b, lib.SFM_FUNDAMENTAL_7PT_MAX_SOLUTIONS, "fundamental_7pt",
                 ("p1", "p2"))


def essential_8pt(x1, x2):
    """Least-squares essential matrix from n >= 8 bearing pairs.

    x1, x2: (n, 3) bearings. Returns E (3, 3), or None for a degenerate
    set."""
    a, b = _pair(x1, x2, 3, None, ("x1", "x2"))
    _at_least(a, 8, "x1")
    return _one(lib.sfm_relpose_8pt, a, b, "essential_8pt", ("x1", "x2"))


def fundamental_8pt(p1, p2):
    """Normalized eight-point fundamental matrix from n >= 8 pixel pairs.

    p1, p2: (n, 2) pixels. Returns F (3, 3), or None for a degenerate set."""
    a, b = _pair(p1, p2, 2, None, ("p1", "p2"))
    _at_least(a, 8, "p1")
    return _one(lib.sfm_fundamental_8pt, a, b, "fundamental_8pt", ("p1", "p2"))


def homography_4pt(q1, q2):
    """Homography from exactly 4 point pairs.

    q1, q2: (4, 2) points (pixels or plane coordinates). Returns H (3, 3),
    q2h ~ H q1h, or None when three points are collinear."""
    a, b = _pair(q1, q2, 2, 4, ("q1", "q2"))
    out = ffi.new("sfm_mat3 *")
    n = check(lib.sfm_homography_4pt(dptr(a), dptr(b), out), "homography_4pt", {"q1": a, "q2": b})
    if n == 0:
        return None
    return np.frombuffer(ffi.buffer(out.m), dtype=np.float64).reshape(3, 3).copy()


def homography_dlt(q1, q2):
    """Normalized DLT homography from n >= 4 point pairs.

    q1, q2: (n, 2) points. Returns H (3, 3), q2h ~ H q1h, or None for a
    degenerate set."""
    a, b = _pair(q1, q2, 2, None, ("q1", "q2"))
    _at_least(a, 4, "q1")
    return _one(lib.sfm_homography_dlt, a, b, "homography_dlt", ("q1", "q2"))
