"""The binding's contract: one style for every estimator, arguments checked
and named before any C call, one seed rule, defaults that are the C
library's, cameras accepted everywhere, help() that shows the API."""
import inspect
import os
import pydoc
import re

import cv2
import numpy as np
import pytest

import libsfm
from libsfm import Camera, SfmError

K = np.array([[500.0, 0, 320], [0, 500, 240], [0, 0, 1]])
W, H = 640, 480
ROOT = os.path.join(os.path.dirname(os.path.abspath(__file__)), "..", "..")
HJ = os.path.join(ROOT, "..", "shared", "data", "herzjesu-p8")

ESTIMATORS = ["estimate_relative_pose", "estimate_relative_pose_upright", "estimate_absolute_pose",
              "estimate_fundamental", "estimate_homography", "estimate_trifocal",
              "estimate_three_view_pose"]
OPTIONS = ["threshold_px", "seed", "confidence", "max_iterations", "min_iterations", "lo_rounds",
           "polish_rounds", "use_sprt", "quality"]


def scene(rng, n, views=2, cam=None, outliers=0.0, sigma=0.5):
    """n points seen by `views` cameras (camera 0 the world frame) through
    `cam` (default the pinhole K), pixel noise sigma, a share of outliers in
    the last view. Returns (pixels per view, poses (R, t), X)."""
    cam = cam or Camera.from_K(K)
    poses = [(np.eye(3), np.zeros(3))]
    for v in range(1, views):
        R = cv2.Rodrigues(rng.normal(scale=0.08, size=3))[0]
        t = np.array([-0.6 * v, 0.1 * rng.normal(), 0.1 * rng.normal()])
        poses.append((R, t))
    X = np.column_stack([rng.uniform(-3, 3, 4 * n), rng.uniform(-2, 2, 4 * n), rng.uniform(4, 9, 4 * n)])
    px, keep = [], np.ones(4 * n, bool)
    for R, t in poses:
        Y = X @ R.T + t
        q = cam.project(Y)
        keep &= (Y[:, 2] > 0.5) & (q[:, 0] >= 0) & (q[:, 0] < W) & (q[:, 1] >= 0) & (q[:, 1] < H)
        px.append(q)
    idx = np.flatnonzero(keep)[:n]
    assert idx.size == n
    px = [q[idx] + rng.normal(scale=sigma, size=(n, 2)) for q in px]
    bad = rng.uniform(size=n) < outliers
    px[-1][bad] = np.column_stack([rng.uniform(0, W, bad.sum()), rng.uniform(0, H, bad.sum())])
    return px, poses, X[idx], ~bad


def rot_err(Ra, Rb):
    return np.degrees(np.arccos(np.clip((np.trace(Ra.T @ Rb) - 1) / 2, -1, 1)))


def dir_err(a, b):
    return np.degrees(np.arccos(np.clip(a @ b / np.linalg.norm(a) / np.linalg.norm(b), -1, 1)))


def run_all(rng, **opts):
    """Every estimator once on one consistent three-view scene."""
    (p1, p2, p3), poses, X, _ = scene(rng, 120, views=3, outliers=0.15)
    g1 = np.array([0.0, 1.0, 0.0])
    g2 = poses[1][0] @ g1
    return {
        "estimate_relative_pose": libsfm.estimate_relative_pose(p1, p2, K, K, **opts),
        "estimate_relative_pose_upright": libsfm.estimate_relative_pose_upright(p1, p2, K, K, g1, g2, **opts),
        "estimate_absolute_pose": libsfm.estimate_absolute_pose(p2, X, K, **opts),
        "estimate_fundamental": libsfm.estimate_fundamental(p1, p2, **opts),
        "estimate_homography": libsfm.estimate_homography(p1, p2, **opts),
        "estimate_trifocal": libsfm.estimate_trifocal(p1, p2, p3, **opts),
        "estimate_three_view_pose": libsfm.estimate_three_view_pose(p1, p2, p3, K, K, K, **opts),
    }


