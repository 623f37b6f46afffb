"""mono_wall against its chessboard: which assumption of the camera model
moves the focal length. The pipeline's answer from the images (seed 1,
default options) is refitted by a metric bundle adjustment (Huber at 2 px,
the metric stage's loss; poses, points, f and the radial terms free) under
one changed assumption at a time; per row the cost rise against the
answer's refit in noise variances (white noise at the answer's residual,
and at the 0.2 px floor the focal sigma assumes), and f against the
chessboard's fx 701.0. A per-view shear x <- x - s_v (y - c_y) (views 2
and 3, view 1 the reference) is profiled by parabolic coordinate steps.

--synthetic N: the same refits on N noise draws of mono_wall's geometry
seen through the chessboard's whole model (principal point (308.5, 246.8),
fy / fx 0.997, k1, k2; --noise px): the bias the centred model leaves and
what each refit removes. --herzjesu: the shear rise on the Herz-Jesu-P8
triplets (still images, ground truth f 2760 px).
Figures: bench/README.md ("mono_wall against its chessboard").
--warp: the features' own shear, on images warped by a known rotation.
Usage: PYTHONPATH=python python bench/mono_wall_models.py [--synthetic 32 --noise 0.12 [--shear3 0.0019]]
       [--herzjesu] [--scene rockview] [--no-align] [--features 10000] [--warp]"""
import argparse
import os
import sys

HERE = os.path.dirname(os.path.abspath(__file__))
sys.path.insert(0, os.path.join(HERE, "..", "tests", "python"))
sys.path.insert(0, os.path.join(HERE, "..", "python"))
import numpy as np  # noqa: E402

import libsfm  # noqa: E402
from test_recon import MONO_WALL as CB, boof_images, herz_triplets  # noqa: E402

FLOOR = 0.2  # px, FOCAL_NOISE_FLOOR of libsfm/recon/metric_upgrade.c


def inlier_obs(r, xs):
    keep = r["inliers"] & np.any(r["X"] != 0, axis=1)
    idx = np.nonzero(keep)[0]
    obs = np.array([[v, j, xs[v][i, 0], xs[v][i, 1]] for v in range(3) for j, i in enumerate(idx)])
    return r["X"][keep], obs


def refit(r, X, obs, intr, refine, shear=(0.0, 0.0, 0.0), cy=None, models=None):
    o = obs.copy()
    for v in range(3):
        s = o[:, 0] == v
        o[s, 2] -= shear[v] * (o[s, 3] - cy)
    cams = dict(rotations=r["R"].copy(), translations=r["t"].copy())
    if models is not None:
        cams["models"] = models
    else:
        cams["intrinsics"] = np.tile(np.array(intr, float), (3, 1))
    opt = dict(intrinsics="shared" if refine else "fixed", refine=refine, loss="huber", loss_scale=2.0,
               scale_gauge="distance", scale_camera=1, scale_distance=1.0, max_iterations=200)
    q = libsfm.bundle_adjust(cams, X.copy(), o, opt)
    if models is not None:
        m = q["cameras"]["models"][0]
        return q["cost"], np.array([m.fx, m.fy, m.cx, m.cy] + list(m.dist))
    return q["cost"], q["cameras"]["intrinsics"][0]


def fit_shear(fn, views=(1, 2), step=1e-3, rounds=4):
    """Minimum of fn(shear) over the shears of `views`: Newton steps on a
    quadratic through the cost at the current shears and at +-step along
    each and along their sum (a valley runs along a shear shared by the
    views, which coordinate steps cross slowly)."""
    s = np.zeros(3)
    vs = list(views)
    k = len(vs)
    for it in range(rounds):
        h = step / (1 + it)
        c0 = fn(s)[0]
        g, H = np.zeros(k), np.zeros((k, k))
        cp = []
        for a, v in enumerate(vs):
            t = s.copy(); t[v] += h
            u = s.copy(); u[v] -= h
            ca, cb = fn(t)[0], fn(u)[0]
            cp.append(ca)
            g[a] = (ca - cb) / (2 * h)
            H[a, a] = (ca - 2 * c0 + cb) / h ** 2
        for a in range(k):
            for b in range(a + 1, k):
                t = s.copy(); t[vs[a]] += h; t[vs[b]] += h
                H[a, b] = H[b, a] = (fn(t)[0] - cp[a] - cp[b] + c0) / h ** 2
        if np.all(np.linalg.eigvalsh(H) > 0):
            d = -np.linalg.solve(H, g)
        else:
            d = -g / max(np.abs(np.diag(H)).max(), 1e-12)
        d = np.clip(d, -4 * h, 4 * h)
        for _ in range(4):  # halved until the cost falls
            t = s.copy()
            for a, v in enumerate(vs):
                t[v] += d[a]
            if fn(t)[0] < c0:
                s = t
                break
            d = d / 2
    return s, fn(s)


