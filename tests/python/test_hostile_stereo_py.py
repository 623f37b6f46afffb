"""Hostile arguments of the stereo wrappers: complex or non-integer arrays
are refused with a TypeError naming them, shapes and ranges with a
ValueError naming them, a corrupted rectification with an SfmError, never a
silent answer."""
import numpy as np
import pytest

import libsfm
from libsfm import SfmError

K = np.array([[60.0, 0, 31.5], [0, 60.0, 23.5], [0, 0, 1]])


@pytest.fixture(scope="module")
def rect():
    return libsfm.rectify_pair(K, K, np.eye(3), [-0.1, 0, 0], (64, 48), alpha=0.0)


def test_remap_refuses_a_view_other_than_1_or_2(rect):
    img = np.zeros((48, 64), np.uint8)
    for view in (0, -1, 3):
        with pytest.raises(ValueError, match="view"):
            libsfm.remap(img, rect["maps"], view=view)


def test_remap_refuses_maps_that_are_not_integers(rect):
    img = np.zeros((48, 64), np.uint8)
    m = rect["maps"][0].astype(np.float64) + 0.5
    with pytest.raises(TypeError, match="map"):
        libsfm.remap(img, m)
    with pytest.raises(TypeError, match="map"):
        libsfm.remap(img, rect["maps"][0] + 0j)


def test_disparity_to_depth_refuses_complex_and_bad_shapes(rect):
    d = np.full((48, 64), 5.0, np.float32)
    assert np.isfinite(libsfm.disparity_to_depth(d, rect)).any()
    with pytest.raises(TypeError, match="disparity"):
        libsfm.disparity_to_depth(d + 1j, rect)
    with pytest.raises(TypeError, match="disparity"):
        libsfm.disparity_to_points(d + 1j, rect)
    for bad in (d[0], d[None]):
        with pytest.raises(ValueError, match="disparity"):
            libsfm.disparity_to_depth(bad, rect)
        with pytest.raises(ValueError, match="disparity"):
            libsfm.disparity_to_points(bad, rect)


def test_disparity_to_points_names_a_nan_max_depth(rect):
    d = np.full((48, 64), 5.0, np.float32)
    with pytest.raises(ValueError, match="max_depth"):
        libsfm.disparity_to_points(d, rect, max_depth=float("nan"))
    with pytest.raises(TypeError, match="max_depth"):
        libsfm.disparity_to_points(d, rect, max_depth=1 + 2j)
    with pytest.raises(ValueError, match="baseline"):
        libsfm.disparity_to_depth(d, K=K, baseline=float("nan"))


def test_rectification_error_refuses_a_corrupted_rect(rect):
    x1 = np.array([[10.0, 10.0], [20.0, 30.0]])
    x2 = x1 + [2.0, 0.0]
    med, mx, n = libsfm.rectification_error(x1, x2, rect, K1=K, K2=K)
    assert n == 2 and np.isfinite(med) and np.isfinite(mx)
    bad = dict(rect)
    bad["R1"] = rect["R1"].copy()
    bad["R1"][0, 0] = np.nan
    with pytest.raises(SfmError) as e:
        libsfm.rectification_error(x1, x2, bad, K1=K, K2=K)
    assert e.value.name == "SFM_E_NONFINITE"
