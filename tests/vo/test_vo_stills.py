"""Still images through the VO front end (../shared/data, see its README):
the twelve BoofCV triplets (unknown cameras but mono_wall's) and the eight
Herz-Jesu views (K and metric poses known). These are not sequences: the
baselines are wide and the frames few, so the test holds the pipeline to
honesty (no frame tracked without a focal length; every reported segment
consistent with the truth where there is one) and to what it measured
(docs/vo.md has the table this prints)."""
import glob
import os

import numpy as np
import pytest

from libsfm import replay

DATA = os.environ.get("VO_STILLS_DATA", "../shared/data")
BOOF = os.path.join(DATA, "boofcv-triple", "triple")
HJ = os.path.join(DATA, "herzjesu-p8")
# wide baselines: search the whole neighbourhood a still can move by
WIDE = dict(init_radius=600.0, track_radius=200.0)


def _rec(name, files, camera, gt=None):
    return replay.Recording(name, [(i * 1000000000, f) for i, f in enumerate(files)], camera, gt,
                            None, "stills")


def _states(rep):
    return " ".join(r.state for r in rep["results"])


def _strecha(path):
    """Strecha .camera: R (camera-to-world) on lines 5-7, the centre on 8."""
    rows = [ln.split() for ln in open(path)]
    R = np.array([[float(x) for x in rows[i]] for i in (4, 5, 6)])
    return R, np.array([float(x) for x in rows[7]])


def _herzjesu():
    if not os.path.isdir(os.path.join(HJ, "images")):
        pytest.skip("SKIP: %s not found (Herz-Jesu is not part of the project)" % HJ)
    files = sorted(glob.glob(os.path.join(HJ, "images", "*.jpg")))
    K = [ln.split() for ln in open(os.path.join(HJ, "images", "K.txt"))]
    cam = (float(K[0][0]), float(K[1][1]), float(K[0][2]), float(K[1][2]))
    gt = [_strecha(os.path.join(HJ, "gt_dense_cameras", os.path.basename(f) + ".camera"))
          for f in files]
    return files, cam, gt


def _segments_hold(rep, gt, bound):
    """Each segment's tracked poses, aligned on their own, against the truth."""
    out = []
    for seg in sorted({r.segment for r in rep["results"]}):
        sel = [r for r in rep["results"] if r.segment == seg and r.has_pose]
        if len(sel) < 3:
            continue
        ev = replay.evaluate([(r.R_wc, r.c_w) for r in sel], [gt[r.frame_index] for r in sel])
        assert ev["ate_rmse"] < bound, (seg, ev["ate_rmse"])
        out.append((seg, len(sel), ev["ate_rmse"]))
    return out


def test_herzjesu_self_calibrated():
    """Measured: 7 of 8 views with a pose, focal 2750.0 px (K: 2759.5),
    ATE RMSE 0.014 m (Sim3) over the views."""
    files, cam, gt = _herzjesu()
    rep = replay.run(_rec("herzjesu", files, None, gt), progress=False, max_features=2000,
                     window=5, **WIDE)
    print("\nherzjesu, no camera: %s; focal %.1f; ATE %.4f over %d"
          % (_states(rep), rep["focal"], rep.get("ate_rmse", -1), rep.get("count", 0)))
    assert rep["with_pose"] >= 6 and rep["segments"] == 1
    assert abs(rep["focal"] / cam[0] - 1) < 0.02, rep["focal"]
    assert rep["ate_rmse"] < 0.1


def test_herzjesu_calibrated_segments_are_consistent():
    """With K given the wide steps may lose the map: frame 2 holds about a
    quarter of its 124 matches, at the 0.25 share bound (measured: 32
    inliers, one segment of 8 poses, ATE 0.0066 m; with the relative-pose
    polish's influence test the first pair moves by 2e-4 in t, frame 2 has
    27 inliers and is lost, three lost frames, then a second segment of
    three, ATE 0.0007 m). Every segment it does report matches the truth on
    its own."""
    files, cam, gt = _herzjesu()
    rep = replay.run(_rec("herzjesu", files, cam, gt), progress=False, max_features=2000,
                     window=5, **WIDE)
    segs = _segments_hold(rep, gt, 0.1)
    print("\nherzjesu, K: %s; segments %s" % (_states(rep), segs))
    assert all(r.state != "tracking" or r.has_pose for r in rep["results"])


def test_boofcv_triplets():
    """Unknown cameras: the self-calibration needs a third frame with twice
    the middle one's parallax, which three stills rarely offer, so the
    pipeline stays initialising (never a pose it cannot stand behind).
    mono_wall with its known camera (Brown k1, k2) is tracked."""
    if not os.path.isdir(BOOF):
        pytest.skip("SKIP: %s not found (BoofCV triplets are not part of the project)" % BOOF)
    lines = []
    for first in sorted(glob.glob(os.path.join(BOOF, "*_01.jpg"))):
        name = os.path.basename(first)[:-7]
        files = [first[:-6] + "%02d.jpg" % k for k in (1, 2, 3)]
        rep = replay.run(_rec(name, files, None), progress=False, max_features=2000, window=3, **WIDE)
        for r in rep["results"]:
            assert r.state != "tracking" or r.focal > 0, (name, r.frame_index)
        lines.append("%-18s %s  focal %.1f" % (name, _states(rep), rep["focal"]))
    files = [os.path.join(BOOF, "mono_wall_%02d.jpg" % k) for k in (1, 2, 3)]
    cam = (701.0, 698.7, 308.5, 246.8, -0.256, 0.100, 0.0, 0.0, 0.0)
    rep = replay.run(_rec("mono_wall+K", files, cam), progress=False, max_features=2000, window=3)
    lines.append("%-18s %s" % ("mono_wall, K", _states(rep)))
    print("\n" + "\n".join(lines))
    assert len(lines) == 13
    assert rep["with_pose"] == 3 and rep["tracked"] == 2
