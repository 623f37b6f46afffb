"""Degenerate-scene suite: every robust estimator on scenes whose support
cannot determine its model (collinear, one cluster, one plane, pure rotation,
zero parallax, random matches) and on general scenes of the same size.

The bar (issue 11): zero confident wrong answers -- status OK without a
degeneracy flag while the rotation error exceeds 5 deg, the translation
direction 10 deg, or the transfer error 5 px, all against the scene's truth
-- and no false alarm (a flag or a refusal) on at least 99 % of the general
scenes. Transfer errors are measured on noise-free probe correspondences of
a general scene seen by the same cameras, so a model is judged where its
support did not reach too. `python tests/python/test_degenerate.py [N]`
prints the table of outcomes.
"""
import os
import sys
from collections import Counter

import numpy as np
import pytest

HERE = os.path.dirname(os.path.abspath(__file__))
sys.path.insert(0, HERE)
sys.path.insert(0, os.path.join(HERE, "..", "..", "python"))
import degenerate_scenes as ds  # noqa: E402

import libsfm  # noqa: E402
from libsfm import SfmError, lib  # noqa: E402

N_INSTANCES = 50
REFUSALS = (getattr(lib, "SFM_E_DEGENERATE", -13), getattr(lib, "SFM_E_NO_MODEL", -14))


def degeneracy(r):
    """The result's degeneracy name (from its flags, so that the suite also
    runs against a build without the names)."""
    if "degeneracy" in r:
        return r["degeneracy"]
    f = r.get("flags", 0)
    return ("pure_rotation" if f & 2 else "low_parallax" if f & 8 else
            "planar" if f & 5 else "")


def rel_truth(s, v=1):
    R, t = s["poses"][v]
    return R, t


def judge_pose(R, t, Rt, tt, degeneracy, cls):
    """'right', 'wrong' or 'flagged' for a returned relative pose."""
    if degeneracy in ("pure_rotation", "low_parallax"):
        return "flagged" if ds.rot_err(R, Rt) <= 5 else "wrong"
    if degeneracy:
        return "flagged"
    if cls == "outliers":
        return "wrong"
    if ds.rot_err(R, Rt) > 5:
        return "wrong"
    if np.linalg.norm(tt) > 1e-9 and cls not in ("pure_rotation",) and ds.dir_err(t, tt) > 10:
        return "wrong"
    if cls in ("pure_rotation",):
        return "wrong"  # a translation direction without a flag
    return "right"


def epipolar_px(F, a, b):
    """Distance of b to the epipolar line of a (pixels)."""
    ah = np.column_stack([a, np.ones(len(a))])
    bh = np.column_stack([b, np.ones(len(b))])
    lines = ah @ F.T
    return np.abs(np.sum(lines * bh, axis=1)) / np.hypot(lines[:, 0], lines[:, 1])


def transfer_px(Hm, a, b):
    ah = np.column_stack([a, np.ones(len(a))])
    q = ah @ Hm.T
    return np.linalg.norm(q[:, :2] / q[:, 2:3] - b, axis=1)


def true_F(s, v=1):
    R, t = s["poses"][v]
    tx = np.array([[0, -t[2], t[1]], [t[2], 0, -t[0]], [-t[1], t[0], 0]])
    Ki = np.linalg.inv(ds.K)
    return Ki.T @ tx @ R @ Ki


def call(fn):
    try:
        return fn(), None
    except SfmError as e:
        return None, e.status


def run_relpose(s, cls, seed, upright=False):
    Rt, tt = rel_truth(s)
    if upright:
        d1 = np.array([0.0, 1.0, 0.0])
        d2 = Rt @ d1
        r, err = call(lambda: libsfm.estimate_relative_pose_upright(
            s["x"][0], s["x"][1], ds.K, ds.K, d1, d2, seed=seed))
    else:
        r, err = call(lambda: libsfm.estimate_relative_pose(s["x"][0], s["x"][1], ds.K, ds.K,
                                                            seed=seed))
    if r is None:
        return "refused" if err in REFUSALS else "error%d" % err
    return judge_pose(r["R"], r["t"], Rt, tt, degeneracy(r), cls)


