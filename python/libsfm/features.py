"""Corners, oriented binary descriptors, Hamming matching, three-view association.

Keypoints come back as an (n, 6) float64 array with columns
x, y, angle, response, scale, level: x, y in level-0 pixels with the origin at
the centre of the top-left pixel; angle in radians from +x towards +y.
Descriptors are (n, 32) uint8 (256 bits each).
"""
import threading

import numpy as np

from ._ffi import check, ffi, lib

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


def _int_pairs(m, cols, name):
    arr = np.asarray(m)
    if arr.size == 0:
        arr = arr.reshape(0, cols)
    if arr.ndim != 2 or arr.shape[1] != cols:
        raise ValueError("%s must have shape (n, %d), got %s" % (name, cols, arr.shape))
    if arr.size and not np.issubdtype(arr.dtype, np.integer):
        raise ValueError("%s must hold integers" % name)
    return np.ascontiguousarray(arr, dtype=np.int32)


def _descriptors(d, name):
    arr = np.asarray(d)
    if arr.size == 0:
        arr = arr.reshape(0, 32)
    if arr.ndim != 2 or arr.shape[1] != 32 or arr.dtype != np.uint8:
        raise ValueError("%s must be a (n, 32) uint8 array, got %s %s" % (name, arr.shape, arr.dtype))
    return np.ascontiguousarray(arr)


def detect_and_describe(image, max_features=2000, n_levels=None, scale_factor=None,
                        fast_threshold=None, cell_size=None):
    """Detect keypoints in a 2-D uint8 gray image and describe them.

    Returns (keypoints (n, 6) float64, descriptors (n, 32) uint8).
    """
    img = np.asarray(image)
    if img.ndim != 2 or img.dtype != np.uint8:
        raise ValueError("image must be a 2-D uint8 array, got %s %s" % (img.shape, img.dtype))
    img = np.ascontiguousarray(img)
    p = ffi.new("sfm_features_params *")
    check(lib.sfm_features_default_params(p))
    p.max_features = int(max_features)
    if n_levels is not None:
        p.n_levels = int(n_levels)
    if scale_factor is not None:
        p.scale_factor = float(scale_factor)
    if fast_threshold is not None:
        p.fast_threshold = int(fast_threshold)
    if cell_size is not None:
        p.cell_size = int(cell_size)
    h, w = img.shape
    need = lib.sfm_features_workspace_size(p, w, h)
    if need == 0:
        raise ValueError("invalid feature parameters or image size %dx%d" % (w, h))
    ws = _workspace(need)
    view = ffi.new("sfm_image_u8 *")
    view.data = ffi.cast("const uint8_t *", ffi.from_buffer(img))
    view.width, view.height, view.stride = w, h, img.strides[0]
    cap = max(p.max_features, 1)
    kps = np.empty(cap, dtype=_KP_DTYPE)
    desc = np.empty((cap, 32), dtype=np.uint8)
    n = check(lib.sfm_features_detect(view, p, ffi.from_buffer(ws), ws.nbytes,
                                      ffi.cast("sfm_keypoint *", ffi.from_buffer(kps)),
                                      ffi.cast("uint8_t *", ffi.from_buffer(desc)), cap),
              "sfm_features_detect")
    kps = kps[:n]
    out = np.empty((n, 6), dtype=np.float64)
    for c, name in enumerate(KEYPOINT_COLUMNS):
        out[:, c] = kps[name]
    return out, desc[:n].copy()


def match(d1, d2, ratio=0.8, mutual=True, max_distance=256, return_distances=False):
    """Brute-force Hamming matching: (m, 2) int array of (index in d1, index in d2).

    ratio: Lowe's test best < ratio * second (1.0 disables); mutual: keep a
    pair only when each is the other's nearest neighbour.
    """
    a = _descriptors(d1, "d1")
    b = _descriptors(d2, "d2")
    p = ffi.new("sfm_match_params *")
    check(lib.sfm_features_default_match_params(p))
    p.ratio = float(ratio)
    p.mutual = 1 if mutual else 0
    p.max_distance = int(max_distance)
    n1, n2 = a.shape[0], b.shape[0]
    ws = np.empty(max(lib.sfm_features_match_workspace_size(n1, n2), 1), dtype=np.uint8)
    out = np.zeros((max(n1, 1), 2), dtype=np.int32)
    dist = np.zeros(max(n1, 1), dtype=np.int32)
    n = check(lib.sfm_features_match(ffi.cast("const uint8_t *", ffi.from_buffer(a)), n1,
                                     ffi.cast("const uint8_t *", ffi.from_buffer(b)), n2, p,
                                     ffi.from_buffer(ws), ws.nbytes,
                                     ffi.cast("int *", ffi.from_buffer(out)),
                                     ffi.cast("int *", ffi.from_buffer(dist)), n1),
              "sfm_features_match")
    m = out[:n].astype(np.intp)
    if return_distances:
        return m, dist[:n].copy()
    return m


def associate_three_views(m12, m23, m31, n1=None, n2=None, n3=None):
    """Cyclic three-view association: (t, 3) int array of (i1, i2, i3).

    m12: (n, 2) pairs (i1, i2); m23: (i2, i3); m31: (i3, i1). n1, n2, n3 are
    the feature counts of the views (default: one more than the largest index
    seen). A triplet is kept when 1 -> 2 -> 3 -> 1 returns to its start.
    """
    a = _int_pairs(m12, 2, "m12")
    b = _int_pairs(m23, 2, "m23")
    c = _int_pairs(m31, 2, "m31")

    def count(given, *cols):
        if given is not None:
            return int(given)
        return int(max([col.max() + 1 for col in cols if col.size] + [0]))

    n1 = count(n1, a[:, 0], c[:, 1])
    n2 = count(n2, a[:, 1], b[:, 0])
    n3 = count(n3, b[:, 1], c[:, 0])
    cap = max(min(len(a), len(b), len(c)), 1)
    ws = np.empty(max(lib.sfm_features_associate_workspace_size(n1, n2, n3), 1), dtype=np.uint8)
    out = np.zeros((cap, 3), dtype=np.int32)

    def ptr(x):
        return ffi.cast("const int *", ffi.from_buffer(x)) if x.size else ffi.NULL

    n = check(lib.sfm_features_associate_three_views(ptr(a), len(a), ptr(b), len(b), ptr(c), len(c),
                                                     n1, n2, n3, ffi.from_buffer(ws), ws.nbytes,
                                                     ffi.cast("int *", ffi.from_buffer(out)), cap),
              "sfm_features_associate_three_views")
    return out[:n].astype(np.intp)
