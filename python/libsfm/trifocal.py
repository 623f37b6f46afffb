"""The trifocal tensor of three views: T[i, j, k] = T_i^{jk} (Hartley &
Zisserman), view 1 the reference. Pixels are (n, 2) arrays; cameras 3x4."""
import numpy as np

from ._ffi import as_array, check, dptr, ffi, lib, workspace
from .geometry import Camera


def trifocal_from_cameras(P1, P2, P3):
    """(3,3,3) tensor of three 3x4 cameras, unit Frobenius norm."""
    Ps = [as_array(P, (3, 4), name) for P, name in ((P1, "P1"), (P2, "P2"), (P3, "P3"))]
    T = np.empty((3, 3, 3))
    check(lib.sfm_trifocal_from_cameras(dptr(Ps[0]), dptr(Ps[1]), dptr(Ps[2]), dptr(T)),
          "trifocal_from_cameras")
    return T


def trifocal_7pt(x1, x2, x3):
    """Tensor from n >= 7 pixel triplets (normalized linear estimate and
    algebraic minimization, H&Z alg. 16.2)."""
    x1 = as_array(x1, (None, 2), "x1")
    n = x1.shape[0]
    x2 = as_array(x2, (n, 2), "x2")
    x3 = as_array(x3, (n, 2), "x3")
    T = np.empty((3, 3, 3))
    buf, ws, size = workspace(lib.sfm_trifocal_7pt_workspace_size())
    check(lib.sfm_trifocal_7pt(dptr(x1), dptr(x2), dptr(x3), n, dptr(T), ws, size), "trifocal_7pt")
    return T


def trifocal_epipoles(T):
    """Epipoles e' and e'' (unit 3-vectors) of views 2 and 3."""
    T = as_array(T, (3, 3, 3), "T")
    e2, e3 = np.empty(3), np.empty(3)
    check(lib.sfm_trifocal_epipoles(dptr(T), dptr(e2), dptr(e3)), "trifocal_epipoles")
    return e2, e3


def trifocal_fundamentals(T):
    """(F21, F31, F32) with x2^T F21 x1 = 0, x3^T F31 x1 = 0, x3^T F32 x2 = 0."""
    T = as_array(T, (3, 3, 3), "T")
    F = np.empty((3, 3, 3))
    check(lib.sfm_trifocal_fundamentals(dptr(T), dptr(F[0]), dptr(F[1]), dptr(F[2])),
          "trifocal_fundamentals")
    return F[0], F[1], F[2]


def cameras_from_trifocal(T):
    """(3,3,4) compatible projective cameras, the first [I | 0]."""
    T = as_array(T, (3, 3, 3), "T")
    P = np.zeros((3, 3, 4))
    P[0, :, :3] = np.eye(3)
    check(lib.sfm_trifocal_cameras(dptr(T), dptr(P[1]), dptr(P[2])), "cameras_from_trifocal")
    return P


def trifocal_transfer(T, x1, x2):
    """Points in view 3 predicted from (n,2) points in views 1 and 2."""
    T = as_array(T, (3, 3, 3), "T")
    one = np.ndim(x1) == 1
    x1 = as_array(np.atleast_2d(x1), (None, 2), "x1")
    n = x1.shape[0]
    x2 = as_array(np.atleast_2d(x2), (n, 2), "x2")
    F21, _, _ = trifocal_fundamentals(T)
    F21 = np.ascontiguousarray(F21)
    out = np.empty((n, 2))
    for p in range(n):
        check(lib.sfm_trifocal_transfer(dptr(T), dptr(F21), dptr(x1[p]), dptr(x2[p]), dptr(out[p])),
              "trifocal_transfer")
    return out[0] if one else out


def trifocal_point_error(P1, P2, P3, x1, x2, x3):
    """Summed squared three-view reprojection error of one triplet (after
    optimal triangulation) and the homogeneous point."""
    Ps = [as_array(P, (3, 4), "P") for P in (P1, P2, P3)]
    xs = [as_array(x, (2,), "x") for x in (x1, x2, x3)]
    err = ffi.new("double *")
    X = np.empty(4)
    check(lib.sfm_trifocal_point_error(dptr(Ps[0]), dptr(Ps[1]), dptr(Ps[2]), dptr(xs[0]), dptr(xs[1]),
                                       dptr(xs[2]), err, dptr(X)), "trifocal_point_error")
    return float(err[0]), X


