"""Dense stereo beside OpenCV, single thread, in one run: libsfm's SGM
against StereoSGBM (5-direction mode, the same 64 disparities) and the
multiple-window correlation matcher against StereoBM, on a rendered
640x480 pair with exact depth (tools/gen_demo_scene.py). Prints ms per
frame (best and median of the repetitions), the ratio to the anchor, the
workspace bytes, and accuracy (valid share, bad-1, bad-2).

    PYTHONPATH=python .venv/bin/python bench/stereo_bench.py [--reps N]
"""
import argparse
import os
import sys
import time

import cv2
import numpy as np

sys.path.insert(0, os.path.join(os.path.dirname(__file__), "..", "tools"))
import gen_demo_scene as scene  # noqa: E402

import libsfm  # noqa: E402
from libsfm._ffi import ffi, lib  # noqa: E402

ND = 64


def pair():
    rng = np.random.default_rng(scene.SEED)
    quads = scene.scene()
    tex = [scene.texture(rng, np.linalg.norm(u), np.linalg.norm(v)) for _, u, v in quads]
    C1 = np.array([0.0, 0.0, 0.5])
    L, Z = scene.render(quads, tex, np.eye(3), -C1, return_depth=True)
    R = scene.render(quads, tex, np.eye(3), -(C1 + [0.3, 0, 0]))
    noise = np.random.default_rng(1)
    q = lambda a: np.clip(np.rint(a + noise.normal(0, scene.NOISE_SIGMA, a.shape)), 0, 255).astype(np.uint8)  # noqa: E731
    return q(L), q(R), scene.FX * 0.3 / Z


def timed_all(fns, reps):
    """Every matcher once per repetition, in turn, so that a slow spell of
    the machine hits them alike; returns (output, ms per repetition) each."""
    outs = [fn() for fn in fns]
    ts = [[] for _ in fns]
    for _ in range(reps):
        for k, fn in enumerate(fns):
            t0 = time.perf_counter()
            outs[k] = fn()
            ts[k].append(1e3 * (time.perf_counter() - t0))
    return outs, [np.array(t) for t in ts]


def quality(d, truth):
    m = truth < ND
    v = np.isfinite(d) & m
    e = np.abs(d - truth)
    return v.sum() / m.sum(), (e[v] > 1).mean(), (e[v] > 2).mean()


def cv_disp(raw):
    d = raw.astype(np.float32) / 16.0
    d[d < 0] = np.nan
    return d


def main():
    ap = argparse.ArgumentParser()
    ap.add_argument("--reps", type=int, default=15)
    a = ap.parse_args()
    cv2.setNumThreads(1)
    L, R, truth = pair()
    h, w = L.shape
    sgbm = cv2.StereoSGBM_create(0, ND, 5, P1=200, P2=800, disp12MaxDiff=1, uniquenessRatio=10)
    bm = cv2.StereoBM_create(ND, 7)
    so = ffi.new("sfm_stereo_sgm_options *")
    lib.sfm_stereo_sgm_default_options(so)
    bo = ffi.new("sfm_stereo_block_options *")
    lib.sfm_stereo_block_default_options(bo)
    runs = (("libsfm SGM, 5 paths", lambda: libsfm.disparity_sgm(L, R, ND), "sgbm"),
            ("libsfm SGM, 8 paths", lambda: libsfm.disparity_sgm(L, R, ND, paths=8), "sgbm"),
            ("OpenCV StereoSGBM", lambda: cv_disp(sgbm.compute(L, R)), None),
            ("libsfm block (MW-SAD r=2)", lambda: libsfm.disparity_block(L, R, ND), "bm"),
            ("OpenCV StereoBM 7x7", lambda: cv_disp(bm.compute(L, R)), None))
    outs, ts = timed_all([r[1] for r in runs], a.reps)
    rows = [(name, float(t.min()), float(np.median(t)), quality(d, truth), anchor, t)
            for (name, _, anchor), d, t in zip(runs, outs, ts)]
    tt = {r[0]: r[5] for r in rows}
    ref = {"sgbm": tt["OpenCV StereoSGBM"], "bm": tt["OpenCV StereoBM 7x7"]}
    ws = {"libsfm SGM, 5 paths": lib.sfm_stereo_sgm_workspace_size(w, h, so),
          "libsfm block (MW-SAD r=2)": lib.sfm_stereo_block_workspace_size(w, h, bo)}
    so.paths = 8
    ws["libsfm SGM, 8 paths"] = lib.sfm_stereo_sgm_workspace_size(w, h, so)
    print("%dx%d, %d disparities, single thread, %d repetitions" % (w, h, ND, a.reps))
    print("ratio: the median over repetitions of this matcher's time over its anchor's in the same repetition")
    print("%-28s %9s %9s %7s %10s %7s %7s %7s" % ("matcher", "best ms", "med ms", "ratio", "ws bytes",
                                                "valid", "bad-1", "bad-2"))
    for name, best, med, (v, b1, b2), anchor, t in rows:
        ratio = "%.2f" % float(np.median(t / ref[anchor])) if anchor else "-"
        print("%-28s %9.2f %9.2f %7s %10s %7.3f %7.4f %7.4f" % (name, best, med, ratio,
                                                              ws.get(name, "-"), v, b1, b2))


if __name__ == "__main__":
    main()
