"""Uncalibrated reconstruction through the binding: projective factorization
(synthetic tracks with missing observations, Oxford Model House against its
ground-truth cameras), linear self-calibration (synthetic table over noise
levels, a critical sequence refused), the three- and two-view pipelines on
Herz-Jesu-P8 match triplets against the known focal length, and the
BoofCV triplets from images."""
import os

import numpy as np
import pytest

import libsfm
from test_three_view_herzjesu import triplets as herz_index

ROOT = os.path.join(os.path.dirname(__file__), "..", "..", "..", "shared", "data")
HOUSE = os.path.join(ROOT, "oxford-house")
HERZ = os.path.join(ROOT, "herzjesu-p8")
BOOF = os.path.join(ROOT, "boofcv-triple", "triple")
F_HERZ = 2759.48  # K.txt of Herz-Jesu-P8, fx at 3072x2048


def rot(aa):
    th = np.linalg.norm(aa)
    if th == 0:
        return np.eye(3)
    k = aa / th
    Kx = np.array([[0, -k[2], k[1]], [k[2], 0, -k[0]], [-k[1], k[0], 0]])
    return np.eye(3) + np.sin(th) * Kx + (1 - np.cos(th)) * Kx @ Kx


def scene(rng, m=5, n=120, f=800.0, w=640, h=480, sigma=0.0):
    """Cameras turning about two axes around a cloud; returns tracks (m,n,2),
    clean projections and the metric cameras."""
    K = np.array([[f, 0, (w - 1) / 2], [0, f, (h - 1) / 2], [0, 0, 1]])
    Ps = []
    for i in range(m):
        aa = np.array([0.12 * np.sin(i), 0.2 * (i - (m - 1) / 2) / m * 2, 0.03 * i]) if i else np.zeros(3)
        C = np.array([0.6 * (i - (m - 1) / 2), 0.4 * np.cos(i), 0.1 * i]) if i else np.zeros(3)
        R = rot(aa)
        Ps.append(K @ np.c_[R, -R @ C])
    X = np.c_[rng.uniform(-2, 2, n), rng.uniform(-1.5, 1.5, n), rng.uniform(5, 9, n), np.ones(n)]
    clean = np.stack([(X @ P.T)[:, :2] / (X @ P.T)[:, 2:] for P in Ps])
    return clean + rng.normal(0, sigma, clean.shape), clean, np.array(Ps)


def reproj_rms(P, X, x):
    se, c = 0.0, 0
    for i in range(len(P)):
        y = X @ P[i].T
        ok = ~np.isnan(x[i, :, 0]) & np.any(X != 0, axis=1)
        p = y[ok, :2] / y[ok, 2:]
        se += np.sum((p - x[i, ok]) ** 2)
        c += ok.sum()
    return np.sqrt(se / c)


def test_factorize_missing_observations_reaches_the_noise():
    rng = np.random.default_rng(14)
    x, clean, _ = scene(rng, sigma=0.5)
    drop = rng.uniform(size=x.shape[:2]) < 0.3
    drop[:2] = False  # every track keeps two views
    x[drop] = np.nan
    r = libsfm.factorize_projective(x)
    assert r["P"].shape == (5, 3, 4) and r["X"].shape == (120, 4)
    assert r["points_recovered"] == 120
    assert r["reproj_rms"] <= r["factorization_rms"] + 1e-12
    # against the noise-free projections: at the noise floor (0.5 px per axis)
    assert reproj_rms(r["P"], r["X"], np.where(np.isnan(x), np.nan, clean)) < 0.6
    with pytest.raises(ValueError):
        libsfm.factorize_projective(x[:, :, 0])


def load_house():
    m = 10
    corners = [np.loadtxt(os.path.join(HOUSE, "2D", "house.%03d.corners" % i)) for i in range(m)]
    rows = [line.split() for line in open(os.path.join(HOUSE, "2D", "house.nview-corners"))]
    x = np.full((m, len(rows), 2), np.nan)
    for j, r in enumerate(rows):
        for i, v in enumerate(r):
            if v not in ("*", "-1"):
                x[i, j] = corners[i][int(v)]
    P = np.array([np.loadtxt(os.path.join(HOUSE, "3D", "house.%03d.P" % i)) for i in range(m)])
    X = np.loadtxt(os.path.join(HOUSE, "3D", "house.p3d"))
    return x, P, np.c_[X, np.ones(len(X))]


@pytest.mark.skipif(not os.path.isdir(HOUSE), reason="SKIP: ../shared/data/oxford-house not found")
def test_factorize_oxford_house_at_or_below_ground_truth_rms():
    x, P, X = load_house()
    gt = reproj_rms(P, X, x)
    r = libsfm.factorize_projective(x)
    print("\nOxford house: %d tracks, %d observations; block %dx%d, %d iterations (monotone %s); "
          "factorization %.4f px, after projective BA %.4f px (%d steps); ground-truth cameras %.4f px"
          % (x.shape[1], r["n_observations"], r["block_views"], r["block_points"], r["iterations"],
             r["monotone"], r["factorization_rms"], r["reproj_rms"], r["ba_iterations"], gt))
    assert r["points_recovered"] == x.shape[1]
    assert abs(reproj_rms(r["P"], r["X"], x) - r["reproj_rms"]) < 1e-9
    assert r["reproj_rms"] <= gt


@pytest.mark.skipif(not os.path.isdir(HOUSE), reason="SKIP: ../shared/data/oxford-house not found")
def test_self_calibrate_oxford_house_gives_no_wrong_focal():
    """The house's cameras turn about one axis and their intrinsics break
    the linear method's priors (principal point up to 96 px off-centre,
    skew, a focal length changing from view to view): the linear method
    must refuse or be right."""
    x, P, _ = load_house()
    r = libsfm.factorize_projective(x)
    try:
        s = libsfm.self_calibrate(r["P"], (768, 576), r["X"])
    except libsfm.SfmError as e:
        print("\nOxford house self-calibration refused: flags %d, null ratio %.3f" % (e.flags, e.null_ratio))
        assert e.flags & 8
        return
    fgt = [np.linalg.qr(np.linalg.inv(Pi[:, :3]))[1] for Pi in P]
    for K, R in zip(s["K"], fgt):
        Kg = np.linalg.inv(R)
        Kg = Kg / Kg[2, 2]
        assert abs(K[0, 0] / abs(Kg[0, 0]) - 1) < 0.05


def house_cameras(P):
    """(K, R, C) of each ground-truth camera by RQ, K with a positive
    diagonal. The house's frame is left-handed (every det P[:, :3] < 0 with
    the points at positive depth w), so R has det -1."""
    out = []
    for Pi in P:
        Q, U = np.linalg.qr(np.flipud(Pi[:, :3]).T)
        K, R = np.flipud(U.T)[:, ::-1], Q.T[::-1, :]
        D = np.diag(np.sign(np.diag(K)))
        K, R = K @ D, D @ R
        out.append((K / K[2, 2], R, -np.linalg.solve(Pi[:, :3], Pi[:, 3])))
    return out


