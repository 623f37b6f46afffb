"""Camera intrinsics (sfm_camera.h): pinhole, Brown-Conrady, Kannala-Brandt.

Every function of the package that takes intrinsics accepts a Camera or a
3x3 matrix K (zero skew; with an optional OpenCV Brown-Conrady vector beside
it). Points are in the camera frame (z forward, x right, y down); pixels have
their origin at the centre of the top-left pixel. Distortion coefficients
follow OpenCV: Brown (k1, k2, p1, p2, k3) as cv2.projectPoints, fisheye
(k1, k2, k3, k4) as cv2.fisheye.
"""
import numpy as np

from ._ffi import SfmError, as_array, check, dptr, ffi, lib, to_float, to_int

__all__ = ["Camera"]


def _K_entries(K, name):
    """(fx, fy, cx, cy) of a 3x3 intrinsic matrix; refuses what the models
    cannot represent instead of dropping it (skew, a bottom row other than
    (0, 0, 1))."""
    K = as_array(K, (3, 3), name)
    if not np.all(np.isfinite(K)):
        raise ValueError("%s must be finite" % name)
    if K[1, 0] != 0 or K[2, 0] != 0 or K[2, 1] != 0 or K[2, 2] != 1:
        raise ValueError("%s must be [[fx, s, cx], [0, fy, cy], [0, 0, 1]], got %s"
                         % (name, K.tolist()))
    if abs(K[0, 1]) > 1e-12 * max(abs(K[0, 0]), 1.0):
        raise ValueError("%s has skew %g: the camera models have none" % (name, K[0, 1]))
    return K[0, 0], K[1, 1], K[0, 2], K[1, 2]


