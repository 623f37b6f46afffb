"""Hostile inputs of self_calibrate, align_points and
reconstruct_three_view_images: every bad argument is refused before the C
call with an error naming it (TypeError for complex or non-integer values,
ValueError for a range), or by an SfmError whose .argument names it; odd but
valid inputs give an answer or an SfmError, never a crash or a silent
wrong answer."""
import numpy as np
import pytest

import libsfm
from libsfm import SfmError
from test_recon import views


@pytest.fixture(scope="module")
def proj():
    rng = np.random.default_rng(31)
    x = views(rng, "general", m=5, n=60, sigma=0.3)
    r = libsfm.factorize_projective(x)
    return r["P"], r["X"], x


def test_self_calibrate_answers_the_truth_on_the_scene(proj):
    P, X, x = proj
    s = libsfm.self_calibrate(P, (640, 480), X, tracks=x)
    assert abs(s["focal"] / 800 - 1) < 4 * s["focal_sigma"]


@pytest.mark.parametrize("arg", ["P", "image_sizes", "X", "tracks"])
def test_self_calibrate_refuses_complex_arrays(proj, arg):
    P, X, x = proj
    kw = dict(P=P, image_sizes=np.array([640.0, 480.0]), X=X, tracks=x)
    kw[arg] = np.asarray(kw[arg]) * (1 + 1e-3j)
    with pytest.raises(TypeError, match=arg):
        libsfm.self_calibrate(**kw)
    if arg != "tracks":  # the linear path too
        kw.pop("tracks")
        with pytest.raises(TypeError, match=arg):
            libsfm.self_calibrate(**kw)


@pytest.mark.parametrize("arg, where", [("P", (1, 2, 3)), ("X", (7, 0)), ("image_sizes", (2, 1))])
@pytest.mark.parametrize("value", [np.nan, np.inf, -np.inf])
def test_self_calibrate_names_the_non_finite_argument(proj, arg, where, value):
    P, X, x = proj
    kw = dict(P=P.copy(), image_sizes=np.tile([640.0, 480.0], (5, 1)), X=X.copy())
    kw[arg][where] = value
    for tracks in (x, None):
        with pytest.raises((SfmError, ValueError)) as e:
            libsfm.self_calibrate(**kw, tracks=tracks)
        if isinstance(e.value, SfmError):
            assert e.value.argument == arg, (e.value, tracks is None)
        else:
            assert arg in str(e.value)


@pytest.mark.parametrize("bad", [np.inf, -np.inf, "half"])
def test_self_calibrate_tracks_take_nan_only_as_a_whole_missing_point(proj, bad):
    P, X, x = proj
    t = x.copy()
    if bad == "half":
        t[2, 5, 1] = np.nan  # x given, y missing
    else:
        t[2, 5, 0] = bad
    with pytest.raises((SfmError, ValueError)) as e:
        libsfm.self_calibrate(P, (640, 480), X, tracks=t)
    assert getattr(e.value, "argument", None) == "tracks" or "tracks" in str(e.value)


@pytest.mark.parametrize("size", [(0, 480), (640, -1), (0, 0), (-0.0, 480)])
def test_self_calibrate_names_bad_image_sizes(proj, size):
    P, X, x = proj
    for tracks in (x, None):
        with pytest.raises(ValueError, match="image_sizes"):
            libsfm.self_calibrate(P, size, X, tracks=tracks)


@pytest.mark.parametrize("m", [0, 1, 2, 33])
def test_self_calibrate_view_counts(proj, m):
    P, X, x = proj
    Pm = np.resize(P, (m, 3, 4))
    xm = np.resize(x, (m,) + x.shape[1:])
    for tracks in (xm, None):
        with pytest.raises(ValueError, match="P"):
            libsfm.self_calibrate(Pm, (640, 480), X, tracks=tracks)


