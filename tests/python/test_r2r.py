"""libsfm.r2r_solve / r2r_predict / r2r_classify against a numpy model of
two robots in a world: orientations and positions of both robots at every
step are drawn at random, and the ego-motions, the truth (C, p) and the
measurements follow from world geometry (not from the library)."""
import numpy as np
import pytest
from scipy.spatial.transform import Rotation

import libsfm
from libsfm import SfmError

D, B1, B2 = 1, 2, 4
NAMES = ["DB1B2_D", "B1B2_B1", "B1B2_D_D", "DB1_DB1", "DB1_DB2", "DB1_B1_D", "DB1_B2_D",
         "DB1_D_D_D", "B1_B1_B1", "B1_B1_B2", "B1_B1_D_D", "B1_B2_D_D", "B1_D_D_D_D", "D6"]
RANK_DEFICIENT = {"DB1_DB1", "DB1_DB2"}  # six equations of rank five


def pattern(name):
    if name == "D6":
        return [D] * 6
    out = []
    for part in name.split("_"):
        m = D if "D" in part else 0
        m |= B1 if "B1" in part else 0
        m |= B2 if "B2" in part else 0
        out.append(m)
    return out


def world(rng, n):
    """Body-to-world orientations and positions of both robots (a few
    metres apart, at least 0.5 m from each other)."""
    W1 = Rotation.random(n, random_state=rng).as_matrix()
    W2 = Rotation.random(n, random_state=rng).as_matrix()
    P1 = rng.uniform(-3, 3, (n, 3))
    P2 = rng.uniform(-3, 3, (n, 3))
    for k in range(n):
        while np.linalg.norm(P2[k] - P1[k]) < 0.5:
            P2[k] = rng.uniform(-3, 3, 3)
    return W1, P1, W2, P2


def scene(W1, P1, W2, P2, masks):
    """Steps (dicts) and the truth (C, p) from world poses."""
    C = W1[0].T @ W2[0]
    p = W1[0].T @ (P2[0] - P1[0])
    steps = []
    for k, m in enumerate(masks):
        v = P2[k] - P1[k]
        dist = np.linalg.norm(v)
        st = {"R1": W1[0].T @ W1[k], "t1": W1[0].T @ (P1[k] - P1[0]),
              "R2": W2[0].T @ W2[k], "t2": W2[0].T @ (P2[k] - P2[0])}
        if m & D:
            st["d"] = dist
        if m & B1:
            st["b1"] = W1[k].T @ v / dist
        if m & B2:
            st["b2"] = -W2[k].T @ v / dist
        steps.append(st)
    return steps, C, p


def random_scene(rng, masks):
    return scene(*world(rng, len(masks)), masks)


def has_truth(sols, C, p, tol=1e-6):
    return any(np.abs(Cs - C).max() < tol and np.abs(ps - p).max() < tol for Cs, ps in sols)


def test_predict_matches_world_model():
    rng = np.random.default_rng(1)
    for _ in range(50):
        steps, C, p = random_scene(rng, [7] * 4)
        for st in steps:
            d, b1, b2 = libsfm.r2r_predict(st, C, p)
            assert d == pytest.approx(st["d"], abs=1e-12)
            np.testing.assert_allclose(b1, st["b1"], atol=1e-12)
            np.testing.assert_allclose(b2, st["b2"], atol=1e-12)


def test_systems_are_named_as_in_the_header():
    assert list(libsfm.R2R_SYSTEMS.values()) == NAMES
    assert list(libsfm.R2R_SYSTEMS) == list(range(1, 15))


@pytest.mark.parametrize("name", NAMES)
def test_six_equations_any_order_and_exchange(name):
    """Each base system's pattern, steps shuffled and robots exchanged at
    random: classified as the system, and the truth among the solutions."""
    rng = np.random.default_rng(NAMES.index(name) + 100)
    found = runs = 0
    for it in range(60):
        masks = pattern(name)
        rng.shuffle(masks)
        if it % 2:
            masks = [(m & D) | (B2 if m & B1 else 0) | (B1 if m & B2 else 0) for m in masks]
        steps, C, p = random_scene(rng, masks)
        assert libsfm.r2r_classify(steps) == name
        try:
            sols = libsfm.r2r_solve(steps)
        except SfmError as e:
            if name in RANK_DEFICIENT and e.name == "SFM_E_DEGENERATE":
                runs += 1
                found += 1
                continue
            raise
        assert name not in RANK_DEFICIENT, "rank-deficient system answered"
        runs += 1
        found += has_truth(sols, C, p)
        for Cs, ps in sols:  # every answer fits the six equations
            for st in steps:
                d, b1, b2 = libsfm.r2r_predict(st, Cs, ps)
                if "d" in st:
                    assert abs(d - st["d"]) < 1e-4 * st["d"]
                if "b1" in st:
                    assert np.abs(b1 - st["b1"]).max() < 1e-3
    assert found >= runs - 1, "%s: truth in %d of %d" % (name, found, runs)


def test_long_sequences_truth_first():
    rng = np.random.default_rng(7)
    ok = runs = 0
    for it in range(60):
        n = int(rng.integers(7, 21))
        masks = [7] * n if it % 2 == 0 else list(rng.integers(1, 8, n))
        steps, C, p = random_scene(rng, masks)
        sols = libsfm.r2r_solve(steps)
        runs += 1
        ok += len(sols) >= 1 and has_truth(sols[:1], C, p)
    assert runs > 0
    assert ok >= runs - 1, "truth first in %d of %d" % (ok, runs)


