"""Robot-to-robot refinement and RANSAC (sfm_r2r_refine, sfm_r2r_ransac).

Steps are the dicts of libsfm.r2r (R1, t1, R2, t2 and any of d, b1, b2; the
conversion is that module's). (C, p) maps x_{1} = C x_{2} + p. Covariances
are (6, 6) over (w, p): w the rotation increment of C <- exp([w]x) C in
radians, then p, from the Gauss-Newton matrix of the residuals whitened by
sigma_d (distances) and sigma_b (bearings, radians).
"""
import numpy as np

from ._ffi import check, ffi, lib, to_float, to_int, to_seed, workspace
from .r2r import _check_steps, _steps, _transform
from .results import ransac_result

__all__ = ["r2r_refine", "r2r_ransac", "R2R_LOSSES"]

#: Robust losses of r2r_refine by name (SFM_R2R_LOSS_*).
R2R_LOSSES = {"squared": lib.SFM_R2R_LOSS_SQUARED, "huber": lib.SFM_R2R_LOSS_HUBER,
              "cauchy": lib.SFM_R2R_LOSS_CAUCHY}

_STOP = {lib.SFM_R2R_STOP_GRADIENT: "gradient", lib.SFM_R2R_STOP_FUNCTION: "function",
         lib.SFM_R2R_STOP_STEP: "step", lib.SFM_R2R_STOP_MAX_ITERATIONS: "max_iterations",
         lib.SFM_R2R_STOP_TRUST_REGION: "trust_region", lib.SFM_R2R_STOP_NONE: "none"}


def _refine_options(o, sigma_d, sigma_b, max_iterations=None, loss=None, loss_scale=None):
    check(lib.sfm_r2r_refine_default_options(o), "sfm_r2r_refine_default_options")
    o.sigma_d = to_float(sigma_d, "sigma_d")
    o.sigma_b = to_float(sigma_b, "sigma_b")
    if max_iterations is not None:
        o.max_iterations = to_int(max_iterations, "max_iterations", 0)
    if loss is not None:
        if loss not in R2R_LOSSES:
            raise ValueError("loss must be one of %s, got %r" % (sorted(R2R_LOSSES), loss))
        o.loss = R2R_LOSSES[loss]
    if loss_scale is not None:
        o.loss_scale = to_float(loss_scale, "loss_scale")


def _unpack(T):
    return (np.array(list(T.C.m)).reshape(3, 3), np.array(list(T.p.v)))


def r2r_refine(steps, C, p, sigma_d, sigma_b, max_iterations=None, loss="squared",
               loss_scale=None, return_stats=False):
    """Maximum-likelihood (C, p) from the initial (C, p) over every
    measurement of steps (sfm_r2r_refine): returns (C, p, covariance), and a
    dict of the run (iterations, successful_steps, initial_cost, final_cost,
    stop_reason, n_equations) as a fourth item with return_stats.
    loss: "squared", "huber" or "cauchy" on each measurement's whitened
    residual, loss_scale in sigmas."""
    arr = _steps(steps)
    T = _transform(C, p)
    o = ffi.new("sfm_r2r_refine_options *")
    _refine_options(o, sigma_d, sigma_b, max_iterations, loss, loss_scale)
    out = ffi.new("sfm_r2r_transform *")
    cov = np.empty(36)
    st = ffi.new("sfm_r2r_refine_stats *")
    _check_steps(lib.sfm_r2r_refine(arr, len(arr), T, o, out,
                                    ffi.cast("double *", ffi.from_buffer(cov)), st),
                 "sfm_r2r_refine", steps, C=C, p=p)
    Cr, pr = _unpack(out)
    res = (Cr, pr, cov.reshape(6, 6))
    if return_stats:
        res += (dict(iterations=int(st.iterations), successful_steps=int(st.successful_steps),
                     initial_cost=float(st.initial_cost), final_cost=float(st.final_cost),
                     stop_reason=_STOP.get(int(st.stop_reason), str(int(st.stop_reason))),
                     n_equations=int(st.n_equations)),)
    return res


def r2r_ransac(steps, sigma_d, sigma_b, threshold=3.0, seed=None, confidence=None,
               max_iterations=None, min_iterations=None, lo_rounds=None, use_sprt=None):
    """(C, p) from steps whose measurements may hold gross outliers
    (sfm_r2r_ransac): a libsfm.Result with C, p, covariance and inliers, an
    (n_steps, 3) bool array over (d, b1, b2) (False where a step carries no
    such measurement); num_inliers counts inlier measurements. threshold is
    the normalised residual (in sigmas) of an inlier; the other options are
    those of sfm_ransac_options (defaults from sfm_r2r_ransac_default_options)."""
    arr = _steps(steps)
    n = len(arr)
    o = ffi.new("sfm_r2r_ransac_options *")
    check(lib.sfm_r2r_ransac_default_options(o), "sfm_r2r_ransac_default_options")
    _refine_options(ffi.addressof(o[0], "refine"), sigma_d, sigma_b)
    o.ransac.threshold = to_float(threshold, "threshold")
    if seed is not None:
        o.ransac.seed = to_seed(seed)
    if confidence is not None:
        o.ransac.confidence = to_float(confidence, "confidence")
    if max_iterations is not None:
        o.ransac.max_iterations = to_int(max_iterations, "max_iterations", 1)
    if min_iterations is not None:
        o.ransac.min_iterations = to_int(min_iterations, "min_iterations", 0)
    if lo_rounds is not None:
        o.ransac.lo_rounds = to_int(lo_rounds, "lo_rounds", 0)
    if use_sprt is not None:
        o.ransac.use_sprt = 1 if use_sprt else 0
    buf, ptr, size = workspace(lib.sfm_r2r_ransac_workspace_size(n))
    out = ffi.new("sfm_r2r_transform *")
    inl = ffi.new("unsigned[]", n)
    cov = np.empty(36)
    st = ffi.new("sfm_ransac_stats *")
    _check_steps(lib.sfm_r2r_ransac(arr, n, o, out, inl, ffi.cast("double *", ffi.from_buffer(cov)),
                                    st, ptr, size), "sfm_r2r_ransac", steps)
    mask = np.array([[(inl[k] >> b) & 1 for b in range(3)] for k in range(n)], dtype=np.uint8)
    C, p = _unpack(out)
    return ransac_result(st, mask, "sfm_r2r_ransac", C=C, p=p)
