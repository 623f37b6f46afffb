"""Dense stereo: rectification, disparity (semi-global and correlation
matching) and disparity to points (include/sfm/sfm_stereo.h).

Images are 2-D uint8 arrays. Poses as everywhere in libsfm: camera 2 is
x_cam2 = R x_cam1 + t. Rectified image 1 is always the left one, and a
disparity d = u1 - u2 is NaN where the matcher has no answer.
"""
import numpy as np

from .camera import as_camera
from ._ffi import as_array, check, dptr, ffi, lib, mptr, to_float, to_int, workspace

__all__ = ["rectify_pair", "remap", "rectify_uncalibrated", "homography_maps",
           "rectification_error", "disparity_sgm", "disparity_block", "disparity_to_depth",
           "disparity_to_points"]


def _camera(K, dist, name):
    """The C camera of a Camera or of a 3x3 K with an OpenCV distortion
    vector (the rule of every libsfm function taking intrinsics)."""
    return as_camera(K, dist, name)._c


def _gray(img, name):
    a = np.asarray(img)
    if a.ndim != 2 or a.dtype != np.uint8:
        raise ValueError("%s must be a 2-D uint8 image, got %s %s" % (name, a.dtype, a.shape))
    return np.ascontiguousarray(a)


def _disparity(disparity):
    """A 2-D float32 disparity image; complex and non-numeric input refused
    (numpy's cast would drop an imaginary part)."""
    a = np.asarray(disparity)
    if np.iscomplexobj(a) or a.dtype.kind not in "biuf":
        raise TypeError("disparity must hold real numbers, got dtype %s" % a.dtype)
    if a.ndim != 2:
        raise ValueError("disparity must be a 2-D image, got shape %s" % (a.shape,))
    return np.ascontiguousarray(a, dtype=np.float32)


def _size(size, name="size"):
    w, h = size
    return to_int(w, name + "[0]", 0, 32767), to_int(h, name + "[1]", 0, 32767)


def _rect_dict(r):
    m = lambda f, n: np.array([f[i] for i in range(n)], dtype=np.float64)  # noqa: E731
    return {
        "R1": m(r.R1, 9).reshape(3, 3), "R2": m(r.R2, 9).reshape(3, 3),
        "K1": m(r.K1, 9).reshape(3, 3), "K2": m(r.K2, 9).reshape(3, 3),
        "baseline": float(r.baseline), "Q": m(r.Q, 16).reshape(4, 4),
        "size": (int(r.width), int(r.height)),
        "roi1": tuple(int(r.roi1[i]) for i in range(4)),
        "roi2": tuple(int(r.roi2[i]) for i in range(4)),
    }


def _rect_struct(d):
    r = ffi.new("sfm_stereo_rectification *")
    for name, n in (("R1", 9), ("R2", 9), ("K1", 9), ("K2", 9), ("Q", 16)):
        v = np.asarray(d[name], dtype=np.float64).ravel()
        arr = getattr(r, name)
        for i in range(n):
            arr[i] = v[i]
    r.baseline = float(d["baseline"])
    r.width, r.height = d["size"]
    for k in ("roi1", "roi2"):
        for i, v in enumerate(d[k]):
            getattr(r, k)[i] = int(v)
    return r


def _map(cam, src_size, rect, view):
    w, h = rect.width, rect.height
    out = np.empty((h, w, 2), dtype=np.int32)
    check(lib.sfm_stereo_rectify_map(cam, src_size[0], src_size[1], rect, view,
                                     ffi.cast("int32_t *", ffi.from_buffer(out)), out.size),
          "sfm_stereo_rectify_map")
    return out


