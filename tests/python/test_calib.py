"""Calibration files: each format read back from a file written by the
program that defines it (OpenCV's cv2.FileStorage) or in its documented
layout (ROS camera_calibration_parsers, Kalibr, EuRoC, KITTI), and a clear
error naming the file and the field when one is missing or malformed."""
import os
import subprocess

import cv2
import numpy as np
import pytest

import libsfm
from libsfm import Camera
from libsfm.calib import CalibrationError, read_camera, read_cameras, write_opencv

KITTI = os.path.join(os.path.dirname(os.path.abspath(__file__)), "..", "..", "..", "shared", "data",
                     "kitti-seq1", "calib.txt")
SFM_CALIB = os.path.join(os.path.dirname(os.path.abspath(__file__)), "..", "..", "build", "bin", "sfm-calib")
K = np.array([[812.25, 0.0, 639.5], [0.0, 811.75, 359.25], [0.0, 0.0, 1.0]])
D5 = np.array([-0.281, 0.0742, 1.9e-4, -1.8e-5, -0.0113])
D4F = np.array([0.0315, -0.0072, 0.0041, -0.0011])


def c_read(path, camera=None):
    """The C programs' reader (firmware_examples/linux/calib_file.c) through
    build/bin/sfm-calib: (Camera or None, stderr)."""
    assert os.path.exists(SFM_CALIB), "build/bin/sfm-calib missing: make build/bin/sfm-calib"
    cmd = [SFM_CALIB, str(path)] + ([camera] if camera is not None else [])
    r = subprocess.run(cmd, capture_output=True, text=True, timeout=30)
    if r.returncode != 0:
        assert r.returncode == 1, r.stderr
        return None, r.stderr
    f = r.stdout.split()
    dist = [float(v) for v in f[5:10]][:Camera.NDIST[f[0]]]
    w, h = int(f[10]), int(f[11])
    return Camera(f[0], *map(float, f[1:5]), dist, w or None, h or None), ""


def both(path, camera=None):
    """Python's reading of a file, after checking the C reader agrees to the
    bit (a zero-padded Brown vector and a missing one are the same camera)."""
    py = read_camera(path, camera)
    c, err = c_read(path, camera)
    assert c is not None, err
    assert c == py, (c, py)
    return py


def c_fails(path, field, camera=None):
    c, err = c_read(path, camera)
    assert c is None, c
    assert str(path) in err and field in err, err


def write(tmp_path, name, text):
    p = tmp_path / name
    p.write_text(text)
    return str(p)


def opencv_write(path, K, d, w=1280, h=720, fisheye=None):
    fs = cv2.FileStorage(str(path), cv2.FILE_STORAGE_WRITE)
    fs.write("calibration_time", "Tue Dec  1 2026")
    fs.write("image_width", w)
    fs.write("image_height", h)
    fs.write("camera_matrix", K)
    fs.write("distortion_coefficients", np.asarray(d, dtype=np.float64).reshape(-1, 1))
    if fisheye is not None:
        fs.write("fisheye_model", int(fisheye))
    fs.write("avg_reprojection_error", 0.21)
    fs.release()


@pytest.mark.parametrize("ext", ["yaml", "xml"])
def test_opencv_filestorage_written_by_cv2(tmp_path, ext):
    path = tmp_path / ("calib." + ext)
    opencv_write(path, K, D5)
    cam = both(path)
    assert cam.model == "brown" and (cam.width, cam.height) == (1280, 720)
    assert np.array_equal(cam.K, K) and np.array_equal(cam.dist, D5)
    # the camera projects as OpenCV does with what it wrote
    X = np.array([[0.3, -0.2, 1.0], [-0.5, 0.4, 2.0], [0.01, 0.0, 5.0]])
    q, _ = cv2.projectPoints(X, np.zeros(3), np.zeros(3), K, D5)
    assert np.allclose(cam.project(X), q.reshape(-1, 2), atol=1e-9)
    assert Camera.from_file(path) == cam