def similarity(A, B):
    """s, Q, T with B ~ s Q A + T by least squares (Umeyama), Q orthogonal;
    a reflection is allowed (the house's frame is left-handed)."""
    ma, mb = A.mean(0), B.mean(0)
    U, S, Vt = np.linalg.svd((B - mb).T @ (A - ma))
    Q = U @ Vt
    s = S.sum() / ((A - ma) ** 2).sum()
    return s, Q, mb - s * Q @ ma


def against_house(s, P, X):
    """Per view: rotation error (deg), camera-centre error / scene radius,
    focal / fx - 1 and / fy - 1, after the similarity that best maps the
    adjusted points onto the ground-truth points; and the median point
    error / scene radius."""
    gt = house_cameras(P)
    ok = np.any(s["X"] != 0, axis=1)
    sc, Q, T = similarity(s["X"][ok], X[ok, :3])
    radius = np.linalg.norm(X[:, :3] - X[:, :3].mean(0), axis=1).max()
    rot, cen = [], []
    for (Kg, Rg, Cg), R, t in zip(gt, s["R"], s["t"]):
        # x ~ K Rg (Xg - Cg) with Xg = sc Q X + T: the estimate's R ~ Rg Q
        c = (np.trace(R.T @ Rg @ Q) - 1) / 2
        rot.append(np.degrees(np.arccos(np.clip(c, -1, 1))))
        cen.append(np.linalg.norm(sc * Q @ (-R.T @ t) + T - Cg) / radius)
    fx = np.array([g[0][0, 0] for g in gt])
    fy = np.array([g[0][1, 1] for g in gt])
    pts = np.linalg.norm((sc * (Q @ s["X"][ok].T)).T + T - X[ok, :3], axis=1) / radius
    return np.array(rot), np.array(cen), s["focal_view"] / fx - 1, s["focal_view"] / fy - 1, np.median(pts)


@pytest.mark.skipif(not os.path.isdir(HOUSE), reason="SKIP: ../shared/data/oxford-house not found")
def test_self_calibrate_oxford_house_metric_against_ground_truth():
    """The linear dual quadric refuses the house (critical for a focal
    length per view); the focal search, one shared f, is not flat (the
    fixed-focal cost 1.5x away rises by thousands of noise variances) and
    gives a metric reconstruction whose points match the ground truth
    after a similarity. The ground truth's own intrinsics break the priors
    (fx 594-666, principal point up to 96 px off-centre, skew to -26), so
    with the principal point held at the centre the focal length comes out
    9-22 % above fx and the rotations absorb the principal point (up to
    11.5 deg in the last view, where it is 96 px off); a principal point
    per view (principal="per_view") brings f within 3.5 % of fy."""
    x, P, X = load_house()
    r = libsfm.factorize_projective(x)
    rows = {}
    modes = {"shared f": {}, "f per view": dict(per_view_focal=True), "shared pp": dict(principal="shared"),
             "pp per view": dict(principal="per_view")}
    for mode, kw in modes.items():
        s = libsfm.self_calibrate(r["P"], (768, 576), r["X"], tracks=x, **kw)
        rows[mode] = (s,) + against_house(s, P, X)
    print("\nOxford house, m-view self-calibration (linear status %d flags %d); after a similarity on the points:"
          % (s["linear_status"], s["linear_flags"]))
    print("  mode | path | f shared | sigma f | far rise | rms px | rot err deg max | centre err / radius max"
          " | f/fx-1 range | f/fy-1 range | point err / radius median")
    for mode, (s, rot, cen, efx, efy, pts) in rows.items():
        print("  %-11s | %s | %.1f | %.4f | %.0f | %.4f | %.2f | %.3f | %+.3f..%+.3f | %+.3f..%+.3f | %.4f"
              % (mode, s["path"], s["focal"], s["focal_sigma"], s["profile_rise"], s["rms"], rot.max(), cen.max(),
                 efx.min(), efx.max(), efy.min(), efy.max(), pts))
        print("    rotation error per view", np.round(rot, 2), "centre error", np.round(cen, 3))
        print("    focal per view", np.round(s["focal_view"], 1), "principal point x", np.round(s["K"][:, 0, 2], 1))
        # the linear method refuses; the search answers
        assert s["linear_status"] == -5 and s["linear_flags"] & 8 and s["path"] == "sweep"
        assert s["profile_rise"] > 1000 and s["focal_sigma"] < 0.01
        assert s["rms"] < 0.7 and s["front_fraction"] == 1.0 and s["points"] == x.shape[1]
        # measured: points 0.73-0.77 % of the radius; rotations 11.5 deg, centres 0.21 radius
        assert pts < 0.012 and rot.max() < 15 and cen.max() < 0.3
    s, rot, cen, efx, efy, pts = rows["shared f"]
    print("  the profile (fixed-focal cost, Huber, over f; inf: no metric cameras for that f):")
    print("   ", " ".join("%.0f:%.0f" % fc for fc in zip(s["sweep_focal"], s["sweep_cost"])))
    again = libsfm.self_calibrate(r["P"], (768, 576), r["X"], tracks=x)
    assert np.array_equal(again["K"], s["K"]) and np.array_equal(again["R"], s["R"])  # deterministic
    assert np.all(np.abs(efx) < 0.3) and np.all(efx > 0)  # measured +9 .. +22 %: the priors' bias
    s, rot, cen, efx, efy, pts = rows["pp per view"]
    assert s["per_view"] and s["principal"] == "per_view" and np.all(np.abs(efy) < 0.06)  # measured -1.0 .. +3.5 %
    assert np.all(np.abs(efx) < 0.16) and cen.max() < 0.16  # measured -1.6 .. +11.4 %, 0.12


