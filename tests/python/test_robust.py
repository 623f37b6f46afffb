"""libsfm robust estimators beside PoseLib 2.0.5 and OpenCV on the same
inputs, with synthetic truth and Herz-Jesu-P8 ground truth."""
import glob
import os

import cv2
import numpy as np
import poselib
import pytest

import libsfm
from libsfm import SfmError

K = np.array([[500.0, 0, 320], [0, 500, 240], [0, 0, 1]])
W, H = 640, 480
ROOT = os.path.join(os.path.dirname(os.path.abspath(__file__)), "..", "..")
HJ = os.path.join(ROOT, "..", "shared", "data", "herzjesu-p8")
PL_CAM = {"model": "PINHOLE", "width": W, "height": H, "params": [500.0, 500.0, 320.0, 240.0]}


def rot_err(Ra, Rb):
    return np.degrees(np.arccos(np.clip((np.trace(Ra.T @ Rb) - 1) / 2, -1, 1)))


def dir_err(a, b):
    return np.degrees(np.arccos(np.clip(a @ b / np.linalg.norm(a) / np.linalg.norm(b), -1, 1)))


def rotation(rng, max_deg):
    ax = rng.normal(size=3)
    ax /= np.linalg.norm(ax)
    return cv2.Rodrigues(ax * np.radians(rng.uniform(0, max_deg)))[0]


def twoview(rng, n, outliers, sigma=1.0, planar=False, rot_only=False):
    while True:
        R = rotation(rng, 20)
        t = np.zeros(3) if rot_only else rng.normal(size=3)
        if not rot_only:
            t /= np.linalg.norm(t)
        m = 5 * n
        px = np.column_stack([rng.uniform(0, W, m), rng.uniform(0, H, m)])
        rays = np.column_stack([(px - K[:2, 2]) / 500.0, np.ones(m)])
        if planar:
            nrm = np.array([0.1, -0.2, 1.0])
            depth = 5.0 / (rays @ nrm)
        else:
            depth = rng.uniform(2, 10, m)
        X2 = (rays * depth[:, None]) @ R.T + t
        q = X2[:, :2] / X2[:, 2:3] * 500.0 + K[:2, 2]
        ok = (X2[:, 2] > 0.1) & (q[:, 0] >= 0) & (q[:, 0] < W) & (q[:, 1] >= 0) & (q[:, 1] < H)
        if ok.sum() >= n:
            break
    s = np.flatnonzero(ok)[:n]
    p1 = px[s] + rng.normal(scale=sigma, size=(n, 2))
    p2 = q[s] + rng.normal(scale=sigma, size=(n, 2))
    truth = rng.uniform(size=n) >= outliers
    k = (~truth).sum()
    p2[~truth] = np.column_stack([rng.uniform(0, W, k), rng.uniform(0, H, k)])
    return p1, p2, R, t, truth


def absolute(rng, n, outliers, sigma=1.0):
    R = rotation(rng, 180)
    t = rng.normal(size=3)
    px = np.column_stack([rng.uniform(0, W, n), rng.uniform(0, H, n)])
    Xc = np.column_stack([(px - K[:2, 2]) / 500.0, np.ones(n)]) * rng.uniform(2, 10, n)[:, None]
    X = (Xc - t) @ R
    p = px + rng.normal(scale=sigma, size=(n, 2))
    truth = rng.uniform(size=n) >= outliers
    k = (~truth).sum()
    p[~truth] = np.column_stack([rng.uniform(0, W, k), rng.uniform(0, H, k)])
    return p, X, R, t, truth


# PoseLib under the stopping rule libsfm uses (confidence 0.999, standard
# trial count, no minimum, same cap), so the comparison is like for like.
PL_OPT = {"success_prob": 0.999, "dyn_num_trials_mult": 1.0, "min_iterations": 0,
          "max_iterations": 10000}


def poselib_rel(p1, p2, thr, cam1=PL_CAM, cam2=PL_CAM):
    pose, info = poselib.estimate_relative_pose(p1, p2, cam1, cam2,
                                                dict(PL_OPT, max_epipolar_error=thr), {})
    return pose.R, pose.t


