"""Corners, oriented binary descriptors, Hamming matching, three-view association.

Keypoints come back as an (n, 6) float64 array with columns
x, y, angle, response, scale, level: x, y in level-0 pixels with the origin at
the centre of the top-left pixel; angle in radians from +x towards +y.
Descriptors are (n, 32) uint8 (256 bits each).
"""
import threading

import numpy as np

from ._ffi import SfmError, as_array, check, dptr, ffi, int_array, lib, to_float, to_int

__all__ = ["detect_and_describe", "match", "associate_three_views", "align_points", "KEYPOINT_COLUMNS",
           "FEATURE_DEFAULTS", "MATCH_DEFAULTS", "ALIGN_DEFAULTS"]

# One detector workspace per thread, grown on demand and reused: a frame loop
# then touches the same pages every call instead of mapping ~2 MB afresh.
_local = threading.local()


def _workspace(nbytes):
    buf = getattr(_local, "ws", None)
    if buf is None or buf.nbytes < nbytes:
        buf = np.empty(nbytes, dtype=np.uint8)
        _local.ws = buf
    return buf

KEYPOINT_COLUMNS = ("x", "y", "angle", "response", "scale", "level")

_KP_DTYPE = np.dtype([("x", "<f8"), ("y", "<f8"), ("angle", "<f8"), ("response", "<f8"),
                      ("scale", "<f8"), ("level", "<i4"), ("reserved", "<i4")])


def _int_pairs(m, cols, name, hi):
    """An (n, cols) int32 copy of integer indices, each in [0, hi], checked
    before narrowing (an int64 2**32 + 3 would otherwise wrap to 3)."""
    arr = np.asarray(m)
    if arr.size == 0:
        arr = arr.reshape(0, cols)
    return int_array(arr, (None, cols), name, 0, hi)


def _c_defaults():
    p = ffi.new("sfm_features_params *")
    check(lib.sfm_features_default_params(p), "sfm_features_default_params")
    q = ffi.new("sfm_match_params *")
    check(lib.sfm_features_default_match_params(q), "sfm_features_default_match_params")
    return (dict(max_features=p.max_features, n_levels=p.n_levels,
                 scale_factor=p.scale_factor, fast_threshold=p.fast_threshold,
                 cell_size=p.cell_size),
            dict(ratio=q.ratio, mutual=bool(q.mutual), max_distance=q.max_distance))


#: The C defaults (sfm_features_default_params, sfm_features_default_match_params).
FEATURE_DEFAULTS, MATCH_DEFAULTS = _c_defaults()
_F, _M = FEATURE_DEFAULTS, MATCH_DEFAULTS


def _descriptors(d, name):
    arr = np.asarray(d)
    if arr.size == 0:
        arr = arr.reshape(0, 32)
    if arr.ndim != 2 or arr.shape[1] != 32 or arr.dtype != np.uint8:
        raise ValueError("%s must be a (n, 32) uint8 array, got %s %s" % (name, arr.shape, arr.dtype))
    return np.ascontiguousarray(arr)


def _gray_view(img, name):
    arr = np.asarray(img)
    if arr.ndim != 2 or arr.dtype != np.uint8:
        raise ValueError("%s must be a 2-D uint8 array, got %s %s" % (name, arr.shape, arr.dtype))
    if arr.size == 0:
        raise ValueError("%s must have at least one pixel, got shape %s" % (name, arr.shape))
    arr = np.ascontiguousarray(arr)
    view = ffi.new("sfm_image_u8 *")
    view.data = ffi.cast("const uint8_t *", ffi.from_buffer(arr))
    view.height, view.width = arr.shape
    view.stride = arr.strides[0]
    return arr, view


