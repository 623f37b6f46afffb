"""Robust estimation: relative pose, upright relative pose, absolute pose,
fundamental matrix and homography by RANSAC (SPRT, MSAC, LO, PROSAC).

Every estimator takes pixel coordinates ((n, 2) float arrays) and the
cameras' intrinsics as a libsfm.Camera (pinhole, Brown-Conrady or
Kannala-Brandt fisheye) or a 3x3 matrix K with an optional OpenCV
Brown-Conrady vector dist (k1, k2, p1, p2[, k3]), and returns a
libsfm.Result (a dict whose entries are also attributes; see Result for the
entries every estimator shares) with the model entries listed per function.
Poses map the first camera (or the world) to the camera: x_cam2 = R x_cam1 +
t, |t| = 1 for relative poses.

Options are keyword arguments, the same for every estimator (the trifocal
ones included), their defaults read from the C library's
sfm_ransac_default_options (see RANSAC_DEFAULTS):

  threshold_px    inlier threshold in pixels (> 0)
  seed            any Python int, taken modulo 2**64; the same seed gives the
                  same result, bit for bit
  confidence      in (0, 1): stop when a better model is that unlikely
  max_iterations  >= 1; min_iterations >= 0 samples drawn at least
  lo_rounds       local-optimisation rounds (0: none)
  polish_rounds   final polish rounds on the winner (0: none)
  use_sprt        early rejection of bad models (SPRT and bail-out)
  quality         optional (n,) per-match quality, higher is better
                  (PROSAC sampling)

Arguments are checked before any C call (ValueError or TypeError naming the
argument); a C failure raises SfmError.
"""
import numpy as np

from ._ffi import (as_array, check, dptr, ffi, lib, mptr, to_float, to_int, to_seed, u8ptr,
                   workspace)
from .camera import as_camera
from .results import ransac_result

__all__ = ["estimate_relative_pose", "estimate_relative_pose_upright", "estimate_absolute_pose",
           "estimate_fundamental", "estimate_homography", "RANSAC_DEFAULTS"]


def _c_defaults():
    o = ffi.new("sfm_ransac_options *")
    check(lib.sfm_ransac_default_options(o), "sfm_ransac_default_options")
    return dict(threshold_px=float(o.threshold), seed=int(o.seed), confidence=float(o.confidence),
                max_iterations=int(o.max_iterations), min_iterations=int(o.min_iterations),
                lo_rounds=int(o.lo_rounds), polish_rounds=int(o.polish_rounds),
                use_sprt=bool(o.use_sprt))


#: The C library's RANSAC defaults (sfm_ransac_default_options), the
#: defaults of every estimator's keyword options.
RANSAC_DEFAULTS = _c_defaults()
_D = RANSAC_DEFAULTS


#: The keyword options every estimator takes, in signature order.
OPTION_NAMES = ("threshold_px", "seed", "confidence", "max_iterations", "min_iterations",
                "lo_rounds", "polish_rounds", "use_sprt", "quality")


def options_of(args):
    """The options among an estimator's arguments (its locals())."""
    return {k: args[k] for k in OPTION_NAMES}


def ransac_options(threshold_px, seed, confidence, max_iterations, min_iterations, lo_rounds,
                   polish_rounds, use_sprt, quality, n):
    """An sfm_ransac_options from the keyword options, each checked and named
    (and the quality array it points into, to keep alive)."""
    opt = ffi.new("sfm_ransac_options *")
    check(lib.sfm_ransac_default_options(opt), "sfm_ransac_default_options")
    thr = to_float(threshold_px, "threshold_px")
    if not thr > 0:
        raise ValueError("threshold_px must be > 0, got %r" % thr)
    conf = to_float(confidence, "confidence")
    if not 0 < conf < 1:
        raise ValueError("confidence must be in (0, 1), got %r" % conf)
    opt.threshold = thr
    opt.confidence = conf
    opt.seed = to_seed(seed)
    opt.max_iterations = to_int(max_iterations, "max_iterations", 1)
    opt.min_iterations = to_int(min_iterations, "min_iterations", 0, opt.max_iterations)
    opt.lo_rounds = to_int(lo_rounds, "lo_rounds", 0)
    opt.polish_rounds = to_int(polish_rounds, "polish_rounds", 0)
    if use_sprt not in (True, False, 0, 1):
        raise ValueError("use_sprt must be True or False, got %r" % (use_sprt,))
    opt.use_sprt = 1 if use_sprt else 0
    keep = None
    if quality is not None:
        keep = as_array(quality, (n,), "quality")
        if not np.all(np.isfinite(keep)):
            raise ValueError("quality must be finite")
        opt.quality = dptr(keep)
    return opt, keep