@pytest.mark.parametrize("name, value, exc", [
    ("sweep_steps", 2, ValueError), ("sweep_steps", 65, ValueError), ("sweep_steps", 2 ** 32 + 17, ValueError),
    ("sweep_steps", 17.5, TypeError), ("sweep_steps", True, TypeError),
    ("focal_range", (4.0, 0.25), ValueError), ("focal_range", (0.0, 4.0), ValueError),
    ("focal_range", (np.nan, 4.0), ValueError), ("focal_range", (0.25, np.inf), ValueError),
    ("focal_range", (0.25, 4 + 1j), TypeError), ("focal_range", 3.0, TypeError),
    ("max_rms", 0.0, ValueError), ("max_rms", np.nan, ValueError), ("max_rms", 1j, TypeError),
    ("loss_scale", -2.0, ValueError), ("loss_scale", np.inf, ValueError),
    ("max_focal_sigma", 0.0, ValueError), ("max_focal_sigma", "0.1", TypeError),
    ("min_profile", -1.0, ValueError), ("min_profile", np.nan, ValueError),
])
def test_self_calibrate_options_are_checked_and_named(proj, name, value, exc):
    P, X, x = proj
    with pytest.raises(exc, match=name):
        libsfm.self_calibrate(P, (640, 480), X, tracks=x, **{name: value})


def test_self_calibrate_refusal_writes_a_report_and_no_answer(proj):
    P, X, x = proj
    blind = x.copy()
    blind[2] = np.nan  # view 3 sees nothing
    with pytest.raises(SfmError) as e:
        libsfm.self_calibrate(P, (640, 480), X, tracks=blind)
    assert e.value.name in ("SFM_E_SINGULAR", "SFM_E_NO_CONVERGENCE")
    assert isinstance(e.value.report, dict)


def test_self_calibrate_points_at_infinity_and_zero_rows(proj):
    P, X, x = proj
    with pytest.raises(SfmError) as e:
        libsfm.self_calibrate(P, (640, 480), np.zeros_like(X), tracks=x)
    assert e.value.name in ("SFM_E_SINGULAR", "SFM_E_NO_CONVERGENCE")
    # w = 0 in the projective frame is not metric infinity: the adjustment
    # moves the points onto their observations, the answer is the truth's
    # or refused
    try:
        s = libsfm.self_calibrate(P, (640, 480), np.c_[X[:, :3], np.zeros(len(X))], tracks=x)
        assert abs(s["focal"] / 800 - 1) < 4 * s["focal_sigma"]
    except SfmError as e:
        assert e.name in ("SFM_E_SINGULAR", "SFM_E_NO_CONVERGENCE")


# --- align_points ---------------------------------------------------------------

def blobs(rng, h=120, w=160, shift=(0.0, 0.0)):
    yy, xx = np.mgrid[0:h, 0:w].astype(float)
    img = np.full((h, w), 128.0)
    for _ in range(60):
        cx, cy, s, a = rng.uniform(-10, w + 10), rng.uniform(-10, h + 10), rng.uniform(2.5, 5), rng.uniform(40, 90)
        img += (a if rng.random() < 0.5 else -a) * np.exp(-0.5 * ((xx + shift[0] - cx) ** 2 + (yy + shift[1] - cy) ** 2)
                                                          / s ** 2)
    return np.clip(np.round(img), 0, 255).astype(np.uint8)


@pytest.fixture(scope="module")
def pair():
    rng = np.random.default_rng(5)
    state = rng.bit_generator.state
    a = blobs(rng)
    rng.bit_generator.state = state
    b = blobs(rng, shift=(0.6, -0.3))
    pts = np.array([[40.0, 40.0], [80.0, 60.0], [120.0, 80.0], [60.0, 90.0]])
    return a, b, pts


def test_align_points_recovers_the_shift(pair):
    a, b, pts = pair
    out, ok = libsfm.align_points(a, pts, b, pts)
    assert ok.sum() >= 2
    # b(x) = a(x + shift): a's point p is at p - shift in b
    assert np.allclose(out[ok], pts[ok] - [0.6, -0.3], atol=0.05)


