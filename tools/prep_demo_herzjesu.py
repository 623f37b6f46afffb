#!/usr/bin/env python3
"""Prepares the demo's real triplet: Herz-Jesu-P8 views 0000, 0001, 0002
(3072x2048 JPEGs) reduced by 3 to 1024x683 gray PGMs in a replay directory,
with the ground truth scaled to match, in the format tools/gen_demo_scene.py
writes (camera <view> fx fy cx cy; pose <view> R t, x_cam = R X + t).

    python3 tools/prep_demo_herzjesu.py SRC_DIR OUT_DIR

SRC_DIR is ../shared/data/herzjesu-p8 (never copied into the project; the
reduced frames go under build/). Strecha's .camera files hold K, distortion
(zero), R camera-to-world, the centre C and the size: x_cam = R^T (X - C).
With the pixel origin at the centre of the top-left pixel, reducing by s
maps x to (x + 0.5) / s - 0.5: fx / s and (cx + 0.5) / s - 0.5.
"""
import os
import sys

import cv2
import numpy as np

VIEWS = ("0000", "0001", "0002")
REDUCE = 3


def load_camera(path):
    v = np.array([float(x) for x in open(path).read().split()[:24]])
    K = v[:9].reshape(3, 3)
    Rcw = v[12:21].reshape(3, 3)
    C = v[21:24]
    R = Rcw.T
    return K, R, -R @ C


def main():
    if len(sys.argv) != 3:
        sys.exit("usage: prep_demo_herzjesu.py SRC_DIR OUT_DIR")
    src, out = sys.argv[1], sys.argv[2]
    os.makedirs(out, exist_ok=True)
    rows = ["sequence,timestamp_ns,file"]
    cams, poses = [], []
    for i, stem in enumerate(VIEWS):
        img = cv2.imread(os.path.join(src, "images", stem + ".jpg"), cv2.IMREAD_GRAYSCALE)
        if img is None:
            sys.exit("prep_demo_herzjesu: cannot read %s/images/%s.jpg" % (src, stem))
        h, w = img.shape
        small = cv2.resize(img, (w // REDUCE, h // REDUCE), interpolation=cv2.INTER_AREA)
        name = "view%d.pgm" % (i + 1)
        with open(os.path.join(out, name), "wb") as f:
            f.write(b"P5\n%d %d\n255\n" % (small.shape[1], small.shape[0]))
            f.write(np.ascontiguousarray(small).tobytes())
        rows.append("%d,%d,%s" % (i, i * 100000000, name))
        K, R, t = load_camera(os.path.join(src, "gt_dense_cameras", stem + ".jpg.camera"))
        cams.append((K[0, 0] / REDUCE, K[1, 1] / REDUCE, (K[0, 2] + 0.5) / REDUCE - 0.5,
                     (K[1, 2] + 0.5) / REDUCE - 0.5))
        poses.append((R, t))
    with open(os.path.join(out, "manifest.csv"), "w") as f:
        f.write("\n".join(rows) + "\n")
    with open(os.path.join(out, "ground_truth.txt"), "w") as f:
        f.write("# Herz-Jesu-P8 views %s reduced %dx (tools/prep_demo_herzjesu.py)\n" % (" ".join(VIEWS), REDUCE))
        f.write("# camera <view> fx fy cx cy; pose <view> R (row-major) t, x_cam = R X + t\n")
        for i, c in enumerate(cams):
            f.write("camera %d %.17g %.17g %.17g %.17g\n" % ((i + 1,) + c))
        for i, (R, t) in enumerate(poses):
            f.write("pose %d %s\n" % (i + 1, " ".join("%.17g" % x for x in list(R.ravel()) + list(t))))
    print("wrote %s: 3 frames %dx%d, manifest.csv, ground_truth.txt" % (out, small.shape[1], small.shape[0]))


if __name__ == "__main__":
    main()
