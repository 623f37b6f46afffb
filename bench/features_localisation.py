#!/usr/bin/env python3
"""Keypoint localisation accuracy of libsfm's features beside OpenCV's, on
image pairs related by a known homography.

Each pair is made from one full-resolution photograph (Herz-Jesu-P8, 3072 px
wide, and the twelve BoofCV scenes at their own size): view a is the image
reduced by area averaging (INTER_AREA, factor 3 for Herz-Jesu, 1 for BoofCV
where the image itself is view a), view b the same image warped by a random
homography (a few degrees of rotation, +-4 % scale, a little perspective, a
sub-pixel shift; Lanczos interpolation at full resolution) and then reduced
the same way. Pixel centres sit at integers in every image (the libsfm and
OpenCV convention), so the homography between the reduced views is
S H S^-1 with x' = (x + 0.5) / s - 0.5.

Every method detects and describes both views and matches them with the
same rule (ratio 0.8 + mutual nearest neighbour). A match whose view-b point
lies within 2.5 px of the homography's image of its view-a point is counted
as correct; the figure is the RMS over correct matches of that distance (a
2-D error combining both keypoints' errors: one keypoint's per-axis error is
that over 2), its median, and the count. Methods: libsfm's
detect_and_describe; libsfm followed by the photometric refinement of the
view-b positions onto view a's patches (sfm_features_align_points, when the
library has it; the points it leaves alone count with their start);
libsfm followed by OpenCV's Lucas-Kanade (calcOpticalFlowPyrLK, 15x15, one
level, from the same starts: the same idea implemented independently); OpenCV
ORB; ORB followed by cv2.cornerSubPix (5x5 window); OpenCV SIFT
(sub-pixel DoG extrema). libsfm's error is also split by pyramid level.

Usage: python bench/features_localisation.py [--features 2000] [--pairs 2] [--seed 3]
"""
import argparse
import os
import sys

import numpy as np

ROOT = os.path.dirname(os.path.dirname(os.path.abspath(__file__)))
sys.path.insert(0, os.path.join(ROOT, "python"))
DATA = os.environ.get("SFM_DATA_DIR", os.path.join(ROOT, "..", "shared", "data"))
HERZ = os.path.join(DATA, "herzjesu-p8", "images")
BOOF = os.path.join(DATA, "boofcv-triple", "triple")
TOL = 2.5


def random_homography(rng, w, h):
    """A homography about the image centre: rotation, scale, a little
    perspective and a shift (full-resolution pixels)."""
    c = np.array([[1, 0, -(w - 1) / 2], [0, 1, -(h - 1) / 2], [0, 0, 1.0]])
    a = np.deg2rad(rng.uniform(-6, 6))
    s = rng.uniform(0.96, 1.04)
    R = np.array([[s * np.cos(a), -s * np.sin(a), 0], [s * np.sin(a), s * np.cos(a), 0], [0, 0, 1.0]])
    P = np.eye(3)
    P[2, :2] = rng.uniform(-0.04, 0.04, 2) / max(w, h)
    T = np.eye(3)
    T[:2, 2] = rng.uniform(-3, 3, 2)
    return T @ np.linalg.inv(c) @ P @ R @ c


def make_pair(cv2, full, H, factor):
    h, w = full.shape
    warped = cv2.warpPerspective(full, H, (w, h), flags=cv2.INTER_LANCZOS4, borderMode=cv2.BORDER_REFLECT)
    if factor == 1:
        return full, warped, H
    size = (int(round(w / factor)), int(round(h / factor)))
    sx, sy = size[0] / w, size[1] / h
    S = np.array([[sx, 0, 0.5 * sx - 0.5], [0, sy, 0.5 * sy - 0.5], [0, 0, 1.0]])
    a = cv2.resize(full, size, interpolation=cv2.INTER_AREA)
    b = cv2.resize(warped, size, interpolation=cv2.INTER_AREA)
    return a, b, S @ H @ np.linalg.inv(S)


def apply_h(H, x):
    y = np.c_[x, np.ones(len(x))] @ H.T
    return y[:, :2] / y[:, 2:]


def cv_match(bf, d1, d2, ratio=0.8):
    knn = bf.knnMatch(d1, d2, k=2)
    back = {m.queryIdx: m.trainIdx for m in bf.match(d2, d1)}
    out = []
    for pair in knn:
        if len(pair) < 2:
            continue
        m = pair[0]
        if m.distance < ratio * pair[1].distance and back.get(m.trainIdx) == m.queryIdx:
            out.append((m.queryIdx, m.trainIdx))
    return np.array(out, dtype=np.intp).reshape(-1, 2)


def errors(H, xa, xb):
    e = np.linalg.norm(apply_h(H, xa) - xb, axis=1)
    return e, e < TOL


class Tally:
    def __init__(self):
        self.e = []

    def add(self, e):
        self.e.append(e)

    def row(self):
        e = np.concatenate(self.e) if self.e else np.zeros(0)
        if len(e) == 0:
            return "      -       -      0"
        return "%7.3f %7.3f %6d" % (np.sqrt(np.mean(e ** 2)), np.median(e), len(e))