def pairs(p1, p2, minimum, names=("p1", "p2")):
    """Two (n, 2) pixel arrays of one length n >= minimum."""
    p1 = as_array(p1, (None, 2), names[0])
    p2 = as_array(p2, (p1.shape[0], 2), names[1])
    if p1.shape[0] < minimum:
        raise ValueError("need at least %d point pairs, got %d" % (minimum, p1.shape[0]))
    if p1.shape[0] > lib.SFM_RANSAC_MAX_POINTS:
        raise ValueError("at most %d points, got %d" % (lib.SFM_RANSAC_MAX_POINTS, p1.shape[0]))
    return p1, p2


def _pose(pose):
    return np.array(list(pose.R)).reshape(3, 3), np.array(list(pose.t))


def _want_covariance(opt, covariance):
    if covariance not in (True, False, 0, 1):
        raise ValueError("covariance must be True or False, got %r" % (covariance,))
    opt.want_covariance = 1 if covariance else 0


def _relative(upright, p1, p2, K1, K2, d1, d2, dist1, dist2, options, covariance=False):
    p1, p2 = pairs(p1, p2, 3 if upright else 5)
    n = p1.shape[0]
    c1, c2 = as_camera(K1, dist1, "K1"), as_camera(K2, dist2, "K2")
    opt, keep = ransac_options(n=n, **options)
    _want_covariance(opt, covariance)
    pose = ffi.new("sfm_pose *")
    E = np.zeros((3, 3))
    mask = np.zeros(n, dtype=np.uint8)
    st = ffi.new("sfm_ransac_stats *")
    inputs = {"p1": p1, "p2": p2}
    if upright:
        d1 = as_array(d1, (3,), "d1")
        d2 = as_array(d2, (3,), "d2")
        inputs.update(d1=d1, d2=d2)
        where = "sfm_ransac_relpose_upright"
        buf, ws, wsn = workspace(lib.sfm_ransac_relpose_upright_workspace_size(n))
        rc = lib.sfm_ransac_relpose_upright(dptr(p1), dptr(p2), n, c1._c, c2._c, dptr(d1), dptr(d2),
                                            opt, pose, mptr(E), u8ptr(mask), st, ws, wsn)
    else:
        where = "sfm_ransac_relpose"
        buf, ws, wsn = workspace(lib.sfm_ransac_relpose_workspace_size(n))
        rc = lib.sfm_ransac_relpose(dptr(p1), dptr(p2), n, c1._c, c2._c, opt, pose, mptr(E),
                                    u8ptr(mask), st, ws, wsn)
    check(rc, where, inputs)
    R, t = _pose(pose)
    del keep, buf
    twin = None
    if st.has_twin:
        twin = (np.array(list(st.twin.R)).reshape(3, 3), np.array(list(st.twin.t)))
    return ransac_result(st, mask, where, R=R, t=t, E=E,
                         planar=bool(st.flags & lib.SFM_RANSAC_FLAG_PLANAR),
                         pure_rotation=bool(st.flags & lib.SFM_RANSAC_FLAG_PURE_ROTATION),
                         twin=twin)


