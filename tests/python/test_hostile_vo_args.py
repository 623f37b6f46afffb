"""VisualOdometry's arguments under the binding's rules: integers are not
truncated (TypeError for 640.5), out-of-range values are ValueError naming
the argument, complex input is refused (numpy would drop the imaginary part),
seeds are any int taken modulo 2**64."""
import numpy as np
import pytest

import libsfm

W, H = 160, 120


def _vo(**kw):
    return libsfm.VisualOdometry(W, H, (160.0, 160.0, 79.5, 59.5), max_features=200, window=3,
                                 timing=False, **kw)


@pytest.mark.parametrize("field", ["width", "height", "max_features", "window"])
def test_vo_integer_sizes_are_not_truncated(field):
    args = dict(width=W, height=H, max_features=200, window=3)
    args[field] = args[field] + 0.5
    with pytest.raises(TypeError, match=field):
        libsfm.VisualOdometry(args["width"], args["height"], (160.0, 160.0, 79.5, 59.5),
                              max_features=args["max_features"], window=args["window"], timing=False)


def test_vo_timestamp_checked():
    vo = _vo()
    img = np.zeros((H, W), np.uint8)
    with pytest.raises(TypeError, match="timestamp_ns"):
        vo.push(img, 1.5)
    with pytest.raises(ValueError, match="timestamp_ns"):
        vo.push(img, 2 ** 63)
    r = vo.push(img, np.int64(5))
    assert r.frame_index == 0
    with pytest.raises(libsfm.SfmError):
        vo.push(img, 4)  # backwards
    assert vo.push(img, 5).frame_index == 1  # repeated: allowed, state kept


def test_vo_gravity_complex_refused():
    vo = _vo()
    img = np.zeros((H, W), np.uint8)
    with pytest.raises(TypeError, match="gravity"):
        vo.push(img, 0, gravity=np.array([0, 1 + 1j, 0]))
    with pytest.raises(ValueError, match="gravity"):
        vo.push(img, 0, gravity=[0, 1])
    assert vo.push(img, 0, gravity=[0, 9.8, 0]).frame_index == 0


def test_vo_seed_any_int_mod_2_64():
    a = _vo(seed=-1)
    b = _vo(seed=2 ** 64 - 1)
    assert a._params.seed == b._params.seed == 2 ** 64 - 1
    c = _vo(seed=2 ** 70 + 3)
    assert c._params.seed == 3
    with pytest.raises(TypeError, match="seed"):
        _vo(seed=1.5)


CAM = (160.0, 160.0, 79.5, 59.5)


def _vo_cam(camera, **kw):
    return libsfm.VisualOdometry(W, H, camera, max_features=200, window=3, timing=False, **kw)


@pytest.mark.parametrize("camera", [(160 + 1j, 160.0, 79.5, 59.5), np.array(CAM, complex),
                                    ("160", "160", "79.5", "59.5"), "abcd", {"fx": 160.0}])
def test_vo_camera_entries_must_be_real_numbers(camera):
    # complex lost its imaginary part and strings were parsed by float()
    with pytest.raises(TypeError, match="camera"):
        _vo_cam(camera)


@pytest.mark.parametrize("camera, model", [((160.0, 160.0, 79.5), "pinhole"),
                                           (CAM + (0.1,) * 6, "pinhole"),   # 10 values: was cut to 9
                                           (CAM + (0.1,) * 5, "fisheye"),   # fisheye has 4 coefficients
                                           (np.zeros((2, 4)), "pinhole"),
                                           (160.0, "pinhole")])
def test_vo_camera_length_checked(camera, model):
    with pytest.raises(ValueError, match="camera"):
        _vo_cam(camera, model=model)


@pytest.mark.parametrize("camera", [CAM, None])
@pytest.mark.parametrize("model", ["pinhol", "Fisheye", 1, None])
def test_vo_unknown_model_is_a_value_error(camera, model):
    with pytest.raises(ValueError, match="model"):  # was a KeyError (or a silent pinhole)
        _vo_cam(camera, model=model)


@pytest.mark.parametrize("index, value, field, status", [
    (0, 0.0, "fx", "SFM_E_ARGUMENT"), (1, 0.0, "fy", "SFM_E_ARGUMENT"),
    (3, float("nan"), "cy", "SFM_E_NONFINITE"), (0, float("inf"), "fx", "SFM_E_NONFINITE")])
def test_vo_camera_error_names_the_entry(index, value, field, status):
    cam = list(CAM)
    cam[index] = value
    with pytest.raises(libsfm.SfmError) as e:
        _vo_cam(tuple(cam))
    assert e.value.argument == "camera." + field and e.value.name == status


def test_vo_camera_nan_distortion_named():
    with pytest.raises(libsfm.SfmError) as e:
        _vo_cam(CAM + (0.1, float("nan")))
    assert e.value.argument == "camera.dist"


def test_vo_takes_a_camera_object_and_the_tuple_forms():
    a = _vo_cam(libsfm.Camera("fisheye", 160.0, 160.0, 79.5, 59.5, (0.01, 0.0, 0.0, 0.002)))
    b = _vo_cam(CAM + (0.01, 0.0, 0.0, 0.002), model="fisheye")
    for vo in (a, b):
        c = vo._params.camera
        assert c.model == libsfm.lib.SFM_CAMERA_FISHEYE
        assert (c.fx, c.fy, c.cx, c.cy) == CAM and c.dist[0] == 0.01 and c.dist[3] == 0.002
    brown = _vo_cam(CAM + (-0.1, 0.01))  # pinhole with distortion: Brown, the rest zero
    assert brown._params.camera.model == libsfm.lib.SFM_CAMERA_BROWN
    assert list(brown._params.camera.dist) == [-0.1, 0.01, 0.0, 0.0, 0.0]
    assert _vo_cam(np.array(CAM, np.float32))._params.camera.cx == 79.5
    with pytest.raises(ValueError, match="model"):
        _vo_cam(libsfm.Camera("brown", *CAM), model="fisheye")


@pytest.mark.parametrize("value, exc", [(1 + 0j, TypeError), ("500", TypeError), (True, TypeError),
                                        (float("nan"), ValueError), (float("inf"), ValueError)])
def test_vo_focal_guess_is_a_real_number(value, exc):
    with pytest.raises(exc, match="focal_guess"):
        _vo_cam(None, focal_guess=value)


def test_vo_focal_guess_with_a_camera_refused():
    # it only steers self-calibration: with a camera it was dropped silently
    with pytest.raises(ValueError, match="focal_guess"):
        _vo_cam(CAM, focal_guess=200.0)
    assert _vo_cam(None, focal_guess=np.float32(200))._params.camera.fx == 200.0


@pytest.mark.parametrize("field, value, exc", [("n_levels", 2.5, TypeError), ("n_levels", 0, ValueError),
                                               ("n_levels", 2 ** 32 + 2, ValueError),
                                               ("fast_threshold", 20.5, TypeError),
                                               ("fast_threshold", 255, ValueError),
                                               ("fast_threshold", 1j, TypeError)])
def test_vo_feature_integers_checked(field, value, exc):
    # int() truncated 2.5 to 2 and 2**32 + 2 wrapped to 2 in the C int
    with pytest.raises(exc, match=field):
        _vo_cam(CAM, **{field: value})
    assert getattr(_vo_cam(CAM, **{field: np.int16(3)})._params.features, field) == 3
