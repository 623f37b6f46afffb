"""Three uncalibrated images to a dense point cloud: the last stage of the
three-view pipeline.

    python -m libsfm.stereo_demo IMG1 IMG2 IMG3 --out DIR [--seed N] [--scale S]

1. Self-calibrated metric cameras and sparse points from the three images
   (libsfm.reconstruct_three_view_images: features, cyclic association,
   trifocal RANSAC, absolute-dual-quadric self-calibration, metric BA with
   the focal length and the radial distortion; the rectification below
   goes through that distortion).
2. The best-conditioned pair: of the three, the one whose baseline is
   longest against the scene's depth among those a planar rectification
   exists for (baseline far from the viewing direction).
3. Rectification (sfm_stereo_rectify), remap, semi-global matching over the
   disparity range the sparse points span, disparity to points.
4. DIR/dense.ply (x y z r g b, camera i's frame of the chosen pair i-j, in
   the reconstruction's scale: |t2| = 1 as the pipeline returns it) and
   DIR/disparity.png (8-bit, 0 = invalid).

Exit status 1 with the library's status named when a stage fails, 2 on bad
usage. The function form is stereo_from_three_views(img1, img2, img3).
"""
import argparse
import os
import sys
import time

import numpy as np

from . import recon, stereo
from ._ffi import SfmError

PAIRS = ((0, 1), (0, 2), (1, 2))


def _relative(R, t, i, j):
    """Pose of camera j in camera i's frame: x_j = R x_i + t."""
    Rr = R[j] @ R[i].T
    return Rr, t[j] - Rr @ t[i]


def choose_pair(K, R, t, X, size, dist=None):
    """The pair (i, j) with the largest baseline over median depth that can
    be rectified, and its rectification (through the lens distortion dist,
    an OpenCV vector shared by the views, or None); raises SfmError when
    none can."""
    best = None
    last = None
    for i, j in PAIRS:
        Rr, tr = _relative(R, t, i, j)
        B = np.linalg.norm(Rr.T @ tr)
        depth = np.median((R[i] @ X.T).T[:, 2] + t[i][2])
        score = B / depth if depth > 0 else 0.0
        if best is not None and score <= best[0]:
            continue
        try:
            rect = stereo.rectify_pair(K[i], K[j], Rr, tr, size, dist1=dist, dist2=dist)
        except SfmError as e:
            last = e
            continue
        best = (score, i, j, rect)
    if best is None:
        raise last or SfmError(-5, "no rectifiable pair")
    return best


def stereo_from_three_views(img1, img2, img3, seed=0, max_disparities=256, color=None):
    """Dense points from three uncalibrated images (uint8, gray or RGB, one
    size). Returns dict(points (n,3) in camera i's frame, colors (n,3) uint8
    or None, disparity (h,w) float32 NaN invalid, pair (i, j), K (3,3),
    rect (rectify_pair's dict), recon (reconstruct_three_view_images's dict),
    disparity_range (min, count), times (seconds per stage))."""
    imgs = [img1, img2, img3]
    grays = [recon._gray(im, "img%d" % (k + 1)) for k, im in enumerate(imgs)]
    times = {}
    t0 = time.perf_counter()
    rec = recon.reconstruct_three_view_images(*grays, seed=seed)
    times["self-calibrated reconstruction"] = time.perf_counter() - t0
    K, R, t = rec["K"], rec["R"], rec["t"]
    X = rec["X"][rec["inliers"]]
    t0 = time.perf_counter()
    h, w = grays[0].shape
    dist = rec["dist"] if np.any(rec["dist"] != 0) else None
    score, i, j, rect = choose_pair(K, R, t, X, (w, h), dist)
    Li = stereo.remap(grays[i], rect["maps"], 1)
    Rj = stereo.remap(grays[j], rect["maps"], 2)
    times["rectification"] = time.perf_counter() - t0
    # Disparity range spanned by the sparse points, with a margin.
    xr = (rect["R1"] @ ((R[i] @ X.T).T + t[i]).T).T
    f, B = rect["K1"][0, 0], rect["baseline"]
    doff = rect["K1"][0, 2] - rect["K2"][0, 2]
    d = f * B / xr[xr[:, 2] > 0, 2] + doff
    lo, hi = np.percentile(d, 1) - 16, np.percentile(d, 99) + 16
    dmin = int(np.floor(lo / 8.0)) * 8
    num = int(np.ceil((hi - dmin) / 8.0)) * 8
    num = max(16, min(num, max_disparities))
    t0 = time.perf_counter()
    disp = stereo.disparity_sgm(Li, Rj, num_disparities=num, min_disparity=dmin)
    times["semi-global matching"] = time.perf_counter() - t0
    pts, idx = stereo.disparity_to_points(disp, rect=rect)
    colors = None
    src = imgs[i] if color is None else color
    if np.asarray(src).ndim == 3:
        chans = [stereo.remap(np.ascontiguousarray(np.asarray(src)[..., c]), rect["maps"], 1) for c in range(3)]
        colors = np.stack([ch.ravel()[idx] for ch in chans], axis=1)
    else:
        colors = np.repeat(Li.ravel()[idx][:, None], 3, axis=1)
    return dict(points=pts, colors=colors, disparity=disp, pair=(i, j), K=K[i], rect=rect, recon=rec,
                disparity_range=(dmin, num), times=times, score=score, pixel_index=idx)


