"""Camera calibration files: read a Camera from what a robot builder has.

Formats (detected from the file's content; the file name is not trusted):

  OpenCV FileStorage   YAML (%YAML:1.0, !!opencv-matrix) or XML, as written by
                       cv2.FileStorage after calibrateCamera: camera_matrix
                       (or cameraMatrix, K), distortion_coefficients (or
                       distCoeffs, dist_coeffs, D), image_width, image_height;
                       a fisheye calibration (cv2.fisheye) is marked by
                       fisheye_model: 1 or distortion_model: fisheye /
                       equidistant.
  ROS camera_info      YAML of camera_calibration_parsers: image_width,
                       image_height, camera_matrix {rows, cols, data},
                       distortion_model (plumb_bob, rational_polynomial,
                       equidistant), distortion_coefficients {data}.
  Kalibr camchain      YAML with cam0, cam1, ...: camera_model pinhole,
                       intrinsics [fu, fv, pu, pv], distortion_model radtan
                       or equidistant, distortion_coeffs, resolution [w, h].
  EuRoC sensor.yaml    sensor_type camera, camera_model pinhole, intrinsics
                       [fu, fv, cu, cv], distortion_model radial-tangential
                       or equidistant, distortion_coefficients, resolution.
  KITTI calib.txt      lines "P0: p00 ... p23" (12 numbers, the rectified
                       3x4 projection matrices; K is its left 3x3), also
                       without the "P0:" labels; or calib_cam_to_cam.txt
                       with K_00, D_00, S_00.

Radial-tangential (radtan, plumb_bob) is the Brown-Conrady model;
equidistant is Kannala-Brandt ("fisheye"). A missing or malformed field
raises CalibrationError (a ValueError) naming the file and the field.
"""
import os
import re
import xml.etree.ElementTree as ET

import numpy as np

from .camera import Camera

__all__ = ["read_camera", "read_cameras", "write_opencv", "CalibrationError"]


class CalibrationError(ValueError):
    """A calibration file that cannot be read; path and field name where."""

    def __init__(self, path, field, problem):
        self.path, self.field, self.problem = path, field, problem
        where = "%s: field %r" % (path, field) if field else str(path)
        super().__init__("%s: %s" % (where, problem))


def _yaml():
    try:
        import yaml
    except ImportError as e:  # pragma: no cover - PyYAML is a dependency
        raise ImportError("reading YAML calibration files needs PyYAML (pip install pyyaml)") from e
    return yaml


def _load_yaml(path, text):
    yaml = _yaml()

    class Loader(yaml.SafeLoader):
        pass

    def matrix(loader, node):
        m = loader.construct_mapping(node, deep=True)
        m["__opencv_matrix__"] = True
        return m

    for tag in ("tag:yaml.org,2002:opencv-matrix", "tag:yaml.org,2002:opencv-nd-matrix"):
        Loader.add_constructor(tag, matrix)
    # OpenCV writes the directive as "%YAML:1.0", which is not YAML 1.1.
    text = re.sub(r"^%YAML[: ]\d+\.\d+[^\n]*\n", "", text)
    try:
        doc = yaml.load(text, Loader=Loader)
    except yaml.YAMLError as e:
        raise CalibrationError(path, None, "not valid YAML (%s)" % str(e).replace("\n", " ")) from None
    if not isinstance(doc, dict):
        raise CalibrationError(path, None, "expected a YAML mapping at the top level")
    return doc


def _numbers(path, field, value, count=None, shape=None):
    """A float array from a YAML/XML value: a list, an {rows, cols, data}
    mapping (OpenCV, ROS) or a string of numbers."""
    if value is None:
        raise CalibrationError(path, field, "missing")
    rows = cols = None
    if isinstance(value, dict):
        if "data" not in value:
            raise CalibrationError(path, field + ".data", "missing")
        rows, cols = value.get("rows"), value.get("cols")
        value = value["data"]
    if isinstance(value, str):
        value = value.split()
    try:
        arr = np.array(value, dtype=np.float64).ravel()
    except (TypeError, ValueError):
        raise CalibrationError(path, field, "expected numbers, got %r" % (value,)) from None
    if rows is not None and cols is not None:
        try:
            r, c = int(rows), int(cols)
        except (TypeError, ValueError):
            raise CalibrationError(path, field, "rows and cols must be integers") from None
        if r * c != arr.size:
            raise CalibrationError(path, field, "rows x cols is %d x %d but data holds %d numbers"
                                   % (r, c, arr.size))
    if count is not None and arr.size not in np.atleast_1d(count):
        raise CalibrationError(path, field, "expected %s numbers, got %d"
                               % (" or ".join(str(c) for c in np.atleast_1d(count)), arr.size))
    if not np.all(np.isfinite(arr)):
        raise CalibrationError(path, field, "holds a NaN or an infinity")
    return arr.reshape(shape) if shape is not None else arr


