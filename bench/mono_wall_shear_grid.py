"""mono_wall: how well a rolling-shutter shear pins the focal length.

The whole uncalibrated pipeline (libsfm.reconstruct_three_view, default
options) is run on mono_wall's matched pixels with views 2 and 3 deskewed,
x <- x - s_v (y - c_y), over a grid of (s_2, s_3) (view 1 the reference).
Per cell: the answer's RMS and f. Then the cells whose sum of squared
residuals is within --rise noise variances of the best cell's (at the 0.2 px
per-observation floor the focal sigma assumes; the cells' inlier counts
differ by a few, so this is approximate), and the range of f over them
against the chessboard's fx 701.0.

--synthetic: the same on one noise draw of mono_wall's geometry seen
through the chessboard's whole model with known shears added to views 2 and
3 (--shears), 0.12 px noise: where the truth lies in the valley.
Figures: bench/README.md ("mono_wall against its chessboard").
Usage: PYTHONPATH=python python bench/mono_wall_shear_grid.py [--span 0.004 --cells 9]
       [--synthetic --shears 0.002,-0.0015]"""
import argparse
import os
import sys

HERE = os.path.dirname(os.path.abspath(__file__))
sys.path.insert(0, os.path.join(HERE, "..", "tests", "python"))
sys.path.insert(0, os.path.join(HERE, "..", "python"))
import numpy as np  # noqa: E402

import libsfm  # noqa: E402
from mono_wall_models import chessboard_views  # noqa: E402
from test_recon import MONO_WALL as CB, boof_images  # noqa: E402

FLOOR = 0.2  # px, FOCAL_NOISE_FLOOR of libsfm/recon/metric_upgrade.c


def main():
    ap = argparse.ArgumentParser()
    ap.add_argument("--span", type=float, default=0.004)
    ap.add_argument("--cells", type=int, default=9)
    ap.add_argument("--rise", type=float, default=9.0)
    ap.add_argument("--synthetic", action="store_true")
    ap.add_argument("--shears", default="0.002,-0.0015")
    ap.add_argument("--noise", type=float, default=0.12)
    a = ap.parse_args()
    imgs = boof_images("mono_wall")
    h, w = imgs[0].shape
    g = libsfm.reconstruct_three_view_images(*imgs, seed=1, max_focal_sigma=1.0 if a.synthetic else None)
    if a.synthetic:
        truth = [float(v) for v in a.shears.split(",")]
        xs = chessboard_views(g, h, np.random.default_rng(2020), a.noise, [0.0] + truth)
        print("synthetic: mono_wall's geometry, the chessboard's model (f %.1f), shears %s, %.2f px noise"
              % (CB["fx"], truth, a.noise))
    else:
        xs = [np.asarray(x, float) for x in g["x"]]
        print("mono_wall, images path: f %.1f px without a shear, RMS %.4f px, %d inliers"
              % (g["K"][0, 0, 0], g["report"]["rms"], g["report"]["inliers"]))
    cy = (h - 1) / 2
    vals = np.linspace(-a.span, a.span, a.cells)
    res = {}
    for s2 in vals:
        for s3 in vals:
            ob = [x.copy() for x in xs]
            ob[1][:, 0] -= s2 * (ob[1][:, 1] - cy)
            ob[2][:, 0] -= s3 * (ob[2][:, 1] - cy)
            try:
                r = libsfm.reconstruct_three_view(ob[0], ob[1], ob[2], w, h, seed=1,
                                                  max_focal_sigma=1.0 if a.synthetic else None)
                rep = r["report"]
                res[(s2, s3)] = (rep["rms"], r["K"][0, 0, 0], rep["inliers"])
            except libsfm.SfmError:
                res[(s2, s3)] = None
    print("RMS px / f px; rows s_2, columns s_3 from %+.4f to %+.4f" % (vals[0], vals[-1]))
    for s2 in vals:
        print("%+.4f " % s2 + "".join("     refused" if res[(s2, s3)] is None else
                                      "  %.4f/%4.0f" % res[(s2, s3)][:2] for s3 in vals))
    ok = {k: v for k, v in res.items() if v is not None}
    ss = {k: v[0] ** 2 * 3 * v[2] for k, v in ok.items()}
    best = min(ss, key=ss.get)
    near = [k for k in ok if ss[k] - ss[best] < a.rise * FLOOR ** 2]
    fs = np.array([ok[k][1] for k in near])
    print("best cell s = (%+.4f, %+.4f): RMS %.4f, f %.1f px (%+.2f %%); %d cells within %g noise variances "
          "(at %.1f px): f %.1f-%.1f px (%+.2f to %+.2f %% against %.1f)"
          % (best[0], best[1], ok[best][0], ok[best][1], 100 * (ok[best][1] / CB["fx"] - 1), len(near), a.rise,
             FLOOR, fs.min(), fs.max(), 100 * (fs.min() / CB["fx"] - 1), 100 * (fs.max() / CB["fx"] - 1),
             CB["fx"]))


if __name__ == "__main__":
    main()