def test_opencv_fisheye_and_4_and_8_entry_vectors(tmp_path):
    p = tmp_path / "fish.yml"
    opencv_write(p, K, D4F, fisheye=1)
    cam = both(p)
    assert cam.model == "fisheye" and np.array_equal(cam.dist, D4F)
    X = np.array([[0.3, -0.2, 1.0], [-1.0, 0.5, 1.2]])
    q, _ = cv2.fisheye.projectPoints(X.reshape(-1, 1, 3), np.zeros(3), np.zeros(3), K, D4F)
    assert np.allclose(cam.project(X), q.reshape(-1, 2), atol=1e-9)
    p4 = tmp_path / "d4.yml"
    opencv_write(p4, K, D5[:4])
    c4 = both(p4)
    assert c4.model == "brown" and np.array_equal(c4.dist, np.r_[D5[:4], 0])
    p8 = tmp_path / "d8.xml"
    opencv_write(p8, K, np.r_[D5, 0.01, 0, 0])
    with pytest.raises(CalibrationError, match="distortion_coefficients") as e:
        read_camera(p8)
    assert str(p8) in str(e.value)


def test_write_opencv_is_read_by_cv2(tmp_path):
    for cam in (Camera("brown", 700.5, 701.25, 320.125, 240.5, D5, 640, 480),
                Camera("fisheye", 300.0, 300.5, 321.0, 239.0, D4F, 640, 480),
                Camera("pinhole", 500.0, 500.0, 320.0, 240.0)):
        p = tmp_path / ("w_%s.yaml" % cam.model)
        write_opencv(p, cam)
        fs = cv2.FileStorage(str(p), cv2.FILE_STORAGE_READ)
        assert np.array_equal(fs.getNode("camera_matrix").mat(), cam.K)
        d = fs.getNode("distortion_coefficients").mat().ravel()
        assert np.array_equal(d, cam.to_opencv()[1])
        if cam.width:
            assert int(fs.getNode("image_width").real()) == cam.width
        fs.release()
        got = both(p)
        if cam.model == "pinhole":  # written as OpenCV's zero vector, read back as Brown
            assert got.model == "brown" and not got.dist.any() and np.array_equal(got.K, cam.K)
        else:
            assert got == cam


ROS = """image_width: 752
image_height: 480
camera_name: narrow_stereo/left
camera_matrix:
  rows: 3
  cols: 3
  data: [458.654, 0, 367.215, 0, 457.296, 248.375, 0, 0, 1]
distortion_model: {model}
distortion_coefficients:
  rows: 1
  cols: {nd}
  data: [{d}]
rectification_matrix:
  rows: 3
  cols: 3
  data: [1, 0, 0, 0, 1, 0, 0, 0, 1]
projection_matrix:
  rows: 3
  cols: 4
  data: [458.654, 0, 367.215, 0, 0, 457.296, 248.375, 0, 0, 0, 1, 0]
"""


def test_ros_camera_info(tmp_path):
    d = [-0.28340811, 0.07395907, 0.00019359, 1.76187114e-05, 0.0]
    p = write(tmp_path, "left.yaml", ROS.format(model="plumb_bob", nd=5, d=", ".join(map(str, d))))
    cam = both(p)
    assert cam.model == "brown" and (cam.fx, cam.fy, cam.cx, cam.cy) == (458.654, 457.296, 367.215, 248.375)
    assert np.array_equal(cam.dist, d) and (cam.width, cam.height) == (752, 480)
    p = write(tmp_path, "eq.yaml", ROS.format(model="equidistant", nd=4, d=", ".join(map(str, D4F))))
    assert both(p).model == "fisheye"
    p = write(tmp_path, "rat.yaml", ROS.format(model="rational_polynomial", nd=8,
                                               d=", ".join(map(str, d + [0, 0, 0]))))
    assert both(p).model == "brown"
    p = write(tmp_path, "fov.yaml", ROS.format(model="fov", nd=1, d="0.9"))
    with pytest.raises(CalibrationError, match="distortion_model"):
        read_camera(p)
    c_fails(p, "distortion_model")
    p = write(tmp_path, "bad.yaml", ROS.format(model="plumb_bob", nd=5, d="-0.28, 0.07, x, 0, 0"))
    with pytest.raises(CalibrationError, match="distortion_coefficients") as e:
        read_camera(p)
    assert p in str(e.value)
    c_fails(p, "distortion_coefficients")