@pytest.mark.skipif(not os.path.isdir(HOUSE), reason="SKIP: ../shared/data/oxford-house not found")
def test_self_calibrate_house_motion_with_known_focal():
    """The house's ground-truth motion (rotation about one axis, 11-89 deg)
    and points, re-imaged by one camera of f = 640 px with 0.5 px noise and
    the house's missing observations. Principal point at the centre: the
    linear method answers and the search with it is within 0.3 % (0.9 %
    with the principal point free, found 13 px off). Principal point at
    (460, 300), 77 px off: the linear method refuses (a second null
    direction) and the search recovers f within 1.1 % with the principal
    point held at the centre, 0.4 % with it free (shared), found within
    7 px."""
    xh, P, X = load_house()
    gt = house_cameras(P)
    F = np.diag([1.0, 1.0, -1.0])  # a right-handed copy of the left-handed frame
    Xh = np.c_[X[:, :3] @ F, np.ones(len(X))]
    rng = np.random.default_rng(16)
    print("\nhouse motion, f = 640 px: principal point | linear | path | f (pp at centre) | f (pp shared) | pp found")
    for pp in ((383.5, 287.5), (460.0, 300.0)):
        K = np.array([[640.0, 0, pp[0]], [0, 640.0, pp[1]], [0, 0, 1]])
        Ps = [K @ np.c_[Rg @ F, -(Rg @ F) @ (F @ Cg)] for (_, Rg, Cg) in gt]
        x = np.stack([(Xh @ Pi.T)[:, :2] / (Xh @ Pi.T)[:, 2:] for Pi in Ps]) + rng.normal(0, 0.5, xh.shape)
        x[np.isnan(xh)] = np.nan
        r = libsfm.factorize_projective(x)
        s = libsfm.self_calibrate(r["P"], (768, 576), r["X"], tracks=x)
        t = libsfm.self_calibrate(r["P"], (768, 576), r["X"], tracks=x, principal="shared")
        print("  (%.1f, %.1f) | %d flags %d | %s | %.1f | %.1f | (%.1f, %.1f)"
              % (pp + (s["linear_status"], s["linear_flags"], s["path"], s["focal"], t["focal"], t["K"][0, 0, 2],
                       t["K"][0, 1, 2])))
        assert t["principal"] == "shared" and abs(t["focal"] / 640 - 1) < 0.02
        assert np.hypot(t["K"][0, 0, 2] - pp[0], t["K"][0, 1, 2] - pp[1]) < 20
        if pp[0] == 383.5:
            assert s["linear_status"] == 0 and abs(s["focal"] / 640 - 1) < 0.02
        else:
            assert s["linear_status"] == -5 and s["linear_flags"] & 8 and s["path"] == "sweep"
            assert abs(s["focal"] / 640 - 1) < 0.03


def views(rng, kind, m=8, n=150, f=800.0, w=640, h=480, sigma=0.5, pp=None, span=1.2):
    """Tracks (m,n,2) of a cloud 6 units in front of the cameras: kind
    "general" (random rotations and centres), "turntable" (rotation about
    the vertical axis through the cloud, optical axes through its centre),
    "translation" (no rotation), "optical_axis" (rotation about the optical
    axis with a translation in the image plane)."""
    cx, cy = ((w - 1) / 2, (h - 1) / 2) if pp is None else pp
    K = np.array([[f, 0, cx], [0, f, cy], [0, 0, 1]])
    X = np.c_[rng.uniform(-1.5, 1.5, n), rng.uniform(-1.2, 1.2, n), rng.uniform(-1.5, 1.5, n), np.ones(n)]
    Ps = []
    for i in range(m):
        if kind == "general":
            R, t = rot(rng.normal(0, 0.25, 3)), np.array([0, 0, 6.0]) + rng.normal(0, 0.5, 3)
        elif kind == "turntable":
            R, t = rot(np.array([0, span * i / (m - 1), 0])), np.array([0, 0, 6.0])
        elif kind == "translation":
            R, t = np.eye(3), np.array([0.8 * np.cos(2 * i), 0.6 * np.sin(2 * i), 6 + 0.3 * np.sin(i)])
        else:
            R, t = rot(np.array([0, 0, 0.3 * i])), np.array([0.5 * np.cos(i), 0.5 * np.sin(i), 6.0])
        Ps.append(K @ np.c_[R, t])
    x = np.stack([(X @ P.T)[:, :2] / (X @ P.T)[:, 2:] for P in Ps])
    return x + rng.normal(0, sigma, x.shape)


def test_self_calibrate_sweep_against_linear_and_truth():
    """Synthetic 8-view scenes, f = 800 px, 0.5 px noise. Where the linear
    method works, the search finds the same f (within noise); on a
    turntable the linear method refuses (a focal length per view is not
    determined by orbital motion) and the search alone is right; with the
    principal point 40 px off-centre the shared model is biased a few % and
    a principal point per view removes the bias."""
    rng = np.random.default_rng(14)
    rows = []
    print("\nm-view self-calibration, 8 views, f = 800 px, 0.5 px noise:")
    print("  scene | linear status | f linear | f sweep (held) | f from linear start | f shared | f per view median"
          " | sigma f | path | rms px")
    for kind, kw in (("general", {}), ("turntable", {}), ("pp off-centre", dict(pp=(360.0, 200.0)))):
        for trial in range(3):
            x = views(rng, "general" if kind != "turntable" else "turntable", **kw)
            r = libsfm.factorize_projective(x)
            opts = dict(principal="shared" if kind == "pp off-centre" else "centre", max_rms=1.5)
            s = libsfm.self_calibrate(r["P"], (640, 480), r["X"], tracks=x, **opts)
            lin = libsfm.self_calibrate(r["P"], (640, 480), r["X"], tracks=x, sweep="when_needed", **opts)
            rows.append((kind, s["linear_status"], s["focal_linear"], s["focal_sweep"], lin["focal"], s["focal"],
                         np.median(s["focal_view"]), s["focal_sigma"], s["path"], s["rms"]))
            print("  %s | %d | %.1f | %.1f | %.1f | %.1f | %.1f | %.4f | %s | %.3f" % rows[-1])
            ef = abs(np.median(s["focal_view"]) / 800 - 1)
            assert ef < 0.015  # measured <= 0.8 %
            if kind == "turntable":
                # the linear method refuses (it answered 558-559 px as success)
                assert s["linear_status"] == -5 and s["linear_flags"] & 8 and s["path"] == "sweep"
            else:
                assert s["linear_status"] == 0
            assert abs(s["focal_sweep"] / 800 - 1) < (0.04 if kind == "pp off-centre" else 0.015)
            # the linear start alone, refined, reaches the search's answer
            assert abs(lin["focal"] / s["focal"] - 1) < 3 * s["focal_sigma"] + 1e-9
            if kind == "pp off-centre":
                assert s["principal"] == "shared" and np.all(np.abs(s["K"][:, 0, 2] - 360) < 15)
                assert np.all(np.abs(s["K"][:, 1, 2] - 200) < 15) and s["rms"] < 0.7


def test_self_calibrate_linear_refuses_turntable_answers_general_motion():
    """The linear method alone (no tracks), 8 views, f = 800 px, factorized
    tracks: on a turntable (optical axes through the centre of the cloud,
    17-172 deg, 0.25-1 px) the strong equations leave the image of a
    sphere about that centre as free as the absolute conic, the weak focal
    prior used to choose f (558-559 px answered as success), and the answer
    must now be refused with the critical-motion flag; general motion about
    the same cloud is answered within 3 %."""
    rng = np.random.default_rng(21)
    print("\nlinear self-calibration alone, 8 views, f = 800 px: motion | sigma px | span rad | status | flags |"
          " null ratio | weak ratio | median f")
    for kind in ("turntable", "general"):
        for sigma in (0.25, 0.5, 1.0):
            for span in ((0.3, 1.2, 3.0) if kind == "turntable" else (None,)):
                for trial in range(3):
                    kw = dict(sigma=sigma) if span is None else dict(sigma=sigma, span=span)
                    x = views(rng, kind, **kw)
                    r = libsfm.factorize_projective(x)
                    if kind == "turntable":
                        with pytest.raises(libsfm.SfmError) as e:
                            libsfm.self_calibrate(r["P"], (640, 480), r["X"])
                        print("  %s | %.2f | %.1f | %d | %d | %.3f | %.2f | -" % (
                            kind, sigma, span, e.value.status, e.value.flags, e.value.null_ratio,
                            e.value.weak_ratio))
                        assert e.value.status == -5 and e.value.flags & 8
                    else:
                        s = libsfm.self_calibrate(r["P"], (640, 480), r["X"])
                        f = np.median(s["K"][:, 0, 0])
                        print("  %s | %.2f | - | 0 | %d | %.3f | %.2f | %.1f" % (
                            kind, sigma, s["flags"], s["null_ratio"], s["weak_ratio"], f))
                        assert np.all(np.abs(s["K"][:, 0, 0] / 800 - 1) < 0.03)


