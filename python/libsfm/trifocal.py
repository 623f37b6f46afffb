"""The trifocal tensor of three views: T[i, j, k] = T_i^{jk} (Hartley &
Zisserman), view 1 the reference, and the calibrated three-view pose.
Pixels are (n, 2) float arrays; cameras (3, 4)."""
import numpy as np

from ._ffi import as_array, check, dptr, ffi, lib, mptr, u8ptr, workspace
from .camera import as_camera
from .results import ransac_result
from .robust import RANSAC_DEFAULTS as _D
from .robust import options_of, ransac_options

__all__ = ["trifocal_from_cameras", "trifocal_7pt", "trifocal_epipoles", "trifocal_fundamentals",
           "cameras_from_trifocal", "trifocal_transfer", "trifocal_point_error",
           "estimate_trifocal", "estimate_three_view_pose"]


def trifocal_from_cameras(P1, P2, P3):
    """The trifocal tensor of three cameras.

    P1, P2, P3: (3, 4) projection matrices (pixels). Returns T (3, 3, 3),
    T[i, j, k] = T_i^{jk}, unit Frobenius norm."""
    Ps = [as_array(P, (3, 4), name) for P, name in ((P1, "P1"), (P2, "P2"), (P3, "P3"))]
    T = np.empty((3, 3, 3))
    check(lib.sfm_trifocal_from_cameras(dptr(Ps[0]), dptr(Ps[1]), dptr(Ps[2]), dptr(T)),
          "trifocal_from_cameras", dict(zip(("P1", "P2", "P3"), Ps)))
    return T


def trifocal_7pt(x1, x2, x3):
    """Trifocal tensor from n >= 7 triplets, no outliers (normalized linear
    estimate and algebraic minimization, H&Z alg. 16.2).

    x1, x2, x3: (n, 2) pixels. Returns T (3, 3, 3), unit Frobenius norm."""
    x1 = as_array(x1, (None, 2), "x1")
    n = x1.shape[0]
    x2 = as_array(x2, (n, 2), "x2")
    x3 = as_array(x3, (n, 2), "x3")
    T = np.empty((3, 3, 3))
    buf, ws, size = workspace(lib.sfm_trifocal_7pt_workspace_size())
    check(lib.sfm_trifocal_7pt(dptr(x1), dptr(x2), dptr(x3), n, dptr(T), ws, size), "trifocal_7pt",
          {"x1": x1, "x2": x2, "x3": x3})
    return T


def trifocal_epipoles(T):
    """Epipoles of T (3, 3, 3) in views 2 and 3: (e2 (3,), e3 (3,)), unit
    homogeneous pixel vectors (the images of camera 1's centre)."""
    T = as_array(T, (3, 3, 3), "T")
    e2, e3 = np.empty(3), np.empty(3)
    check(lib.sfm_trifocal_epipoles(dptr(T), dptr(e2), dptr(e3)), "trifocal_epipoles", {"T": T})
    return e2, e3


def trifocal_fundamentals(T):
    """Fundamental matrices of T (3, 3, 3): (F21, F31, F32), each (3, 3),
    with x2^T F21 x1 = 0, x3^T F31 x1 = 0, x3^T F32 x2 = 0 for homogeneous
    pixels."""
    T = as_array(T, (3, 3, 3), "T")
    F = np.empty((3, 3, 3))
    check(lib.sfm_trifocal_fundamentals(dptr(T), mptr(F[0]), mptr(F[1]), mptr(F[2])),
          "trifocal_fundamentals", {"T": T})
    return F[0], F[1], F[2]


def cameras_from_trifocal(T):
    """Projective cameras compatible with T (3, 3, 3): P (3, 3, 4), P[0] =
    [I | 0]."""
    T = as_array(T, (3, 3, 3), "T")
    P = np.zeros((3, 3, 4))
    P[0, :, :3] = np.eye(3)
    check(lib.sfm_trifocal_cameras(dptr(T), dptr(P[1]), dptr(P[2])), "cameras_from_trifocal", {"T": T})
    return P


def trifocal_transfer(T, x1, x2):
    """Point transfer: pixels in view 3 predicted from matching pixels x1,
    x2 ((n, 2), or (2,) for one) in views 1 and 2 through T (3, 3, 3).
    Returns (n, 2) (or (2,)) pixels."""
    T = as_array(T, (3, 3, 3), "T")
    one = np.ndim(x1) == 1
    x1 = as_array(np.atleast_2d(x1), (None, 2), "x1")
    n = x1.shape[0]
    x2 = as_array(np.atleast_2d(x2), (n, 2), "x2")
    F21, _, _ = trifocal_fundamentals(T)
    F21 = np.ascontiguousarray(F21)
    out = np.empty((n, 2))
    for p in range(n):
        check(lib.sfm_trifocal_transfer(dptr(T), mptr(F21), dptr(x1[p]), dptr(x2[p]), dptr(out[p])),
              "trifocal_transfer", {"T": T, "x1": x1, "x2": x2})
    return out[0] if one else out


