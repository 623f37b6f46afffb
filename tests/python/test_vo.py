"""The VO binding and the replay tool's pure parts: statuses, shape checks,
the Sim3 alignment against a known similarity, recording layouts."""
import os

import numpy as np
import pytest

import libsfm
from libsfm import replay


def test_self_calibration_of_a_fisheye_is_unsupported():
    """Without a camera the pipeline self-calibrates a pinhole camera; a
    distortion model cannot be found that way: unsupported, not a guess."""
    vo = libsfm.VisualOdometry(320, 240, None, max_features=200, window=3)
    r = vo.push(np.zeros((240, 320), np.uint8), 0)
    assert r.focal == 0.0  # nothing self-calibrated yet
    with pytest.raises(libsfm.SfmError) as e:
        libsfm.VisualOdometry(320, 240, None, max_features=200, window=3, model="fisheye")
    assert e.value.status == libsfm.lib.SFM_E_UNSUPPORTED


def test_bad_inputs():
    vo = libsfm.VisualOdometry(320, 240, (300, 300, 159.5, 119.5), max_features=200, window=3)
    with pytest.raises(ValueError):
        vo.push(np.zeros((240, 321), np.uint8), 0)
    with pytest.raises(ValueError):
        vo.push(np.zeros((240, 320), np.float32), 0)
    with pytest.raises(libsfm.SfmError):
        vo.push(np.zeros((240, 320), np.uint8), 0, gravity=[0, np.nan, 0])
    r = vo.push(np.zeros((240, 320), np.uint8), 10)
    assert r.state == "initialising" and r.n_features == 0
    with pytest.raises(libsfm.SfmError):
        vo.push(np.zeros((240, 320), np.uint8), 5)  # time going backwards
    with pytest.raises(TypeError):
        libsfm.VisualOdometry(320, 240, (300, 300, 160, 120), no_such_parameter=1)
    with pytest.raises(libsfm.SfmError):
        libsfm.VisualOdometry(320, 240, (300, 300, 160, 120), window=SFM_WIN_TOO_BIG)


SFM_WIN_TOO_BIG = 17


def test_umeyama_recovers_a_known_similarity():
    rng = np.random.default_rng(3)
    P = rng.normal(size=(50, 3))
    q = rng.normal(size=4)
    q /= np.linalg.norm(q)
    R = replay.quat_to_rot(*q)
    G = 2.5 * P @ R.T + [1, -2, 3]
    s, R2, t = replay.umeyama(P, G)
    assert abs(s - 2.5) < 1e-12 and np.allclose(R2, R, atol=1e-12) and np.allclose(t, [1, -2, 3])
    # quaternion writer/reader agree
    qx, qy, qz, qw = replay.rot_to_quat(R)
    assert np.allclose(replay.quat_to_rot(qw, qx, qy, qz), R, atol=1e-12)


def test_evaluate_is_zero_on_a_scaled_copy():
    rng = np.random.default_rng(4)
    gt = [(np.eye(3), rng.normal(size=3)) for _ in range(10)]
    est = [(R, 0.3 * c) for R, c in gt]
    ev = replay.evaluate(est, gt)
    assert ev["ate_rmse"] < 1e-12 and abs(ev["scale"] - 1 / 0.3) < 1e-9
    assert ev["rpe_trans_rmse"] < 1e-12 and ev["rpe_rot_median_deg"] < 1e-6


def test_kitti_layout_without_times(tmp_path):
    import cv2
    d = tmp_path / "kitti"
    (d / "image_0").mkdir(parents=True)
    for i in range(3):
        cv2.imwrite(str(d / "image_0" / ("%06d.png" % i)), np.zeros((40, 60), np.uint8))
    (d / "calib.txt").write_text("P0: 700 0 300 0 0 701 180 0 0 0 1 0\n")
    rec = replay.open_recording(str(d))
    assert rec.kind == "kitti" and rec.camera == (700.0, 701.0, 300.0, 180.0)
    assert [t for t, _ in rec.frames] == [0, 100000000, 200000000]


def test_euroc_layout(tmp_path):
    base = tmp_path / "MH" / "mav0" / "cam0"
    (base / "data").mkdir(parents=True)
    (base / "data.csv").write_text("#timestamp [ns],filename\n1403636579763555584,1403636579763555584.png\n")
    (base / "sensor.yaml").write_text("intrinsics: [458.654, 457.296, 367.215, 248.375]\n"
                                      "distortion_coefficients: [-0.28340811, 0.07395907, 0.00019359, 1.76187114e-05]\n")
    rec = replay.open_recording(str(tmp_path / "MH"))
    assert rec.kind == "euroc" and rec.frames[0][0] == 1403636579763555584
    assert rec.camera[:4] == (458.654, 457.296, 367.215, 248.375) and len(rec.camera) == 9
    assert os.path.basename(rec.frames[0][1]) == "1403636579763555584.png"
