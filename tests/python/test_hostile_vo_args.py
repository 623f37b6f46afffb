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