def real(w, h, r, xs):
    cx, cy = (w - 1) / 2, (h - 1) / 2
    X, obs = inlier_obs(r, xs)
    f0, k1, k2 = r["K"][0, 0, 0], r["report"]["k1"], r["report"]["k2"]
    c0, _ = refit(r, X, obs, [f0, f0, cx, cy, k1, k2], ["focal", "radial"], cy=cy)
    n = len(X)
    s2 = 2 * c0 / (6 * n - 3 * n - 6)
    print("answer: f %.1f (%+.2f %%), sigma %.2f %%, k1 %.3f k2 %.3f, %d points, residual %.3f px"
          % (f0, 100 * (f0 / CB["fx"] - 1), 100 * r["report"]["focal_sigma"], k1, k2, n, np.sqrt(s2)))
    print("%-44s %9s %9s %8s %8s %7s %7s %7s %7s" % ("refit", "rise", "rise@0.2", "f", "vs 701", "cx", "cy",
                                                      "k1", "k2"))

    def row(label, c, I):
        print("%-44s %9.1f %9.1f %8.1f %+7.2f%% %7.1f %7.1f %7.3f %7.3f"
              % (label, 2 * (c - c0) / s2, 2 * (c - c0) / FLOOR ** 2, I[0], 100 * (I[0] / CB["fx"] - 1), I[2], I[3],
                 I[4], I[5]))

    cb = [CB["fx"], CB["fy"], CB["cx"], CB["cy"], CB["k1"], CB["k2"]]
    asp = CB["fy"] / CB["fx"]
    rows = [("answer (centre, unit aspect)", [f0, f0, cx, cy, k1, k2], ["focal", "radial"]),
            ("principal point free (no prior)", [f0, f0, cx, cy, k1, k2], ["focal", "radial", "principal"]),
            ("chessboard principal point held", [f0, f0, CB["cx"], CB["cy"], k1, k2], ["focal", "radial"]),
            ("chessboard principal point and aspect held", [f0, f0 * asp, CB["cx"], CB["cy"], k1, k2],
             ["focal", "radial"]),
            ("chessboard aspect held", [f0, f0 * asp, cx, cy, k1, k2], ["focal", "radial"]),
            ("k2 held at the chessboard's 0.100", [f0, f0, cx, cy, k1, CB["k2"]], ["focal", "k1"]),
            ("k2 held at 0", [f0, f0, cx, cy, k1, 0.0], ["focal", "k1"]),
            ("f held at 701", [701.0, 701.0, cx, cy, k1, k2], ["radial"]),
            ("chessboard k1, k2 held", [f0, f0, cx, cy, CB["k1"], CB["k2"]], ["focal"]),
            ("chessboard intrinsics held", cb, [])]
    for label, intr, ref in rows:
        row(label, *refit(r, X, obs, intr, ref, cy=cy))
    cam = libsfm.Camera("brown", f0, f0, cx, cy, (k1, k2, 0, 0, 0))
    c, I = refit(r, X, obs, None, ["focal", "distortion"], cy=cy, models=[cam] * 3)
    row("Brown k1 k2 p1 p2 k3 (p1 %+.4f p2 %+.4f k3 %+.3f)" % (I[6], I[7], I[8]), c, I)
    for views, label in (((2,), "view 3"), ((1, 2), "views 2, 3")):
        s, (c, I) = fit_shear(lambda t: refit(r, X, obs, [f0, f0, cx, cy, k1, k2], ["focal", "radial"], t, cy),
                              views)
        row("shear of %s (%+.5f, %+.5f)" % (label, s[1], s[2]), c, I)
    s, (c, I) = fit_shear(lambda t: refit(r, X, obs, [f0, f0, cx, cy, k1, k2], ["focal", "radial", "principal"],
                                          t, cy))
    row("shear of views 2, 3 and principal point free", c, I)
    s, (c, I) = fit_shear(lambda t: refit(r, X, obs, [f0, f0 * asp, CB["cx"], CB["cy"], k1, k2],
                                          ["focal", "radial"], t, cy))
    row("shear of views 2, 3, chessboard pp and aspect", c, I)


