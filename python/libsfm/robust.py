"""Robust estimation: relative pose, upright relative pose, absolute pose,
fundamental matrix and homography by RANSAC (SPRT, MSAC, LO, PROSAC).

Every function takes pixel coordinates (n x 2 float arrays) and camera
intrinsics K (3x3) with optional distortion (OpenCV's Brown-Conrady 5-vector
k1, k2, p1, p2, k3), and returns a plain dict:

  inliers       bool array (n,): the returned model's inliers
  num_inliers   int
  iterations    samples drawn
  models        models verified
  sprt_rejected models dropped early (SPRT or the bail-out test)
  lo_runs       local optimisations run
  polished      the final polish (refit on the points within 3.5 robust
                standard deviations of the winner's residuals, between 1 and
                3 thresholds, under a Cauchy loss) was kept
  score         MSAC cost (pixels squared)
  seed          the seed used
  stop_reason   "confidence", "max_iterations" or "time"
  flags         raw SFM_RANSAC_FLAG_* bits
  degenerate    bool: the model is a partial answer (see degeneracy)
  degeneracy    "" or "pure_rotation" (R without t), "low_parallax" (R
                determined, the direction of t not), "planar" (a dominant
                plane: a relative pose may be the twin of the true one, F
                rests on the few points off the plane)
  covariance    pose estimators: 6x6 covariance of (w, t), w the rotation
                increment R <- exp([w]x) R in radians (see sfm_ransac.h);
                None for F and H

A support that does not determine the model (points on one line, one tight
cluster, all points on one plane for F) raises SfmError with status
SFM_E_DEGENERATE; a support no better than random matches raises SfmError
with SFM_E_NO_MODEL.

plus the model entries listed per function. Poses map the first camera (or
the world) to the camera: x_cam2 = R x_cam1 + t, |t| = 1 for relative poses.
The same seed gives the same result, bit for bit.
Shapes are checked before any C call (ValueError); a C failure raises
SfmError.
"""
import numpy as np

from ._ffi import as_array, check, dptr, ffi, lib, workspace

_STOP = {0: "confidence", 1: "max_iterations", 2: "time"}


def _camera(K, dist, name):
    K = as_array(K, (3, 3), name)
    cam = ffi.new("sfm_camera *")
    cam.fx, cam.fy, cam.cx, cam.cy = K[0, 0], K[1, 1], K[0, 2], K[1, 2]
    if dist is None:
        cam.model = lib.SFM_CAMERA_PINHOLE
    else:
        d = np.asarray(dist, dtype=np.float64).ravel()
        if d.size not in (4, 5):
            raise ValueError("distortion of %s must have 4 or 5 entries (k1, k2, p1, p2[, k3])" % name)
        cam.model = lib.SFM_CAMERA_BROWN
        for i in range(d.size):
            cam.dist[i] = d[i]
    return cam


def _options(threshold_px, seed, confidence, max_iterations, min_iterations, lo_rounds,
             use_sprt, quality, n, polish_rounds=2):
    opt = ffi.new("sfm_ransac_options *")
    lib.sfm_ransac_default_options(opt)
    opt.threshold = float(threshold_px)
    opt.seed = int(seed) & 0xFFFFFFFFFFFFFFFF
    opt.confidence = float(confidence)
    opt.max_iterations = int(max_iterations)
    opt.min_iterations = int(min_iterations)
    opt.lo_rounds = int(lo_rounds)
    opt.polish_rounds = int(polish_rounds)
    opt.use_sprt = 1 if use_sprt else 0
    keep = None
    if quality is not None:
        keep = as_array(quality, (n,), "quality")
        opt.quality = dptr(keep)
    return opt, keep


def _pairs(p1, p2, minimum):
    p1 = as_array(p1, (None, 2), "p1")
    p2 = as_array(p2, (p1.shape[0], 2), "p2")
    if p1.shape[0] < minimum:
        raise ValueError("need at least %d point pairs, got %d" % (minimum, p1.shape[0]))
    return p1, p2


def degeneracy_name(flags):
    """The degeneracy named by SFM_RANSAC_FLAG_* bits ("" when none)."""
    for bit, name in ((lib.SFM_RANSAC_FLAG_PURE_ROTATION, "pure_rotation"),
                      (lib.SFM_RANSAC_FLAG_LOW_PARALLAX, "low_parallax"),
                      (lib.SFM_RANSAC_FLAG_PLANAR, "planar"),
                      (lib.SFM_RANSAC_FLAG_DEGENSAC, "planar")):
        if bit is not None and flags & bit:
            return name
    return ""


def _degeneracy(st):
    name = degeneracy_name(int(st.flags))
    cov = None
    if st.cov_dim == 6:
        cov = np.array(list(st.covariance)).reshape(6, 6)
    return dict(degenerate=bool(name), degeneracy=name, covariance=cov)