# --- one result type ---------------------------------------------------------

def test_every_estimator_returns_one_result_type_with_fixed_field_types():
    res = run_all(np.random.default_rng(1), seed=3)
    assert set(res) == set(ESTIMATORS)
    for name, r in res.items():
        assert isinstance(r, libsfm.Result), name
        assert r.inliers.dtype == bool and r.inliers is r["inliers"], name
        assert type(r.num_inliers) is int and r.num_inliers == int(r.inliers.sum()), name
        for f in ("iterations", "models", "sprt_rejected", "lo_runs", "seed", "flags"):
            assert type(r[f]) is int, (name, f)
        assert type(r.score) is float and type(r.polished) is bool, name
        assert r.stop_reason in ("confidence", "max_iterations", "time"), (name, r.stop_reason)
        assert type(r.degenerate) is bool and r.degeneracy in (
            "", "pure_rotation", "low_parallax", "planar", "collinear", "clustered", "no_support"), name
        assert r.degenerate == (r.degeneracy != ""), name
        assert r.seed == 3, name


@pytest.mark.skipif(not os.path.exists(os.path.join(HJ, "triplets", "triplet_0000_0001_0002.txt")),
                    reason="SKIP: ../shared/data/herzjesu-p8 not found")
def test_three_view_pose_counts_the_inliers_it_returns_on_herzjesu():
    """Herz-Jesu 0000-0002: the C stats carried the trifocal search's count
    (533) while the mask of the returned metric cameras held 631."""
    x = np.loadtxt(os.path.join(HJ, "triplets", "triplet_0000_0001_0002.txt"))
    Ks = []
    for s in ("0000", "0001", "0002"):
        v = open(os.path.join(HJ, "gt_dense_cameras", "%s.jpg.camera" % s)).read().split()
        Ks.append(np.array([float(a) for a in v[:9]]).reshape(3, 3))
    r = libsfm.estimate_three_view_pose(x[:, 0:2], x[:, 2:4], x[:, 4:6], *Ks, threshold_px=1.0,
                                        seed=1, max_iterations=2000)
    assert r.num_inliers == int(r.inliers.sum())
    assert r.num_inliers > 0.7 * len(x)


# --- one way to pass options, defaults from C -------------------------------

def c_ransac_defaults():
    o = libsfm.ffi.new("sfm_ransac_options *")
    assert libsfm.lib.sfm_ransac_default_options(o) == 0
    return dict(threshold_px=o.threshold, seed=o.seed, confidence=o.confidence,
                max_iterations=o.max_iterations, min_iterations=o.min_iterations,
                lo_rounds=o.lo_rounds, polish_rounds=o.polish_rounds, use_sprt=bool(o.use_sprt),
                quality=None)


def header_default_seed():
    text = open(os.path.join(ROOT, "include", "sfm", "sfm_rng.h")).read()
    return int(re.search(r"#define SFM_RNG_DEFAULT_SEED (0x[0-9a-fA-F]+)", text).group(1), 16)


def test_every_estimator_takes_the_same_keyword_options_with_the_c_defaults():
    want = c_ransac_defaults()
    assert want["seed"] == header_default_seed()
    for name in ESTIMATORS:
        sig = inspect.signature(getattr(libsfm, name))
        params = sig.parameters
        assert not any(p.kind is p.VAR_KEYWORD for p in params.values()), name
        for opt in OPTIONS:
            assert opt in params, (name, opt)
            assert params[opt].kind is inspect.Parameter.KEYWORD_ONLY, (name, opt)
            assert params[opt].default == want[opt], (name, opt, params[opt].default)


def test_default_seed_is_the_c_one():
    (p1, p2), _, _, _ = scene(np.random.default_rng(2), 60)
    r = libsfm.estimate_relative_pose(p1, p2, K, K)
    assert r.seed == header_default_seed()
    t = libsfm.estimate_trifocal(*scene(np.random.default_rng(2), 60, views=3)[0])
    assert t.seed == header_default_seed()