def detect_and_describe(image, max_features=_F["max_features"], n_levels=_F["n_levels"],
                        scale_factor=_F["scale_factor"], fast_threshold=_F["fast_threshold"],
                        cell_size=_F["cell_size"]):
    """Detect FAST-9 corners ranked by Harris response on an image pyramid
    (grid-bucketed) and describe them with steered BRIEF-256.

    image: (h, w) uint8 gray. max_features: budget over all levels
    (1..SFM_FEATURES_MAX_FEATURES); n_levels: pyramid levels; scale_factor:
    size ratio between levels, in [1.05, 2]; fast_threshold: intensity
    threshold 1..254; cell_size: bucketing cell side in level pixels, 8..1024.
    Defaults are the C library's (FEATURE_DEFAULTS).

    Returns (keypoints (n, 6) float64, descriptors (n, 32) uint8); keypoint
    columns x, y (level-0 pixels), angle (radians), response, scale, level.
    """
    img, view = _gray_view(image, "image")
    p = ffi.new("sfm_features_params *")
    check(lib.sfm_features_default_params(p))
    p.max_features = to_int(max_features, "max_features", 1, lib.SFM_FEATURES_MAX_FEATURES)
    p.n_levels = to_int(n_levels, "n_levels", 1, lib.SFM_FEATURES_MAX_LEVELS)
    p.scale_factor = to_float(scale_factor, "scale_factor")
    if not 1.05 <= p.scale_factor <= 2.0:
        raise ValueError("scale_factor must be in [1.05, 2], got %r" % p.scale_factor)
    p.fast_threshold = to_int(fast_threshold, "fast_threshold", 1, 254)
    p.cell_size = to_int(cell_size, "cell_size", 8, 1024)
    h, w = img.shape
    need = lib.sfm_features_workspace_size(p, w, h)
    if need == 0:
        raise ValueError("invalid feature parameters or image size %dx%d" % (w, h))
    ws = _workspace(need)
    cap = max(p.max_features, 1)
    kps = np.empty(cap, dtype=_KP_DTYPE)
    desc = np.empty((cap, 32), dtype=np.uint8)
    n = check(lib.sfm_features_detect(view, p, ffi.cast("sfm_keypoint *", ffi.from_buffer(kps)),
                                      ffi.cast("uint8_t *", ffi.from_buffer(desc)), cap,
                                      ffi.from_buffer(ws), ws.nbytes),
              "sfm_features_detect")
    kps = kps[:n]
    out = np.empty((n, 6), dtype=np.float64)
    for c, name in enumerate(KEYPOINT_COLUMNS):
        out[:, c] = kps[name]
    return out, desc[:n].copy()


def match(d1, d2, ratio=_M["ratio"], mutual=_M["mutual"], max_distance=_M["max_distance"],
          return_distances=False):
    """Brute-force Hamming matching of two descriptor sets.

    d1: (n1, 32) uint8, d2: (n2, 32) uint8. ratio: Lowe's test best < ratio
    * second, in (0, 1] (1.0 disables); mutual: keep a pair only when each is
    the other's nearest neighbour; max_distance: 0..256 bits. Defaults are
    the C library's (MATCH_DEFAULTS).

    Returns (m, 2) int array of (index in d1, index in d2), and with
    return_distances also their (m,) Hamming distances.
    """
    a = _descriptors(d1, "d1")
    b = _descriptors(d2, "d2")
    p = ffi.new("sfm_match_params *")
    check(lib.sfm_features_default_match_params(p))
    p.ratio = to_float(ratio, "ratio")
    if not 0 < p.ratio <= 1:
        raise ValueError("ratio must be in (0, 1], got %r" % p.ratio)
    p.mutual = 1 if mutual else 0
    p.max_distance = to_int(max_distance, "max_distance", 0, 256)
    n1, n2 = a.shape[0], b.shape[0]
    ws = np.empty(max(lib.sfm_features_match_workspace_size(n1, n2), 1), dtype=np.uint8)
    out = np.zeros((max(n1, 1), 2), dtype=np.int32)
    dist = np.zeros(max(n1, 1), dtype=np.int32)
    n = check(lib.sfm_features_match(ffi.cast("const uint8_t *", ffi.from_buffer(a)), n1,
                                     ffi.cast("const uint8_t *", ffi.from_buffer(b)), n2, p,
                                     ffi.cast("int *", ffi.from_buffer(out)),
                                     ffi.cast("int *", ffi.from_buffer(dist)), n1,
                                     ffi.from_buffer(ws), ws.nbytes),
              "sfm_features_match")
    m = out[:n].astype(np.intp)
    if return_distances:
        return m, dist[:n].copy()
    return m