def trifocal_point_error(P1, P2, P3, x1, x2, x3):
    """Three-view reprojection error of one triplet after optimal
    triangulation.

    P1, P2, P3: (3, 4) cameras; x1, x2, x3: (2,) pixels. Returns (err, X):
    err the summed squared error in pixels squared over the three views, X
    (4,) the homogeneous point."""
    Ps = [as_array(P, (3, 4), nm) for P, nm in ((P1, "P1"), (P2, "P2"), (P3, "P3"))]
    xs = [as_array(x, (2,), nm) for x, nm in ((x1, "x1"), (x2, "x2"), (x3, "x3"))]
    err = ffi.new("double *")
    X = np.empty(4)
    check(lib.sfm_trifocal_point_error(dptr(Ps[0]), dptr(Ps[1]), dptr(Ps[2]), dptr(xs[0]), dptr(xs[1]),
                                       dptr(xs[2]), err, dptr(X)), "trifocal_point_error",
          dict(zip(("P1", "P2", "P3", "x1", "x2", "x3"), Ps + xs)))
    return float(err[0]), X


def _triplets(x1, x2, x3):
    x1 = as_array(x1, (None, 2), "x1")
    n = x1.shape[0]
    x2 = as_array(x2, (n, 2), "x2")
    x3 = as_array(x3, (n, 2), "x3")
    if n < lib.SFM_TRIFOCAL_MIN_POINTS:
        raise ValueError("need at least %d triplets, got %d" % (lib.SFM_TRIFOCAL_MIN_POINTS, n))
    if n > lib.SFM_RANSAC_MAX_POINTS:
        raise ValueError("at most %d triplets, got %d" % (lib.SFM_RANSAC_MAX_POINTS, n))
    return x1, x2, x3, n


def estimate_trifocal(x1, x2, x3, *, threshold_px=_D["threshold_px"], seed=_D["seed"],
                      confidence=_D["confidence"], max_iterations=_D["max_iterations"],
                      min_iterations=_D["min_iterations"], lo_rounds=_D["lo_rounds"],
                      polish_rounds=_D["polish_rounds"], use_sprt=_D["use_sprt"], quality=None):
    """Trifocal tensor by RANSAC over n >= 7 pixel triplets.

    x1, x2, x3: (n, 2) pixels in views 1, 2, 3 (uncalibrated). threshold_px
    is a per-view pixel distance (the three-view reprojection error after
    optimal triangulation, averaged over the views). Options: see
    libsfm.robust. Returns a Result with T (3, 3, 3), unit Frobenius norm,
    and P (3, 3, 4), projective cameras compatible with T, P[0] = [I | 0]."""
    x1, x2, x3, n = _triplets(x1, x2, x3)
    opt, keep = ransac_options(n=n, **options_of(locals()))
    T = np.empty((3, 3, 3))
    P = np.empty((3, 3, 4))
    mask = np.zeros(n, dtype=np.uint8)
    stats = ffi.new("sfm_ransac_stats *")
    buf, ws, size = workspace(lib.sfm_ransac_trifocal_workspace_size(n))
    check(lib.sfm_ransac_trifocal(dptr(x1), dptr(x2), dptr(x3), n, opt, dptr(T), dptr(P),
                                  u8ptr(mask), stats, ws, size),
          "sfm_ransac_trifocal", {"x1": x1, "x2": x2, "x3": x3})
    del keep, buf
    return ransac_result(stats, mask, "sfm_ransac_trifocal", T=T, P=P)


def estimate_three_view_pose(x1, x2, x3, K1, K2, K3, *, dist1=None, dist2=None, dist3=None,
                             threshold_px=_D["threshold_px"], seed=_D["seed"],
                             confidence=_D["confidence"], max_iterations=_D["max_iterations"],
                             min_iterations=_D["min_iterations"], lo_rounds=_D["lo_rounds"],
                             polish_rounds=_D["polish_rounds"], use_sprt=_D["use_sprt"],
                             quality=None):
    """Calibrated poses of views 2 and 3 relative to view 1 from n >= 7 pixel
    triplets with outliers, through trifocal RANSAC (sfm_recon_three_view_pose).

    x1, x2, x3: (n, 2) pixels. K1, K2, K3: libsfm.Camera or 3x3 K (dist1..3:
    OpenCV Brown vectors for a K). threshold_px: per view, on the three-view
    reprojection error. Options: see libsfm.robust.

    Returns a Result with R (3, 3, 3) and t (3, 3): x_cam_v = R[v] x_cam1 +
    t[v], R[0] = I, t[0] = 0, |t[1]| = 1 and t[2] on the same scale. Its
    inliers (and num_inliers) are those of the returned metric cameras; the
    search counters (iterations, score, stop_reason, ...) are the trifocal
    RANSAC's."""
    x1, x2, x3, n = _triplets(x1, x2, x3)
    cams = [as_camera(K, d, name) for K, d, name in
            ((K1, dist1, "K1"), (K2, dist2, "K2"), (K3, dist3, "K3"))]
    opt, keep = ransac_options(n=n, **options_of(locals()))
    poses = ffi.new("sfm_pose[3]")
    mask = np.zeros(n, dtype=np.uint8)
    stats = ffi.new("sfm_ransac_stats *")
    buf, ws, size = workspace(lib.sfm_recon_three_view_pose_workspace_size(n))
    check(lib.sfm_recon_three_view_pose(dptr(x1), dptr(x2), dptr(x3), n, cams[0]._c, cams[1]._c,
                                        cams[2]._c, opt, poses, u8ptr(mask), stats, ws, size),
          "sfm_recon_three_view_pose", {"x1": x1, "x2": x2, "x3": x3})
    R = np.array([list(poses[v].R) for v in range(3)]).reshape(3, 3, 3)
    t = np.array([list(poses[v].t) for v in range(3)])
    del keep, buf
    return ransac_result(stats, mask, "sfm_recon_three_view_pose", R=R, t=t)