def test_self_calibrate_sweep_refuses_degenerate_motions():
    """Pure translation and rotation about the optical axis leave f free:
    the profile over f is flat and the answer is refused."""
    rng = np.random.default_rng(15)
    for kind in ("translation", "optical_axis"):
        for trial in range(3):
            x = views(rng, kind)
            r = libsfm.factorize_projective(x)
            with pytest.raises(libsfm.SfmError) as e:
                libsfm.self_calibrate(r["P"], (640, 480), r["X"], tracks=x)
            rep = e.value.report
            print("\n%s: refused, far rise %.2f noise variances, sigma f %.3f" % (kind, rep["profile_rise"],
                                                                                   rep["focal_sigma"]))
            assert e.value.status == -5 and rep["profile_rise"] < 10

def test_self_calibrate_table_over_noise():
    rng = np.random.default_rng(7)
    rows = []
    for sigma in (0.0, 0.25, 0.5, 1.0):
        errs, refused = [], 0
        for _ in range(10):
            x, _, _ = scene(rng, sigma=sigma)
            r = libsfm.factorize_projective(x)
            try:
                s = libsfm.self_calibrate(r["P"], (640, 480), r["X"])
            except libsfm.SfmError:
                refused += 1
                continue
            errs.append(np.median(np.abs(s["K"][:, 0, 0] / 800.0 - 1)))
        rows.append((sigma, np.median(errs) if errs else np.nan, np.max(errs) if errs else np.nan, refused))
    print("\nlinear self-calibration, 5 views, f = 800 px: sigma px | median |f err| | max | refused of 10")
    for row in rows:
        print("  %.2f | %.4f | %.4f | %d" % row)
    assert rows[0][2] < 0.01 and rows[0][3] == 0
    med = [r[1] for r in rows]
    assert med[1] < 0.05 and med[3] < 0.15
    assert med[3] >= med[0]


def test_reconstruct_three_view_pure_rotation_is_an_error():
    rng = np.random.default_rng(3)
    K = np.array([[700, 0, 319.5], [0, 700, 239.5], [0, 0, 1]])
    X = np.c_[rng.uniform(-2, 2, 100), rng.uniform(-1.5, 1.5, 100), rng.uniform(5, 9, 100)]
    xs = []
    for aa in ([0, 0, 0], [0.02, 0.15, 0], [0.1, -0.1, 0.03]):
        y = X @ (K @ rot(np.array(aa, float))).T
        xs.append(y[:, :2] / y[:, 2:] + rng.normal(0, 0.3, (100, 2)))
    with pytest.raises(libsfm.SfmError) as e:
        libsfm.reconstruct_three_view(xs[0], xs[1], xs[2], 640, 480)
    # refused by the trifocal support test, or later by the metric checks
    assert e.value.report["stage"] in ("ransac", "ba", "validate")
    with pytest.raises(ValueError):
        libsfm.reconstruct_three_view(xs[0], xs[1][:50], xs[2], 640, 480)


def herz_triplets():
    """Paths of the match triplets listed in the data set's index."""
    return [os.path.join(HERZ, "triplets", "triplet_%s_%s_%s.txt" % t) for t in herz_index()]


@pytest.mark.skipif(not herz_triplets(), reason="SKIP: ../shared/data/herzjesu-p8 not found")
def test_three_view_uncalibrated_herzjesu():
    """54 of 56 within 5 %, none wrong; the reported sigma honest against
    the known focal length (median |z| = |log(f / f_true)| / sigma about
    0.67 for an honest one; 1.32 with the profile's sigma alone)."""
    errs, z, failed, paths = [], [], 0, {}
    for path in herz_triplets():
        x = np.loadtxt(path)
        try:
            r = libsfm.reconstruct_three_view(x[:, 0:2], x[:, 2:4], x[:, 4:6], 3072, 2048, seed=1)
        except libsfm.SfmError:
            failed += 1
            continue
        errs.append(r["K"][0, 0, 0] / F_HERZ - 1)
        z.append(np.log(r["K"][0, 0, 0] / F_HERZ) / r["report"]["focal_sigma"])
        paths[r["report"]["path"]] = paths.get(r["report"]["path"], 0) + 1
    errs = np.abs(errs)
    n = len(herz_triplets())
    within = int(np.sum(errs < 0.05))
    print("\nHerz-Jesu-P8 uncalibrated three-view: %d of %d within 5 %% (%.1f %%), %d refused, %d wrong "
          "answers returned as success, median |f error| %.4f, median |z| %.2f, paths %s (BoofCV 1.2.2: 13 of 56)"
          % (within, n, 100.0 * within / n, failed, len(errs) - within, np.median(errs), np.median(np.abs(z)),
             paths))
    assert len(errs) - within == 0
    assert within >= 0.9 * n
    assert np.median(errs) < 0.01
    assert 0.4 < np.median(np.abs(z)) < 1.0


@pytest.mark.skipif(not herz_triplets(), reason="SKIP: ../shared/data/herzjesu-p8 not found")
def test_two_view_uncalibrated_herzjesu():
    """The pairs 1-2 of the 56 triplets: no wrong answer returned as success
    at the default bound (sigma <= 5/3 %), the sigma honest (median |z|
    0.63; 1.43 with the profile's sigma alone, which returned one answer
    6.6 % off at sigma 1.4 %)."""
    errs, z, failed = [], [], 0
    for path in herz_triplets():
        x = np.loadtxt(path)
        try:
            r = libsfm.reconstruct_two_view(x[:, 0:2], x[:, 2:4], 3072, 2048, seed=1)
        except libsfm.SfmError:
            failed += 1
            continue
        errs.append(abs(r["K"][0, 0, 0] / F_HERZ - 1))
        z.append(np.log(r["K"][0, 0, 0] / F_HERZ) / r["report"]["focal_sigma"])
    errs = np.array(errs)
    n = len(herz_triplets())
    within = int(np.sum(errs < 0.05))
    print("\nHerz-Jesu-P8 uncalibrated two-view (views 1, 2 of each triplet): %d of %d within 5 %%, "
          "%d refused, %d wrong answers, median |f error| %.4f, median |z| %.2f"
          % (within, n, failed, len(errs) - within, np.median(errs), np.median(np.abs(z))))
    assert within >= 0.6 * n
    assert len(errs) - within == 0
    assert 0.4 < np.median(np.abs(z)) < 1.0