def associate_three_views(m12, m23, m31, n1=None, n2=None, n3=None):
    """Cyclic three-view association: (t, 3) int array of (i1, i2, i3).

    m12: (k12, 2) integer pairs (i1, i2); m23: (i2, i3); m31: (i3, i1). n1,
    n2, n3 are the feature counts of the views (default: one more than the
    largest index seen). Indices must lie in [0, n_view); each list must map
    a source index once. A triplet is kept when 1 -> 2 -> 3 -> 1 returns to
    its start; triplets come in increasing i1.
    """
    int_max = 2 ** 31 - 2
    a = _int_pairs(m12, 2, "m12", int_max)
    b = _int_pairs(m23, 2, "m23", int_max)
    c = _int_pairs(m31, 2, "m31", int_max)

    def count(given, name, *cols):
        seen = int(max([col.max() + 1 for col in cols if col.size] + [0]))
        if given is None:
            return seen
        v = to_int(given, name, 0)
        if seen > v:
            raise ValueError("%s is %d but an index %d is given for that view" % (name, v, seen - 1))
        return v

    n1 = count(n1, "n1", a[:, 0], c[:, 1])
    n2 = count(n2, "n2", a[:, 1], b[:, 0])
    n3 = count(n3, "n3", b[:, 1], c[:, 0])
    cap = max(min(len(a), len(b), len(c)), 1)
    need = lib.sfm_features_associate_workspace_size(n1, n2, n3)
    ws = np.empty(max(need, 1), dtype=np.uint8)
    out = np.zeros((cap, 3), dtype=np.int32)

    def ptr(x):
        return ffi.cast("const int *", ffi.from_buffer(x)) if x.size else ffi.NULL

    try:
        n = check(lib.sfm_features_associate_three_views(ptr(a), len(a), ptr(b), len(b), ptr(c),
                                                         len(c), n1, n2, n3,
                                                         ffi.cast("int *", ffi.from_buffer(out)), cap,
                                                         ffi.from_buffer(ws), ws.nbytes),
                  "sfm_features_associate_three_views")
    except SfmError as e:
        # The one argument error left once the ranges are checked here: a
        # source index repeated within one list.
        for name, arr in (("m12", a), ("m23", b), ("m31", c)):
            if arr.size and np.unique(arr[:, 0]).size != arr.shape[0]:
                raise SfmError(e.status, e.where, name) from None
        raise
    return out[:n].astype(np.intp)


def _c_align_defaults():
    p = ffi.new("sfm_align_params *")
    check(lib.sfm_features_default_align_params(p), "sfm_features_default_align_params")
    return dict(radius=p.radius, max_iterations=p.max_iterations, max_shift=p.max_shift,
                min_zncc=p.min_zncc, min_eigen_ratio=p.min_eigen_ratio)


#: The C defaults of sfm_features_align_points (sfm_features_default_align_params).
ALIGN_DEFAULTS = _c_align_defaults()
_A = ALIGN_DEFAULTS


def align_points(ref, x_ref, img, x, radius=_A["radius"], max_iterations=_A["max_iterations"],
                 max_shift=_A["max_shift"], min_zncc=_A["min_zncc"], min_eigen_ratio=_A["min_eigen_ratio"]):
    """Photometric (Lucas-Kanade) refinement of correspondences: the patch of
    ref around each x_ref[k] is found in img starting from x[k].

    ref, img: (h, w) uint8 gray (sizes may differ); x_ref, x: (n, 2) pixels.
    Returns (points (n, 2) float64, refined (n,) bool); a point not refined
    (no corner-like patch, not settled, moved more than max_shift, left the
    image, correlation below min_zncc) keeps its start. Defaults are the C
    library's (ALIGN_DEFAULTS).
    """
    a, va = _gray_view(ref, "ref")
    b, vb = _gray_view(img, "img")
    xr = as_array(x_ref, (None, 2), "x_ref")
    xs = as_array(x, (xr.shape[0], 2), "x")
    p = ffi.new("sfm_align_params *")
    check(lib.sfm_features_default_align_params(p))
    p.radius = to_int(radius, "radius", 2, lib.SFM_FEATURES_ALIGN_MAX_RADIUS)
    p.max_iterations = to_int(max_iterations, "max_iterations", 1, 100)
    p.max_shift = to_float(max_shift, "max_shift")
    if not p.max_shift > 0:
        raise ValueError("max_shift must be > 0, got %r" % p.max_shift)
    p.min_zncc = to_float(min_zncc, "min_zncc")
    if not -1 <= p.min_zncc <= 1:
        raise ValueError("min_zncc must be in [-1, 1], got %r" % p.min_zncc)
    p.min_eigen_ratio = to_float(min_eigen_ratio, "min_eigen_ratio")
    if not 0 <= p.min_eigen_ratio <= 1:
        raise ValueError("min_eigen_ratio must be in [0, 1], got %r" % p.min_eigen_ratio)
    n = xr.shape[0]
    out = np.empty((max(n, 1), 2))
    ok = np.zeros(max(n, 1), dtype=np.uint8)
    check(lib.sfm_features_align_points(va, dptr(xr), vb, dptr(xs), n, p, dptr(out),
                                        ffi.cast("uint8_t *", ffi.from_buffer(ok))),
          "sfm_features_align_points", inputs={"x_ref": xr, "x": xs})
    del a, b
    return out[:n].copy(), ok[:n].astype(bool)