def chessboard_views(g, h, rng, noise, shears=(0.0, 0.0, 0.0)):
    """The inlier points of answer g seen by its cameras through the
    chessboard's whole model (its fx, fy, principal point, k1, k2), with
    Gaussian noise and each view v's x moved by shears[v] (y - c_y), c_y
    the centre row of an image h rows high: (n, 2) pixels per view."""
    cv2 = __import__("cv2")
    keep = g["inliers"] & np.any(g["X"] != 0, axis=1)
    X = g["X"][keep]
    K = np.array([[CB["fx"], 0, CB["cx"]], [0, CB["fy"], CB["cy"]], [0, 0, 1]])
    D = np.array([CB["k1"], CB["k2"], 0, 0, 0])
    xs = [cv2.projectPoints(X, cv2.Rodrigues(g["R"][v])[0], g["t"][v], K, D)[0].reshape(-1, 2)
          + rng.normal(0, noise, (len(X), 2)) for v in range(3)]
    for v in range(3):
        xs[v][:, 0] += shears[v] * (xs[v][:, 1] - (h - 1) / 2)
    return xs


def synthetic(w, h, g, draws, noise, shear3=0.0):
    cx, cy = (w - 1) / 2, (h - 1) / 2
    rng = np.random.default_rng(2018)
    out = []
    for _ in range(draws):
        xs = chessboard_views(g, h, rng, noise, (0.0, 0.0, shear3))
        try:
            q = libsfm.reconstruct_three_view(*xs, w, h, seed=1, max_focal_sigma=1.0)
        except libsfm.SfmError:
            continue
        f, k1, k2 = q["K"][0, 0, 0], q["report"]["k1"], q["report"]["k2"]
        Xq, obs = inlier_obs(q, xs)
        c0, _ = refit(q, Xq, obs, [f, f, cx, cy, k1, k2], ["focal", "radial"], cy=cy)
        _, Ip = refit(q, Xq, obs, [f, f, cx, cy, k1, k2], ["focal", "radial", "principal"], cy=cy)
        _, It = refit(q, Xq, obs, [f, f, CB["cx"], CB["cy"], k1, k2], ["focal", "radial"], cy=cy)
        s, (cs, Is) = fit_shear(lambda t: refit(q, Xq, obs, [f, f, cx, cy, k1, k2], ["focal", "radial"], t, cy))
        asp = CB["fy"] / CB["fx"]
        _, (_, Ist) = fit_shear(lambda t: refit(q, Xq, obs, [f, f * asp, CB["cx"], CB["cy"], k1, k2],
                                                ["focal", "radial"], t, cy))
        n = len(Xq)
        s2 = max(2 * c0 / (3 * n - 6), FLOOR ** 2)
        out.append((f, Ip[0], Ip[2], Ip[3], It[0], Is[0], 2 * (c0 - cs) / s2, q["report"]["focal_sigma"], Ist[0]))
    a = np.array(out)
    lf = np.log(a[:, [0, 1, 4, 5, 8]] / CB["fx"])
    print("synthetic: mono_wall's geometry, the chessboard's model, %.2f px, view-3 shear %g, %d of %d answered"
          % (noise, shear3, len(a), draws))
    for k, label in enumerate(("centred answer", "principal point free", "chessboard pp held",
                               "shear of views 2, 3 free", "shear, chessboard pp, aspect")):
        print("  %-24s mean f %.1f (%+.2f %% +- %.2f), spread %.2f %%"
              % (label, CB["fx"] * np.exp(lf[:, k].mean()), 100 * lf[:, k].mean(),
                 100 * lf[:, k].std(ddof=1) / np.sqrt(len(a)), 100 * lf[:, k].std(ddof=1)))
    print("  principal point free: mean (%.1f, %.1f), spread (%.1f, %.1f) px; reported sigma median %.2f %%"
          % (a[:, 2].mean(), a[:, 3].mean(), a[:, 2].std(ddof=1), a[:, 3].std(ddof=1), 100 * np.median(a[:, 7])))
    print("  shear's rise (2 terms, at >= 0.2 px): median %.1f, max %.1f" % (np.median(a[:, 6]), a[:, 6].max()))


