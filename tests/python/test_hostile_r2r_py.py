"""Hostile measurements through the robot-to-robot wrappers: a NaN/Inf in a
step is an SfmError naming that step's field, complex and mis-shaped
fields are refused before the C call, seeds are any integer mod 2**64."""
import numpy as np
import pytest

import libsfm
from libsfm import SfmError


def _steps():
    # robot 2 one metre ahead of robot 1, both moving; bearings from the geometry
    rng = np.random.default_rng(5)
    C = np.eye(3)
    p = np.array([1.0, 0.5, 0.2])
    out = []
    for k in range(6):
        t1 = np.zeros(3) if k == 0 else rng.uniform(-1, 1, 3)
        t2 = np.zeros(3) if k == 0 else rng.uniform(-1, 1, 3)
        w = C @ t2 + p - t1
        out.append({"R1": np.eye(3), "t1": t1, "R2": np.eye(3), "t2": t2,
                    "d": float(np.linalg.norm(w)), "b1": w / np.linalg.norm(w),
                    "b2": -(C.T @ w) / np.linalg.norm(w)})
    return out, C, p


@pytest.mark.parametrize("field", ["b1", "b2", "d", "t2", "R1"])
def test_nonfinite_field_is_named(field):
    steps, C, p = _steps()
    bad = [dict(s) for s in steps]
    v = np.array(bad[3][field], dtype=float)
    v.flat[0] = np.nan
    bad[3][field] = v if v.ndim else float(v)
    want = "steps[3][%r]" % field
    for call in (lambda: libsfm.r2r_solve(bad),
                 lambda: libsfm.r2r_refine(bad, C, p, 0.01, 0.01),
                 lambda: libsfm.r2r_ransac(bad, 0.01, 0.01, seed=1)):
        with pytest.raises(SfmError) as e:
            call()
        assert e.value.name == "SFM_E_NONFINITE"
        assert e.value.argument == want


def test_complex_and_misshaped_fields_refused():
    steps, C, p = _steps()
    bad = [dict(s) for s in steps]
    bad[2]["b1"] = bad[2]["b1"] + 0j
    with pytest.raises(TypeError, match=r"steps\[2\]\['b1'\]"):
        libsfm.r2r_solve(bad)
    bad = [dict(s) for s in steps]
    bad[2]["d"] = 1 + 1j
    with pytest.raises(TypeError, match=r"steps\[2\]\['d'\]"):
        libsfm.r2r_refine(bad, C, p, 0.01, 0.01)
    bad = [dict(s) for s in steps]
    bad[1]["b2"] = [1.0, 0.0]
    with pytest.raises(ValueError, match=r"steps\[1\]\['b2'\]"):
        libsfm.r2r_ransac(bad, 0.01, 0.01)
    with pytest.raises(TypeError, match="seed"):
        libsfm.r2r_ransac(steps, 0.01, 0.01, seed=1.5)


def test_zero_distance_and_zero_bearing_refused():
    steps, C, p = _steps()
    for field, value in (("d", 0.0), ("b1", [0.0, 0.0, 0.0])):
        bad = [dict(s) for s in steps]
        bad[4][field] = value
        with pytest.raises(SfmError) as e:
            libsfm.r2r_refine(bad, C, p, 0.01, 0.01)
        assert e.value.name == "SFM_E_ARGUMENT"


def test_non_unit_bearings_and_seed_rule():
    steps, C, p = _steps()
    scaled = [dict(s, b1=5.0 * s["b1"], b2=0.1 * s["b2"]) for s in steps]
    Cr, pr, _ = libsfm.r2r_refine(scaled, C, p + 0.01, 0.01, 0.01)
    assert np.abs(pr - p).max() < 1e-8 and np.abs(Cr - C).max() < 1e-8
    a = libsfm.r2r_ransac(steps, 0.01, 0.01, seed=-1)
    b = libsfm.r2r_ransac(steps, 0.01, 0.01, seed=2 ** 64 - 1)
    assert np.array_equal(a["p"], b["p"]) and np.array_equal(a["C"], b["C"])
    assert np.abs(a["p"] - p).max() < 1e-6