def _stats_dict(st, mask):
    return dict(**_degeneracy(st), inliers=mask.astype(bool), num_inliers=int(st.num_inliers),
                iterations=int(st.iterations), models=int(st.models),
                sprt_rejected=int(st.sprt_rejected), lo_runs=int(st.lo_runs),
                polished=bool(st.polished),
                score=float(st.score), seed=int(st.seed),
                stop_reason=_STOP.get(int(st.stop_reason), str(int(st.stop_reason))),
                flags=int(st.flags))


_KW = ("seed", "confidence", "max_iterations", "min_iterations", "lo_rounds", "use_sprt",
       "polish_rounds")


def _common_kwargs(kw):
    bad = set(kw) - set(_KW)
    if bad:
        raise TypeError("unknown option(s): %s" % ", ".join(sorted(bad)))
    return dict(polish_rounds=kw.get("polish_rounds", 2), seed=kw.get("seed", 0), confidence=kw.get("confidence", 0.999),
                max_iterations=kw.get("max_iterations", 10000),
                min_iterations=kw.get("min_iterations", 0), lo_rounds=kw.get("lo_rounds", 3),
                use_sprt=kw.get("use_sprt", True))


def estimate_relative_pose(p1, p2, K1, K2, threshold_px=1.0, seed=0, confidence=0.999,
                           max_iterations=10000, min_iterations=0, lo_rounds=3, use_sprt=True,
                           quality=None, dist1=None, dist2=None, polish_rounds=2):
    """Relative pose from n >= 5 pixel pairs (5-point RANSAC).

    Returns the common entries plus R (3x3), t (3,), E (3x3, unit norm),
    planar and pure_rotation (bools: the inliers are explained by one
    homography, or by a rotation alone; t is then not to be trusted).
    """
    p1, p2 = _pairs(p1, p2, 5)
    n = p1.shape[0]
    c1, c2 = _camera(K1, dist1, "K1"), _camera(K2, dist2, "K2")
    opt, keep = _options(threshold_px, seed, confidence, max_iterations, min_iterations,
                         lo_rounds, use_sprt, quality, n, polish_rounds)
    buf, ws, wsn = workspace(lib.sfm_ransac_relpose_workspace_size(n))
    pose = ffi.new("sfm_pose *")
    E = np.zeros((3, 3))
    mask = np.zeros(n, dtype=np.uint8)
    st = ffi.new("sfm_ransac_stats *")
    check(lib.sfm_ransac_relpose(dptr(p1), dptr(p2), n, c1, c2, opt, pose, dptr(E),
                                 ffi.cast("uint8_t *", ffi.from_buffer(mask)), st, ws, wsn),
          "sfm_ransac_relpose")
    out = _stats_dict(st, mask)
    out.update(R=np.array(list(pose.R)).reshape(3, 3), t=np.array(list(pose.t)), E=E,
               planar=bool(st.flags & lib.SFM_RANSAC_FLAG_PLANAR),
               pure_rotation=bool(st.flags & lib.SFM_RANSAC_FLAG_PURE_ROTATION))
    del keep, buf
    return out


def estimate_relative_pose_upright(p1, p2, K1, K2, d1, d2, threshold_px=1.0, seed=0,
                                   confidence=0.999, max_iterations=10000, min_iterations=0,
                                   lo_rounds=3, use_sprt=True, quality=None, dist1=None,
                                   dist2=None, polish_rounds=2):
    """Relative pose from n >= 3 pixel pairs and a direction known in both
    frames (d1 in camera 1, d2 = R d1 in camera 2, e.g. gravity).

    Returns the same entries as estimate_relative_pose."""
    p1, p2 = _pairs(p1, p2, 3)
    n = p1.shape[0]
    d1 = as_array(d1, (3,), "d1")
    d2 = as_array(d2, (3,), "d2")
    c1, c2 = _camera(K1, dist1, "K1"), _camera(K2, dist2, "K2")
    opt, keep = _options(threshold_px, seed, confidence, max_iterations, min_iterations,
                         lo_rounds, use_sprt, quality, n, polish_rounds)
    buf, ws, wsn = workspace(lib.sfm_ransac_relpose_upright_workspace_size(n))
    pose = ffi.new("sfm_pose *")
    E = np.zeros((3, 3))
    mask = np.zeros(n, dtype=np.uint8)
    st = ffi.new("sfm_ransac_stats *")
    check(lib.sfm_ransac_relpose_upright(dptr(p1), dptr(p2), n, c1, c2, dptr(d1), dptr(d2), opt,
                                         pose, dptr(E),
                                         ffi.cast("uint8_t *", ffi.from_buffer(mask)), st, ws,
                                         wsn), "sfm_ransac_relpose_upright")
    out = _stats_dict(st, mask)
    out.update(R=np.array(list(pose.R)).reshape(3, 3), t=np.array(list(pose.t)), E=E,
               planar=bool(st.flags & lib.SFM_RANSAC_FLAG_PLANAR),
               pure_rotation=bool(st.flags & lib.SFM_RANSAC_FLAG_PURE_ROTATION))
    del keep, buf
    return out