def write_ply(path, points, colors):
    with open(path, "wb") as f:
        f.write(("ply\nformat binary_little_endian 1.0\nelement vertex %d\n"
                 "property float x\nproperty float y\nproperty float z\n"
                 "property uchar red\nproperty uchar green\nproperty uchar blue\nend_header\n"
                 % len(points)).encode())
        rec = np.zeros(len(points), dtype=[("p", "<f4", 3), ("c", "u1", 3)])
        rec["p"] = points
        rec["c"] = colors
        f.write(rec.tobytes())


def disparity_png(disp):
    """8-bit disparity image scaled to its valid range, 0 where invalid."""
    out = np.zeros(disp.shape, np.uint8)
    v = np.isfinite(disp)
    if v.any():
        lo, hi = np.nanmin(disp), np.nanmax(disp)
        out[v] = (1 + 254 * (disp[v] - lo) / max(hi - lo, 1e-9)).astype(np.uint8)
    return out


def main(argv=None):
    ap = argparse.ArgumentParser(prog="python -m libsfm.stereo_demo",
                                 description="Three uncalibrated images to a dense point cloud.")
    ap.add_argument("images", nargs=3)
    ap.add_argument("--out", default=".", help="directory for dense.ply and disparity.png")
    ap.add_argument("--seed", type=int, default=0)
    ap.add_argument("--scale", type=float, default=1.0, help="resize the images by this factor first")
    a = ap.parse_args(argv)
    import cv2
    imgs = []
    for p in a.images:
        im = cv2.imread(p, cv2.IMREAD_COLOR)
        if im is None:
            print("cannot read %s" % p, file=sys.stderr)
            return 2
        if a.scale != 1.0:
            im = cv2.resize(im, None, fx=a.scale, fy=a.scale, interpolation=cv2.INTER_AREA)
        imgs.append(np.ascontiguousarray(im[..., ::-1]))
    try:
        r = stereo_from_three_views(*imgs, seed=a.seed)
    except SfmError as e:
        print("failed: %s" % e, file=sys.stderr)
        return 1
    os.makedirs(a.out, exist_ok=True)
    write_ply(os.path.join(a.out, "dense.ply"), r["points"], r["colors"])
    cv2.imwrite(os.path.join(a.out, "disparity.png"), disparity_png(r["disparity"]))
    rep = r["recon"]["report"]
    i, j = r["pair"]
    print("self-calibrated focal length %.1f px (path %s, %d inliers, %.3f px RMS)"
          % (rep["focal"], rep["path"], rep["inliers"], rep["rms"]))
    print("pair %d-%d (baseline / median depth %.3f), disparities %d..%d"
          % (i + 1, j + 1, r["score"], r["disparity_range"][0], sum(r["disparity_range"]) - 1))
    print("dense points: %d (%.1f %% of the pixels) -> %s"
          % (len(r["points"]), 100.0 * np.isfinite(r["disparity"]).mean(), os.path.join(a.out, "dense.ply")))
    print("times: " + ", ".join("%s %.0f ms" % (k, 1e3 * v) for k, v in r["times"].items()))
    return 0


if __name__ == "__main__":
    sys.exit(main())