def estimate_relative_pose(p1, p2, K1, K2, *, dist1=None, dist2=None,
                           threshold_px=_D["threshold_px"], seed=_D["seed"],
                           confidence=_D["confidence"], max_iterations=_D["max_iterations"],
                           min_iterations=_D["min_iterations"], lo_rounds=_D["lo_rounds"],
                           polish_rounds=_D["polish_rounds"], use_sprt=_D["use_sprt"],
                           quality=None, covariance=False):
    """Calibrated relative pose from n >= 5 pixel pairs (5-point RANSAC).

    p1, p2: (n, 2) pixels in images 1 and 2. K1, K2: libsfm.Camera or 3x3 K
    (dist1, dist2: OpenCV Brown vectors for a K). Options: see
    libsfm.robust.

    Returns a Result with R (3, 3), t (3,), |t| = 1, x_cam2 = R x_cam1 + t;
    E (3, 3), unit Frobenius norm, x2^T E x1 = 0 for normalized x; planar and
    pure_rotation (bools: the inliers are explained by one homography, or by
    a rotation alone; t is then not to be trusted); twin: with planar, the
    plane's second pose (R, t), the truth being (R, t) or twin (None
    otherwise). covariance=True adds the
    (6, 6) pose covariance (Result.covariance; None otherwise)."""
    return _relative(False, p1, p2, K1, K2, None, None, dist1, dist2, options_of(locals()),
                     covariance)


def estimate_relative_pose_upright(p1, p2, K1, K2, d1, d2, *, dist1=None, dist2=None,
                                   threshold_px=_D["threshold_px"], seed=_D["seed"],
                                   confidence=_D["confidence"],
                                   max_iterations=_D["max_iterations"],
                                   min_iterations=_D["min_iterations"],
                                   lo_rounds=_D["lo_rounds"], polish_rounds=_D["polish_rounds"],
                                   use_sprt=_D["use_sprt"], quality=None, covariance=False):
    """Relative pose from n >= 3 pixel pairs and a direction known in both
    frames (3-point upright RANSAC).

    p1, p2: (n, 2) pixels; K1, K2 as estimate_relative_pose; d1 (3,): the
    direction (e.g. gravity) in camera 1, d2 (3,) = R d1 in camera 2.
    Returns the entries of estimate_relative_pose."""
    return _relative(True, p1, p2, K1, K2, d1, d2, dist1, dist2, options_of(locals()), covariance)


def estimate_absolute_pose(p, X, K, *, dist=None, threshold_px=_D["threshold_px"],
                           seed=_D["seed"], confidence=_D["confidence"],
                           max_iterations=_D["max_iterations"],
                           min_iterations=_D["min_iterations"], lo_rounds=_D["lo_rounds"],
                           polish_rounds=_D["polish_rounds"], use_sprt=_D["use_sprt"],
                           quality=None, covariance=False):
    """Absolute pose from n >= 3 pixels and their world points (P3P RANSAC).

    p: (n, 2) pixels; X: (n, 3) world points (any unit); K: libsfm.Camera or
    3x3 K (dist: OpenCV Brown vector for a K). Options: see libsfm.robust.
    Returns a Result with R (3, 3), t (3,) in X's unit, x_cam = R X + t;
    covariance=True adds the (6, 6) pose covariance."""
    p = as_array(p, (None, 2), "p")
    n = p.shape[0]
    X = as_array(X, (n, 3), "X")
    if n < 3:
        raise ValueError("need at least 3 points, got %d" % n)
    if n > lib.SFM_RANSAC_MAX_POINTS:
        raise ValueError("at most %d points, got %d" % (lib.SFM_RANSAC_MAX_POINTS, n))
    cam = as_camera(K, dist, "K")
    opt, keep = ransac_options(n=n, **options_of(locals()))
    _want_covariance(opt, covariance)
    buf, ws, wsn = workspace(lib.sfm_ransac_abspose_workspace_size(n))
    pose = ffi.new("sfm_pose *")
    mask = np.zeros(n, dtype=np.uint8)
    st = ffi.new("sfm_ransac_stats *")
    check(lib.sfm_ransac_abspose(dptr(p), dptr(X), n, cam._c, opt, pose, u8ptr(mask), st, ws, wsn),
          "sfm_ransac_abspose", {"p": p, "X": X})
    R, t = _pose(pose)
    del keep, buf
    return ransac_result(st, mask, "sfm_ransac_abspose", R=R, t=t)