def herzjesu():
    rises, moves = [], []
    for path in herz_triplets():
        x = np.loadtxt(path)
        xs = [x[:, 0:2], x[:, 2:4], x[:, 4:6]]
        try:
            r = libsfm.reconstruct_three_view(*xs, 3072, 2048, seed=1)
        except libsfm.SfmError:
            continue
        cx, cy = 3071 / 2, 2047 / 2
        f, k1, k2 = r["K"][0, 0, 0], r["report"]["k1"], r["report"]["k2"]
        X, obs = inlier_obs(r, xs)
        ref = ["focal"] + (["radial"] if k2 != 0 else ["k1"] if k1 != 0 else [])
        c0, _ = refit(r, X, obs, [f, f, cx, cy, k1, k2], ref, cy=cy)
        s, (cs, I) = fit_shear(lambda t: refit(r, X, obs, [f, f, cx, cy, k1, k2], ref, t, cy), step=2e-5)
        n = len(X)
        s2 = max(2 * c0 / (3 * n - 6), FLOOR ** 2)
        rises.append(2 * (c0 - cs) / s2)
        moves.append(100 * np.log(I[0] / f))
        print("  %s f %.1f -> %.1f (%+.2f %%), shear (%+.5f, %+.5f), rise %.1f"
              % (os.path.basename(path), f, I[0], moves[-1], s[1], s[2], rises[-1]))
    print("Herz-Jesu-P8: %d answered, shear rise median %.1f, above 9: %d; |f move| median %.2f %%, max %.2f %%"
          % (len(rises), np.median(rises), int(np.sum(np.array(rises) > 9)), np.median(np.abs(moves)),
             np.max(np.abs(moves))))


def warp_bias(scenes=("mono_wall", "rockview", "turkey")):
    """Whether the features themselves shear: view 1 of a scene warped by a
    known rotation about the centre (no shear; Lanczos), detected, matched
    and aligned as reconstruct_three_view_images does, and the error against
    the warp fitted as an affine function of the position: e_x = a + b x +
    c y, e_y likewise (the y-slope of e_x is what a view's shear would
    show)."""
    cv2 = __import__("cv2")
    from libsfm.features import align_points, detect_and_describe, match
    for sc in scenes:
        a = boof_images(sc)[0]
        h, w = a.shape
        C = np.array([[1, 0, (w - 1) / 2], [0, 1, (h - 1) / 2], [0, 0, 1]])
        for rot in (2.0, 5.0):
            c, s = np.cos(np.radians(rot)), np.sin(np.radians(rot))
            H = C @ np.array([[c, -s, 0.3], [s, c, -0.2], [0, 0, 1]]) @ np.linalg.inv(C)
            b = cv2.warpPerspective(a, H, (w, h), flags=cv2.INTER_LANCZOS4)
            fa, da = detect_and_describe(a, max_features=5000)
            fb, db = detect_and_describe(b, max_features=5000)
            m = match(da, db)
            pa, pb = fa[m[:, 0], :2].astype(float), fb[m[:, 1], :2].astype(float)
            pb2, ok = align_points(a, pa, b, pb)
            ph = cv2.perspectiveTransform(pa.reshape(-1, 1, 2), H).reshape(-1, 2)
            e = pb2 - ph
            g = ok & (np.hypot(e[:, 0], e[:, 1]) < 2)
            A = np.c_[np.ones(g.sum()), ph[g, 0] - (w - 1) / 2, ph[g, 1] - (h - 1) / 2]
            ex = np.linalg.lstsq(A, e[g, 0], rcond=None)[0]
            ey = np.linalg.lstsq(A, e[g, 1], rcond=None)[0]
            print("%-10s rotated %.0f deg: %d aligned, RMS %.3f px; e_x y-slope %+.5f, x-slope %+.5f; e_y y-slope "
                  "%+.5f" % (sc, rot, g.sum(), np.sqrt((e[g] ** 2).sum(1).mean()), ex[2], ex[1], ey[2]))


def main():
    ap = argparse.ArgumentParser()
    ap.add_argument("--synthetic", type=int, default=0)
    ap.add_argument("--noise", type=float, default=0.12)
    ap.add_argument("--shear3", type=float, default=0.0, help="view-3 shear added to the synthetic pixels")
    ap.add_argument("--herzjesu", action="store_true")
    ap.add_argument("--features", type=int, default=5000)
    ap.add_argument("--seed", type=int, default=1)
    ap.add_argument("--no-align", action="store_true", help="the detector's positions (max_focal_sigma 1)")
    ap.add_argument("--scene", default="mono_wall", help="another BoofCV triplet (the chessboard column then "
                    "means nothing): the shear's rise there")
    ap.add_argument("--warp", action="store_true", help="the features' own shear on warped images")
    a = ap.parse_args()
    if a.warp:
        warp_bias()
        return
    if a.herzjesu:
        herzjesu()
        return
    imgs = boof_images(a.scene)
    h, w = imgs[0].shape
    r = libsfm.reconstruct_three_view_images(*imgs, seed=a.seed, max_features=a.features, align=not a.no_align,
                                             **(dict(max_focal_sigma=1.0) if a.no_align else {}))
    if a.synthetic:
        g = libsfm.reconstruct_three_view_images(*imgs, seed=1, max_focal_sigma=1.0)
        synthetic(w, h, g, a.synthetic, a.noise, a.shear3)
    else:
        real(w, h, r, r["x"])


if __name__ == "__main__":
    main()