def main():
    ap = argparse.ArgumentParser()
    ap.add_argument("--features", type=int, default=2000)
    ap.add_argument("--pairs", type=int, default=2, help="homographies per source image")
    ap.add_argument("--seed", type=int, default=3)
    args = ap.parse_args()
    import cv2

    import libsfm

    cv2.setNumThreads(1)
    sources = []
    if os.path.isdir(HERZ):
        for i in range(8):
            sources.append(("herzjesu %d" % i, os.path.join(HERZ, "%04d.jpg" % i), 3))
    if os.path.isdir(BOOF):
        for f in sorted(os.listdir(BOOF)):
            if f.endswith("_01.jpg"):
                sources.append((f[:-7], os.path.join(BOOF, f), 1))
    if not sources:
        print("SKIP: neither %s nor %s found" % (HERZ, BOOF))
        return 0
    refine = getattr(libsfm, "align_points", None)
    rng = np.random.default_rng(args.seed)
    orb = cv2.ORB_create(nfeatures=args.features)
    sift = cv2.SIFT_create(nfeatures=args.features)
    bf_h = cv2.BFMatcher(cv2.NORM_HAMMING)
    bf_l2 = cv2.BFMatcher(cv2.NORM_L2)
    crit = (cv2.TERM_CRITERIA_EPS + cv2.TERM_CRITERIA_COUNT, 30, 0.01)
    names = ["libsfm", "libsfm + align_points", "libsfm + opencv LK", "opencv orb", "orb + cornerSubPix",
             "opencv sift"]
    groups = {"herzjesu": {n: Tally() for n in names}, "boofcv": {n: Tally() for n in names}}
    levels = {}
    refined = [0, 0]
    for label, path, factor in sources:
        full = cv2.imread(path, cv2.IMREAD_GRAYSCALE)
        g = groups["herzjesu" if factor == 3 else "boofcv"]
        for _ in range(args.pairs):
            H = random_homography(rng, full.shape[1], full.shape[0])
            a, b, Hl = make_pair(cv2, full, H, factor)
            ka, da = libsfm.detect_and_describe(a, max_features=args.features)
            kb, db = libsfm.detect_and_describe(b, max_features=args.features)
            m = libsfm.match(da, db)
            xa, xb = ka[m[:, 0], :2], kb[m[:, 1], :2]
            e, ok = errors(Hl, xa, xb)
            g["libsfm"].add(e[ok])
            lv = np.maximum(ka[m[:, 0], 5], kb[m[:, 1], 5]).astype(int)
            for l in np.unique(lv[ok]):
                levels.setdefault(l, Tally()).add(e[ok & (lv == l)])
            if refine is not None:
                rb, good = refine(a, xa, b, xb)
                e2, ok2 = errors(Hl, xa, rb)
                g["libsfm + align_points"].add(e2[ok2])
                refined[0] += int(good[ok].sum())
                refined[1] += int(ok.sum())
            q, st, _ = cv2.calcOpticalFlowPyrLK(a, b, xa.astype(np.float32).reshape(-1, 1, 2),
                                                xb.astype(np.float32).reshape(-1, 1, 2).copy(), winSize=(15, 15),
                                                maxLevel=0, flags=cv2.OPTFLOW_USE_INITIAL_FLOW, criteria=crit)
            q = np.where(st.reshape(-1, 1) == 1, q.reshape(-1, 2).astype(float), xb)
            e3, ok3 = errors(Hl, xa, q)
            g["libsfm + opencv LK"].add(e3[ok3])
            kp1, d1 = orb.detectAndCompute(a, None)
            kp2, d2 = orb.detectAndCompute(b, None)
            mo = cv_match(bf_h, d1, d2)
            p1 = np.array([k.pt for k in kp1])[mo[:, 0]]
            p2 = np.array([k.pt for k in kp2])[mo[:, 1]]
            e, ok = errors(Hl, p1, p2)
            g["opencv orb"].add(e[ok])
            q1 = cv2.cornerSubPix(a, p1.astype(np.float32).reshape(-1, 1, 2).copy(), (5, 5), (-1, -1), crit)
            q2 = cv2.cornerSubPix(b, p2.astype(np.float32).reshape(-1, 1, 2).copy(), (5, 5), (-1, -1), crit)
            e, ok = errors(Hl, q1.reshape(-1, 2).astype(float), q2.reshape(-1, 2).astype(float))
            g["orb + cornerSubPix"].add(e[ok])
            kp1, d1 = sift.detectAndCompute(a, None)
            kp2, d2 = sift.detectAndCompute(b, None)
            ms = cv_match(bf_l2, d1, d2)
            e, ok = errors(Hl, np.array([k.pt for k in kp1])[ms[:, 0]], np.array([k.pt for k in kp2])[ms[:, 1]])
            g["opencv sift"].add(e[ok])
    print("Localisation against a known homography: 2-D error of correct matches (< %.1f px), %d features, "
          "%d homographies per image, seed %d" % (TOL, args.features, args.pairs, args.seed))
    for gname, g in groups.items():
        if not g["libsfm"].e:
            continue
        print("%s (%s)" % (gname, "8 views reduced 3x to 1024x683" if gname == "herzjesu"
                           else "twelve scenes, view 1 at its own size"))
        print("  %-26s %7s %7s %6s" % ("method", "RMS px", "median", "n"))
        for n in names:
            if n == "libsfm + align_points" and refine is None:
                continue
            print("  %-26s %s" % (n, g[n].row()))
    if refine is not None:
        print("align_points refined %d of the %d correct libsfm matches (%.1f %%)"
              % (refined[0], refined[1], 100.0 * refined[0] / max(refined[1], 1)))
    print("libsfm by pyramid level (the coarser of the two keypoints), both groups:")
    for l in sorted(levels):
        print("  level %d (x%.2f)          %s" % (l, 1.25 ** l, levels[l].row()))
    return 0


if __name__ == "__main__":
    sys.exit(main())