def _uncalibrated(fn, size_fn, minimum, p1, p2, K1, K2, dist1, dist2, options, where):
    p1, p2 = pairs(p1, p2, minimum)
    n = p1.shape[0]
    if (K1 is None) != (K2 is None):
        raise ValueError("give both K1 and K2 or neither")
    if K1 is None and (dist1 is not None or dist2 is not None):
        raise ValueError("dist1/dist2 need K1 and K2")
    c1 = c2 = ffi.NULL
    if K1 is not None:
        c1, c2 = as_camera(K1, dist1, "K1")._c, as_camera(K2, dist2, "K2")._c
    opt, keep = ransac_options(n=n, **options)
    buf, ws, wsn = workspace(size_fn(n))
    M = np.zeros((3, 3))
    mask = np.zeros(n, dtype=np.uint8)
    st = ffi.new("sfm_ransac_stats *")
    check(fn(dptr(p1), dptr(p2), n, c1, c2, opt, mptr(M), u8ptr(mask), st, ws, wsn), where,
          {"p1": p1, "p2": p2})
    del keep, buf
    return st, mask, M


def estimate_fundamental(p1, p2, K1=None, K2=None, *, dist1=None, dist2=None,
                         threshold_px=_D["threshold_px"], seed=_D["seed"],
                         confidence=_D["confidence"], max_iterations=_D["max_iterations"],
                         min_iterations=_D["min_iterations"], lo_rounds=_D["lo_rounds"],
                         polish_rounds=_D["polish_rounds"], use_sprt=_D["use_sprt"],
                         quality=None):
    """Fundamental matrix from n >= 8 pixel pairs (7-point RANSAC with
    DEGENSAC).

    p1, p2: (n, 2) pixels. With cameras K1, K2 (libsfm.Camera, or 3x3 K with
    dist1, dist2) the pixels are first undistorted to ideal pinhole pixels.
    Options: see libsfm.robust. Returns a Result with F (3, 3), unit
    Frobenius norm, p2h^T F p1h = 0 for homogeneous pixels, and degensac
    (bool: a dominant plane was found and plane-and-parallax applied; F then
    rests on the points off the plane)."""
    st, mask, F = _uncalibrated(lib.sfm_ransac_fundamental, lib.sfm_ransac_fundamental_workspace_size,
                                8, p1, p2, K1, K2, dist1, dist2, options_of(locals()), "sfm_ransac_fundamental")
    return ransac_result(st, mask, "sfm_ransac_fundamental", F=F,
                         degensac=bool(st.flags & lib.SFM_RANSAC_FLAG_DEGENSAC))


def estimate_homography(p1, p2, K1=None, K2=None, *, dist1=None, dist2=None,
                        threshold_px=_D["threshold_px"], seed=_D["seed"],
                        confidence=_D["confidence"], max_iterations=_D["max_iterations"],
                        min_iterations=_D["min_iterations"], lo_rounds=_D["lo_rounds"],
                        polish_rounds=_D["polish_rounds"], use_sprt=_D["use_sprt"],
                        quality=None):
    """Homography from n >= 4 pixel pairs (4-point RANSAC on the Sampson
    error in pixels, noise in both images; LO by DLT and Sampson LM).

    p1, p2: (n, 2) pixels; K1, K2 (optional) as estimate_fundamental.
    Options: see libsfm.robust. Returns a Result with H (3, 3), unit
    Frobenius norm, p2h ~ H p1h for homogeneous pixels."""
    st, mask, H = _uncalibrated(lib.sfm_ransac_homography, lib.sfm_ransac_homography_workspace_size,
                                4, p1, p2, K1, K2, dist1, dist2, options_of(locals()), "sfm_ransac_homography")
    return ransac_result(st, mask, "sfm_ransac_homography", H=H)