def rectify_pair(K1, K2, R, t, size, dist1=None, dist2=None, alpha=-1.0, out_size=None):
    """Rectify a calibrated pair (Fusiello, Trucco, Verri 2000).

    K1, K2: libsfm.Camera (any model: pinhole, Brown-Conrady,
    Kannala-Brandt) or 3x3 intrinsics (pixels) with dist1/dist2 an OpenCV
    distortion vector or None; R (3x3), t (3,): camera 2's pose in
    camera 1's frame, x2 = R x1 + t; size: (width, height) of both images;
    alpha: -1 keeps the mean focal length, 0 keeps only valid pixels, 1 keeps
    every source pixel (as OpenCV's stereoRectify); out_size: rectified
    (width, height), default size.

    Returns a dict: R1, R2 (x_rect_i = R_i x_cam_i), K1, K2 (rectified
    intrinsics: same f and cy), baseline (units of t), Q (4x4, (u, v, d, 1) ->
    homogeneous point in rectified camera 1), size, roi1, roi2 (x, y, w, h of
    the fully valid regions) and maps (the two remap tables for `remap`,
    each (h, w, 2) int32 source coordinates in 1/256 pixel, -1 invalid).
    Raises SfmError (SFM_E_SINGULAR) when the baseline is too short or
    points along the viewing direction.
    """
    c1, c2 = _camera(K1, dist1, "K1"), _camera(K2, dist2, "K2")
    R = as_array(R, (3, 3), "R")
    t = as_array(np.asarray(t, dtype=np.float64).ravel(), (3,), "t")
    w, h = _size(size)
    ow, oh = _size(out_size, "out_size") if out_size is not None else (0, 0)
    rect = ffi.new("sfm_stereo_rectification *")
    check(lib.sfm_stereo_rectify(c1, c2, w, h, dptr(R), dptr(t), to_float(alpha, "alpha"), ow, oh, rect),
          "sfm_stereo_rectify")
    out = _rect_dict(rect)
    out["maps"] = (_map(c1, (w, h), rect, 1), _map(c2, (w, h), rect, 2))
    return out


def homography_maps(H1, H2, size, out_size=None):
    """Remap tables for a pair rectified by homographies (source -> rectified)."""
    w, h = _size(size)
    ow, oh = _size(out_size) if out_size is not None else (w, h)
    maps = []
    for name, H in (("H1", H1), ("H2", H2)):
        H = as_array(H, (3, 3), name)
        out = np.empty((oh, ow, 2), dtype=np.int32)
        check(lib.sfm_stereo_homography_map(mptr(H), w, h, ow, oh,
                                            ffi.cast("int32_t *", ffi.from_buffer(out)), out.size),
              "sfm_stereo_homography_map")
        maps.append(out)
    return tuple(maps)


def remap(image, maps, view=1, fill=0):
    """Apply a remap table (one of rectify_pair(...)["maps"], or a map
    directly) to a uint8 image: bilinear, identical on every target."""
    src = _gray(image, "image")
    if isinstance(maps, (tuple, list)):
        if len(maps) != 2:
            raise ValueError("maps must be a pair of remap tables, got %d" % len(maps))
        m = maps[to_int(view, "view", 1, 2) - 1]  # view 0 would pick maps[-1]
    else:
        m = maps
    m = np.asarray(m)
    if m.dtype.kind not in "iu":  # a float or complex map would be truncated
        raise TypeError("map must hold integers (1/256 pixel), got dtype %s" % m.dtype)
    if m.size and (m.min() < -2 ** 31 or m.max() > 2 ** 31 - 1):
        raise ValueError("map entries must fit int32")
    m = np.ascontiguousarray(m, dtype=np.int32)
    if m.ndim != 3 or m.shape[2] != 2:
        raise ValueError("map must have shape (h, w, 2), got %s" % (m.shape,))
    oh, ow = m.shape[:2]
    dst = np.empty((oh, ow), dtype=np.uint8)
    check(lib.sfm_stereo_remap(ffi.cast("uint8_t *", ffi.from_buffer(src)), src.shape[1],
                               src.shape[0], src.strides[0],
                               ffi.cast("int32_t *", ffi.from_buffer(m)), ow, oh, to_int(fill, "fill", 0, 255),
                               ffi.cast("uint8_t *", ffi.from_buffer(dst)), ow),
          "sfm_stereo_remap")
    return dst