@pytest.mark.skipif(not herz_triplets(), reason="SKIP: ../shared/data/herzjesu-p8 not found")
def test_three_view_fragile_triplet_does_not_depend_on_the_sweep_steps():
    """Herz-Jesu 0000-0005-0006 returned f 7.3 % off as success with 5
    bundle-adjustment steps per sweep candidate (+0.2 % with 4, 6, 7, 8,
    10): after the best fit of its first RANSAC run was refused for its
    sigma, the sweep's costlier fixed-focal answer converged to a local
    optimum whose own curvature passed the bound. Now the best fit's refusal
    ends that run, whatever the steps and with or without the priors."""
    path = os.path.join(HERZ, "triplets", "triplet_0000_0005_0006.txt")
    if not os.path.exists(path):
        pytest.skip("SKIP: %s not found" % path)
    x = np.loadtxt(path)
    for prior in (None, 0.0):
        fs = []
        for it in (3, 4, 5, 6, 7, 8, 10, 12):
            try:
                r = libsfm.reconstruct_three_view(x[:, 0:2], x[:, 2:4], x[:, 4:6], 3072, 2048, seed=1,
                                                  sweep_iterations=it, principal_sigma=prior, aspect_sigma=prior)
            except libsfm.SfmError:
                continue
            fs.append(r["K"][0, 0, 0])
            assert abs(fs[-1] / F_HERZ - 1) < 0.05, (it, prior, fs[-1])
        print("\n0000-0005-0006, sweep steps 3-12, priors %s: f %s" % (prior, np.round(fs, 1)))
        assert len(fs) >= 6 and np.ptp(np.log(fs)) < 0.01


def calib_scene(rng, nv, f=1000.0, w=1280, h=960, n=200, noise=0.5, pp_sigma=0.0, aspect_sigma=0.0):
    """nv views of a cloud of points from cameras on an arc turned towards
    jittered targets (optical axes that do not meet), principal point and
    aspect ratio drawn about the centre and 1 with the given standard
    deviations (pp_sigma of max(w, h)), Gaussian noise in pixels."""
    cx = (w - 1) / 2 + rng.normal(0, pp_sigma * max(w, h))
    cy = (h - 1) / 2 + rng.normal(0, pp_sigma * max(w, h))
    K = np.array([[f, 0, cx], [0, f * (1 + rng.normal(0, aspect_sigma)), cy], [0, 0, 1]])
    X = np.c_[rng.uniform(-2.5, 2.5, 4 * n), rng.uniform(-2, 2, 4 * n), rng.uniform(5, 10, 4 * n), np.ones(4 * n)]
    ok, xs = np.ones(len(X), bool), []
    for i in range(nv):
        a = np.radians(12) * i + rng.normal(0, np.radians(2))
        C = np.array([7 * np.sin(a), rng.normal(0, 0.8), 7.5 - 7 * np.cos(a)])
        zc = np.array([0, 0, 7.5]) + rng.normal(0, 0.8, 3) - C
        zc /= np.linalg.norm(zc)
        xc = np.cross([0, -1.0, 0], zc)
        xc /= np.linalg.norm(xc)
        R = np.array([xc, np.cross(zc, xc), zc])
        y = X @ (K @ np.c_[R, -R @ C]).T
        p = y[:, :2] / y[:, 2:]
        ok &= (y[:, 2] > 0) & (p[:, 0] > 0) & (p[:, 0] < w) & (p[:, 1] > 0) & (p[:, 1] < h)
        xs.append(p)
    idx = np.flatnonzero(ok)[:n]
    return [x[idx] + rng.normal(0, noise, (len(idx), 2)) for x in xs]


@pytest.mark.parametrize("nv", [2, 3])
@pytest.mark.parametrize("prior", [0.0, 0.01])
def test_focal_sigma_is_calibrated_on_synthetic_scenes(nv, prior):
    """z = log(f / f_true) / sigma over 60 synthetic scenes (0.5 px noise)
    must spread as a standard normal: std within [0.8, 1.25]. prior 0: the
    model exact (principal point at the centre, aspect 1) and the priors
    off, so the profile's sigma alone is tested; prior 0.01: the principal
    point drawn with 1 % of max(w, h) per axis and the aspect with 0.25 %,
    the defaults of principal_sigma and aspect_sigma that sigma includes.
    Measured: std z 1.00 / 1.14 (two / three views, exact model), 0.98 /
    1.12 (priors); the profile's sigma alone under the drawn intrinsics
    gives 1.60 / 3.67."""
    rng = np.random.default_rng(1400 + nv)
    kw = {} if prior > 0 else dict(principal_sigma=0.0, aspect_sigma=0.0)
    z = []
    for k in range(60):
        obs = calib_scene(rng, nv, pp_sigma=prior, aspect_sigma=prior / 4)
        try:
            if nv == 2:
                r = libsfm.reconstruct_two_view(obs[0], obs[1], 1280, 960, seed=k, max_focal_sigma=1.0, **kw)
            else:
                r = libsfm.reconstruct_three_view(obs[0], obs[1], obs[2], 1280, 960, seed=k, max_focal_sigma=1.0,
                                                  **kw)
        except libsfm.SfmError:
            continue
        z.append(np.log(r["K"][0, 0, 0] / 1000.0) / r["report"]["focal_sigma"])
    z = np.array(z)
    print("\n%d views, prior %.2f: %d of 60 answered, std z %.2f, median |z| %.2f, mean z %+.2f"
          % (nv, prior, len(z), z.std(ddof=1), np.median(np.abs(z)), z.mean()))
    assert len(z) >= 55
    assert 0.8 <= z.std(ddof=1) <= 1.25
    assert abs(z.mean()) < 3 / np.sqrt(len(z))


BOOF_F = dict(bobcats=1141.5, books=999.5, chicken=1128.4, minecraft_cave1=543.5, minecraft_distant=212.4,
              mono_wall=759.8, pebbles=480.9, rock_leaves=690.9, rockview=591.4, skull=1059.1,
              triflowers=460.9, turkey=603.9)


# Sony DSC-HX5V chessboard calibration (Sony_DSC-HX5V_Chess/intrinsic.yaml) of mono_wall
MONO_WALL = dict(fx=701.0116882676376, fy=698.6537946928421, cx=308.4551818095542, cy=246.84300560315452,
                 k1=-0.25559248570886445, k2=0.09997127476560613)


def boof_images(name):
    cv2 = pytest.importorskip("cv2")
    imgs = [cv2.imread(os.path.join(BOOF, "%s_%02d.jpg" % (name, k)), cv2.IMREAD_GRAYSCALE) for k in (1, 2, 3)]
    assert all(im is not None for im in imgs)
    return imgs


def radial_shift(f, k1, k2, r_px):
    """Pixels a point at r_px from the centre moves under Brown k1, k2."""
    r = r_px / f
    return f * r * (k1 * r ** 2 + k2 * r ** 4)


