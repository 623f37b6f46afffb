"""The demo loop rendered through a Kannala-Brandt fisheye lens
(tools/gen_demo_scene.py --sequence 120 --fisheye: f 300 px, k = 0.03,
-0.01, 0.002, 0, about 150 degrees across the diagonal, the loop at twice
the pinhole sequence's speed) run with the fisheye camera model: every
keypoint goes through sfm_camera_unproject, the geometry works on ideal
pinhole pixels. The trajectory is held to a bound against the rendered truth
(measured at the default settings, 500 features, 5 keyframes: ATE RMSE
0.111 m, 118 of 120 frames tracking, none lost; the pinhole sequence gives
0.028 m: rays far off the axis become far-out ideal pixels, where a pixel of
fisheye noise weighs several, so the periphery contributes little)."""
import os

import pytest

from libsfm import replay

SEQ = os.environ.get("VO_FISH", "build/demo/sequence_fisheye")


@pytest.fixture(scope="module")
def rec():
    if not os.path.exists(os.path.join(SEQ, "ground_truth.txt")):
        pytest.fail("rendered fisheye sequence missing: make %s/ground_truth.txt" % SEQ)
    r = replay.open_recording(SEQ)
    assert r.model == "fisheye" and len(r.camera) == 8
    return r


def test_fisheye_sequence_ate(rec):
    rep = replay.run(rec, progress=False, max_features=500, window=5)
    print("\n" + "\n".join(replay.summary_lines(rep)))
    assert rep["lost"] == 0 and rep["with_pose"] >= rep["frames"] - 6
    assert rep["ate_rmse"] < 0.2, rep["ate_rmse"]  # loop ~2.3 x 2.6 m
    assert rep["rpe_rot_median_deg"] < 0.3


def test_fisheye_as_pinhole_is_worse(rec):
    """The same frames with the lens taken for a pinhole camera of the same
    focal length: the pipeline must not do as well (the model matters)."""
    import copy
    r2 = copy.copy(rec)
    r2.camera, r2.model = tuple(rec.camera[:4]), "pinhole"
    rep = replay.run(r2, progress=False, max_features=500, window=5, max_frames=60)
    good = replay.run(rec, progress=False, max_features=500, window=5, max_frames=60)
    assert "ate_rmse" not in rep or rep["ate_rmse"] > 1.5 * good["ate_rmse"] or rep["lost"] > 0 \
        or rep["with_pose"] < good["with_pose"] - 10, (rep.get("ate_rmse"), good["ate_rmse"])
