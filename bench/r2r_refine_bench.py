"""sfm_r2r_refine beside scipy.optimize.least_squares (MINPACK LM) on the
same whitened cost, and sfm_r2r_ransac on sequences with outlier
measurements: wall clock per call, one process, printed as a ratio.

    PYTHONPATH=python .venv/bin/python bench/r2r_refine_bench.py
"""
import os
import sys
import time

import numpy as np
from scipy.optimize import least_squares
from scipy.spatial.transform import Rotation

sys.path.insert(0, os.path.join(os.path.dirname(os.path.abspath(__file__)), "..", "tests", "python"))
import libsfm  # noqa: E402
from libsfm._ffi import ffi, lib  # noqa: E402
from libsfm.r2r import _steps, _transform  # noqa: E402
from test_r2r_refine import residuals, rot_err, world_steps  # noqa: E402


def timed(fn, reps):
    best = np.inf
    for _ in range(3):
        t0 = time.perf_counter()
        for _ in range(reps):
            fn()
        best = min(best, (time.perf_counter() - t0) / reps)
    return best


def main():
    rng = np.random.default_rng(0)
    sd, sb = 0.05, 0.01
    n_steps = 10
    rows = []
    for _ in range(10):
        steps, C, p = world_steps(rng, n_steps, sd, sb)
        C0 = Rotation.from_rotvec(rng.normal(0, 0.05, 3)).as_matrix() @ C
        p0 = p + rng.normal(0, 0.2, 3)
        t_lib = timed(lambda: libsfm.r2r_refine(steps, C0, p0, sd, sb), 20)
        arr, T = _steps(steps), _transform(C0, p0)
        o = ffi.new("sfm_r2r_refine_options *")
        lib.sfm_r2r_refine_default_options(o)
        o.sigma_d, o.sigma_b = sd, sb
        out, cov = ffi.new("sfm_r2r_transform *"), ffi.new("double[36]")
        t_c = timed(lambda: lib.sfm_r2r_refine(arr, n_steps, T, o, out, cov, ffi.NULL), 200)
        t_sp = timed(lambda: least_squares(residuals, np.r_[np.zeros(3), p0], args=(steps, C0, sd, sb),
                                           method="lm", xtol=1e-12, ftol=1e-12), 3)
        Cr, pr, _ = libsfm.r2r_refine(steps, C0, p0, sd, sb)
        sol = least_squares(residuals, np.r_[np.zeros(3), p0], args=(steps, C0, sd, sb), method="lm",
                            xtol=1e-12, ftol=1e-12)
        Cs = Rotation.from_rotvec(sol.x[:3]).as_matrix() @ C0
        rows.append((t_lib, t_sp, rot_err(Cr, Cs), np.linalg.norm(pr - sol.x[3:]), t_c))
    r = np.array(rows)
    print("r2r refine, %d steps (30 measurements), sigma_d %.2f m, sigma_b %.2f rad, 10 problems"
          % (n_steps, sd, sb))
    print("  libsfm.r2r_refine   median %8.1f us/call (cffi call and step conversion included)"
          % (1e6 * np.median(r[:, 0])))
    print("  sfm_r2r_refine      median %8.1f us/call (the C call alone, inputs converted once)"
          % (1e6 * np.median(r[:, 4])))
    print("  scipy least_squares median %8.1f us/call (lm, numerical Jacobian, Python residuals)"
          % (1e6 * np.median(r[:, 1])))
    print("  ratio scipy / libsfm %.0f (binding) %.0f (C call); answers agree to %.1e rad, %.1e m"
          % (np.median(r[:, 1] / r[:, 0]), np.median(r[:, 1] / r[:, 4]), r[:, 2].max(), r[:, 3].max()))

    times, errs = [], []
    for trial in range(10):
        steps, C, p = world_steps(rng, n_steps, 0.02, sb)
        for k, j in rng.permutation([(k, j) for k in range(n_steps) for j in range(3)])[:9]:
            if j == 0:
                steps[k]["d"] += rng.uniform(1, 3)
            else:
                steps[k]["b%d" % j] = Rotation.random(random_state=rng).apply([1.0, 0, 0])
        times.append(timed(lambda: libsfm.r2r_ransac(steps, 0.02, sb, seed=trial), 5))
        res = libsfm.r2r_ransac(steps, 0.02, sb, seed=trial)
        errs.append((rot_err(res.C, C), np.linalg.norm(res.p - p), res.iterations))
    e = np.array(errs)
    print("r2r RANSAC, %d steps, 9 of 30 measurements outliers, 10 problems" % n_steps)
    print("  libsfm.r2r_ransac   median %8.1f us/call, %d-%d samples; errors up to %.4f rad, %.4f m"
          % (1e6 * np.median(times), e[:, 2].min(), e[:, 2].max(), e[:, 0].max(), e[:, 1].max()))
    print("  ratio RANSAC / refine %.1f" % (np.median(times) / np.median(r[:, 0])))


if __name__ == "__main__":
    main()