def check_physical(r, width, height):
    """An answer checked from its own outputs with OpenCV's projection:
    positive focal length, the inlier points in front of the three cameras
    and reprojecting at the reported RMS within the threshold, a distortion
    that does not fold the image."""
    cv2 = pytest.importorskip("cv2")
    rep, K, dist = r["report"], r["K"][0], r["dist"]
    assert K[0, 0] > 0 and rep["front_fraction"] >= 0.95
    keep = r["inliers"] & np.any(r["X"] != 0, axis=1)
    X = r["X"][keep]
    se, front = 0.0, np.ones(len(X), bool)
    for v in range(3):
        front &= (X @ r["R"][v].T + r["t"][v])[:, 2] > 0
        p, _ = cv2.projectPoints(X, cv2.Rodrigues(r["R"][v])[0], r["t"][v], K, dist)
        se += np.sum((p.reshape(-1, 2) - r["x"][v][keep]) ** 2)
    rms = np.sqrt(se / (3 * len(X)))
    assert abs(rms - rep["rms"]) < 1e-6 and rms <= 1.0
    assert front.mean() >= 0.95
    # r (1 + k1 r^2 + k2 r^4) increasing out to the image corners
    rc = np.hypot(width / 2, height / 2) / K[0, 0]
    rr = np.linspace(0, rc, 200)
    assert np.all(1 + 3 * dist[0] * rr ** 2 + 5 * dist[1] * rr ** 4 > 0)


@pytest.mark.skipif(not os.path.isdir(BOOF), reason="SKIP: ../shared/data/boofcv-triple not found")
def test_boofcv_triplets_from_images():
    """Every scene answered or refused with its reason; an answer must be
    physically valid, and mono_wall's within the 5 % that the acceptance
    bound (three standard deviations of f) promises."""
    print("\nBoofCV triplets (name: ours | BoofCV 1.2.2 shared focal)")
    answered = 0
    for name, fb in sorted(BOOF_F.items()):
        imgs = boof_images(name)
        h, w = imgs[0].shape
        try:
            r = libsfm.reconstruct_three_view_images(*imgs, seed=1)
        except libsfm.SfmError as e:
            rep = e.report
            print("  %-18s refused, %s at %s: %d triplets, %d trifocal inliers, linear flags %d, far-profile "
                  "rise %.1f, sweep f %.1f; candidate f %.1f (sigma %.3f), k1 %.3f k2 %.3f, %d inliers, RMS %.3f"
                  " | %.1f" % (name, e.name, rep["stage"], rep["n_input"], rep["ransac_inliers"], rep["linear_flags"],
                               rep["profile_rise"], rep["focal_sweep"], rep["focal"], rep["focal_sigma"], rep["k1"],
                               rep["k2"], rep["inliers"], rep["rms"], fb))
            continue
        answered += 1
        rep = r["report"]
        f = r["K"][0, 0, 0]
        print("  %-18s f %.1f (sigma %.3f), k1 %.3f k2 %.3f, %d of %d triplets, RMS %.3f px, path %s | %.1f"
              % (name, f, rep["focal_sigma"], rep["k1"], rep["k2"], rep["inliers"], rep["n_input"], rep["rms"],
                 rep["path"], fb))
        check_physical(r, w, h)
        if name == "mono_wall":
            assert abs(f / MONO_WALL["fx"] - 1) < 0.05
    print("  answered %d of %d" % (answered, len(BOOF_F)))


@pytest.mark.skipif(not os.path.isdir(BOOF), reason="SKIP: ../shared/data/boofcv-triple not found")
def test_boofcv_mono_wall_against_the_chessboard():
    """mono_wall's lens (k1 = -0.256 by the chessboard) from the images
    alone, at the default bound on the focal length's standard deviation
    (answered since the view-2 and view-3 points are aligned onto view 1's
    patches: 729.7 px, sigma 1.5 %, RMS 0.121 px; before, 762.6 px at sigma
    3.3 % and only with the bound lifted). The chessboard focal length lies
    within three of the reported standard deviations (+4.1 % at sigma 1.5
    %: no allowance for the centred principal point, which on these pixels
    does not move f toward the chessboard: 732.5 px with the chessboard's
    held, bench/mono_wall_models.py); the radial terms are kept and move
    the image corners as the chessboard's do (within 30 %); the pinhole
    model on the same triplets puts f far off and, at the default bound, is
    refused. (With the bound lifted, max_focal_sigma = 1, the pinhole
    answer, 1724 px at sigma 3.6 %, is accepted first and the radial
    cascade refitted from it stops at 783.9 px, k1 -0.237 alone, RMS 0.136
    px: a poorer fit than the default's, reached by the cascade's order.)"""
    imgs = boof_images("mono_wall")
    h, w = imgs[0].shape
    mw = MONO_WALL
    r = libsfm.reconstruct_three_view_images(*imgs, seed=1)
    rep = r["report"]
    f, k1, k2 = r["K"][0, 0, 0], rep["k1"], rep["k2"]
    corner = np.hypot(w / 2, h / 2)
    s_ours, s_cb = radial_shift(f, k1, k2, corner), radial_shift(mw["fx"], mw["k1"], mw["k2"], corner)
    print("\nmono_wall: f %.1f px (%+.1f %% against the chessboard %.1f, sigma %.1f %%), k1 %.3f k2 %.3f "
          "(chessboard %.3f %.3f), corner shift %.1f px (chessboard %.1f), rises %s, %d inliers, RMS %.3f px"
          % (f, 100 * (f / mw["fx"] - 1), mw["fx"], 100 * rep["focal_sigma"], k1, k2, mw["k1"], mw["k2"],
             s_ours, s_cb, np.round(rep["radial_rise"], 1), rep["inliers"], rep["rms"]))
    check_physical(r, w, h)
    assert abs(np.log(f / mw["fx"])) < 3 * rep["focal_sigma"]
    assert max(rep["radial_rise"]) > 9 and k1 < 0
    assert abs(s_ours / s_cb - 1) < 0.3
    try:
        p = libsfm.reconstruct_three_view_images(*imgs, seed=1, max_focal_sigma=1.0, radial=0)
        fp = p["K"][0, 0, 0]
        print("  pinhole model: f %.1f px (sigma %.1f %%)" % (fp, 100 * p["report"]["focal_sigma"]))
        assert abs(fp / mw["fx"] - 1) > 0.3
    except libsfm.SfmError as e:
        print("  pinhole model: refused (%s at %s)" % (e.name, e.report["stage"]))
    with pytest.raises(libsfm.SfmError):
        libsfm.reconstruct_three_view_images(*imgs, seed=1, radial=0)


