"""libsfm (through cffi) beside PoseLib (pip wheel) on identical inputs.

Both are called from Python, so the per-call times include each binding's
overhead (cffi argument conversion for libsfm, pybind11 for PoseLib); the
instruction counts of bench/pose_callgrind.sh are the figure for the solvers
themselves. Timing is process CPU time, median of repeated runs.
"""
import os
import sys
import time

import numpy as np
import poselib

import libsfm

sys.path.insert(0, os.path.join(os.path.dirname(os.path.abspath(__file__)), "..", "tests", "python"))
from pose_scenes import rand_rot, rot_y, unit_rows  # noqa: E402

N = 2000
RUNS = 7


def p3p_problems(rng):
    out = []
    for _ in range(N):
        R, t = rand_rot(rng), rng.uniform(-2, 2, 3)
        Xc = np.column_stack([rng.uniform(-0.8, 0.8, (3, 2)), np.ones(3)]) * rng.uniform(1, 10, (3, 1))
        out.append((unit_rows(Xc), np.ascontiguousarray((Xc - t) @ R), R, t))
    return out


def upright_problems(rng):
    out = []
    ey = np.array([0.0, 1.0, 0.0])
    for _ in range(N):
        R = rot_y(rng.uniform(-np.pi, np.pi))
        t = unit_rows(rng.normal(size=(1, 3)))[0]
        X = np.column_stack([rng.uniform(-0.8, 0.8, (3, 2)), np.ones(3)]) * rng.uniform(2, 10, (3, 1))
        out.append((unit_rows(X), unit_rows(X @ R.T + t), ey, R, t))
    return out


def timed(fn, items):
    best = []
    for _ in range(RUNS):
        t0 = time.process_time()
        for it in items:
            fn(it)
        best.append((time.process_time() - t0) / len(items) * 1e6)
    return float(np.median(best))


def truth_rate(sols_list, items, up_to_sign):
    hit = 0
    for sols, it in zip(sols_list, items):
        R, t = it[-2], it[-1]
        for Rs, ts in sols:
            tn = ts / np.linalg.norm(ts) if up_to_sign else ts
            dt = min(np.abs(tn - t).max(), np.abs(tn + t).max()) if up_to_sign else np.abs(ts - t).max()
            if np.abs(Rs - R).max() < 1e-6 and dt < 1e-6 * (1 + np.linalg.norm(t)):
                hit += 1
                break
    return hit / len(items)


def main():
    rng = np.random.default_rng(2026)
    P = p3p_problems(rng)
    U = upright_problems(rng)
    rows = []
    # p3p
    ts = timed(lambda it: libsfm.p3p(it[0], it[1]), P)
    tp = timed(lambda it: poselib.p3p(it[0], it[1]), P)
    s_ours = [libsfm.p3p(it[0], it[1]) for it in P]
    s_pl = [[(p.R, p.t) for p in poselib.p3p(it[0], it[1])] for it in P]
    rows.append(("p3p", ts, tp, np.mean([len(s) for s in s_ours]), np.mean([len(s) for s in s_pl]),
                 truth_rate(s_ours, P, False), truth_rate(s_pl, P, False)))
    # upright, y up for PoseLib; the same y direction given to libsfm
    ts = timed(lambda it: libsfm.relpose_upright_3pt(it[0], it[1], it[2], it[2]), U)
    tp = timed(lambda it: poselib.relpose_upright_3pt(it[0], it[1]), U)
    s_ours = [libsfm.relpose_upright_3pt(it[0], it[1], it[2], it[2]) for it in U]
    s_pl = [[(p.R, p.t) for p in poselib.relpose_upright_3pt(it[0], it[1])] for it in U]
    rows.append(("relpose_upright_3pt", ts, tp, np.mean([len(s) for s in s_ours]),
                 np.mean([len(s) for s in s_pl]), truth_rate(s_ours, U, True), truth_rate(s_pl, U, True)))
    print("libsfm (cffi) beside PoseLib %s (pybind11), %d problems, CPU time per call incl. binding"
          % (getattr(poselib, "__version__", "?"), N))
    print("%-22s %11s %12s %7s %9s %9s %11s %11s" % ("solver", "libsfm us", "poselib us", "ratio",
                                                      "sols sfm", "sols pl", "truth sfm", "truth pl"))
    for name, a, b, na, nb, ra, rb in rows:
        print("%-22s %11.2f %12.2f %7.2f %9.2f %9.2f %11.4f %11.4f" % (name, a, b, a / b, na, nb, ra, rb))


if __name__ == "__main__":
    main()