@pytest.mark.parametrize("outliers", [0.25, 0.5, 0.75])
def test_relative_pose_beside_poselib_and_opencv(outliers):
    rng = np.random.default_rng(int(outliers * 100))
    errs = {"libsfm": [], "poselib": [], "cv2": []}
    for k in range(10):
        p1, p2, R, t, truth = twoview(rng, 500, outliers)
        r = libsfm.estimate_relative_pose(p1, p2, K, K, threshold_px=2.0, seed=k)
        assert r["inliers"].dtype == bool and r["inliers"].shape == (500,)
        assert r["num_inliers"] == r["inliers"].sum()
        assert not r["planar"] and not r["pure_rotation"]
        assert (r["inliers"] & ~truth).sum() <= 10
        errs["libsfm"].append((rot_err(r["R"], R), dir_err(r["t"], t)))
        Rp, tp = poselib_rel(p1, p2, 2.0)
        errs["poselib"].append((rot_err(Rp, R), dir_err(tp, t)))
        E, mask = cv2.findEssentialMat(p1, p2, K, method=cv2.USAC_MAGSAC, prob=0.999, threshold=2.0)
        _, Rc, tc, _ = cv2.recoverPose(E[:3], p1, p2, K, mask=mask)
        errs["cv2"].append((rot_err(Rc, R), dir_err(tc.ravel(), t)))
    med = {k: np.median(np.array(v), axis=0) for k, v in errs.items()}
    print("outliers %.2f median (rot deg, t deg):" % outliers, med)
    best = min(med["poselib"][0], med["cv2"][0])
    assert med["libsfm"][0] < 0.4
    assert med["libsfm"][0] <= 1.5 * best + 0.02
    assert med["libsfm"][1] <= 1.5 * min(med["poselib"][1], med["cv2"][1]) + 0.2


def test_relative_pose_same_seed_same_mask_and_shapes():
    rng = np.random.default_rng(3)
    p1, p2, R, t, truth = twoview(rng, 300, 0.5)
    a = libsfm.estimate_relative_pose(p1, p2, K, K, seed=11)
    b = libsfm.estimate_relative_pose(p1, p2, K, K, seed=11)
    assert np.array_equal(a["inliers"], b["inliers"])
    assert np.array_equal(a["R"], b["R"]) and np.array_equal(a["t"], b["t"])
    assert a["seed"] == 11 and a["stop_reason"] in ("confidence", "max_iterations")
    with pytest.raises(ValueError):
        libsfm.estimate_relative_pose(p1[:, :1], p2, K, K)
    with pytest.raises(ValueError):
        libsfm.estimate_relative_pose(p1, p2[:-1], K, K)
    with pytest.raises(ValueError):
        libsfm.estimate_relative_pose(p1, p2, K[:2], K)
    with pytest.raises(ValueError):
        libsfm.estimate_relative_pose(p1[:4], p2[:4], K, K)
    bad = p1.copy()
    bad[3, 0] = np.nan
    with pytest.raises(SfmError):
        libsfm.estimate_relative_pose(bad, p2, K, K)


def test_relative_pose_degeneracy_flags():
    rng = np.random.default_rng(5)
    p1, p2, R, t, _ = twoview(rng, 300, 0.3, sigma=0.5, planar=True)
    r = libsfm.estimate_relative_pose(p1, p2, K, K, threshold_px=1.5)
    assert r["planar"] and r.degenerate and r.degeneracy == "planar"
    p1, p2, R, t, _ = twoview(rng, 300, 0.3, sigma=0.5, rot_only=True)
    r = libsfm.estimate_relative_pose(p1, p2, K, K, threshold_px=1.5)
    assert r["pure_rotation"] and r.degenerate and r.degeneracy == "pure_rotation"
    assert rot_err(r["R"], R) < 0.5


def test_upright_relative_pose():
    rng = np.random.default_rng(8)
    errs = []
    for k in range(8):
        p1, p2, R, t, _ = twoview(rng, 300, 0.5)
        d1 = rng.normal(size=3)
        d1 /= np.linalg.norm(d1)
        r = libsfm.estimate_relative_pose_upright(p1, p2, K, K, d1, R @ d1, threshold_px=2.0, seed=k)
        errs.append((rot_err(r["R"], R), dir_err(r["t"], t)))
        assert dir_err(r["R"] @ d1, R @ d1) < 1e-6
    med = np.median(np.array(errs), axis=0)
    assert med[0] < 0.2 and med[1] < 2.0