@pytest.mark.skipif(not os.path.isdir(BOOF), reason="SKIP: ../shared/data/boofcv-triple not found")
def test_boofcv_mono_wall_geometry_synthetic_lens():
    """The focal length's reported standard deviation against its spread:
    mono_wall's cameras and points (as reconstructed) seen through a known
    lens of the model the pipeline assumes (f 701, principal point at the
    centre, the chessboard's k1 and k2), 0.4 px noise, eight draws. The
    mean lands within three standard errors of the truth and the spread
    of log f within a factor two of the median reported sigma."""
    cv2 = pytest.importorskip("cv2")
    imgs = boof_images("mono_wall")
    h, w = imgs[0].shape
    g = libsfm.reconstruct_three_view_images(*imgs, seed=1, max_focal_sigma=1.0)
    keep = g["inliers"] & np.any(g["X"] != 0, axis=1)
    X = g["X"][keep]
    K = np.array([[701.0, 0, (w - 1) / 2], [0, 701.0, (h - 1) / 2], [0, 0, 1]])
    dist = np.array([MONO_WALL["k1"], MONO_WALL["k2"], 0, 0, 0])
    rng = np.random.default_rng(2018)
    logf, sig = [], []
    for _ in range(8):
        obs = [cv2.projectPoints(X, cv2.Rodrigues(g["R"][v])[0], g["t"][v], K, dist)[0].reshape(-1, 2)
               + rng.normal(0, 0.4, (len(X), 2)) for v in range(3)]
        r = libsfm.reconstruct_three_view(obs[0], obs[1], obs[2], w, h, seed=1, max_focal_sigma=1.0)
        logf.append(np.log(r["K"][0, 0, 0] / 701.0))
        sig.append(r["report"]["focal_sigma"])
    logf, s_med = np.array(logf), np.median(sig)
    print("\nmono_wall geometry, synthetic lens: f %s px, mean %+.2f %%, spread %.2f %% against the "
          "reported sigma %.2f %% (median)" % (np.round(701 * np.exp(logf), 1), 100 * logf.mean(),
                                               100 * logf.std(ddof=1), 100 * s_med))
    assert abs(logf.mean()) < 3 * s_med / np.sqrt(len(logf))
    assert 0.5 * s_med < logf.std(ddof=1) < 2 * s_med


def view3_shear_refit(r, xs, width, height, step=1e-3, rounds=3):
    """An answer's metric bundle adjustment (Huber at 2 px, poses, points,
    f and its radial terms free, as in the metric stage) with view 3's
    pixels sheared, x <- x - s (y - c_y), s profiled by parabolic steps:
    the first-order effect of a rolling shutter whose row-to-row image
    motion differs between the frames (view 1 the reference). Returns
    (f, s, cost rise of s = 0 over the best s in noise variances at the
    0.2 px per-observation floor of the focal sigma)."""
    keep = r["inliers"] & np.any(r["X"] != 0, axis=1)
    idx = np.nonzero(keep)[0]
    obs = np.array([[v, j, xs[v][i, 0], xs[v][i, 1]] for v in range(3) for j, i in enumerate(idx)])
    cx, cy = (width - 1) / 2, (height - 1) / 2
    f0, k1, k2 = r["K"][0, 0, 0], r["report"]["k1"], r["report"]["k2"]
    v3 = obs[:, 0] == 2

    def fit(sh):
        o = obs.copy()
        o[v3, 2] -= sh * (o[v3, 3] - cy)
        cams = dict(rotations=r["R"].copy(), translations=r["t"].copy(),
                    intrinsics=np.tile([f0, f0, cx, cy, k1, k2], (3, 1)))
        q = libsfm.bundle_adjust(cams, r["X"][keep].copy(), o,
                                 dict(intrinsics="shared", refine=["focal", "radial"], loss="huber", loss_scale=2.0,
                                      scale_gauge="distance", scale_camera=1, scale_distance=1.0,
                                      max_iterations=200))
        return q["cost"], q["cameras"]["intrinsics"][0, 0]

    c0, _ = fit(0.0)
    sh = 0.0
    for it in range(rounds):
        h = step / (1 + it)
        c = [fit(sh + d)[0] for d in (-h, 0.0, h)]
        den = c[0] - 2 * c[1] + c[2]
        if den > 0:
            sh += float(np.clip(0.5 * h * (c[0] - c[2]) / den, -4 * h, 4 * h))
    cs, f = fit(sh)
    return f, sh, 2 * (c0 - cs) / 0.2 ** 2


@pytest.mark.skipif(not os.path.isdir(BOOF), reason="SKIP: ../shared/data/boofcv-triple not found")
def test_boofcv_mono_wall_view3_shear():
    """A term the model lacks, measured against the chessboard: a shear of
    view 3 against view 1 (x <- x - s (y - c_y), the first-order image of a
    rolling shutter whose row-to-row motion differs between frames;
    mono_wall's JPEGs are video frames, they carry libavcodec's tag) lowers
    the cost of mono_wall's answer by far more than the 9 noise variances
    at which the metric stage keeps a term, and with it f is within 3 % of
    the chessboard (713 px, +1.7 %), where the principal point, the aspect
    and the tangential terms leave it at 728-734 px
    (bench/mono_wall_models.py). The same refit on mono_wall's geometry
    through the chessboard's whole model (principal point off the centre,
    fy / fx 0.997, k1, k2), 0.12 px noise: without a shear the term is not
    significant in any draw (it would lower f there, -1.5 %: a term to
    keep only when significant), and with the measured shear added to view
    3 the pipeline's f is biased by more than 3 % and the refit's lands
    within 3 % of the truth. Not in the pipeline: the term is as
    significant on still photographs (rockview, turkey: see
    bench/README.md), so what it stands for is not settled."""
    cv2 = pytest.importorskip("cv2")
    imgs = boof_images("mono_wall")
    h, w = imgs[0].shape
    r = libsfm.reconstruct_three_view_images(*imgs, seed=1)
    f, sh, rise = view3_shear_refit(r, r["x"], w, h)
    print("\nmono_wall: f %.1f px, with view 3 sheared by %+.5f: %.1f px (%+.2f %%), rise %.1f"
          % (r["K"][0, 0, 0], sh, f, 100 * (f / MONO_WALL["fx"] - 1), rise))
    assert rise > 9 and abs(f / MONO_WALL["fx"] - 1) < 0.03
    g = libsfm.reconstruct_three_view_images(*imgs, seed=1, max_focal_sigma=1.0)
    keep = g["inliers"] & np.any(g["X"] != 0, axis=1)
    X = g["X"][keep]
    mw = MONO_WALL
    K = np.array([[mw["fx"], 0, mw["cx"]], [0, mw["fy"], mw["cy"]], [0, 0, 1]])
    dist = np.array([mw["k1"], mw["k2"], 0, 0, 0])
    rng = np.random.default_rng(2019)
    for s_true in (0.0, sh):
        fa, fr, rises = [], [], []
        for _ in range(6):
            obs = [cv2.projectPoints(X, cv2.Rodrigues(g["R"][v])[0], g["t"][v], K, dist)[0].reshape(-1, 2)
                   + rng.normal(0, 0.12, (len(X), 2)) for v in range(3)]
            obs[2][:, 0] += s_true * (obs[2][:, 1] - (h - 1) / 2)
            q = libsfm.reconstruct_three_view(obs[0], obs[1], obs[2], w, h, seed=1, max_focal_sigma=1.0)
            f_s, _, rise_s = view3_shear_refit(q, obs, w, h)
            fa.append(q["K"][0, 0, 0])
            fr.append(f_s)
            rises.append(rise_s)
        la, lr = np.log(np.array(fa) / mw["fx"]), np.log(np.array(fr) / mw["fx"])
        print("  synthetic, view-3 shear %+.5f: pipeline mean %+.2f %%, refit mean %+.2f %%, rises %s"
              % (s_true, 100 * la.mean(), 100 * lr.mean(), np.round(rises, 1)))
        if s_true == 0:
            assert max(rises) < 9
        else:
            assert min(rises) > 9 and la.mean() > 0.03 and abs(lr.mean()) < 0.03


