"""Minimal pose solvers and triangulation (sfm_pose.h, sfm_triangulate.h).

Poses are world-to-camera, x_cam = R X + t; for relative poses frame 1 is the
world: x_cam2 = R x_cam1 + t. Bearings are (n, 3) arrays, image points (n, 2).
"""
import numpy as np

from ._ffi import as_array, check, dptr, ffi, iptr, lib, mptr

_TRI_METHODS = ("dlt", "midpoint", "optimal")

__all__ = ["p3p", "relpose_upright_3pt", "essential_to_poses", "triangulate", "BEHIND", "INFINITY"]

BEHIND = lib.SFM_TRI_BEHIND
INFINITY = lib.SFM_TRI_INFINITY


def _in(a, shape, name):
    """as_array with a fast path for arrays that already fit (the solvers
    are called per RANSAC sample, where conversion would dominate)."""
    if (type(a) is np.ndarray and a.dtype == np.float64 and a.shape == shape
            and a.flags.c_contiguous):
        return a
    return as_array(a, shape, name)


def _dp(arr):
    return ffi.from_buffer("double[]", arr)


def _pose_buffer(k):
    """A (k, 12) float64 array laid out as sfm_pose[k], and its pointer."""
    buf = np.empty((k, 12), dtype=np.float64)
    return buf, ffi.cast("sfm_pose *", ffi.from_buffer(buf))


def _poses_to_list(buf, n):
    """(R, t) pairs (views into a fresh buffer) from the first n poses."""
    return [(buf[k, :9].reshape(3, 3), buf[k, 9:]) for k in range(n)]


def p3p(x, X):
    """Absolute pose from 3 bearings and their world points (P3P, Lambda
    Twist).

    x: (3, 3) bearings (rows; directions in the camera frame), X: (3, 3)
    world points. Returns a list of up to 4 (R (3, 3), t (3,)) with x_cam =
    R X + t, t in X's unit."""
    x = _in(x, (3, 3), "x")
    X = _in(X, (3, 3), "X")
    buf, poses = _pose_buffer(4)
    n = lib.sfm_p3p(_dp(x), _dp(X), poses)
    if n < 0:
        check(n, "sfm_p3p", {"x": x, "X": X})
    return _poses_to_list(buf, n)


def relpose_upright_3pt(x1, x2, d1, d2):
    """Relative pose from 3 bearing pairs and a direction known in both
    frames.

    x1, x2: (3, 3) bearings (rows) in cameras 1 and 2; d1 (3,): the
    direction in frame 1, d2 (3,) = R d1 in frame 2. Returns up to 4 (R (3,
    3), t (3,)), x2 ~ R x1 + t, |t| = 1; solutions leaving a point behind a
    camera are not returned."""
    x1 = _in(x1, (3, 3), "x1")
    x2 = _in(x2, (3, 3), "x2")
    d1 = _in(d1, (3,), "d1")
    d2 = _in(d2, (3,), "d2")
    buf, poses = _pose_buffer(4)
    n = lib.sfm_relpose_upright_3pt(_dp(x1), _dp(x2), _dp(d1), _dp(d2), poses)
    if n < 0:
        check(n, "sfm_relpose_upright_3pt", {"x1": x1, "x2": x2, "d1": d1, "d2": d2})
    return _poses_to_list(buf, n)


def essential_to_poses(E, x1=None, x2=None):
    """The four decompositions (R, t) of E = [t]x R, best first.

    E: (3, 3). With bearing pairs x1, x2 ((n, 3)) the poses are ordered by
    the number of points in front of both cameras. Returns (list of 4 (R
    (3, 3), t (3,)), counts (4,) int array); an empty list and zero counts
    when E has rank below 2."""
    E = as_array(E, (3, 3), "E")
    if (x1 is None) != (x2 is None):
        raise ValueError("give both x1 and x2, or neither")
    buf, poses = _pose_buffer(4)
    counts = np.zeros(4, dtype=np.int32)
    if x1 is None:
        n = check(lib.sfm_essential_to_poses(mptr(E), ffi.NULL, ffi.NULL, 0, poses, iptr(counts)),
                  "sfm_essential_to_poses", {"E": E})
    else:
        x1 = as_array(x1, (None, 3), "x1")
        x2 = as_array(x2, (x1.shape[0], 3), "x2")
        n = check(lib.sfm_essential_to_poses(mptr(E), dptr(x1), dptr(x2), x1.shape[0], poses,
                                             iptr(counts)), "sfm_essential_to_poses",
                  {"E": E, "x1": x1, "x2": x2})
    return _poses_to_list(buf, n), counts


def triangulate(P_list, x_list, method="dlt"):
    """Triangulate m points seen in v >= 2 views.

    P_list: v projection matrices (3,4) (K [R|t] for pixels, [R|t] for
    normalized coordinates); x_list: v arrays (m,2) of observations.
    method: "dlt" (any v), "optimal" (Lindstrom niter2, v = 2) or "midpoint"
    (P must be [R|t]; observations (m,2) normalized or (m,3) bearings).
    Returns (X (m,3), flags (m,) int32): flags has BEHIND (1) and INFINITY (2)
    bits; for INFINITY points X is a unit direction."""
    if method not in _TRI_METHODS:
        raise ValueError("method must be one of %s" % (_TRI_METHODS,))
    P_list = list(P_list)
    x_list = list(x_list)
    if len(P_list) < 2 or len(P_list) != len(x_list):
        raise ValueError("need at least 2 views and one observation array per view")
    if method == "optimal" and len(P_list) != 2:
        raise ValueError("the optimal method takes exactly 2 views")
    P = np.ascontiguousarray(np.stack([as_array(p, (3, 4), "P") for p in P_list]))
    first = np.asarray(x_list[0])
    if first.ndim != 2:
        raise ValueError("observations must be (m,2) arrays")
    m = first.shape[0]
    v = len(P_list)
    X = np.zeros((m, 3), dtype=np.float64)
    flags = np.zeros(m, dtype=np.int32)
    if method == "midpoint":
        obs = []
        for o in x_list:
            o = np.asarray(o, dtype=np.float64)
            if o.ndim == 2 and o.shape == (m, 2):
                o = np.hstack([o, np.ones((m, 1))])
            obs.append(as_array(o, (m, 3), "x"))
        f = np.ascontiguousarray(np.stack(obs))
        poses = ffi.new("sfm_pose[]", v)
        for k in range(v):
            poses[k].R = list(P[k, :, :3].ravel())
            poses[k].t = list(P[k, :, 3])
        check(lib.sfm_triangulate_midpoint(v, poses, m, dptr(f), dptr(X), iptr(flags)),
              "sfm_triangulate_midpoint", {"P_list": P, "x_list": f})
        return X, flags
    x = np.ascontiguousarray(np.stack([as_array(o, (m, 2), "x") for o in x_list]))
    if method == "dlt":
        check(lib.sfm_triangulate_dlt(v, dptr(P), m, dptr(x), dptr(X), iptr(flags)),
              "sfm_triangulate_dlt", {"P_list": P, "x_list": x})
    else:
        x1 = np.ascontiguousarray(x[0])
        x2 = np.ascontiguousarray(x[1])
        P1 = np.ascontiguousarray(P[0])
        P2 = np.ascontiguousarray(P[1])
        check(lib.sfm_triangulate_optimal2(dptr(P1), dptr(P2), m, dptr(x1), dptr(x2), dptr(X),
                                           iptr(flags)), "sfm_triangulate_optimal2",
              {"P_list": P, "x_list": x})
    return X, flags
