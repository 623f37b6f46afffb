#!/usr/bin/env python3
"""libsfm features beside OpenCV's ORB on Herz-Jesu-P8, in one run.

Both get the same grayscale views (downscaled with INTER_AREA to 1024 px wide),
the same feature budget and the same matching rule (ratio test, mutual nearest
neighbour). Times are the best of --repeat runs, the two methods run
alternately. A match is an inlier when both points lie within 2 px of the
epipolar line that the ground-truth cameras predict. OpenCV runs on one
thread. Prints, per method: inlier share, matches per pair, time per image for
detect+describe and per pair for matching, and the
ratios libsfm / OpenCV.

Usage: python bench/features_vs_orb.py [--features 2000] [--ratio 0.8] [--repeat 5]
"""
import argparse
import os
import sys
import time

import numpy as np

ROOT = os.path.dirname(os.path.dirname(os.path.abspath(__file__)))
sys.path.insert(0, os.path.join(ROOT, "python"))
# ../shared/data from the project root; SFM_DATA_DIR overrides (e.g. from a worktree).
DATA = os.path.join(os.environ.get("SFM_DATA_DIR", os.path.join(ROOT, "..", "shared", "data")), "herzjesu-p8")
WIDTH = 1024


def load_camera(path):
    rows = [list(map(float, line.split())) for line in open(path) if line.strip()]
    K = np.array(rows[0:3])
    Rc2w = np.array(rows[4:7])
    C = np.array(rows[7])
    R = Rc2w.T
    return K, R, -R @ C


def load_views(data=DATA, width=WIDTH):
    import cv2

    views = []
    for i in range(8):
        img = cv2.imread(os.path.join(data, "images", "%04d.jpg" % i), cv2.IMREAD_GRAYSCALE)
        if img is None:
            raise FileNotFoundError("image %d" % i)
        K, R, t = load_camera(os.path.join(data, "gt_dense_cameras", "%04d.jpg.camera" % i))
        s = width / img.shape[1]
        h = int(round(img.shape[0] * s))
        small = cv2.resize(img, (width, h), interpolation=cv2.INTER_AREA)
        sx, sy = width / img.shape[1], h / img.shape[0]
        # pixel centres at integers in both images: x' = (x + 0.5) s - 0.5
        S = np.array([[sx, 0, 0.5 * sx - 0.5], [0, sy, 0.5 * sy - 0.5], [0, 0, 1]])
        views.append((small, S @ K, R, t))
    return views


def fundamental(v1, v2):
    K1, R1, t1 = v1[1:]
    K2, R2, t2 = v2[1:]
    R = R2 @ R1.T
    t = t2 - R @ t1
    tx = np.array([[0, -t[2], t[1]], [t[2], 0, -t[0]], [-t[1], t[0], 0]])
    return np.linalg.inv(K2).T @ tx @ R @ np.linalg.inv(K1)


def epipolar_inliers(F, x1, x2, tol=2.0):
    """Boolean mask: both points within tol px of their epipolar lines."""
    if len(x1) == 0:
        return np.zeros(0, dtype=bool)
    h1 = np.c_[x1, np.ones(len(x1))]
    h2 = np.c_[x2, np.ones(len(x2))]
    l2 = h1 @ F.T
    l1 = h2 @ F
    d2 = np.abs(np.sum(l2 * h2, axis=1)) / np.hypot(l2[:, 0], l2[:, 1])
    d1 = np.abs(np.sum(l1 * h1, axis=1)) / np.hypot(l1[:, 0], l1[:, 1])
    return (d1 <= tol) & (d2 <= tol)


def cv_match(bf, d1, d2, ratio, mutual):
    knn = bf.knnMatch(d1, d2, k=2)
    back = {m.queryIdx: m.trainIdx for m in bf.match(d2, d1)} if mutual else None
    out = []
    for pair in knn:
        if not pair:
            continue
        m = pair[0]
        if len(pair) > 1 and ratio < 1.0 and not m.distance < ratio * pair[1].distance:
            continue
        if mutual and back.get(m.trainIdx) != m.queryIdx:
            continue
        out.append((m.queryIdx, m.trainIdx))
    return np.array(out, dtype=np.intp).reshape(-1, 2)


def paired_min_times(fa, fb, repeat):
    """Best-of-repeat wall time of fa and fb, run alternately so that load
    from other processes hits both alike (the minimum is the least disturbed
    run)."""
    ta, tb = [], []
    for _ in range(repeat):
        t0 = time.perf_counter()
        fa()
        t1 = time.perf_counter()
        fb()
        t2 = time.perf_counter()
        ta.append(t1 - t0)
        tb.append(t2 - t1)
    return min(ta), min(tb)