@pytest.mark.parametrize("arg", ["x_ref", "x"])
def test_align_points_names_non_finite_points(pair, arg):
    a, b, pts = pair
    bad = pts.copy()
    bad[2, 1] = np.nan
    kw = dict(x_ref=pts, x=pts)
    kw[arg] = bad
    with pytest.raises(SfmError) as e:
        libsfm.align_points(a, kw["x_ref"], b, kw["x"])
    assert e.value.argument == arg and e.value.name == "SFM_E_NONFINITE"


@pytest.mark.parametrize("arg", ["x_ref", "x"])
def test_align_points_refuses_complex_points(pair, arg):
    a, b, pts = pair
    kw = dict(x_ref=pts, x=pts)
    kw[arg] = pts + 0j
    with pytest.raises(TypeError, match=arg):
        libsfm.align_points(a, kw["x_ref"], b, kw["x"])


@pytest.mark.parametrize("shape", [(0, 0), (0, 10), (10, 0)])
@pytest.mark.parametrize("arg", ["ref", "img"])
def test_align_points_names_empty_images(pair, shape, arg):
    a, b, pts = pair
    kw = dict(ref=a, img=b)
    kw[arg] = np.zeros(shape, np.uint8)
    with pytest.raises(ValueError, match=arg):
        libsfm.align_points(kw["ref"], pts, kw["img"], pts)


@pytest.mark.parametrize("name, value, exc", [
    ("radius", 1, ValueError), ("radius", 9, ValueError), ("radius", 2 ** 32 + 7, ValueError),
    ("radius", 7.0, TypeError), ("radius", True, TypeError),
    ("max_iterations", 0, ValueError), ("max_iterations", 101, ValueError), ("max_iterations", -2 ** 31, ValueError),
    ("max_shift", 0.0, ValueError), ("max_shift", -1.0, ValueError), ("max_shift", np.inf, ValueError),
    ("max_shift", 1j, TypeError),
    ("min_zncc", 1.5, ValueError), ("min_zncc", -1.01, ValueError), ("min_zncc", np.nan, ValueError),
    ("min_eigen_ratio", -0.1, ValueError), ("min_eigen_ratio", 1.1, ValueError),
])
def test_align_points_parameters_are_checked_and_named(pair, name, value, exc):
    a, b, pts = pair
    with pytest.raises(exc, match=name):
        libsfm.align_points(a, pts, b, pts, **{name: value})


def test_align_points_odd_images_and_points(pair):
    a, b, pts = pair
    far = np.array([[-1e300, 5.0], [1e300, 5.0], [2.0 ** 31, 60.0], [-2.0 ** 31 - 1, 60.0], [0.0, 0.0],
                    [159.0, 119.0], [7.999, 8.0], [150.0, 110.0]])
    out, ok = libsfm.align_points(a, far, b, far)
    assert not ok[:6].any() and np.array_equal(out[~ok], far[~ok])
    one = np.array([[7]], np.uint8)
    for r, i in ((one, b), (a, one), (one, one)):
        out, ok = libsfm.align_points(r, pts, i, pts)
        assert not ok.any() and np.array_equal(out, pts)
    out, ok = libsfm.align_points(a, np.zeros((0, 2)), b, np.zeros((0, 2)))
    assert out.shape == (0, 2) and ok.shape == (0,)
    # a strided view is the same image as its copy
    big = np.zeros((240, 320), np.uint8)
    big[::2, ::2] = b
    o1, k1 = libsfm.align_points(a, pts, b, pts)
    o2, k2 = libsfm.align_points(a, pts, big[::2, ::2], pts)
    assert np.array_equal(o1, o2) and np.array_equal(k1, k2)


def test_align_points_refuses_images_that_are_not_gray_uint8(pair):
    a, b, pts = pair
    for bad in (a.astype(np.float64), a.astype(np.int8), a.astype(np.complex64), a[..., None], a.astype(bool)):
        with pytest.raises((TypeError, ValueError), match="ref"):
            libsfm.align_points(bad, pts, b, pts)