class Camera:
    """A calibrated camera.

    Camera(model, fx, fy, cx, cy, dist=(), width=None, height=None)

    model: "pinhole", "brown" (dist = k1, k2, p1, p2, k3; fewer entries are
    padded with zeros) or "fisheye" (equidistant Kannala-Brandt, dist = k1,
    k2, k3, k4). fx, fy, cx, cy in pixels; width and height (pixels,
    optional) are the image size the calibration holds for. The parameters
    are checked by the C library (sfm_camera_validate): SfmError naming the
    argument on a zero focal length or a NaN.

    Constructors: Camera.from_K(K, dist), Camera.from_opencv(K, dist,
    fisheye=False), Camera.from_file(path) (OpenCV FileStorage YAML/XML, ROS
    camera_info, Kalibr camchain, EuRoC sensor.yaml, KITTI calib.txt; see
    libsfm.calib).
    """

    MODELS = {"pinhole": lib.SFM_CAMERA_PINHOLE, "brown": lib.SFM_CAMERA_BROWN,
              "fisheye": lib.SFM_CAMERA_FISHEYE}
    NDIST = {"pinhole": 0, "brown": 5, "fisheye": 4}

    def __init__(self, model, fx, fy, cx, cy, dist=(), width=None, height=None):
        if model not in self.MODELS:
            raise ValueError("model must be one of %s, got %r" % (", ".join(self.MODELS), model))
        dist = as_array(np.ravel(dist), (None,), "dist")
        if dist.shape[0] > self.NDIST[model]:
            raise ValueError("%s takes at most %d distortion coefficients, got %d"
                             % (model, self.NDIST[model], dist.shape[0]))
        self.model = model
        self.fx, self.fy = to_float(fx, "fx", finite=False), to_float(fy, "fy", finite=False)
        self.cx, self.cy = to_float(cx, "cx", finite=False), to_float(cy, "cy", finite=False)
        self.dist = np.zeros(self.NDIST[model])
        self.dist[:dist.shape[0]] = dist
        self.width = None if width is None else to_int(width, "width", 1)
        self.height = None if height is None else to_int(height, "height", 1)
        self._c = ffi.new("sfm_camera *")
        self._c.model = self.MODELS[model]
        self._c.fx, self._c.fy, self._c.cx, self._c.cy = self.fx, self.fy, self.cx, self.cy
        for i, v in enumerate(self.dist):
            self._c.dist[i] = float(v)
        st = lib.sfm_camera_validate(self._c)
        if st < 0:
            vals = dict(fx=self.fx, fy=self.fy, cx=self.cx, cy=self.cy)
            bad = [k for k, v in vals.items() if not np.isfinite(v)]
            if not bad and not np.all(np.isfinite(self.dist)):
                bad = ["dist"]
            if not bad:
                bad = [k for k in ("fx", "fy") if vals[k] == 0]
            raise SfmError(st, "Camera", bad[0] if bad else None)

    @classmethod
    def from_K(cls, K, dist=(), model=None, width=None, height=None):
        """From a 3x3 intrinsic matrix K (zero skew) and distortion
        coefficients. model defaults to "brown" when dist is given, else
        "pinhole"; dist is read as OpenCV's Brown vector (k1, k2, p1, p2[,
        k3]) unless model="fisheye" (k1..k4)."""
        if model in (None, "brown") and dist is not None and np.size(dist) > 5:
            return cls.from_opencv(K, dist, width=width, height=height)
        fx, fy, cx, cy = _K_entries(K, "K")
        dist = () if dist is None else dist
        if model is None:
            model = "brown" if np.size(dist) else "pinhole"
        return cls(model, fx, fy, cx, cy, dist, width, height)

    @classmethod
    def from_opencv(cls, K, dist=None, fisheye=False, width=None, height=None):
        """From OpenCV's camera matrix and distortion vector.

        fisheye=False: dist as cv2.calibrateCamera writes it (4, 5, 8, 12 or
        14 entries k1, k2, p1, p2[, k3[, k4, k5, k6[, s1..s4[, tx, ty]]]]);
        the rational, thin-prism and tilt terms must be zero (the Brown model
        has k1, k2, p1, p2, k3 only): ValueError otherwise, not a silently
        different camera. fisheye=True: dist as cv2.fisheye.calibrate writes
        it (k1, k2, k3, k4), giving the Kannala-Brandt model."""
        fx, fy, cx, cy = _K_entries(K, "K")
        if dist is None or np.size(dist) == 0:
            return cls("pinhole", fx, fy, cx, cy, (), width, height)
        d = as_array(np.ravel(dist), (None,), "dist")
        if fisheye:
            if d.shape[0] != 4:
                raise ValueError("fisheye dist must have 4 entries (k1, k2, k3, k4), got %d" % d.shape[0])
            return cls("fisheye", fx, fy, cx, cy, d, width, height)
        if d.shape[0] not in (4, 5, 8, 12, 14):
            raise ValueError("OpenCV dist must have 4, 5, 8, 12 or 14 entries, got %d" % d.shape[0])
        if d.shape[0] > 5 and np.any(d[5:] != 0):
            raise ValueError("dist entries beyond k3 (rational k4-k6, thin prism, tilt) must be 0: "
                             "the Brown model has k1, k2, p1, p2, k3 only; got %s" % d[5:].tolist())
        return cls("brown", fx, fy, cx, cy, d[:5], width, height)

    @classmethod
    def from_file(cls, path, camera=None):
        """The camera of a calibration file (see libsfm.calib.read_camera):
        OpenCV FileStorage (.yaml/.yml/.xml), ROS camera_info YAML, Kalibr
        camchain YAML, EuRoC sensor.yaml or KITTI calib.txt. camera selects
        one of several (Kalibr "cam1", KITTI "P2", or an index)."""
        from .calib import read_camera
        return read_camera(path, camera)

    @property
    def K(self):
        """The 3x3 intrinsic matrix."""
        return np.array([[self.fx, 0.0, self.cx], [0.0, self.fy, self.cy], [0.0, 0.0, 1.0]])

    def to_opencv(self):
        """(K (3,3), dist) for OpenCV: dist is the 5-vector of cv2.projectPoints
        for "brown" and "pinhole", the 4-vector of cv2.fisheye for "fisheye"."""
        return self.K, (self.dist.copy() if self.model != "pinhole" else np.zeros(5))

    def __eq__(self, other):
        return (isinstance(other, Camera) and self.model == other.model
                and (self.fx, self.fy, self.cx, self.cy) == (other.fx, other.fy, other.cx, other.cy)
                and np.array_equal(self.dist, other.dist)
                and (self.width, self.height) == (other.width, other.height))

    __hash__ = None

    def __reduce__(self):
        # picklable (for process pools): rebuilt from its parameters
        return (Camera, (self.model, self.fx, self.fy, self.cx, self.cy, self.dist.copy(),
                         self.width, self.height))

    def __repr__(self):
        size = "" if self.width is None else ", width=%d, height=%d" % (self.width, self.height or 0)
        return "Camera(%r, fx=%g, fy=%g, cx=%g, cy=%g, dist=%s%s)" % (
            self.model, self.fx, self.fy, self.cx, self.cy, [float(v) for v in self.dist], size)

    def _many(self, fn, a, cols_in, cols_out, name, where):
        """fn over the rows of a ((n, cols_in), or one row (cols_in,))."""
        single = np.ndim(a) == 1
        a = as_array(np.reshape(a, (1, -1)) if single else a, (None, cols_in), name)
        out = np.empty((a.shape[0], cols_out), dtype=np.float64)
        check(fn(self._c, dptr(a), a.shape[0], dptr(out)), where, {name: a})
        return out[0] if single else out

    def project(self, X):
        """Pixels (n, 2) of points X (n, 3) in the camera frame, or (2,) of
        one point (3,)."""
        return self._many(lib.sfm_camera_project_many, X, 3, 2, "X", "sfm_camera_project_many")

    def project_jacobian(self, X):
        """(px (2,), J (2, 3)) for one point X (3,): J = d(px)/dX, pixels per
        camera-frame unit."""
        X = as_array(X, (3,), "X")
        px = np.empty(2, dtype=np.float64)
        J = np.empty((2, 3), dtype=np.float64)
        check(lib.sfm_camera_project(self._c, dptr(X), dptr(px), dptr(J)), "sfm_camera_project",
              {"X": X})
        return px, J

    def unproject(self, px):
        """Unit bearings (n, 3) of pixels px (n, 2), or (3,) of one (2,).
        Raises SfmError with status SFM_E_NO_CONVERGENCE for a pixel outside
        the region where the distortion can be inverted."""
        return self._many(lib.sfm_camera_unproject_many, px, 2, 3, "px", "sfm_camera_unproject_many")


def as_camera(K, dist=None, name="K"):
    """A Camera from what a caller passed as intrinsics: a Camera (dist must
    then be None: it carries its own) or a 3x3 K with an optional OpenCV
    Brown-Conrady vector dist. Errors name the argument."""
    if isinstance(K, Camera):
        if dist is not None:
            raise ValueError("%s is a Camera, which carries its distortion: give no dist for it" % name)
        return K
    try:
        fx, fy, cx, cy = _K_entries(K, name)
    except (TypeError, ValueError) as e:
        if isinstance(K, (list, tuple, np.ndarray)):
            raise
        raise TypeError("%s must be a libsfm.Camera or a 3x3 matrix, got %s"
                        % (name, type(K).__name__)) from e
    if dist is None or np.size(dist) == 0:
        return Camera("pinhole", fx, fy, cx, cy)
    try:
        return Camera.from_opencv(K, dist)
    except ValueError as e:
        raise ValueError("distortion of %s: %s" % (name, e)) from None
