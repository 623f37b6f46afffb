"""Monocular visual odometry over a frame sequence (sfm_vo.h).

    vo = libsfm.VisualOdometry(width, height, camera=(fx, fy, cx, cy))
    for img, ts in frames:
        r = vo.push(img, ts)          # a FrameResult
        if r.has_pose: ... r.R_cw, r.t_cw (world-to-camera), r.R_wc, r.c_w

Poses: world-to-camera x_cam = R_cw X + t_cw; camera-to-world
X = R_wc x_cam + c_w (c_w is the camera centre). The world frame is the first
frame's camera. The work happens in C; this module only converts.
"""
import time

import numpy as np

from .camera import Camera
from ._ffi import SfmError, as_array, check, ffi, lib, to_float, to_int, to_seed

INT64_MIN, INT64_MAX = -2 ** 63, 2 ** 63 - 1

STATES = {
    lib.SFM_VO_INITIALISING: "initialising",
    lib.SFM_VO_TRACKING: "tracking",
    lib.SFM_VO_LOST: "lost",
    lib.SFM_VO_INSUFFICIENT_PARALLAX: "insufficient_parallax",
    lib.SFM_VO_PURE_ROTATION: "pure_rotation",
}
QUALITIES = {lib.SFM_VO_QUALITY_NONE: "none", lib.SFM_VO_QUALITY_GOOD: "good",
             lib.SFM_VO_QUALITY_DEGRADED: "degraded"}
STAGES = ("features", "tracking", "mapping", "trifocal", "ba")



class FrameResult:
    """One frame's output; arrays are float64 copies."""

    __slots__ = ("timestamp_ns", "frame_index", "state", "quality", "has_pose", "is_keyframe",
                 "R_cw", "t_cw", "R_wc", "c_w", "covariance", "n_features", "n_matches",
                 "n_inliers", "n_map_points", "n_keyframes", "degraded", "stage_seconds",
                 "median_parallax_deg", "focal", "segment")

    def __init__(self, r):
        self.timestamp_ns = int(r.timestamp_ns)
        self.frame_index = int(r.frame_index)
        self.state = STATES.get(r.state, "unknown")
        self.quality = QUALITIES.get(r.quality, "unknown")
        self.has_pose = bool(r.has_pose)
        self.is_keyframe = bool(r.is_keyframe)
        self.R_cw = np.array(list(r.R_cw)).reshape(3, 3)
        self.t_cw = np.array(list(r.t_cw))
        self.R_wc = np.array(list(r.R_wc)).reshape(3, 3)
        self.c_w = np.array(list(r.c_w))
        self.covariance = np.array(list(r.covariance)).reshape(6, 6) if r.has_covariance else None
        self.n_features = int(r.n_features)
        self.n_matches = int(r.n_matches)
        self.n_inliers = int(r.n_inliers)
        self.n_map_points = int(r.n_map_points)
        self.n_keyframes = int(r.n_keyframes)
        self.degraded = int(r.degraded)
        self.stage_seconds = dict(zip(STAGES, list(r.stage_seconds)))
        self.median_parallax_deg = float(r.median_parallax_deg)
        self.focal = float(r.focal)
        self.segment = int(r.segment)


@ffi.callback("double(void *)")
def _clock(_ctx):
    return time.perf_counter()


def _model(model):
    if not isinstance(model, str) or model not in Camera.MODELS:
        raise ValueError("model must be one of %s, got %r" % (", ".join(Camera.MODELS), model))
    return model


def _camera(camera, model="pinhole"):
    """The C camera of a libsfm.Camera, or of a sequence (fx, fy, cx, cy[,
    dist...]) read under model (a "pinhole" with distortion is Brown), under
    the Camera constructor's rules: TypeError for complex or non-numbers,
    ValueError for a wrong length or model, SfmError naming the entry
    (camera.fx, ...) for a zero focal length or a NaN."""
    model = _model(model)
    if isinstance(camera, Camera):
        if model not in ("pinhole", camera.model):
            raise ValueError("camera is a %s Camera, model=%r contradicts it" % (camera.model, model))
        return camera._c
    vals = as_array(camera, (None,), "camera")
    if model == "pinhole" and vals.shape[0] > 4:
        model = "brown"
    most = 4 + Camera.NDIST[model]
    if not 4 <= vals.shape[0] <= most:
        raise ValueError("camera must be (fx, fy, cx, cy%s) for model %r, got %d values"
                         % (", up to %d distortion coefficients" % Camera.NDIST[model]
                            if Camera.NDIST[model] else "", model, vals.shape[0]))
    try:
        return Camera(model, *vals[:4], dist=vals[4:])._c
    except SfmError as e:
        raise SfmError(e.status, "VisualOdometry",
                       "camera.%s" % e.argument if e.argument else "camera") from None