def run_abspose(s, cls, seed):
    R, t = s["poses"][1]
    r, err = call(lambda: libsfm.estimate_absolute_pose(s["x"][1], s["X"], ds.K, seed=seed))
    if r is None:
        return "refused" if err in REFUSALS else "error%d" % err
    if cls == "outliers":
        return "wrong"
    C, Ct = -r["R"].T @ r["t"], -R.T @ t
    depth = np.mean((s["X"] @ R.T + t)[:, 2])
    if ds.rot_err(r["R"], R) > 5 or np.linalg.norm(C - Ct) > 0.1 * depth:
        return "wrong"
    return "right"


def verdict_of_status(r, err, cls):
    """The verdict a refusal, a flag or a class without a model decides;
    None when the model itself has to be judged."""
    if r is None:
        return "refused" if err in REFUSALS else "error%d" % err
    if degeneracy(r):
        return "flagged"
    if cls in ("outliers", "pure_rotation"):
        return "wrong"
    return None


def run_fundamental(s, cls, seed):
    r, err = call(lambda: libsfm.estimate_fundamental(s["x"][0], s["x"][1], seed=seed))
    v = verdict_of_status(r, err, cls)
    if v is not None:
        return v
    # the truth's epipolar geometry: probe points must lie on the estimate's lines
    e = epipolar_px(r["F"], s["probe"][0], s["probe"][1])
    return "wrong" if np.median(e) > 5 else "right"


def run_homography(s, cls, seed):
    r, err = call(lambda: libsfm.estimate_homography(s["x"][0], s["x"][1], seed=seed))
    if r is None:
        return "refused" if err in REFUSALS else "error%d" % err
    if cls == "outliers":
        return "wrong"
    if cls in ("planar", "pure_rotation", "zero_parallax"):
        # a true homography exists: across the image for a rotation, on the
        # plane's own points for a plane
        a, b = (s["probe"][0], s["probe"][1]) if cls != "planar" else (
            ds.project(*s["poses"][0], s["X"])[0], ds.project(*s["poses"][1], s["X"])[0])
        return "wrong" if np.median(transfer_px(r["H"], a, b)) > 5 else "right"
    # no plane in the scene: H is right only on its own support
    a = ds.project(*s["poses"][0], s["X"])[0][s["truth"] & r["inliers"]]
    b = ds.project(*s["poses"][1], s["X"])[0][s["truth"] & r["inliers"]]
    if cls in ("collinear", "clustered"):
        # a line or a cluster does not fix H off its support: a model is
        # right only when it transfers the probe points of the whole image
        return "wrong" if np.median(transfer_px(r["H"], s["probe"][0], s["probe"][1])) > 5 \
            else "right"
    return "right" if len(a) == 0 or np.median(transfer_px(r["H"], a, b)) <= 5 else "wrong"


def run_trifocal(s, cls, seed):
    r, err = call(lambda: libsfm.estimate_trifocal(s["x"][0], s["x"][1], s["x"][2], seed=seed))
    v = verdict_of_status(r, err, cls)
    if v is not None:
        return v
    try:
        x3 = libsfm.trifocal_transfer(r["T"], s["probe"][0], s["probe"][1])
    except SfmError:
        return "wrong"
    e = np.linalg.norm(x3 - s["probe"][2], axis=1)
    return "wrong" if not np.median(e) <= 5 else "right"


def run_three_view(s, cls, seed):
    r, err = call(lambda: libsfm.estimate_three_view_pose(s["x"][0], s["x"][1], s["x"][2],
                                                          ds.K, ds.K, ds.K, seed=seed))
    if r is None:
        return "refused" if err in REFUSALS + (lib.SFM_E_SINGULAR,) else "error%d" % err
    worst = "right"
    for v in (1, 2):
        Rt, tt = s["poses"][v]
        j = judge_pose(r["R"][v], r["t"][v], Rt, tt, degeneracy(r), cls)
        if j == "wrong":
            return "wrong"
        if j == "flagged":
            worst = "flagged"
    return worst


ESTIMATORS = {
    "relpose": (2, lambda s, c, k: run_relpose(s, c, k)),
    "upright": (2, lambda s, c, k: run_relpose(s, c, k, upright=True)),
    "abspose": (2, run_abspose),
    "fundamental": (2, run_fundamental),
    "homography": (2, run_homography),
    "trifocal": (3, run_trifocal),
    "three_view": (3, run_three_view),
}
# Absolute pose has world points: pure rotation and zero parallax do not
# concern it, and a plane determines it.
APPLIES = {"abspose": ("general", "collinear", "clustered", "planar", "outliers")}