def _int_field(path, field, value, required=False):
    if value is None:
        if required:
            raise CalibrationError(path, field, "missing")
        return None
    try:
        v = float(value)
    except (TypeError, ValueError):
        raise CalibrationError(path, field, "expected an integer, got %r" % (value,)) from None
    if v != int(v) or v < 1:
        raise CalibrationError(path, field, "expected a positive integer, got %r" % (value,))
    return int(v)


def _first(doc, names):
    for n in names:
        if n in doc:
            return n, doc[n]
    return names[0], None


def _camera(path, field, make):
    """Build a Camera, turning a refused parameter into an error naming the
    file and field."""
    try:
        return make()
    except ValueError as e:
        raise CalibrationError(path, field, str(e)) from None
    except Exception as e:  # SfmError from sfm_camera_validate
        if type(e).__name__ == "SfmError":
            raise CalibrationError(path, field, str(e)) from None
        raise


def _K(path, field, value):
    K = _numbers(path, field, value, 9, (3, 3))
    if K[1, 0] != 0 or K[2, 0] != 0 or K[2, 1] != 0 or K[2, 2] != 1 or K[0, 1] != 0:
        raise CalibrationError(path, field, "expected [[fx, 0, cx], [0, fy, cy], [0, 0, 1]], got %s"
                               % K.tolist())
    return K


# --- OpenCV FileStorage and ROS camera_info ---------------------------------

_K_NAMES = ("camera_matrix", "cameraMatrix", "K", "intrinsic_matrix")
_D_NAMES = ("distortion_coefficients", "distCoeffs", "dist_coeffs", "D", "distortion")


def _opencv_like(path, doc, fmt):
    kname, kval = _first(doc, _K_NAMES)
    dname, dval = _first(doc, _D_NAMES)
    K = _K(path, kname, kval)
    model = str(doc.get("distortion_model", "")).strip().lower()
    fisheye = bool(doc.get("fisheye_model", 0)) or model in ("fisheye", "equidistant",
                                                             "kannala_brandt")
    if dval is None:
        if model not in ("", "none"):
            raise CalibrationError(path, dname, "missing (distortion_model is %r)" % model)
        d = np.zeros(0)
    else:
        d = _numbers(path, dname, dval)
    if model not in ("", "none", "plumb_bob", "rational_polynomial", "radtan",
                     "radial-tangential", "fisheye", "equidistant", "kannala_brandt"):
        raise CalibrationError(path, "distortion_model", "unsupported model %r" % model)
    w = _int_field(path, "image_width", doc.get("image_width"))
    h = _int_field(path, "image_height", doc.get("image_height"))
    if (w is None) != (h is None):
        raise CalibrationError(path, "image_height" if h is None else "image_width", "missing")
    return _camera(path, dname, lambda: Camera.from_opencv(K, d, fisheye=fisheye, width=w,
                                                           height=h))


def _xml_value(el):
    if el.get("type_id") == "opencv-matrix":
        def child(tag):
            c = el.find(tag)
            return None if c is None else (c.text or "")
        return {"rows": child("rows"), "cols": child("cols"), "data": child("data") or ""}
    if len(el):
        return {c.tag: _xml_value(c) for c in el}
    text = (el.text or "").strip()
    try:
        return int(text)
    except ValueError:
        try:
            return float(text)
        except ValueError:
            return text.strip('"')