@pytest.mark.parametrize("outliers", [0.25, 0.5, 0.75])
def test_absolute_pose_beside_poselib_and_opencv(outliers):
    rng = np.random.default_rng(10 + int(outliers * 100))
    e = {"libsfm": [], "poselib": [], "cv2": []}
    for k in range(10):
        p, X, R, t, truth = absolute(rng, 500, outliers)
        r = libsfm.estimate_absolute_pose(p, X, K, threshold_px=2.0, seed=k)
        e["libsfm"].append(rot_err(r["R"], R))
        assert (r["inliers"] & ~truth).sum() <= 10
        pose, _ = poselib.estimate_absolute_pose(p, X, PL_CAM, dict(PL_OPT, max_reproj_error=2.0), {})
        e["poselib"].append(rot_err(pose.R, R))
        ok, rv, tv, _ = cv2.solvePnPRansac(X, p, K, None, reprojectionError=2.0, confidence=0.999,
                                           iterationsCount=1000, flags=cv2.SOLVEPNP_P3P)
        e["cv2"].append(rot_err(cv2.Rodrigues(rv)[0], R) if ok else 180)
    med = {k: float(np.median(v)) for k, v in e.items()}
    print("outliers %.2f median rotation error (deg):" % outliers, med)
    assert med["libsfm"] < 0.2
    assert med["libsfm"] <= 1.5 * min(med["poselib"], med["cv2"]) + 0.01
    with pytest.raises(ValueError):
        libsfm.estimate_absolute_pose(p, X[:, :2], K)


def test_fundamental_and_homography_beside_opencv():
    rng = np.random.default_rng(21)
    p1, p2, R, t, truth = twoview(rng, 400, 0.4)
    r = libsfm.estimate_fundamental(p1, p2, threshold_px=1.5)
    F = r["F"]
    Fc, _ = cv2.findFundamentalMat(p1, p2, cv2.USAC_MAGSAC, 1.5, 0.999)

    def epi(Fm):
        h1 = np.column_stack([p1, np.ones(len(p1))])
        h2 = np.column_stack([p2, np.ones(len(p2))])
        lines = h1 @ Fm.T
        return np.abs(np.sum(lines * h2, axis=1)) / np.linalg.norm(lines[:, :2], axis=1)

    ours, theirs = np.median(epi(F)[truth]), np.median(epi(Fc)[truth])
    print("fundamental: median epipolar distance of true matches", ours, theirs)
    # noisy matches (1 px in each image): about 1 px is the floor
    assert ours < 1.5 and ours <= 1.3 * theirs + 0.1
    # homography on a planar scene
    p1, p2, R, t, truth = twoview(rng, 400, 0.5, planar=True)
    r = libsfm.estimate_homography(p1, p2, threshold_px=3.0)
    Hc, _ = cv2.findHomography(p1, p2, cv2.RANSAC, 3.0)

    def transfer(Hm):
        q = np.column_stack([p1, np.ones(len(p1))]) @ Hm.T
        return np.linalg.norm(q[:, :2] / q[:, 2:3] - p2, axis=1)

    ours, theirs = np.median(transfer(r["H"])[truth]), np.median(transfer(Hc)[truth])
    print("homography: median transfer error of true matches", ours, theirs)
    assert ours < 2.0 and ours <= 1.3 * theirs + 0.1
    assert r["inliers"].sum() == r["num_inliers"]


def _hj_camera(v):
    vals = np.loadtxt(os.path.join(HJ, "gt_dense_cameras", "%04d.jpg.camera" % v), max_rows=8)
    # rows: K (3), distortion (1), R camera-to-world (3), C (1)
    return vals[0:3], vals[4:7], vals[7]