def _ransac_options(threshold_px, seed, confidence=None, max_iterations=None):
    opt = ffi.new("sfm_ransac_options *")
    check(lib.sfm_ransac_default_options(opt), "ransac options")
    opt.threshold = float(threshold_px)
    opt.seed = int(seed)
    if confidence is not None:
        opt.confidence = float(confidence)
    if max_iterations is not None:
        opt.max_iterations = int(max_iterations)
    return opt


def _stats_dict(stats):
    from .robust import _degeneracy
    return dict(**_degeneracy(stats), iterations=stats.iterations, num_inliers=stats.num_inliers, score=stats.score,
                seed=int(stats.seed), stop_reason=stats.stop_reason, flags=stats.flags,
                sprt_rejected=stats.sprt_rejected, lo_runs=stats.lo_runs)


def estimate_trifocal(x1, x2, x3, threshold_px=1.0, seed=0, confidence=None, max_iterations=None):
    """Trifocal RANSAC over (n,2) pixel triplets.

    Returns dict(T (3,3,3), P (3,3,4) with P[0] = [I|0], inliers (n,) bool,
    iterations, num_inliers, score, seed, stop_reason, ...). threshold_px is
    a per-view pixel distance (the three-view reprojection error after
    optimal triangulation, averaged over the views).
    """
    x1 = as_array(x1, (None, 2), "x1")
    n = x1.shape[0]
    x2 = as_array(x2, (n, 2), "x2")
    x3 = as_array(x3, (n, 2), "x3")
    opt = _ransac_options(threshold_px, seed, confidence, max_iterations)
    T = np.empty((3, 3, 3))
    P = np.empty((3, 3, 4))
    mask = np.zeros(n, dtype=np.uint8)
    stats = ffi.new("sfm_ransac_stats *")
    need = lib.sfm_ransac_trifocal_workspace_size(n)
    if need == 0:
        raise ValueError("need at least 7 triplets, got %d" % n)
    buf, ws, size = workspace(need)
    check(lib.sfm_ransac_trifocal(dptr(x1), dptr(x2), dptr(x3), n, opt, dptr(T), dptr(P),
                                  ffi.cast("uint8_t *", ffi.from_buffer(mask)), stats, ws, size),
          "estimate_trifocal")
    out = dict(T=T, P=P, inliers=mask.astype(bool))
    out.update(_stats_dict(stats))
    return out


def estimate_three_view_pose(x1, x2, x3, K1, K2, K3, threshold_px=1.0, seed=0, confidence=None,
                             max_iterations=None):
    """Calibrated poses of views 2 and 3 relative to view 1 from (n,2) pixel
    triplets with outliers, through trifocal RANSAC.

    K1, K2, K3 are 3x3 intrinsic matrices or libsfm.Camera objects (with
    distortion). Returns dict(R (3,3,3), t (3,3),
    inliers (n,) bool, iterations, ...): x_cam_v = R[v] x_cam1 + t[v], R[0] = I,
    t[0] = 0, |t[1]| = 1 and t[2] on the same scale.
    """
    x1 = as_array(x1, (None, 2), "x1")
    n = x1.shape[0]
    x2 = as_array(x2, (n, 2), "x2")
    x3 = as_array(x3, (n, 2), "x3")
    cams = [K if isinstance(K, Camera) else Camera.from_K(K) for K in (K1, K2, K3)]
    opt = _ransac_options(threshold_px, seed, confidence, max_iterations)
    poses = ffi.new("sfm_pose[3]")
    mask = np.zeros(n, dtype=np.uint8)
    stats = ffi.new("sfm_ransac_stats *")
    need = lib.sfm_recon_three_view_pose_workspace_size(n)
    if need == 0:
        raise ValueError("need at least 7 triplets, got %d" % n)
    buf, ws, size = workspace(need)
    check(lib.sfm_recon_three_view_pose(dptr(x1), dptr(x2), dptr(x3), n, cams[0]._c, cams[1]._c, cams[2]._c, opt,
                                        poses, ffi.cast("uint8_t *", ffi.from_buffer(mask)), stats, ws, size),
          "estimate_three_view_pose")
    R = np.array([list(poses[v].R) for v in range(3)]).reshape(3, 3, 3)
    t = np.array([list(poses[v].t) for v in range(3)])
    out = dict(R=R, t=t, inliers=mask.astype(bool))
    out.update(_stats_dict(stats))
    return out