KALIBR = """cam0:
  T_cam_imu:
  - [0.0148655429818, 0.999557249008, -0.0257744366974, 0.0652229095355]
  - [-0.999880929698, 0.0149672133247, 0.00375618835797, -0.0207035352557]
  - [0.00414029679422, 0.025715529948, 0.999660727178, -0.0080546143308]
  - [0.0, 0.0, 0.0, 1.0]
  cam_overlaps: [1]
  camera_model: pinhole
  distortion_coeffs: [-0.28340811, 0.07395907, 0.00019359, 1.76187114e-05]
  distortion_model: radtan
  intrinsics: [458.654, 457.296, 367.215, 248.375]
  resolution: [752, 480]
  rostopic: /cam0/image_raw
cam1:
  T_cn_cnm1:
  - [0.999997256477, 0.00231206719, 0.000376008102, -0.110073808127]
  - [-0.002317135723, 0.999898048506, 0.014089835846, 0.000399121547]
  - [-0.000343393121, -0.014090668453, 0.999900662637, -0.000853702503]
  - [0.0, 0.0, 0.0, 1.0]
  camera_model: pinhole
  distortion_coeffs: [0.0034823894022493434, 0.0007150348452162257, -0.0020532361418706202, 0.00020293673591811182]
  distortion_model: equidistant
  intrinsics: [{intr}]
  resolution: [752, 480]
  rostopic: /cam1/image_raw
"""


def test_kalibr_camchain_radtan_and_equi(tmp_path):
    p = write(tmp_path, "camchain.yaml", KALIBR.format(intr="457.587, 456.134, 379.999, 255.238"))
    cams = read_cameras(p)
    assert list(cams) == ["cam0", "cam1"]
    assert cams["cam0"].model == "brown"
    assert np.array_equal(cams["cam0"].dist, [-0.28340811, 0.07395907, 0.00019359, 1.76187114e-05, 0])
    c1 = both(p, "cam1")
    assert both(p) == cams["cam0"]
    assert c1.model == "fisheye" and (c1.fx, c1.cy) == (457.587, 255.238)
    assert c1.dist[3] == 0.00020293673591811182 and (c1.width, c1.height) == (752, 480)
    assert read_camera(p, 1) == c1 and read_camera(p) == cams["cam0"]
    with pytest.raises(CalibrationError, match="cam2"):
        read_camera(p, "cam2")
    p = write(tmp_path, "short.yaml", KALIBR.format(intr="457.587, 456.134, 379.999"))
    with pytest.raises(CalibrationError, match=r"cam1\.intrinsics.*4") as e:
        read_cameras(p)
    assert p in str(e.value)
    c_fails(p, "cam1.intrinsics", "cam1")
    p = write(tmp_path, "omni.yaml", KALIBR.format(intr="1, 2, 3, 4").replace(
        "camera_model: pinhole\n  distortion_coeffs: [0.00", "camera_model: omni\n  distortion_coeffs: [0.00"))
    with pytest.raises(CalibrationError, match=r"cam1\.camera_model"):
        read_cameras(p)
    c_fails(p, "cam1.camera_model", "cam1")


EUROC = """%YAML:1.0
# General sensor definitions.
sensor_type: camera
comment: VI-Sensor cam0 (MT9M034)

# Sensor extrinsics wrt. the body-frame.
T_BS:
  cols: 4
  rows: 4
  data: [0.0148655429818, -0.999880929698, 0.00414029679422, -0.0216401454975,
         0.999557249008, 0.0149672133247, 0.025715529948, -0.064676986768,
        -0.0257744366974, 0.00375618835797, 0.999660727178, 0.00981073058949,
         0.0, 0.0, 0.0, 1.0]

# Camera specific definitions.
rate_hz: 20
resolution: [752, 480]
camera_model: pinhole
intrinsics: [458.654, 457.296, 367.215, 248.375] #fu, fv, cu, cv
distortion_model: radial-tangential
distortion_coefficients: [-0.28340811, 0.07395907, 0.00019359, 1.76187114e-05]
"""