def main():
    ap = argparse.ArgumentParser()
    ap.add_argument("--features", type=int, default=2000)
    ap.add_argument("--ratio", type=float, default=0.8)
    ap.add_argument("--no-mutual", action="store_true")
    ap.add_argument("--repeat", type=int, default=9)
    args = ap.parse_args()
    mutual = not args.no_mutual
    if not os.path.isdir(DATA):
        print("SKIP: %s not found; the benchmark needs Herz-Jesu-P8" % os.path.normpath(DATA))
        return 0
    import cv2

    import libsfm

    cv2.setNumThreads(1)
    views = load_views()
    pairs = [(i, i + 1) for i in range(len(views) - 1)]
    orb = cv2.ORB_create(nfeatures=args.features)
    bf = cv2.BFMatcher(cv2.NORM_HAMMING)

    res = {}
    sfm_feats = [libsfm.detect_and_describe(v[0], max_features=args.features) for v in views]
    cv_feats = []
    for v in views:
        kp, d = orb.detectAndCompute(v[0], None)
        cv_feats.append((np.array([k.pt for k in kp]).reshape(-1, 2), d))

    det = [paired_min_times(lambda v=v: libsfm.detect_and_describe(v[0], max_features=args.features),
                            lambda v=v: orb.detectAndCompute(v[0], None), args.repeat) for v in views]
    t_sfm_det = float(np.mean([d[0] for d in det]))
    t_cv_det = float(np.mean([d[1] for d in det]))
    mt = {"libsfm": [], "opencv-orb": []}
    for i, j in pairs:
        a, b = paired_min_times(
            lambda: libsfm.match(sfm_feats[i][1], sfm_feats[j][1], ratio=args.ratio, mutual=mutual),
            lambda: cv_match(bf, cv_feats[i][1], cv_feats[j][1], args.ratio, mutual), args.repeat)
        mt["libsfm"].append(a)
        mt["opencv-orb"].append(b)

    for name, feats, matcher in (
        ("libsfm", [(k[:, :2], d) for k, d in sfm_feats], lambda a, b: libsfm.match(a, b, ratio=args.ratio, mutual=mutual)),
        ("opencv-orb", cv_feats, lambda a, b: cv_match(bf, a, b, args.ratio, mutual)),
    ):
        tot, inl = 0, 0
        per_pair = []
        for i, j in pairs:
            (x1, d1), (x2, d2) = feats[i], feats[j]
            m = matcher(d1, d2)
            F = fundamental(views[i], views[j])
            ok = epipolar_inliers(F, x1[m[:, 0]], x2[m[:, 1]])
            tot += len(m)
            inl += int(ok.sum())
            per_pair.append("%d-%d: %d/%d" % (i, j, int(ok.sum()), len(m)))
        nf = np.mean([len(f[0]) for f in feats])
        res[name] = dict(share=inl / max(tot, 1), count=tot / len(pairs), inliers=inl / len(pairs),
                         feats=nf, tmatch=float(np.mean(mt[name])), pairs=per_pair)
    res["libsfm"]["tdet"] = t_sfm_det
    res["opencv-orb"]["tdet"] = t_cv_det

    h, w = views[0][0].shape
    print("Herz-Jesu-P8, %d views at %dx%d, %d adjacent pairs, budget %d features, ratio %.2f, mutual %s"
          % (len(views), w, h, len(pairs), args.features, args.ratio, mutual))
    print("%-11s %9s %9s %12s %10s %14s %14s" % ("method", "features", "matches", "inliers/pair", "inlier%", "detect ms/img", "match ms/pair"))
    for name in ("libsfm", "opencv-orb"):
        r = res[name]
        print("%-11s %9.0f %9.1f %12.1f %9.1f%% %14.2f %14.2f" % (name, r["feats"], r["count"], r["inliers"], 100 * r["share"], 1e3 * r["tdet"], 1e3 * r["tmatch"]))
    a, b = res["libsfm"], res["opencv-orb"]
    print("ratio libsfm/opencv: inlier share %.3f, inliers %.3f, detect time %.3f, match time %.3f"
          % (a["share"] / b["share"], a["inliers"] / max(b["inliers"], 1e-9), a["tdet"] / b["tdet"], a["tmatch"] / b["tmatch"]))
    for name in ("libsfm", "opencv-orb"):
        print("  %s per pair (inliers/matches): %s" % (name, ", ".join(res[name]["pairs"])))
    return 0


if __name__ == "__main__":
    sys.exit(main())