def _read_opencv_xml(path, text):
    try:
        root = ET.fromstring(text)
    except ET.ParseError as e:
        raise CalibrationError(path, None, "not valid XML (%s)" % e) from None
    if root.tag != "opencv_storage":
        raise CalibrationError(path, None, "not an OpenCV FileStorage XML file (root <%s>)" % root.tag)
    doc = {c.tag: _xml_value(c) for c in root}
    return {"0": _opencv_like(path, doc, "opencv")}


# --- Kalibr and EuRoC -------------------------------------------------------

def _kalibr_like(path, node, prefix, dist_key):
    def f(name):
        return prefix + name
    model = node.get("camera_model")
    if model is None:
        raise CalibrationError(path, f("camera_model"), "missing")
    if model != "pinhole":
        raise CalibrationError(path, f("camera_model"), "unsupported projection %r (only pinhole)"
                               % model)
    fu, fv, pu, pv = _numbers(path, f("intrinsics"), node.get("intrinsics"), 4)
    dmodel = node.get("distortion_model")
    if dmodel is None:
        raise CalibrationError(path, f("distortion_model"), "missing")
    dmodel = str(dmodel).strip().lower()
    if dmodel in ("radtan", "radial-tangential", "plumb_bob"):
        kind, d = "brown", _numbers(path, f(dist_key), node.get(dist_key), 4)
    elif dmodel in ("equidistant", "equi", "fisheye"):
        kind, d = "fisheye", _numbers(path, f(dist_key), node.get(dist_key), 4)
    elif dmodel == "none":
        kind, d = "pinhole", np.zeros(0)
    else:
        raise CalibrationError(path, f("distortion_model"), "unsupported model %r" % dmodel)
    res = node.get("resolution")
    w = h = None
    if res is not None:
        wh = _numbers(path, f("resolution"), res, 2)
        w = _int_field(path, f("resolution"), wh[0])
        h = _int_field(path, f("resolution"), wh[1])
    return _camera(path, f("intrinsics"), lambda: Camera(kind, fu, fv, pu, pv, d, w, h))


def _read_yaml(path, text):
    doc = _load_yaml(path, text)
    cams = sorted(k for k in doc if re.fullmatch(r"cam\d+", str(k)) and isinstance(doc[k], dict))
    if cams:  # Kalibr camchain
        return {k: _kalibr_like(path, doc[k], k + ".", "distortion_coeffs") for k in cams}
    if "sensor_type" in doc or ("intrinsics" in doc and "camera_model" in doc):  # EuRoC
        if doc.get("sensor_type", "camera") != "camera":
            raise CalibrationError(path, "sensor_type", "not a camera (%r)" % doc["sensor_type"])
        return {"0": _kalibr_like(path, doc, "", "distortion_coefficients")}
    if any(n in doc for n in _K_NAMES):  # OpenCV FileStorage or ROS camera_info
        return {"0": _opencv_like(path, doc, "opencv")}
    raise CalibrationError(path, "camera_matrix", "missing: not an OpenCV, ROS, Kalibr or EuRoC "
                           "calibration (top-level keys: %s)" % ", ".join(map(str, list(doc)[:8])))


# --- KITTI ------------------------------------------------------------------

def _read_kitti(path, text):
    rows = {}
    bare = 0
    for lineno, line in enumerate(text.splitlines(), 1):
        line = line.strip()
        if not line or line.startswith("#"):
            continue
        m = re.match(r"([A-Za-z_][A-Za-z0-9_]*)\s*:(.*)$", line)
        if m:
            name, vals = m.group(1), m.group(2)
        else:
            name, vals = "P%d" % bare, line
            bare += 1
        if name == "calib_time":
            continue
        rows[name] = _numbers(path, name, vals)
    cams = {}
    for name, v in rows.items():
        if re.fullmatch(r"P\d", name) or re.fullmatch(r"P_rect_\d\d", name):
            if v.size != 12:
                raise CalibrationError(path, name, "expected 12 numbers, got %d" % v.size)
            P = v.reshape(3, 4)
            if P[1, 0] != 0 or P[2, 0] != 0 or P[2, 1] != 0 or P[2, 2] != 1 or P[0, 1] != 0:
                raise CalibrationError(path, name, "not a rectified projection matrix K [I | t]")
            size = rows.get("S_rect_" + name[-2:]) if name.startswith("P_rect_") else None
            w, h = (None, None) if size is None else (int(size[0]), int(size[1]))
            cams[name] = _camera(path, name, lambda P=P, w=w, h=h: Camera(
                "pinhole", P[0, 0], P[1, 1], P[0, 2], P[1, 2], (), w, h))
        elif re.fullmatch(r"K_\d\d", name):
            idx = name[2:]
            K = _K(path, name, v)
            d = rows.get("D_" + idx)
            if d is None:
                raise CalibrationError(path, "D_" + idx, "missing")
            s = rows.get("S_" + idx)
            w, h = (None, None) if s is None else (int(s[0]), int(s[1]))
            cams[idx] = _camera(path, "D_" + idx, lambda K=K, d=d, w=w, h=h: Camera.from_opencv(
                K, d, width=w, height=h))
    if not cams:
        raise CalibrationError(path, "P0", "missing: no projection (P0..P3) or K_xx rows")
    return cams