def test_unknown_option_is_a_type_error():
    (p1, p2), _, _, _ = scene(np.random.default_rng(3), 60)
    with pytest.raises(TypeError):
        libsfm.estimate_fundamental(p1, p2, iterations=10)
    with pytest.raises(TypeError):
        libsfm.estimate_relative_pose(p1, p2, K, K, 1.0)  # options are keywords


# --- seeds --------------------------------------------------------------------

def test_seed_is_any_int_taken_modulo_2_64_everywhere():
    rng = np.random.default_rng(4)
    (p1, p2, p3), _, _, _ = scene(rng, 80, views=3, outliers=0.2)
    for fn, args in ((libsfm.estimate_relative_pose, (p1, p2, K, K)),
                     (libsfm.estimate_fundamental, (p1, p2)),
                     (libsfm.estimate_trifocal, (p1, p2, p3)),
                     (libsfm.estimate_three_view_pose, (p1, p2, p3, K, K, K))):
        a = fn(*args, seed=-1)
        b = fn(*args, seed=2 ** 64 - 1)
        c = fn(*args, seed=np.int64(-1))
        d = fn(*args, seed=2 ** 64 * 5 - 1)
        assert a.seed == b.seed == c.seed == d.seed == 2 ** 64 - 1
        assert np.array_equal(a.inliers, b.inliers) and np.array_equal(a.inliers, d.inliers)
        assert a.iterations == b.iterations == c.iterations
    with pytest.raises(TypeError, match="seed"):
        libsfm.estimate_relative_pose(p1, p2, K, K, seed=1.5)


# --- integers, complex, names -------------------------------------------------

def test_int64_indices_beyond_int32_are_refused_not_wrapped():
    m12 = np.array([[0, 1], [2 ** 32 + 3, 0]], dtype=np.int64)
    m23 = np.array([[1, 0], [0, 1]])
    m31 = np.array([[0, 0], [1, 3]])
    with pytest.raises(ValueError, match="m12"):
        libsfm.associate_three_views(m12, m23, m31)
    with pytest.raises(ValueError, match="m31"):
        libsfm.associate_three_views(m12[:1], m23, np.array([[0, -1]]))
    with pytest.raises(ValueError, match="n1"):
        libsfm.associate_three_views(m12[:1], m23, m31, n1=2 ** 31)
    with pytest.raises(ValueError, match="n2"):
        libsfm.associate_three_views(m12[:1], m23, m31, n2=1)  # index 1 given for view 2
    with pytest.raises(TypeError, match="m23"):
        libsfm.associate_three_views(m12[:1], m23.astype(float), m31)


def test_repeated_source_index_is_named():
    with pytest.raises(SfmError) as e:
        libsfm.associate_three_views([[0, 1], [0, 2]], [[1, 0]], [[0, 0]])
    assert e.value.argument == "m12" and e.value.name == "SFM_E_ARGUMENT"


@pytest.mark.parametrize("name, value", [("max_iterations", 2 ** 31), ("max_iterations", 0),
                                         ("min_iterations", -1), ("lo_rounds", 2 ** 40),
                                         ("polish_rounds", -5)])
def test_integer_options_out_of_range_raise_value_error_naming_them(name, value):
    (p1, p2, p3), _, _, _ = scene(np.random.default_rng(5), 40, views=3)
    for call in (lambda: libsfm.estimate_relative_pose(p1, p2, K, K, **{name: value}),
                 lambda: libsfm.estimate_homography(p1, p2, **{name: value}),
                 lambda: libsfm.estimate_trifocal(p1, p2, p3, **{name: value})):
        with pytest.raises(ValueError, match=name):
            call()


def test_feature_integers_are_range_checked():
    img = np.zeros((64, 64), np.uint8)
    with pytest.raises(ValueError, match="max_features"):
        libsfm.detect_and_describe(img, max_features=2 ** 32 + 10)
    with pytest.raises(ValueError, match="fast_threshold"):
        libsfm.detect_and_describe(img, fast_threshold=300)
    d = np.zeros((3, 32), np.uint8)
    with pytest.raises(ValueError, match="max_distance"):
        libsfm.match(d, d, max_distance=2 ** 32)