def rectify_uncalibrated(F, x1, x2, size):
    """Hartley's projective rectification from F (x2^T F x1 = 0, pixels) and
    inlier matches x1, x2 (n x 2, n >= 8). Returns (H1, H2), each mapping
    source pixels to rectified pixels."""
    F = as_array(F, (3, 3), "F")
    x1 = as_array(x1, (None, 2), "x1")
    x2 = as_array(x2, (x1.shape[0], 2), "x2")
    w, h = _size(size)
    H1 = np.empty((3, 3))
    H2 = np.empty((3, 3))
    check(lib.sfm_stereo_rectify_uncalibrated(mptr(F), dptr(x1), dptr(x2), x1.shape[0], w, h,
                                              mptr(H1), mptr(H2)),
          "sfm_stereo_rectify_uncalibrated")
    return H1, H2


def rectification_error(x1, x2, rect=None, K1=None, K2=None, dist1=None, dist2=None,
                        H1=None, H2=None):
    """Vertical disparity (rectified pixels) of matches after rectification:
    (median, max, n_used). Give rect (a rectify_pair result) with K1, K2,
    dist1, dist2, or H1, H2."""
    x1 = as_array(x1, (None, 2), "x1")
    x2 = as_array(x2, (x1.shape[0], 2), "x2")
    med = ffi.new("double *")
    mx = ffi.new("double *")
    if rect is not None:
        n = lib.sfm_stereo_rectification_error(_camera(K1, dist1, "K1"), _camera(K2, dist2, "K2"),
                                               _rect_struct(rect), ffi.NULL, ffi.NULL,
                                               dptr(x1), dptr(x2), x1.shape[0], med, mx)
    else:
        H1 = as_array(H1, (3, 3), "H1")
        H2 = as_array(H2, (3, 3), "H2")
        n = lib.sfm_stereo_rectification_error(ffi.NULL, ffi.NULL, ffi.NULL, mptr(H1), mptr(H2),
                                               dptr(x1), dptr(x2), x1.shape[0], med, mx)
    check(n, "sfm_stereo_rectification_error")
    return float(med[0]), float(mx[0]), int(n)


def _pair(left, right):
    L, R = _gray(left, "left"), _gray(right, "right")
    if L.shape != R.shape:
        raise ValueError("left and right must have the same shape, got %s and %s" % (L.shape, R.shape))
    return L, R


def _match(size_fn, run_fn, L, R, o, what, where):
    """Workspace, output and call shared by the two matchers."""
    h, w = L.shape
    n = size_fn(w, h, o)
    if n == 0:
        raise ValueError("invalid %s options for a %dx%d image" % (what, w, h))
    _, ws, ws_size = workspace(n)
    out = np.empty((h, w), dtype=np.float32)
    check(run_fn(ffi.cast("uint8_t *", ffi.from_buffer(L)), ffi.cast("uint8_t *", ffi.from_buffer(R)),
                 w, h, w, o, ffi.cast("float *", ffi.from_buffer(out)), ws, ws_size),
          where)
    return out


def disparity_sgm(left, right, num_disparities=64, min_disparity=0, p1=5, p2=60, paths=5,
                  uniqueness=10, lr_max_diff=1, subpixel=True):
    """Semi-global matching (Hirschmüller 2008, census cost) of a rectified
    pair. Returns a float32 (h, w) disparity image, NaN invalid. paths is 4,
    5 (one pass, row memory) or 8."""
    L, R = _pair(left, right)
    o = ffi.new("sfm_stereo_sgm_options *")
    o.min_disparity = to_int(min_disparity, "min_disparity")
    o.num_disparities = to_int(num_disparities, "num_disparities")
    o.p1, o.p2, o.paths = to_int(p1, "p1"), to_int(p2, "p2"), to_int(paths, "paths")
    o.uniqueness, o.lr_max_diff = to_int(uniqueness, "uniqueness"), to_int(lr_max_diff, "lr_max_diff")
    o.subpixel = int(bool(subpixel))
    return _match(lib.sfm_stereo_sgm_workspace_size, lib.sfm_stereo_sgm, L, R, o, "SGM", "sfm_stereo_sgm")


