"""The VO demo's sequence (tools/gen_demo_scene.py --sequence, a known loop
through a rendered room): ATE after Sim3 alignment and RPE against the
rendered truth, held to bounds with margin (measured with the demo's
settings: ATE RMSE 0.019 m, 0.016-0.029 m over seeds, 237 of 240 frames
with a pose, none lost),
the same trajectory bit for bit on a second run, and the TUM file read back."""
import os

import numpy as np
import pytest

from libsfm import replay

SEQ = os.environ.get("VO_SEQ", "build/demo/sequence")
# the settings of make demo-vo (mk/85-vo.mk, VO_DEMO_SET)
DEMO = dict(max_features=500, window=5, n_levels=3, point_min_parallax_deg=1.0)


@pytest.fixture(scope="module")
def rec():
    if not os.path.exists(os.path.join(SEQ, "ground_truth.txt")):
        pytest.fail("rendered sequence missing: make %s/ground_truth.txt" % SEQ)
    return replay.open_recording(SEQ)


@pytest.fixture(scope="module")
def rep(rec):
    return replay.run(rec, progress=False, **DEMO)


@pytest.mark.parametrize("seed", [2, 3])
def test_demo_other_seeds(rec, seed):
    r = replay.run(rec, progress=False, seed=seed, **DEMO)
    assert r["lost"] == 0 and r["ate_rmse"] < 0.08, (seed, r["ate_rmse"])


def test_demo_ate_and_tracking(rep):
    n = rep["frames"]
    print("\n" + "\n".join(replay.summary_lines(rep)))
    assert rep["lost"] == 0
    assert rep["with_pose"] >= n - 6
    assert rep["ate_rmse"] < 0.08, rep["ate_rmse"]  # room in metres, loop ~2.3 x 2.6 m
    assert rep["rpe_rot_median_deg"] < 0.15
    assert rep["count"] == rep["with_pose"]


def test_demo_deterministic(rec, rep):
    again = replay.run(rec, progress=False, **DEMO)
    a = np.array([np.r_[R.ravel(), c] for _, R, c in rep["rows"]])
    b = np.array([np.r_[R.ravel(), c] for _, R, c in again["rows"]])
    assert a.shape == b.shape and np.array_equal(a, b)


def test_demo_without_gravity_still_tracks(rec):
    r = replay.run(rec, progress=False, use_gravity=False, max_frames=80, **DEMO)
    assert r["lost"] == 0 and r["with_pose"] >= 74
    assert r["ate_rmse"] < 0.1


def test_tum_round_trip(rep, tmp_path):
    p = tmp_path / "t.tum"
    replay.write_tum(str(p), rep["rows"])
    ts, poses = replay.read_tum(str(p))
    assert len(poses) == len(rep["rows"])
    for (t_ns, R, c), t_s, (R2, c2) in zip(rep["rows"], ts, poses):
        assert abs(t_s - t_ns / 1e9) < 1e-8
        assert np.allclose(R, R2, atol=1e-8) and np.allclose(c, c2, atol=1e-8)


def test_demo_through_the_brown_model(rec):
    """The same frames with the camera given as Brown-Conrady with zero
    distortion: every pixel goes through sfm_camera_unproject (the path of
    distorted and fisheye cameras) and the trajectory must hold the same
    bound."""
    import copy
    r2 = copy.copy(rec)
    r2.camera = tuple(rec.camera[:4]) + (0.0, 0.0, 0.0, 0.0, 0.0)
    r = replay.run(r2, progress=False, max_frames=120, **DEMO)
    assert r["lost"] == 0 and r["with_pose"] >= 114
    assert r["ate_rmse"] < 0.08


def test_demo_self_calibrated(rec):
    """The sequence started without a camera: the focal length found on the
    first good keyframe triple and refined by the windowed BA must be the
    renderer's (500 px) within 3 %, and the trajectory must hold the
    calibrated run's bound (measured: 500.6 px at frame 23, 502.9 px after
    the BA, ATE RMSE 0.0265 over 218 poses, none lost)."""
    import copy
    r2 = copy.copy(rec)
    r2.camera = None
    r = replay.run(r2, progress=False, **DEMO)
    print("\n" + "\n".join(replay.summary_lines(r)))
    assert r["self_calibrated"] and r["focal_frame"] >= 0
    assert abs(r["focal_first"] - 500.0) < 15.0 and abs(r["focal"] - 500.0) < 15.0
    assert r["lost"] == 0 and r["with_pose"] >= r["frames"] - r["focal_frame"] - 6
    assert r["ate_rmse"] < 0.08, r["ate_rmse"]
    # before the focal length is known no frame is tracked
    assert all(x.state != "tracking" for x in r["results"][:r["focal_frame"]])