def test_euroc_sensor_yaml(tmp_path):
    cam = both(write(tmp_path, "sensor.yaml", EUROC))
    assert cam.model == "brown" and (cam.fx, cam.fy, cam.cx, cam.cy) == (458.654, 457.296, 367.215, 248.375)
    assert cam.dist[1] == 0.07395907 and cam.dist[4] == 0 and (cam.width, cam.height) == (752, 480)
    p = write(tmp_path, "nointr.yaml", EUROC.replace("intrinsics: [458.654, 457.296, 367.215, 248.375]",
                                                     "intrinsic: [1, 2, 3, 4]"))
    with pytest.raises(CalibrationError, match="'intrinsics'.*missing") as e:
        read_camera(p)
    assert p in str(e.value)
    c_fails(p, "'intrinsics'")
    p = write(tmp_path, "imu.yaml", EUROC.replace("sensor_type: camera", "sensor_type: imu"))
    with pytest.raises(CalibrationError, match="sensor_type"):
        read_camera(p)
    c_fails(p, "sensor_type")


@pytest.mark.skipif(not os.path.exists(KITTI), reason="SKIP: ../shared/data/kitti-seq1 not found")
def test_kitti_calib_shared_excerpt():
    """The shared excerpt: two unlabelled 3x4 rows, fx 707.0912 (SOURCE.txt)."""
    cams = read_cameras(KITTI)
    assert list(cams) == ["P0", "P1"]
    P0 = np.loadtxt(KITTI)[0].reshape(3, 4)
    c = both(KITTI)
    assert both(KITTI, "P1") == cams["P1"]
    assert c.model == "pinhole" and np.array_equal(c.K, P0[:, :3]) and c.fx == 707.0912


def test_kitti_odometry_and_raw_layouts(tmp_path):
    P = "7.188560000000e+02 0.000000000000e+00 6.071928000000e+02 {tx} 0.000000000000e+00 " \
        "7.188560000000e+02 1.852157000000e+02 0.000000000000e+00 0.000000000000e+00 " \
        "0.000000000000e+00 1.000000000000e+00 0.000000000000e+00"
    text = "".join("P%d: %s\n" % (i, P.format(tx=tx)) for i, tx in
                   enumerate(("0.0", "-3.861448000000e+02", "4.538225000000e+01", "-3.372877000000e+02")))
    text += "Tr: " + " ".join(["0.1"] * 12) + "\n"
    p = write(tmp_path, "calib.txt", text)
    cams = read_cameras(p)
    assert list(cams) == ["P0", "P1", "P2", "P3"]
    assert both(p, "P2").cx == 607.1928 and both(p, "P2").fy == 718.856
    raw = ("calib_time: 09-Jan-2012 13:57:47\ncorner_dist: 9.950000e-02\n"
           "S_00: 1.392000e+03 5.120000e+02\n"
           "K_00: 9.842439e+02 0.000000e+00 6.900000e+02 0.000000e+00 9.808141e+02 2.331966e+02 "
           "0.000000e+00 0.000000e+00 1.000000e+00\n"
           "D_00: -3.728755e-01 2.037299e-01 2.219027e-03 1.383707e-03 -7.233722e-02\n"
           "S_rect_00: 1.242000e+03 3.750000e+02\n"
           "P_rect_00: 7.215377e+02 0.000000e+00 6.095593e+02 0.000000e+00 0.000000e+00 "
           "7.215377e+02 1.728540e+02 0.000000e+00 0.000000e+00 0.000000e+00 1.000000e+00 0.000000e+00\n")
    raw_path = write(tmp_path, "calib_cam_to_cam.txt", raw)
    cams = read_cameras(raw_path)
    assert both(raw_path, "00") == cams["00"] and both(raw_path, "P_rect_00") == cams["P_rect_00"]
    assert cams["00"].model == "brown" and cams["00"].dist[4] == -7.233722e-02
    assert (cams["00"].width, cams["00"].height) == (1392, 512)
    assert cams["P_rect_00"].fx == 721.5377 and cams["P_rect_00"].width == 1242
    p = write(tmp_path, "short.txt", "P0: 1 0 2 0 0 1 2 0 0 0 1\n")
    with pytest.raises(CalibrationError, match="'P0'.*12") as e:
        read_camera(p)
    assert p in str(e.value)
    c_fails(p, "'P0'")