def disparity_block(left, right, num_disparities=64, min_disparity=0, radius=2, uniqueness=15,
                    lr_max_diff=1, texture=8, subpixel=True):
    """Correlation matching with multiple supporting windows (Hirschmüller,
    Innocent, Garibaldi 2002): SAD over (2 radius + 1)^2 plus the two best
    corner windows, left-right check. Returns float32 (h, w), NaN invalid."""
    L, R = _pair(left, right)
    o = ffi.new("sfm_stereo_block_options *")
    o.min_disparity = to_int(min_disparity, "min_disparity")
    o.num_disparities, o.radius = to_int(num_disparities, "num_disparities"), to_int(radius, "radius")
    o.uniqueness, o.lr_max_diff = to_int(uniqueness, "uniqueness"), to_int(lr_max_diff, "lr_max_diff")
    o.texture = to_int(texture, "texture")
    o.subpixel = int(bool(subpixel))
    return _match(lib.sfm_stereo_block_workspace_size, lib.sfm_stereo_block, L, R, o,
                  "block-matching", "sfm_stereo_block")


def _rect_from(rect=None, K=None, baseline=None, doffs=0.0, Q=None):
    if rect is not None:
        return _rect_struct(rect)
    if Q is not None:
        # OpenCV's Q: [1 0 0 -cx1; 0 1 0 -cy; 0 0 0 f; 0 0 1/B -(cx1-cx2)/B]
        Q = as_array(Q, (4, 4), "Q")
        if not Q[3, 2] != 0:
            raise ValueError("Q[3, 2] (1 / baseline) must be non-zero")
        baseline = 1.0 / Q[3, 2]
        K = np.array([[Q[2, 3], 0, -Q[0, 3]], [0, Q[2, 3], -Q[1, 3]], [0, 0, 1.0]])
        doffs = -Q[3, 3] * baseline
    if K is None or baseline is None:
        raise ValueError("give rect, Q, or K and baseline")
    K = as_array(K, (3, 3), "K")
    r = ffi.new("sfm_stereo_rectification *")
    for i, v in enumerate(np.eye(3).ravel()):
        r.R1[i] = v
        r.R2[i] = v
    for i, v in enumerate(K.ravel()):
        r.K1[i] = v
        r.K2[i] = v
    r.K2[2] = K[0, 2] - to_float(doffs, "doffs")
    r.baseline = to_float(baseline, "baseline")
    return r


def disparity_to_depth(disparity, rect=None, K=None, baseline=None, doffs=0.0, Q=None):
    """Depth (rectified camera 1's z, units of the baseline) of every pixel,
    NaN invalid. Give a rectify_pair result, a Q matrix (4x4, as
    rectify_pair's or OpenCV's stereoRectify's), or K and baseline (and
    doffs = cx1 - cx2)."""
    d = _disparity(disparity)
    r = _rect_from(rect, K, baseline, doffs, Q)
    out = np.empty_like(d)
    check(lib.sfm_stereo_depth(ffi.cast("float *", ffi.from_buffer(d)), d.shape[1], d.shape[0], r,
                               ffi.cast("float *", ffi.from_buffer(out))), "sfm_stereo_depth")
    return out


def disparity_to_points(disparity, rect=None, K=None, baseline=None, doffs=0.0, Q=None,
                        max_depth=0.0):
    """3-D points (n x 3) of the valid pixels in camera 1's original frame
    (rectified camera 1's when given Q, or K and baseline) and their pixel
    index (n,) = y * width + x."""
    d = _disparity(disparity)
    max_depth = to_float(max_depth, "max_depth")
    r = _rect_from(rect, K, baseline, doffs, Q)
    dp = ffi.cast("float *", ffi.from_buffer(d))
    n = check(lib.sfm_stereo_points(dp, d.shape[1], d.shape[0], r, max_depth, ffi.NULL,
                                    ffi.NULL, 0), "sfm_stereo_points")
    pts = np.empty((n, 3))
    idx = np.empty(n, dtype=np.int32)
    check(lib.sfm_stereo_points(dp, d.shape[1], d.shape[0], r, max_depth, dptr(pts),
                                ffi.cast("int32_t *", ffi.from_buffer(idx)), n),
          "sfm_stereo_points")
    return pts, idx
