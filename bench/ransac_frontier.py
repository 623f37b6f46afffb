"""One relative-pose row of bench/ransac_bench.py (same scenes and seeds),
libsfm at its defaults and with its local optimisation turned off
(lo_rounds=0: no LO refits, no inner RANSAC; then also polish_rounds=0),
beside PoseLib in the same run: time (median over scenes of the fastest of
--reps calls) and the translation-direction error (median, p90, count above
3 deg). What the time target would cost in accuracy on a row.
Figures: bench/README.md (relative pose, "What the remaining rows would take").
Usage: PYTHONPATH=python python bench/ransac_frontier.py [--row unit,200,0.25,2] [--trials 200] [--reps 5]"""
import argparse
import os
import sys
import time

import numpy as np

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
import ransac_bench as rb  # noqa: E402


def main():
    ap = argparse.ArgumentParser()
    ap.add_argument("--row", default="unit,200,0.25,2")
    ap.add_argument("--trials", type=int, default=200)
    ap.add_argument("--reps", type=int, default=5)
    a = ap.parse_args()
    cls, n, ratio, thr = a.row.split(",")
    n, ratio, thr = int(n), float(ratio), float(thr)
    rng = rb.row_rng(cls, n, ratio, thr)
    scenes = [rb.relpose_scene(rng, n, ratio, cls=cls) for _ in range(a.trials)]
    methods = [("libsfm defaults", {}), ("libsfm lo_rounds=0", dict(lo_rounds=0)),
               ("libsfm lo_rounds=0 polish_rounds=0", dict(lo_rounds=0, polish_rounds=0)),
               ("poselib", None)]
    print("%s N=%d %d%% outliers %g px, %d scenes, fastest of %d calls" % (cls, n, round(100 * ratio), thr,
                                                                           a.trials, a.reps))
    for name, options in methods:
        def fn(p1, p2, seed):
            if options is None:
                return rb.rel_poselib(p1, p2, thr, seed)
            return rb.rel_libsfm(p1, p2, thr, seed, **options)
        ts, err = [], []
        for k, (p1, p2, _, tg) in enumerate(scenes):
            best = float("inf")
            for _ in range(a.reps):
                t0 = time.perf_counter()
                R, t = fn(p1, p2, k)
                best = min(best, time.perf_counter() - t0)
            ts.append(best)
            err.append(180.0 if R is None else rb.dir_angle_deg(t, tg))
        med, _, p90, above = rb.stats(err)
        print("| %s | %.3f ms | %.3f / %.3f / %d |" % (name, 1e3 * np.median(ts), med, p90, above), flush=True)


if __name__ == "__main__":
    main()