def run(est, cls, n_inst, seed0=0):
    views, fn = ESTIMATORS[est]
    out = Counter()
    for k in range(n_inst):
        rng = np.random.default_rng([sum(est.encode()), ds.CLASSES.index(cls), seed0 + k])
        s = ds.scene(rng, cls, views=views)
        out[fn(s, cls, k)] += 1
    return out


@pytest.mark.parametrize("est", sorted(ESTIMATORS))
@pytest.mark.parametrize("cls", [c for c in ds.CLASSES if c != "general"])
def test_no_confident_wrong_answer(est, cls):
    if cls not in APPLIES.get(est, ds.CLASSES):
        pytest.skip("class does not apply")
    out = run(est, cls, N_INSTANCES)
    print(est, cls, dict(out))
    assert out["wrong"] == 0, dict(out)
    assert not any(k.startswith("error") for k in out), dict(out)


@pytest.mark.parametrize("est", sorted(ESTIMATORS))
def test_no_false_alarm_on_general_scenes(est):
    out = run(est, "general", 100)
    print(est, "general", dict(out))
    assert out["wrong"] == 0, dict(out)
    assert out["right"] >= 99, dict(out)


if __name__ == "__main__":
    n = int(sys.argv[1]) if len(sys.argv) > 1 else N_INSTANCES
    ests = sys.argv[2].split(",") if len(sys.argv) > 2 else sorted(ESTIMATORS)
    for est in ests:
        for cls in ds.CLASSES:
            if cls in APPLIES.get(est, ds.CLASSES):
                print("%-12s %-14s %s" % (est, cls, dict(run(est, cls, n))), flush=True)


def test_result_fields_and_refusals():
    rng = np.random.default_rng(5)
    s = ds.scene(rng, "general")
    r = libsfm.estimate_relative_pose(s["x"][0], s["x"][1], ds.K, ds.K)
    assert r["degenerate"] is False and r["degeneracy"] == ""
    assert r["covariance"] is None  # on request only
    r = libsfm.estimate_relative_pose(s["x"][0], s["x"][1], ds.K, ds.K, covariance=True)
    C = r["covariance"]
    assert C.shape == (6, 6) and np.allclose(C, C.T, atol=1e-15)
    w = np.linalg.eigvalsh(C)
    assert w.min() > -1e-15 and np.sum(w > 1e-6 * w.max()) == 5  # rank 5 on the manifold
    # the rotation error within a few of its standard deviations
    err = np.radians(ds.rot_err(r["R"], s["poses"][1][0]))
    assert err < 6 * np.sqrt(np.trace(C[:3, :3]))
    assert libsfm.estimate_homography(s["x"][0], s["x"][1])["covariance"] is None
    s = ds.scene(rng, "collinear")
    with pytest.raises(SfmError) as e:
        libsfm.estimate_relative_pose(s["x"][0], s["x"][1], ds.K, ds.K)
    assert e.value.status == lib.SFM_E_DEGENERATE
    s = ds.scene(rng, "outliers")
    with pytest.raises(SfmError) as e:
        libsfm.estimate_fundamental(s["x"][0], s["x"][1])
    assert e.value.status == lib.SFM_E_NO_MODEL
    s = ds.scene(rng, "pure_rotation")
    r = libsfm.estimate_relative_pose(s["x"][0], s["x"][1], ds.K, ds.K)
    assert r["degenerate"] and r["degeneracy"] in ("pure_rotation", "low_parallax")


@pytest.mark.parametrize("cls,instance,seed", [("clustered", 21, 21), ("pure_rotation", 1097, 97)])
def test_trifocal_strays_leave_a_degenerate_support_degenerate(cls, instance, seed):
    """The trifocal RANSAC's minimal samples fit a stray match exactly, and
    a stray or two in a degenerate support made it look determined: a
    cluster of 160 points with one stray passed the spread test (the stray
    alone widened the view-1 deviation past the bound), a pure rotation of
    155 points with two passed the design test (their rows filled the null
    directions of the rotation). Both came back as confident tensors 75 px
    and more off on the general probe before the checks left out the
    farthest points and the heaviest triplets."""
    rng = np.random.default_rng([sum("trifocal".encode()), ds.CLASSES.index(cls), instance])
    s = ds.scene(rng, cls, views=3)
    assert run_trifocal(s, cls, seed) != "wrong"