def test_errors_name_the_file_and_the_field(tmp_path):
    p = write(tmp_path, "nok.yaml", "%YAML:1.0\n---\nimage_width: 640\nimage_height: 480\n"
                                    "distortion_coefficients: [0, 0, 0, 0, 0]\n")
    with pytest.raises(CalibrationError, match="camera_matrix") as e:
        read_camera(p)
    assert e.value.path == p and isinstance(e.value, ValueError)
    c_fails(p, "camera_matrix")
    p = write(tmp_path, "skew.yaml", "camera_matrix: {rows: 3, cols: 3, data: [500, 3, 320, 0, 500, 240, 0, 0, 1]}\n")
    with pytest.raises(CalibrationError, match="camera_matrix"):
        read_camera(p)
    p = write(tmp_path, "rows.yaml", "camera_matrix: {rows: 3, cols: 2, data: [500, 0, 320, 0, 500, 240, 0, 0, 1]}\n")
    with pytest.raises(CalibrationError, match="camera_matrix.*rows x cols"):
        read_camera(p)
    p = write(tmp_path, "w.yaml", "image_width: -3\nimage_height: 480\ncamera_matrix: [500, 0, 320, 0, 500, 240, 0, 0, 1]\n")
    with pytest.raises(CalibrationError, match="image_width"):
        read_camera(p)
    c_fails(p, "image_width")
    p = write(tmp_path, "f0.yaml", "camera_matrix: [0, 0, 320, 0, 500, 240, 0, 0, 1]\n")
    with pytest.raises(CalibrationError, match="f0.yaml"):
        read_camera(p)
    c_fails(p, "camera_matrix")
    p = write(tmp_path, "junk.yaml", "a: [1, 2\n")
    with pytest.raises(CalibrationError, match="junk.yaml.*YAML"):
        read_camera(p)
    c_fails(p, "junk.yaml")
    with pytest.raises(CalibrationError, match="missing.yaml.*cannot be read"):
        read_camera(str(tmp_path / "missing.yaml"))
    p = write(tmp_path, "bad.xml", "<?xml version=\"1.0\"?>\n<opencv_storage>\n<camera_matrix type_id=\"opencv-matrix\">"
              "<rows>3</rows><cols>3</cols><dt>d</dt><data>500 0 320 0 500</data></camera_matrix>\n</opencv_storage>\n")
    with pytest.raises(CalibrationError, match="camera_matrix"):
        read_camera(p)
    c_fails(p, "camera_matrix")
    c_fails(tmp_path / "missing.yaml", "cannot be opened")


def test_a_camera_from_a_file_drives_an_estimator(tmp_path):
    """The file's Camera goes straight into the estimators."""
    p = tmp_path / "cam.yaml"
    opencv_write(p, np.array([[500.0, 0, 320], [0, 500, 240], [0, 0, 1]]), np.zeros(5), 640, 480)
    cam = Camera.from_file(p)
    rng = np.random.default_rng(1)
    X = np.column_stack([rng.uniform(-2, 2, 80), rng.uniform(-1.5, 1.5, 80), rng.uniform(4, 8, 80)])
    R = cv2.Rodrigues(np.array([0.02, -0.05, 0.01]))[0]
    t = np.array([-0.5, 0.05, 0.02])
    p1, p2 = cam.project(X), cam.project(X @ R.T + t)
    r = libsfm.estimate_relative_pose(p1, p2, cam, cam, seed=1)
    assert np.degrees(np.arccos(np.clip((np.trace(r.R.T @ R) - 1) / 2, -1, 1))) < 0.05