def estimate_absolute_pose(p, X, K, threshold_px=1.0, seed=0, confidence=0.999,
                           max_iterations=10000, min_iterations=0, lo_rounds=3, use_sprt=True,
                           quality=None, dist=None, polish_rounds=2):
    """Absolute pose from n >= 3 pixels (n x 2) and world points X (n x 3)
    (P3P RANSAC). Returns the common entries plus R (3x3), t (3,) with
    x_cam = R X + t."""
    p = as_array(p, (None, 2), "p")
    n = p.shape[0]
    X = as_array(X, (n, 3), "X")
    if n < 3:
        raise ValueError("need at least 3 points, got %d" % n)
    cam = _camera(K, dist, "K")
    opt, keep = _options(threshold_px, seed, confidence, max_iterations, min_iterations,
                         lo_rounds, use_sprt, quality, n, polish_rounds)
    buf, ws, wsn = workspace(lib.sfm_ransac_abspose_workspace_size(n))
    pose = ffi.new("sfm_pose *")
    mask = np.zeros(n, dtype=np.uint8)
    st = ffi.new("sfm_ransac_stats *")
    check(lib.sfm_ransac_abspose(dptr(p), dptr(X), n, cam, opt, pose,
                                 ffi.cast("uint8_t *", ffi.from_buffer(mask)), st, ws, wsn),
          "sfm_ransac_abspose")
    out = _stats_dict(st, mask)
    out.update(R=np.array(list(pose.R)).reshape(3, 3), t=np.array(list(pose.t)))
    del keep, buf
    return out


def _uncalibrated(fn, size_fn, minimum, p1, p2, K1, K2, dist1, dist2, threshold_px, quality, kw,
                  name):
    p1, p2 = _pairs(p1, p2, minimum)
    n = p1.shape[0]
    if (K1 is None) != (K2 is None):
        raise ValueError("give both K1 and K2 or neither")
    c1 = c2 = ffi.NULL
    if K1 is not None:
        c1, c2 = _camera(K1, dist1, "K1"), _camera(K2, dist2, "K2")
    opt, keep = _options(threshold_px, quality=quality, n=n, **_common_kwargs(kw))
    buf, ws, wsn = workspace(size_fn(n))
    M = np.zeros((3, 3))
    mask = np.zeros(n, dtype=np.uint8)
    st = ffi.new("sfm_ransac_stats *")
    check(fn(dptr(p1), dptr(p2), n, c1, c2, opt, dptr(M),
             ffi.cast("uint8_t *", ffi.from_buffer(mask)), st, ws, wsn), name)
    out = _stats_dict(st, mask)
    del keep, buf
    return out, M


def estimate_fundamental(p1, p2, K1=None, K2=None, threshold_px=1.0, quality=None, dist1=None,
                         dist2=None, **kw):
    """Fundamental matrix from n >= 8 pixel pairs (7-point RANSAC with
    DEGENSAC). With K1, K2 (and distortion) the pixels are first undistorted
    to ideal pinhole pixels. Returns the common entries plus F (3x3, unit
    norm, p2h^T F p1h = 0) and degensac (bool: a dominant plane was found and
    plane-and-parallax applied; F then rests on the points off the plane).
    Keyword options: seed, confidence, max_iterations, min_iterations,
    lo_rounds, use_sprt."""
    out, F = _uncalibrated(lib.sfm_ransac_fundamental, lib.sfm_ransac_fundamental_workspace_size,
                           8, p1, p2, K1, K2, dist1, dist2, threshold_px, quality, kw,
                           "sfm_ransac_fundamental")
    out.update(F=F, degensac=bool(out["flags"] & lib.SFM_RANSAC_FLAG_DEGENSAC))
    return out


def estimate_homography(p1, p2, K1=None, K2=None, threshold_px=1.0, quality=None, dist1=None,
                        dist2=None, **kw):
    """Homography from n >= 4 pixel pairs (4-point RANSAC on the Sampson
    error in pixels, noise in both images; LO by DLT and Sampson LM). Returns
    the common entries plus H (3x3, unit norm, p2h ~ H p1h).
    Keyword options as estimate_fundamental."""
    out, H = _uncalibrated(lib.sfm_ransac_homography, lib.sfm_ransac_homography_workspace_size,
                           4, p1, p2, K1, K2, dist1, dist2, threshold_px, quality, kw,
                           "sfm_ransac_homography")
    out.update(H=H)
    return out