@pytest.mark.skipif(not herz_triplets(), reason="SKIP: ../shared/data/herzjesu-p8 not found")
def test_three_view_uncalibrated_is_deterministic_and_reports():
    x = np.loadtxt(herz_triplets()[7])
    a = libsfm.reconstruct_three_view(x[:, 0:2], x[:, 2:4], x[:, 4:6], 3072, 2048, seed=5)
    b = libsfm.reconstruct_three_view(x[:, 0:2], x[:, 2:4], x[:, 4:6], 3072, 2048, seed=5)
    assert np.array_equal(a["K"], b["K"]) and np.array_equal(a["R"], b["R"]) and np.array_equal(a["X"], b["X"])
    rep = a["report"]
    assert rep["stage"] == "done" and rep["path"] in ("linear", "sweep")
    assert rep["inliers"] == int(a["inliers"].sum()) and rep["rms"] < 1.0
    assert np.allclose(a["R"][0], np.eye(3)) and abs(np.linalg.norm(a["t"][1]) - 1) < 1e-9
    # points in front of the three cameras, reprojecting at the reported RMS
    K = a["K"][0]
    se = 0.0
    for v in range(3):
        Y = a["X"][a["inliers"]] @ a["R"][v].T + a["t"][v]
        assert np.all(Y[:, 2] > 0)
        p = Y @ K.T
        se += np.sum((p[:, :2] / p[:, 2:] - x[a["inliers"], 2 * v:2 * v + 2]) ** 2)
    assert abs(np.sqrt(se / (3 * a["inliers"].sum())) - rep["rms"]) < 1e-6


@pytest.mark.skipif(not herz_triplets(), reason="SKIP: ../shared/data/herzjesu-p8 not found")
def test_three_view_uncalibrated_per_view_focal_herzjesu():
    x = np.loadtxt(herz_triplets()[7])
    r = libsfm.reconstruct_three_view(x[:, 0:2], x[:, 2:4], x[:, 4:6], 3072, 2048, seed=1, per_view_focal=True)
    f = r["K"][:, 0, 0]
    print("\nHerz-Jesu-P8 per-view focal lengths:", np.round(f, 1), "(true %.1f)" % F_HERZ)
    assert np.allclose(f, r["report"]["focal_view"])
    assert np.all(np.abs(f / F_HERZ - 1) < 0.05)


SYN = os.path.join(os.path.dirname(__file__), "..", "..", "build", "demo", "synthetic")


@pytest.mark.skipif(not os.path.exists(os.path.join(SYN, "ground_truth.txt")),
                    reason="SKIP: build/demo/synthetic not rendered (make demo)")
def test_reconstruct_three_view_images_on_the_rendered_room():
    """The demo room (tools/gen_demo_scene.py, fx = fy = 500 at 640x480)."""
    cv2 = pytest.importorskip("cv2")
    files = sorted(f for f in os.listdir(SYN) if f.endswith(".pgm"))[:3]
    imgs = [cv2.imread(os.path.join(SYN, f), cv2.IMREAD_GRAYSCALE) for f in files]
    r = libsfm.reconstruct_three_view_images(*imgs, seed=1)
    f = r["K"][0, 0, 0]
    print("\nrendered room from images: f %.1f px (true 500), %d of %d triplets, RMS %.3f px"
          % (f, r["report"]["inliers"], r["x"].shape[1], r["report"]["rms"]))
    assert abs(f / 500.0 - 1) < 0.05
    assert r["x"].shape[0] == 3 and r["inliers"].shape[0] == r["x"].shape[1]


SEQ = os.path.join(os.path.dirname(__file__), "..", "..", "build", "demo", "sequence")


@pytest.mark.skipif(not os.path.exists(os.path.join(SEQ, "ground_truth.txt")),
                    reason="SKIP: build/demo/sequence not rendered (make demo-vo)")
def test_focal_sigma_is_honest_on_aligned_points_of_the_rendered_loop():
    """Frames i, i+8, i+16 (i = 0, 20, ..., 220) of the rendered demo loop
    (tools/gen_demo_scene.py --sequence: fx = fy = 500 px, principal point
    at the centre, no distortion: the model exact), from images with the
    points aligned. With the priors off the reported sigma is the noise's
    alone, and z = log(f / 500) / sigma should spread as a standard normal;
    before the sigma assumed a floor on the per-observation error it had
    RMS 2.32 here (three beyond 3 sigma: the aligned points' residuals,
    0.07-0.14 px, miss their systematic part), 1.06 with it. With the
    default priors (which add variance the exact model does not have) z
    is smaller still. Every answer within 3 %, none beyond 3 sigma."""
    cv2 = pytest.importorskip("cv2")
    gt = open(os.path.join(SEQ, "ground_truth.txt")).read()
    assert "camera 1 500 500 319.5 239.5" in gt
    files = sorted(f for f in os.listdir(SEQ) if f.endswith(".pgm"))
    z, zd, errs = [], [], []
    for i in range(0, 221, 20):
        imgs = [cv2.imread(os.path.join(SEQ, files[i + d]), cv2.IMREAD_GRAYSCALE) for d in (0, 8, 16)]
        for prior, zs in ((0.0, z), (None, zd)):
            try:
                r = libsfm.reconstruct_three_view_images(*imgs, seed=1, principal_sigma=prior, aspect_sigma=prior)
            except libsfm.SfmError:
                continue
            f, s = r["K"][0, 0, 0], r["report"]["focal_sigma"]
            zs.append(np.log(f / 500.0) / s)
            errs.append(f / 500.0 - 1)
    z, zd, errs = np.array(z), np.array(zd), np.array(errs)
    print("\nrendered loop, aligned: priors off %d of 12 answered, z RMS %.2f (max |z| %.2f); default priors %d "
          "answered, z RMS %.2f; errors %+.2f..%+.2f %%" % (len(z), np.sqrt(np.mean(z ** 2)), np.max(np.abs(z)),
                                                          len(zd), np.sqrt(np.mean(zd ** 2)), 100 * errs.min(),
                                                          100 * errs.max()))
    assert len(z) >= 8 and len(zd) >= 6
    assert np.all(np.abs(errs) < 0.03)
    assert np.max(np.abs(z)) < 3 and np.max(np.abs(zd)) < 3
    assert 0.6 < np.sqrt(np.mean(z ** 2)) < 1.6
    assert np.sqrt(np.mean(zd ** 2)) < 1.6
