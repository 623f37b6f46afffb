#!/usr/bin/env python3
"""Writes the byte stream firmware_examples/cortex_m_relpose reads: synthetic
two-view problems with a known relative pose (random scene in front of both
cameras, Gaussian pixel noise, a share of wrong matches).

    python3 tools/gen_relpose_stream.py OUT.bin [--problems 4] [--n 200]
        [--outliers 0.25] [--noise 0.5] [--seed 5]

Format (little endian): "SFMM", uint32 1, uint32 count; per problem uint32 n,
float64 fx fy cx cy, float64 R[9] t[3] (x_cam2 = R x_cam1 + t, |t| = 1),
n x float64 (x1, y1, x2, y2)."""
import argparse
import struct

import numpy as np


def rodrigues(w):
    th = np.linalg.norm(w)
    if th < 1e-15:
        return np.eye(3)
    k = w / th
    K = np.array([[0, -k[2], k[1]], [k[2], 0, -k[0]], [-k[1], k[0], 0]])
    return np.eye(3) + np.sin(th) * K + (1 - np.cos(th)) * K @ K


def main():
    ap = argparse.ArgumentParser()
    ap.add_argument("out")
    ap.add_argument("--problems", type=int, default=4)
    ap.add_argument("--n", type=int, default=200)
    ap.add_argument("--outliers", type=float, default=0.25)
    ap.add_argument("--noise", type=float, default=0.5)
    ap.add_argument("--seed", type=int, default=5)
    a = ap.parse_args()
    rng = np.random.default_rng(a.seed)
    fx = fy = 500.0
    cx, cy = 319.5, 239.5
    buf = [b"SFMM", struct.pack("<II", 1, a.problems)]
    for _ in range(a.problems):
        R = rodrigues(rng.normal(size=3) * 0.08)
        t = rng.normal(size=3)
        t /= np.linalg.norm(t)
        rows = []
        while len(rows) < a.n:
            X = np.array([rng.uniform(-3, 3), rng.uniform(-2, 2), rng.uniform(4, 12)])
            Y = R @ X + t
            if Y[2] <= 0.5:
                continue
            p1 = [fx * X[0] / X[2] + cx, fy * X[1] / X[2] + cy]
            p2 = [fx * Y[0] / Y[2] + cx, fy * Y[1] / Y[2] + cy]
            if not (0 <= p2[0] < 640 and 0 <= p2[1] < 480 and 0 <= p1[0] < 640 and 0 <= p1[1] < 480):
                continue
            p1 = np.array(p1) + rng.normal(size=2) * a.noise
            p2 = np.array(p2) + rng.normal(size=2) * a.noise
            if rng.uniform() < a.outliers:
                p2 = np.array([rng.uniform(0, 640), rng.uniform(0, 480)])
            rows.append(np.r_[p1, p2])
        buf.append(struct.pack("<I", a.n))
        buf.append(np.array([fx, fy, cx, cy], "<f8").tobytes())
        buf.append(np.r_[R.ravel(), t].astype("<f8").tobytes())
        buf.append(np.array(rows, "<f8").tobytes())
    with open(a.out, "wb") as f:
        f.write(b"".join(buf))


if __name__ == "__main__":
    main()
