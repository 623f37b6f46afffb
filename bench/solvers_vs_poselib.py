"""libsfm's solvers beside PoseLib (and OpenCV where PoseLib's Python package
has no such solver) on the same inputs, in one run.

Two libsfm figures per solver: through the public Python wrapper (what a user
calls; includes argument checks and array conversion) and through a raw cffi
call on prepared buffers (closest to the C cost). Anchors are called through
their own Python bindings, so every row carries a binding overhead of about a
microsecond: the C benchmark and callgrind give the solver cost itself.
"""
import time

import cv2
import numpy as np
import poselib

import libsfm
from libsfm._ffi import dptr, ffi, lib

POOL = 500
RUNS = 5


def _rot(rng):
    """Rotation by up to 0.5 rad about a random axis (as bench/solvers_bench.c)."""
    a = rng.normal(size=3)
    a /= np.linalg.norm(a)
    h = 0.5 * rng.uniform(0, 0.5)
    w, x, y, z = np.cos(h), *(np.sin(h) * a)
    return np.array([[1 - 2 * (y * y + z * z), 2 * (x * y - w * z), 2 * (x * z + w * y)],
                     [2 * (x * y + w * z), 1 - 2 * (x * x + z * z), 2 * (y * z - w * x)],
                     [2 * (x * z - w * y), 2 * (y * z + w * x), 1 - 2 * (x * x + y * y)]])


def make_problems(rng, n):
    K = np.array([[800.0, 0, 320], [0, 800.0, 240], [0, 0, 1]])
    out = []
    for _ in range(POOL):
        R = _rot(rng)
        C = rng.normal(size=3)
        C /= np.linalg.norm(C)
        t = -R @ C
        X = np.empty((0, 3))
        while len(X) < n:  # keep points in front of both cameras
            Z = np.column_stack([rng.uniform(-0.6, 0.6, n), rng.uniform(-0.45, 0.45, n), np.ones(n)])
            Z *= rng.uniform(2, 10, n)[:, None]
            X = np.vstack([X, Z[(Z @ R.T + t)[:, 2] > 0.1]])
        X = X[:n]
        Y = X @ R.T + t
        x1 = X / np.linalg.norm(X, axis=1)[:, None]
        x2 = Y / np.linalg.norm(Y, axis=1)[:, None]
        p1 = ((X / X[:, 2:]) @ K.T)[:, :2].copy()
        p2 = ((Y / Y[:, 2:]) @ K.T)[:, :2].copy()
        out.append((np.ascontiguousarray(x1), np.ascontiguousarray(x2), p1, p2))
    return out


def per_call_us(fn, args):
    best = []
    for _ in range(RUNS):
        t0 = time.perf_counter()
        for a in args:
            fn(*a)
        best.append((time.perf_counter() - t0) / len(args) * 1e6)
    return float(np.median(best))


def raw(cfn, cap, with_n):
    out = ffi.new("sfm_mat3[%d]" % cap)
    if with_n:
        return lambda a, b: cfn(dptr(a), dptr(b), a.shape[0], out)
    return lambda a, b: cfn(dptr(a), dptr(b), out)


def main():
    rng = np.random.default_rng(20261122)
    P5 = make_problems(rng, 5)
    P7 = make_problems(rng, 7)
    P8 = make_problems(rng, 8)
    P4 = make_problems(rng, 4)
    P20 = make_problems(rng, 20)
    rows = []

    def row(name, ours_py, ours_raw, anchor_name, anchor):
        a = per_call_us(*anchor)
        o = per_call_us(*ours_py)
        r = per_call_us(*ours_raw)
        rows.append((name, o, r, anchor_name, a))

    b5 = [(x1, x2) for x1, x2, _, _ in P5]
    row("relpose_5pt", (libsfm.relpose_5pt, b5), (raw(lib.sfm_relpose_5pt, 10, False), b5),
        "poselib.essential_matrix_5pt", (poselib.essential_matrix_5pt, b5))
    b8 = [(x1, x2) for x1, x2, _, _ in P8]
    row("relpose_8pt (n=8)", (libsfm.essential_8pt, b8), (raw(lib.sfm_relpose_8pt, 1, True), b8),
        "poselib.essential_matrix_8pt", (poselib.essential_matrix_8pt, b8))
    c7 = [(p1, p2) for _, _, p1, p2 in P7]
    row("relpose_7pt", (libsfm.fundamental_7pt, c7), (raw(lib.sfm_fundamental_7pt, 3, False), c7),
        "cv2.findFundamentalMat 7POINT", (lambda a, b: cv2.findFundamentalMat(a, b, cv2.FM_7POINT), c7))
    c8 = [(p1, p2) for _, _, p1, p2 in P8]
    row("fundamental_8pt (n=8)", (libsfm.fundamental_8pt, c8), (raw(lib.sfm_fundamental_8pt, 1, True), c8),
        "cv2.findFundamentalMat 8POINT", (lambda a, b: cv2.findFundamentalMat(a, b, cv2.FM_8POINT), c8))
    c4 = [(p1, p2) for _, _, p1, p2 in P4]
    c4f = [(a.astype(np.float32), b.astype(np.float32)) for a, b in c4]
    row("homography_4pt", (libsfm.homography_4pt, c4), (raw(lib.sfm_homography_4pt, 1, False), c4),
        "cv2.getPerspectiveTransform", (cv2.getPerspectiveTransform, c4f))
    c20 = [(p1, p2) for _, _, p1, p2 in P20]
    row("homography_dlt (n=20)", (libsfm.homography_dlt, c20), (raw(lib.sfm_homography_dlt, 1, True), c20),
        "cv2.findHomography(method=0)", (lambda a, b: cv2.findHomography(a, b, 0), c20))

    print("%-22s %12s %12s   %-30s %10s %9s %9s" % ("solver", "libsfm py", "libsfm cffi", "anchor",
                                                   "anchor", "py/anc", "cffi/anc"))
    for name, o, r, an, a in rows:
        print("%-22s %9.2f us %9.2f us   %-30s %7.2f us %9.2f %9.2f" % (name, o, r, an, a, o / a, r / a))
    print("(us per call, median of %d runs over %d problems; PoseLib %s, OpenCV %s)"
          % (RUNS, POOL, getattr(poselib, "__version__", "?"), cv2.__version__))


if __name__ == "__main__":
    main()