def test_steps_at_the_same_positions_are_degenerate():
    rng = np.random.default_rng(3)
    W1, P1, W2, P2 = world(rng, 6)
    P1[:] = P1[0]
    P2[:] = P2[0]  # both robots only turn
    steps, _, _ = scene(W1, P1, W2, P2, [7] * 6)
    with pytest.raises(SfmError) as e:
        libsfm.r2r_solve(steps)
    assert e.value.name == "SFM_E_DEGENERATE"


def test_distances_on_parallel_lines_are_degenerate():
    rng = np.random.default_rng(4)
    W1, P1, W2, P2 = world(rng, 8)
    u = rng.normal(size=3)
    u /= np.linalg.norm(u)
    P1 = P1[0] + np.outer(np.arange(8) * 0.4, u)
    P2 = P2[0] + np.outer(np.arange(8) * 0.25 + 0.1, u)
    steps, _, _ = scene(W1, P1, W2, P2, [D] * 8)
    with pytest.raises(SfmError) as e:
        libsfm.r2r_solve(steps)
    assert e.value.name == "SFM_E_DEGENERATE"


def test_first_step_defaults_to_identity():
    rng = np.random.default_rng(5)
    steps, C, p = random_scene(rng, [D | B1, D, D, D])
    short = [dict((k, v) for k, v in steps[0].items() if k not in ("R1", "t1", "R2", "t2"))] + steps[1:]
    assert libsfm.r2r_classify(short) == "DB1_D_D_D"
    try:
        a = libsfm.r2r_solve(steps)
    except SfmError as e:
        pytest.skip(e.name)
    b = libsfm.r2r_solve(short)
    assert len(a) == len(b) and all(has_truth(b, Cs, ps, 1e-9) for Cs, ps in a)
    assert has_truth(b, C, p)


def test_bad_inputs():
    rng = np.random.default_rng(6)
    steps, C, p = random_scene(rng, [D | B1, D, D, D])

    def status(s):
        with pytest.raises(SfmError) as e:
            libsfm.r2r_solve(s)
        return e.value.name

    assert status(steps[:3]) == "SFM_E_ARGUMENT"  # five equations
    bad = [dict(s) for s in steps]
    bad[1]["d"] = -1.0
    assert status(bad) == "SFM_E_ARGUMENT"
    bad[1]["d"] = float("nan")
    assert status(bad) == "SFM_E_NONFINITE"
    bad = [dict(s) for s in steps]
    bad[0]["b1"] = np.zeros(3)
    assert status(bad) == "SFM_E_ARGUMENT"
    bad = [dict(s) for s in steps]
    bad[2]["R2"] = 1.1 * np.eye(3)
    assert status(bad) == "SFM_E_ARGUMENT"
    with pytest.raises(ValueError):
        libsfm.r2r_solve([dict(s) for s in steps[:1]] + [{"d": 1.0}] * 3)  # no ego-motion
    with pytest.raises(ValueError):
        libsfm.r2r_solve([dict(steps[0], x=1)] + steps[1:])
    with pytest.raises(ValueError):
        libsfm.r2r_solve([dict(steps[0], b1=[1.0, 0.0])] + steps[1:])
    with pytest.raises(ValueError):
        libsfm.r2r_solve([])
    with pytest.raises(TypeError):
        libsfm.r2r_solve(steps[0])


def test_d6_six_distances():
    """Six distances (the Stewart-Gough forward kinematics, 40 complex
    solutions): the truth among the answers, every answer a rotation meeting
    the six distances (checked here with numpy), at most 40 real answers and
    an even number of them (the complex ones come in conjugate pairs)."""
    rng = np.random.default_rng(16)
    found = runs = 0
    for _ in range(80):
        steps, C, p = random_scene(rng, [D] * 6)
        assert libsfm.r2r_classify(steps) == "D6"
        sols = libsfm.r2r_solve(steps)
        runs += 1
        found += has_truth(sols, C, p)
        assert len(sols) <= 40 and len(sols) % 2 == 0
        for Cs, ps in sols:
            assert np.abs(Cs @ Cs.T - np.eye(3)).max() < 1e-9 and np.linalg.det(Cs) > 0
            for st in steps:
                assert abs(np.linalg.norm(Cs @ st["t2"] + ps - st["t1"]) - st["d"]) < 1e-7 * st["d"]
    assert found == runs, "truth in %d of %d" % (found, runs)


def test_d6_ground_robots():
    """Both robots on the ground plane (z = 0 in a common world, yaw only):
    planar base and platform, where the solutions come in mirror pairs
    through the plane; the truth is among them."""
    rng = np.random.default_rng(17)
    found = 0
    for _ in range(30):
        yaw1, yaw2 = rng.uniform(-np.pi, np.pi, (2, 6))
        W1 = Rotation.from_euler("z", yaw1[:, None]).as_matrix()
        W2 = Rotation.from_euler("z", yaw2[:, None]).as_matrix()
        P1 = np.c_[rng.uniform(-3, 3, (6, 2)), np.zeros(6)]
        P2 = np.c_[rng.uniform(-3, 3, (6, 2)), np.zeros(6)]
        P2[:, :2] += 1.0
        steps, C, p = scene(W1, P1, W2, P2, [D] * 6)
        sols = libsfm.r2r_solve(steps)
        found += has_truth(sols, C, p)
    assert found >= 29, "truth in %d of 30" % found