def test_herzjesu_relative_pose_beside_poselib():
    if not os.path.isdir(HJ):
        pytest.skip("SKIP: ../shared/data/herzjesu-p8 not found")
    cams = [_hj_camera(v) for v in range(8)]
    ours, theirs = [], []
    for path in sorted(glob.glob(os.path.join(HJ, "triplets", "triplet_*.txt"))):
        a, b = (int(x) for x in os.path.basename(path)[8:-4].split("_")[:2])
        m = np.loadtxt(path, comments="#")
        if len(m) < 30:
            continue
        p1, p2 = m[:, 0:2].copy(), m[:, 2:4].copy()
        (K1, R1, C1), (K2, R2, C2) = cams[a], cams[b]
        Rg = R2.T @ R1
        tg = R2.T @ (C1 - C2)
        r = libsfm.estimate_relative_pose(p1, p2, K1, K2, threshold_px=1.0)
        ours.append((rot_err(r["R"], Rg), dir_err(r["t"], tg)))
        c1 = {"model": "PINHOLE", "width": 3072, "height": 2048,
              "params": [K1[0, 0], K1[1, 1], K1[0, 2], K1[1, 2]]}
        c2 = {"model": "PINHOLE", "width": 3072, "height": 2048,
              "params": [K2[0, 0], K2[1, 1], K2[0, 2], K2[1, 2]]}
        Rp, tp = poselib_rel(p1, p2, 1.0, cam1=c1, cam2=c2)
        theirs.append((rot_err(Rp, Rg), dir_err(tp, tg)))
    npairs = len(ours)
    ours, theirs = np.median(np.array(ours), axis=0), np.median(np.array(theirs), axis=0)
    print("Herz-Jesu-P8 %d pairs, 1 px: median rotation / translation-direction error (deg): "
          "libsfm %.3f / %.3f, poselib %.3f / %.3f" % (npairs, *ours, *theirs))
    assert ours[0] < 0.2 and ours[1] < 1.0
    assert ours[0] <= 1.5 * theirs[0] + 0.02 and ours[1] <= 1.5 * theirs[1] + 0.1


def test_distorted_cameras_fundamental_and_relative_pose():
    """Brown-distorted pixels: the estimators undistort through the camera
    model (OpenCV's projectPoints makes the pixels)."""
    rng = np.random.default_rng(31)
    dist = np.array([-0.2, 0.05, 0.001, -0.001, 0.0])
    n = 300
    R = rotation(rng, 15)
    t = rng.normal(size=3)
    t /= np.linalg.norm(t)
    X1 = np.column_stack([rng.uniform(-2, 2, n), rng.uniform(-1.5, 1.5, n), rng.uniform(4, 10, n)])
    X2 = X1 @ R.T + t
    q1 = cv2.projectPoints(X1, np.zeros(3), np.zeros(3), K, dist)[0].reshape(-1, 2)
    q2 = cv2.projectPoints(X2, np.zeros(3), np.zeros(3), K, dist)[0].reshape(-1, 2)
    ideal1 = (X1[:, :2] / X1[:, 2:3]) * 500 + K[:2, 2]
    ideal2 = (X2[:, :2] / X2[:, 2:3]) * 500 + K[:2, 2]
    p1 = q1 + rng.normal(scale=0.3, size=q1.shape)
    p2 = q2 + rng.normal(scale=0.3, size=q2.shape)
    out = rng.uniform(size=n) < 0.3
    p2[out] = np.column_stack([rng.uniform(0, W, out.sum()), rng.uniform(0, H, out.sum())])
    r = libsfm.estimate_relative_pose(p1, p2, K, K, threshold_px=1.0, dist1=dist, dist2=dist)
    assert rot_err(r["R"], R) < 0.5 and dir_err(r["t"], t) < 3.0
    f = libsfm.estimate_fundamental(p1, p2, K, K, threshold_px=1.0, dist1=dist, dist2=dist)
    h1 = np.column_stack([ideal1, np.ones(n)])
    h2 = np.column_stack([ideal2, np.ones(n)])
    lines = h1 @ f["F"].T
    d = np.abs(np.sum(lines * h2, axis=1)) / np.linalg.norm(lines[:, :2], axis=1)
    assert np.median(d[~out]) < 0.5
    with pytest.raises(ValueError):
        libsfm.estimate_fundamental(p1, p2, K, None)
    with pytest.raises(ValueError):
        libsfm.estimate_relative_pose(p1, p2, K, K, dist1=[0.1, 0.2])
    with pytest.raises(TypeError):
        libsfm.estimate_homography(p1, p2, bogus=1)