# --- reconstruct_three_view_images ------------------------------------------------

@pytest.mark.parametrize("seed, exc", [(1.5, TypeError), (True, TypeError), ("1", TypeError), (1 + 0j, TypeError)])
def test_reconstruct_three_view_images_seed_is_an_integer(seed, exc):
    img = np.zeros((64, 64), np.uint8)
    with pytest.raises(exc, match="seed"):
        libsfm.reconstruct_three_view_images(img, img, img, seed=seed)


@pytest.mark.parametrize("seed", [-1, 2 ** 64 - 1, 2 ** 70 - 1, np.int64(-1), np.uint64(2 ** 64 - 1)])
def test_reconstruct_three_view_seed_any_int_mod_2_64(seed):
    rng = np.random.default_rng(8)
    x = views(rng, "general", m=3, n=80, sigma=0.3)
    ref = libsfm.reconstruct_three_view(x[0], x[1], x[2], 640, 480, seed=2 ** 64 - 1, radial=0)
    r = libsfm.reconstruct_three_view(x[0], x[1], x[2], 640, 480, seed=seed, radial=0)
    assert np.array_equal(r["K"], ref["K"]) and np.array_equal(r["inliers"], ref["inliers"])


@pytest.mark.parametrize("shape", [(1, 1), (1, 64), (2, 2), (40, 40)])
def test_reconstruct_three_view_images_tiny_images_refused(shape):
    img = np.full(shape, 90, np.uint8)
    with pytest.raises((ValueError, SfmError)):
        libsfm.reconstruct_three_view_images(img, img, img)


@pytest.mark.parametrize("name, value, exc", [("threshold_px", np.nan, ValueError), ("threshold_px", -1.0, ValueError),
                                              ("threshold_px", 1j, TypeError), ("max_features", 2 ** 40, ValueError),
                                              ("max_features", 0, ValueError)])
def test_reconstruct_three_view_images_options_named(name, value, exc):
    img = np.zeros((64, 64), np.uint8)
    with pytest.raises(exc, match=name):
        libsfm.reconstruct_three_view_images(img, img, img, **{name: value})


def test_reconstruct_three_view_images_refuses_complex_and_mismatched_images():
    img = np.zeros((64, 64), np.uint8)
    with pytest.raises((TypeError, ValueError), match="img2"):
        libsfm.reconstruct_three_view_images(img, img.astype(np.complex128), img)
    with pytest.raises(ValueError):
        libsfm.reconstruct_three_view_images(img, img, np.zeros((64, 65), np.uint8))


@pytest.mark.parametrize("name, value, exc", [
    ("max_iterations", 2.5, TypeError), ("max_iterations", 0, ValueError), ("max_iterations", 2 ** 31, ValueError),
    ("sweep_iterations", 51, ValueError), ("sweep_iterations", 8.0, TypeError),
    ("max_focal_sigma", 0.0, ValueError), ("max_focal_sigma", 1j, TypeError), ("max_focal_sigma", np.nan, ValueError),
    ("min_parallax_deg", -1.0, ValueError), ("principal_sigma", np.nan, ValueError),
    ("aspect_sigma", -0.1, ValueError), ("width", 640.5, TypeError), ("width", 0, ValueError),
    ("height", 2 ** 31, ValueError), ("height", True, TypeError),
])
def test_reconstruct_three_view_options_named(name, value, exc):
    rng = np.random.default_rng(9)
    x = views(rng, "general", m=3, n=40, sigma=0.3)
    kw = dict(width=640, height=480)
    kw[name] = value
    w, h = kw.pop("width"), kw.pop("height")
    with pytest.raises(exc, match=name):
        libsfm.reconstruct_three_view(x[0], x[1], x[2], w, h, radial=0, **kw)
    if name not in ("width", "height"):  # the images path passes them on
        img = np.zeros((64, 64), np.uint8)
        with pytest.raises(exc, match=name):
            libsfm.reconstruct_three_view_images(img, img, img, **kw)
