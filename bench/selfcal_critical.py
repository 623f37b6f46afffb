"""Linear self-calibration (sfm_selfcal_linear, no tracks) on factorized
tracks of the scenes of tests/python/test_recon.py: turntables (optical axes
through the centre of the cloud, spans 0.3, 1.2 and 3 rad) must be refused,
general motion answered. 12 scenes per row; per row the answers, the largest
|f / 800 - 1| among them and the range of result.weak_ratio. Figures:
bench/README.md ("Linear self-calibration").
Usage: PYTHONPATH=python python bench/selfcal_critical.py"""
import os, sys
HERE = os.path.dirname(os.path.abspath(__file__))
sys.path.insert(0, os.path.join(HERE, "..", "tests", "python"))
sys.path.insert(0, os.path.join(HERE, "..", "python"))
import numpy as np, libsfm
from test_recon import views


def one(kind, rng, **kw):
    x = views(rng, kind, **kw)
    r = libsfm.factorize_projective(x)
    try:
        s = libsfm.self_calibrate(r["P"], (640, 480), r["X"])
        return True, np.median(s["K"][:, 0, 0]), s["weak_ratio"]
    except libsfm.SfmError as e:
        return False, e.flags, e.weak_ratio


print("motion | views | sigma px | span rad | answered | max |f err| | weak ratio min-max")
for kind in ("turntable", "general"):
    for m in (3, 5, 8):
        for sig in (0.1, 0.5, 1.0, 2.0):
            for sp in ((0.3, 1.2, 3.0) if kind == "turntable" else (None,)):
                rng = np.random.default_rng(100 + m)
                kw = dict(m=m, sigma=sig)
                if sp:
                    kw["span"] = sp
                out = [one(kind, rng, **kw) for _ in range(12)]
                errs = [abs(o[1] / 800 - 1) for o in out if o[0]]
                wr = [o[2] for o in out]
                print("%s | %d | %.1f | %s | %d of %d | %s | %.2f-%.2f" % (
                    kind, m, sig, sp if sp else "-", len(errs), len(out),
                    "%.3f" % max(errs) if errs else "-", min(wr), max(wr)), flush=True)