class VisualOdometry:
    """The C pipeline on a workspace this object owns.

    camera: a libsfm.Camera, or (fx, fy, cx, cy) or (fx, fy, cx, cy, k1, k2,
    p1, p2, k3) (Brown, as OpenCV's; fewer coefficients are padded with
    zeros), with model="fisheye" for (fx, fy, cx, cy, k1, k2, k3, k4).
    camera=None asks for self-calibration (a pinhole camera, principal point
    at the image centre, focal length found on the first good keyframe triple
    and refined by the windowed BA; FrameResult.focal reports it, 0 until
    found); focal_guess (px, default the image width) only steers the
    parallax tests before that. Keyword arguments set sfm_vo_params fields
    (threshold, min_inliers, ba_iterations, use_trifocal, seed, ...);
    frame_budget (seconds) turns the timed degradation on; timing=True reads
    a clock for the per-stage seconds.
    """

    def __init__(self, width, height, camera, max_features=1000, window=5, model="pinhole",
                 timing=True, n_levels=None, fast_threshold=None, focal_guess=None, **params):
        dims = ffi.new("sfm_vo_dims *")
        # range checks of the sizes themselves are the C library's (dims_ok)
        dims.width, dims.height = to_int(width, "width"), to_int(height, "height")
        dims.max_features = to_int(max_features, "max_features")
        dims.window = to_int(window, "window")
        p = ffi.new("sfm_vo_params *")
        check(lib.sfm_vo_default_params(dims, p), "sfm_vo_default_params")
        if camera is None:
            p.calibrated = 0
            p.camera.model = Camera.MODELS[_model(model)]
            if focal_guess is not None:
                p.camera.fx = p.camera.fy = to_float(focal_guess, "focal_guess")
        else:
            if focal_guess is not None:
                raise ValueError("focal_guess is for self-calibration (camera=None); a camera was given")
            p.camera = _camera(camera, model)[0]
        # the ranges of sfm_features_params, as detect_and_describe checks them
        if n_levels is not None:
            p.features.n_levels = to_int(n_levels, "n_levels", 1, lib.SFM_FEATURES_MAX_LEVELS)
        if fast_threshold is not None:
            p.features.fast_threshold = to_int(fast_threshold, "fast_threshold", 1, 254)
        for k, v in params.items():
            if not hasattr(p, k) or k in ("camera", "features", "clock", "clock_ctx"):
                raise TypeError("unknown VO parameter %r" % k)
            cur = getattr(p, k)
            if k == "seed":
                v = to_seed(v, k)
            elif k == "use_trifocal" and isinstance(v, (bool, np.bool_)):
                v = int(v)  # a flag: True / False read as they say
            elif isinstance(cur, int):
                v = to_int(v, k)
            else:
                v = to_float(v, k)
            setattr(p, k, v)
        if timing or p.frame_budget > 0:
            p.clock = _clock
        size = lib.sfm_vo_workspace_size(dims)
        if size == 0:
            raise ValueError("VO dimensions out of range")
        self._ws = np.empty(size, np.uint8)
        self._vo = ffi.new("sfm_vo **")
        self._dims = dims
        self._params = p
        check(lib.sfm_vo_init(dims, p, self._vo, ffi.from_buffer(self._ws), size), "sfm_vo_init")
        self.width, self.height = dims.width, dims.height
        self.workspace_bytes = int(size)
        self._img = ffi.new("sfm_image_u8 *")
        self._res = ffi.new("sfm_vo_frame_result *")
        self._grav = ffi.new("double[3]")
        self._cap = dims.max_features * dims.window
        self._xyz = np.empty((self._cap, 3))
        self._ids = np.empty(self._cap, np.uint32)
        self._px = np.empty((self._cap, 2))
        self._frame = np.empty(self._cap, np.int32)

    def push(self, image, timestamp_ns, gravity=None, covariance=False):
        img = np.ascontiguousarray(image)
        if img.ndim != 2 or img.dtype != np.uint8 or img.shape != (self.height, self.width):
            raise ValueError("image must be a (%d, %d) uint8 array" % (self.height, self.width))
        self._img.data = ffi.cast("const uint8_t *", ffi.from_buffer(img))
        self._img.width, self._img.height, self._img.stride = self.width, self.height, self.width
        g = ffi.NULL
        if gravity is not None:
            gv = as_array(np.asarray(gravity).ravel() if not isinstance(gravity, complex) else gravity,
                          (3,), "gravity")
            for i in range(3):
                self._grav[i] = gv[i]
            g = self._grav
        ts = to_int(timestamp_ns, "timestamp_ns", INT64_MIN, INT64_MAX)
        check(lib.sfm_vo_push_frame(self._vo[0], self._img, ts, g,
                                    1 if covariance else 0, self._res), "sfm_vo_push_frame")
        return FrameResult(self._res)

    def map_points(self):
        """(ids (n,) uint32, xyz (n, 3)) of the live map points."""
        n = check(lib.sfm_vo_map_points(self._vo[0], ffi.cast("double *", ffi.from_buffer(self._xyz)),
                                        ffi.cast("uint32_t *", ffi.from_buffer(self._ids)), self._cap))
        return self._ids[:n].copy(), self._xyz[:n].copy()

    def map_points_first_seen(self):
        """(ids (n,) uint32, px (n, 2), frame (n,) int32): where each live map
        point was first seen (image pixel, frame index), in map_points' order."""
        n = check(lib.sfm_vo_map_points_first_seen(
            self._vo[0], ffi.cast("uint32_t *", ffi.from_buffer(self._ids)),
            ffi.cast("double *", ffi.from_buffer(self._px)),
            ffi.cast("int *", ffi.from_buffer(self._frame)), self._cap))
        return self._ids[:n].copy(), self._px[:n].copy(), self._frame[:n].copy()

    def reset(self):
        check(lib.sfm_vo_reset(self._vo[0]), "sfm_vo_reset")