def test_complex_input_is_refused():
    (p1, p2), poses, X, _ = scene(np.random.default_rng(6), 40)
    with pytest.raises(TypeError, match="p1"):
        libsfm.estimate_relative_pose(p1 + 0j, p2, K, K)
    with pytest.raises(TypeError, match="X"):
        libsfm.estimate_absolute_pose(p2, X.astype(np.complex128), K)
    with pytest.raises(TypeError, match="K1"):
        libsfm.estimate_relative_pose(p1, p2, K + 1e-3j, K)
    with pytest.raises(TypeError, match="threshold_px"):
        libsfm.estimate_homography(p1, p2, threshold_px=1 + 1j)
    with pytest.raises(TypeError):
        libsfm.linalg.svd(np.eye(3) * (1 + 1j))


def test_sfm_error_names_the_argument():
    (p1, p2, p3), _, X, _ = scene(np.random.default_rng(7), 40, views=3)
    bad = p2.copy()
    bad[3, 1] = np.nan
    with pytest.raises(SfmError) as e:
        libsfm.estimate_relative_pose(p1, bad, K, K)
    assert e.value.argument == "p2" and e.value.name == "SFM_E_NONFINITE"
    assert "p2" in str(e.value)
    with pytest.raises(SfmError) as e:
        libsfm.estimate_trifocal(p1, p2, bad)
    assert e.value.argument == "x3"
    Xb = X.copy()
    Xb[0, 2] = np.inf
    with pytest.raises(SfmError) as e:
        libsfm.estimate_absolute_pose(p2, Xb, K)
    assert e.value.argument == "X"
    with pytest.raises(SfmError) as e:
        Camera("pinhole", 0.0, 500, 320, 240)
    assert e.value.argument == "fx" and e.value.status == libsfm.lib.SFM_E_ARGUMENT


# --- cameras ------------------------------------------------------------------

def test_camera_is_accepted_by_every_estimator_taking_intrinsics():
    cam = Camera.from_K(K)
    rng = np.random.default_rng(8)
    (p1, p2, p3), poses, X, _ = scene(rng, 100, views=3)
    g1 = np.array([0.0, 1.0, 0.0])
    a = libsfm.estimate_relative_pose(p1, p2, cam, cam, seed=1)
    b = libsfm.estimate_relative_pose(p1, p2, K, K, seed=1)
    assert np.array_equal(a.R, b.R) and np.array_equal(a.inliers, b.inliers)
    libsfm.estimate_relative_pose_upright(p1, p2, cam, K, g1, poses[1][0] @ g1)
    libsfm.estimate_absolute_pose(p2, X, cam)
    libsfm.estimate_fundamental(p1, p2, cam, cam)
    libsfm.estimate_homography(p1, p2, cam, K)
    libsfm.estimate_three_view_pose(p1, p2, p3, cam, cam, K)
    with pytest.raises(ValueError, match="K1"):
        libsfm.estimate_relative_pose(p1, p2, cam, K, dist1=[0.1, 0, 0, 0, 0])
    with pytest.raises(TypeError, match="K2"):
        libsfm.estimate_relative_pose(p1, p2, K, "pinhole")