def test_self_calibration_starts_over_when_the_camera_turns_back(rec):
    """Without a camera the calibration triple waits for its third frame to
    have twice the middle keyframe's parallax to the reference. Frames 0-8
    then back to 0 and forward again (a camera turning back): once the
    parallax has fallen to 0.8 of its peak the triple starts over with that
    frame as the reference (measured: at frame 6 on the way back, 1.71 deg
    against a peak of 2.15), instead of waiting for a parallax that does not
    come; the forward run then calibrates within 3 % (measured: 490.7 px at
    frame 23, 499.5 px at frame 59). Each reference that starts over is the
    origin of a new segment (measured: three, the last one tracked)."""
    from libsfm import VisualOdometry
    vo = VisualOdometry(640, 480, None, max_features=500, window=5, n_levels=3)
    order = list(range(0, 9)) + list(range(7, -1, -1)) + list(range(1, 60))
    res = []
    for k, i in enumerate(order):
        img = replay._load_gray(rec.frames[i][1])
        res.append(vo.push(img, 1000000 * k + 1, gravity=rec.gravity[i]))
    back = res[9:17]
    assert any(r.is_keyframe and r.state == "initialising" for r in back), \
        [(r.state, r.is_keyframe, r.median_parallax_deg) for r in back]
    # each reference that starts over reports the origin of a new segment,
    # not frame 0's origin for another place; the tracked frames share the
    # segment of the reference the map grew from
    origins = [r for r in res if r.is_keyframe and r.state == "initialising" and r.has_pose]
    assert len(origins) >= 2 and [r.segment for r in origins] == list(range(len(origins)))
    tracked = [r for r in res if r.state == "tracking"]
    assert tracked and all(r.segment == origins[-1].segment for r in tracked)
    found = [r for r in res if r.focal > 0]
    assert found and abs(found[0].focal - 500.0) < 15.0 and abs(res[-1].focal - 500.0) < 15.0
    assert res[-1].state == "tracking"


def test_demo_loss_and_new_segment(rec):
    """Frames 100-107 blanked (a covered lens): those frames are lost, with
    no pose; three lost frames drop the map; once the frames come back the
    pipeline re-initialises and reports a new segment (result.segment 1),
    which it tracks again. Each segment on its own matches the truth after
    its own Sim3 alignment; the second's scale, carried over from the speed
    before the gap, is compared with the first's (measured: ratio 1.008 on
    this steady loop, segment ATE RMSE 0.0037 / 0.0043 over 97 / 88 poses)."""
    from libsfm import VisualOdometry
    vo = VisualOdometry(640, 480, rec.camera[:4], max_features=500, window=5,
                        n_levels=3, point_min_parallax_deg=1.0)
    res = []
    for i, (ts, path) in enumerate(rec.frames[:200]):
        img = replay._load_gray(path)
        if 100 <= i < 108:
            img = np.zeros_like(img)
        res.append(vo.push(img, ts, gravity=rec.gravity[i]))
    assert all(r.state == "lost" and not r.has_pose for r in res[100:103])
    assert all(not r.has_pose for r in res[100:108])
    assert all(r.segment == 0 for r in res[:100])
    back = [r for r in res[108:] if r.state == "tracking"]
    assert len(back) >= 70 and all(r.segment == 1 for r in back)
    # never a pose of the new segment before it is initialised
    assert all(r.segment == 1 for r in res[108:] if r.has_pose and r.state == "tracking")
    scales = []
    for seg, sel in ((0, res[:100]), (1, back)):
        est = [(r.R_wc, r.c_w) for r in sel if r.has_pose]
        gt = [rec.gt_index[r.frame_index] for r in sel if r.has_pose]
        ev = replay.evaluate(est, gt)
        print("\nsegment %d: %d poses, ATE RMSE %.4f" % (seg, ev["count"], ev["ate_rmse"]))
        assert ev["ate_rmse"] < 0.08, (seg, ev["ate_rmse"])
        scales.append(ev["scale"])
    ratio = scales[1] / scales[0]
    print("\nsegment scales %.4f %.4f ratio %.3f" % (scales[0], scales[1], ratio))
    assert 0.5 < ratio < 2.0, ratio