# --- entry points -----------------------------------------------------------

def read_cameras(path):
    """Every camera of a calibration file: a dict name -> Camera. Names are
    "0" for single-camera files (OpenCV, ROS, EuRoC), "cam0", "cam1", ... for
    Kalibr, "P0".."P3" (or "P_rect_00", "00", ...) for KITTI."""
    path = os.fspath(path)
    try:
        with open(path, "rb") as f:
            raw = f.read()
    except OSError as e:
        raise CalibrationError(path, None, "cannot be read (%s)" % e.strerror) from None
    try:
        text = raw.decode("utf-8")
    except UnicodeDecodeError:
        raise CalibrationError(path, None, "not a text file") from None
    head = text.lstrip()[:200]
    if head.startswith("<?xml") or head.startswith("<opencv_storage"):
        return _read_opencv_xml(path, text)
    first = next((ln.strip() for ln in text.splitlines() if ln.strip() and not ln.startswith("#")), "")
    if re.match(r"^(P\d|P_rect_\d\d|K_\d\d|calib_time|S_\d\d|R_\d\d)\s*:", first) or \
            re.match(r"^[-+0-9.eE]+(\s+[-+0-9.eE]+){11}\s*$", first):
        return _read_kitti(path, text)
    return _read_yaml(path, text)


def read_camera(path, camera=None):
    """One Camera from a calibration file (see the module's list of formats).

    camera: which one when the file holds several: a name from
    read_cameras ("cam1", "P2") or an index in file order; default the
    first ("cam0", "P0")."""
    cams = read_cameras(path)
    names = list(cams)
    if camera is None:
        return cams[names[0]]
    if isinstance(camera, int) and not isinstance(camera, bool):
        if not 0 <= camera < len(names):
            raise CalibrationError(os.fspath(path), None, "camera %d asked for, the file holds %d (%s)"
                                   % (camera, len(names), ", ".join(names)))
        return cams[names[camera]]
    if camera not in cams:
        raise CalibrationError(os.fspath(path), str(camera), "no such camera; the file holds %s"
                               % ", ".join(names))
    return cams[camera]


def write_opencv(path, camera):
    """Write camera as an OpenCV FileStorage YAML file (what
    cv2.FileStorage reads, and what the tools' C reader reads): image_width
    and image_height when known, camera_matrix, distortion_coefficients
    (Brown 5-vector, or the fisheye 4-vector with fisheye_model: 1)."""
    if not isinstance(camera, Camera):
        raise TypeError("camera must be a libsfm.Camera, got %s" % type(camera).__name__)
    K, d = camera.to_opencv()

    def mat(name, m):
        m = np.atleast_2d(m)
        vals = ", ".join(repr(float(v)) for v in m.ravel())
        return "%s: !!opencv-matrix\n   rows: %d\n   cols: %d\n   dt: d\n   data: [ %s ]\n" % (
            name, m.shape[0], m.shape[1], vals)

    out = ["%YAML:1.0\n---\n"]
    if camera.width is not None and camera.height is not None:
        out.append("image_width: %d\nimage_height: %d\n" % (camera.width, camera.height))
    out.append(mat("camera_matrix", K))
    out.append(mat("distortion_coefficients", d.reshape(1, -1)))
    if camera.model == "fisheye":
        out.append("fisheye_model: 1\n")
    with open(os.fspath(path), "w") as f:
        f.write("".join(out))