def test_fisheye_camera_two_view_and_absolute_pose_recover_the_truth():
    """Kannala-Brandt pixels through a fisheye Camera: before, the only way
    in was a 4-entry dist, read as Brown."""
    fish = Camera("fisheye", 300.0, 300.0, 320.0, 240.0, [0.05, -0.02, 0.004, -0.001])
    # the Camera projects as cv2.fisheye does (independent oracle)
    Y = np.array([[0.3, -0.2, 1.0], [-1.0, 0.5, 1.2], [0.01, 0.02, 3.0]])
    q, _ = cv2.fisheye.projectPoints(Y.reshape(-1, 1, 3), np.zeros(3), np.zeros(3), fish.K, fish.dist)
    assert np.allclose(fish.project(Y), q.reshape(-1, 2), atol=1e-9)
    rng = np.random.default_rng(9)
    (p1, p2), poses, X, _ = scene(rng, 150, cam=fish, sigma=0.3)
    r = libsfm.estimate_relative_pose(p1, p2, fish, fish, seed=2, threshold_px=1.0)
    R, t = poses[1]
    assert rot_err(r.R, R) < 0.3 and dir_err(r.t, t) < 2.0
    a = libsfm.estimate_absolute_pose(p2, X, fish, seed=2)
    assert rot_err(a.R, R) < 0.3 and np.linalg.norm(a.t - t) < 0.05
    # the same pixels read as Brown (what a 4-entry dist gave) are worse
    brown = libsfm.estimate_relative_pose(p1, p2, fish.K, fish.K, dist1=fish.dist, dist2=fish.dist,
                                          seed=2, threshold_px=1.0)
    assert brown.num_inliers < r.num_inliers


def test_camera_constructors_follow_opencv():
    d5 = np.array([-0.2, 0.05, 0.001, -0.002, 0.01])
    c = Camera.from_opencv(K, d5)
    assert c.model == "brown" and np.array_equal(c.dist, d5)
    X = np.array([[0.3, -0.2, 1.0], [-0.4, 0.3, 2.0]])
    q, _ = cv2.projectPoints(X, np.zeros(3), np.zeros(3), K, d5)
    assert np.allclose(c.project(X), q.reshape(-1, 2), atol=1e-9)
    assert Camera.from_opencv(K, d5[:4]).model == "brown"           # OpenCV's 4-vector
    assert Camera.from_opencv(K, np.r_[d5, 0, 0, 0]).model == "brown"  # 8-vector, rational terms 0
    with pytest.raises(ValueError, match="k3"):
        Camera.from_opencv(K, np.r_[d5, 0.1, 0, 0])
    f = Camera.from_opencv(K, [0.1, 0.01, 0.0, 0.0], fisheye=True)
    assert f.model == "fisheye"
    with pytest.raises(ValueError, match="skew"):
        Camera.from_K([[500, 2, 320], [0, 500, 240], [0, 0, 1]])
    with pytest.raises(ValueError):
        Camera.from_K([[500, 0, 320], [0, 500, 240], [0, 0, 2]])
    K2, d = c.to_opencv()
    assert np.array_equal(K2, K) and np.array_equal(d, d5)
    import copy
    import pickle
    for cam in (c, f, Camera("pinhole", 1.0, 2.0, 3.0, 4.0, width=5, height=6)):
        back = pickle.loads(pickle.dumps(cam))
        assert back == cam and np.array_equal(back.project(X), cam.project(X))
        assert copy.deepcopy(cam) == cam


# --- version, docs ------------------------------------------------------------

def test_version_and_help_show_the_api():
    text = open(os.path.join(ROOT, "include", "sfm", "sfm_common.h")).read()
    parts = [re.search(r"#define SFM_VERSION_%s (\d+)" % k, text).group(1) for k in ("MAJOR", "MINOR", "PATCH")]
    assert libsfm.__version__ == ".".join(parts) == libsfm.version()
    doc = pydoc.render_doc(libsfm, renderer=pydoc.plaintext)
    for name in ESTIMATORS + ["Camera", "Result", "detect_and_describe", "bundle_adjust",
                              "triangulate", "__version__"]:
        assert name in doc, name
    for name in libsfm.__all__:
        obj = getattr(libsfm, name)
        if callable(obj) and not isinstance(obj, type(libsfm)):
            assert obj.__doc__ and len(obj.__doc__.strip()) > 20, name


def test_estimator_docstrings_give_shapes():
    for name in ESTIMATORS:
        doc = getattr(libsfm, name).__doc__
        assert "(n, 2)" in doc, name
