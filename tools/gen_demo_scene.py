#!/usr/bin/env python3
"""Renders the demo's bundled data: a textured room (floor, ceiling, three
walls and two boxes) seen by three calibrated pinhole cameras, written as a
replay directory (manifest.csv + three 640x480 PGM frames) and a ground-truth
file the demo program reads.

    python3 tools/gen_demo_scene.py OUT_DIR

Deterministic: the textures come from a fixed seed and the rendering is plain
ray casting (nearest quad per ray, bilinear texture lookup, 3x3 supersampling
per pixel, then a little Gaussian sensor noise from the same seed).

Conventions, as the library's: pixel origin at the centre of the top-left
pixel, y down; camera axes x right, y down, z forward; poses are
world-to-camera, x_cam = R X + t; the world frame is camera 1's.

Ground-truth file (text, '#' comments):
    camera <view> fx fy cx cy
    pose <view> r00 r01 r02 r10 r11 r12 r20 r21 r22 t0 t1 t2
"""
import os
import sys

import cv2
import numpy as np

SEED = 20261122
WIDTH, HEIGHT = 640, 480
FX = FY = 500.0
CX, CY = (WIDTH - 1) / 2.0, (HEIGHT - 1) / 2.0
SUPERSAMPLE = 3
TEXELS_PER_M = 256
NOISE_SIGMA = 1.5  # gray levels


def rot_y(deg):
    a = np.radians(deg)
    c, s = np.cos(a), np.sin(a)
    return np.array([[c, 0, s], [0, 1, 0], [-s, 0, c]])


def rot_x(deg):
    a = np.radians(deg)
    c, s = np.cos(a), np.sin(a)
    return np.array([[1, 0, 0], [0, c, -s], [0, s, c]])


def rot_z(deg):
    a = np.radians(deg)
    c, s = np.cos(a), np.sin(a)
    return np.array([[c, -s, 0], [s, c, 0], [0, 0, 1]])


def texture(rng, w_m, h_m):
    """Random gray texture for a quad of w_m x h_m metres: multi-octave value
    noise under a few hundred antialiased shapes (their corners feed the
    corner detector; the noise keeps descriptors distinct)."""
    w = max(16, int(round(w_m * TEXELS_PER_M)))
    h = max(16, int(round(h_m * TEXELS_PER_M)))
    img = np.zeros((h, w), np.float64)
    for cells, amp in ((4, 60.0), (16, 40.0), (64, 25.0)):
        gw = max(2, int(w_m * cells / 4) + 2)
        gh = max(2, int(h_m * cells / 4) + 2)
        g = rng.uniform(-1, 1, (gh, gw))
        img += amp * cv2.resize(g, (w, h), interpolation=cv2.INTER_CUBIC)
    img = np.clip(img + 128.0, 0, 255).astype(np.uint8)
    n_shapes = int(120 * w_m * h_m) + 20
    for _ in range(n_shapes):
        gray = int(rng.integers(0, 256))
        kind = rng.integers(0, 3)
        x, y = int(rng.integers(0, w)), int(rng.integers(0, h))
        size = int(rng.integers(6, 40))
        if kind == 0:
            cv2.rectangle(img, (x, y), (x + size, y + int(rng.integers(6, 40))), gray, -1, cv2.LINE_AA)
        elif kind == 1:
            cv2.circle(img, (x, y), size // 2, gray, -1, cv2.LINE_AA)
        else:
            pts = np.array([[x, y], [x + int(rng.integers(-40, 40)), y + int(rng.integers(-40, 40))],
                            [x + int(rng.integers(-40, 40)), y + int(rng.integers(-40, 40))]], np.int32)
            cv2.fillConvexPoly(img, pts, gray, cv2.LINE_AA)
    return img.astype(np.float32)


def quad(origin, u, v):
    """A rectangle origin + s u + t v, s, t in [0, 1] (u orthogonal to v)."""
    return np.asarray(origin, float), np.asarray(u, float), np.asarray(v, float)


def box(center, size, yaw_deg):
    """The six faces of an axis-aligned box turned by yaw about the y axis."""
    c = np.asarray(center, float)
    R = rot_y(yaw_deg)
    hx, hy, hz = np.asarray(size, float) / 2.0
    ex, ey, ez = R @ [1, 0, 0], R @ [0, 1, 0], R @ [0, 0, 1]
    faces = []
    for sgn in (-1, 1):
        faces.append(quad(c + sgn * hz * ez - hx * ex - hy * ey, 2 * hx * ex, 2 * hy * ey))
        faces.append(quad(c + sgn * hx * ex - hz * ez - hy * ey, 2 * hz * ez, 2 * hy * ey))
        faces.append(quad(c + sgn * hy * ey - hx * ex - hz * ez, 2 * hx * ex, 2 * hz * ez))
    return faces


def scene():
    x0, x1, y0, y1, z0, z1 = -3.0, 3.0, -2.0, 1.5, -1.0, 7.0
    quads = [
        quad([x0, y0, z1], [x1 - x0, 0, 0], [0, y1 - y0, 0]),   # back wall
        quad([x0, y1, z0], [x1 - x0, 0, 0], [0, 0, z1 - z0]),   # floor
        quad([x0, y0, z0], [x1 - x0, 0, 0], [0, 0, z1 - z0]),   # ceiling
        quad([x0, y0, z0], [0, 0, z1 - z0], [0, y1 - y0, 0]),   # left wall
        quad([x1, y0, z0], [0, 0, z1 - z0], [0, y1 - y0, 0]),   # right wall
    ]
    quads += box([-1.1, y1 - 0.6, 4.0], [1.2, 1.2, 1.2], 25.0)
    quads += box([1.3, y1 - 0.9, 5.2], [1.0, 1.8, 0.8], -30.0)
    return quads


def cameras():
    """Poses of the three views (world = view 1): centres C and rotations R,
    returned as (R, t = -R C). Centres are not collinear, so the three-view
    geometry is well conditioned."""
    views = [
        (np.eye(3), np.zeros(3)),
        (rot_y(-4.0) @ rot_x(1.0), np.array([0.40, -0.05, 0.15])),
        (rot_y(-7.0) @ rot_x(-1.5) @ rot_z(2.0), np.array([0.75, 0.12, 0.35])),
    ]
    return [(R, -R @ C) for R, C in views]


def bilinear(tex, s, t):
    h, w = tex.shape
    x = np.clip(s * (w - 1), 0, w - 1.000001)
    y = np.clip(t * (h - 1), 0, h - 1.000001)
    x0, y0 = np.floor(x).astype(np.intp), np.floor(y).astype(np.intp)
    fx, fy = x - x0, y - y0
    a, b = tex[y0, x0], tex[y0, x0 + 1]
    c, d = tex[y0 + 1, x0], tex[y0 + 1, x0 + 1]
    return (a * (1 - fx) + b * fx) * (1 - fy) + (c * (1 - fx) + d * fx) * fy


def render(quads, textures, R, t, return_depth=False):
    """Gray image of the scene from pose (R, t); with return_depth also the
    exact depth (camera z) of the ray through each pixel's centre."""
    ss = SUPERSAMPLE
    offs = (np.arange(ss) + 0.5) / ss - 0.5
    u = (np.arange(WIDTH)[None, :, None, None] + offs[None, None, None, :])
    v = (np.arange(HEIGHT)[:, None, None, None] + offs[None, None, :, None])
    u, v = [a.ravel() for a in np.broadcast_arrays(u, v)]
    # World ray directions R^T [(u - cx) / fx, (v - cy) / fy, 1] from the centre C.
    xn, yn = (u - CX) / FX, (v - CY) / FY
    d = [R[0, k] * xn + R[1, k] * yn + R[2, k] for k in range(3)]
    C = -R.T @ t
    best = np.full(u.shape, np.inf)
    out = np.full(u.shape, 128.0, np.float32)
    for (o, qu, qv), tex in zip(quads, textures):
        n = np.cross(qu, qv)
        den = d[0] * n[0] + d[1] * n[1] + d[2] * n[2]
        with np.errstate(divide="ignore", invalid="ignore"):
            lam = (n @ (o - C)) / den
        cand = np.flatnonzero((lam > 1e-6) & (lam < best))
        lc = lam[cand]
        s = ((C - o) @ qu + lc * (d[0][cand] * qu[0] + d[1][cand] * qu[1] + d[2][cand] * qu[2])) / (qu @ qu)
        tt = ((C - o) @ qv + lc * (d[0][cand] * qv[0] + d[1][cand] * qv[1] + d[2][cand] * qv[2])) / (qv @ qv)
        inside = (s >= 0) & (s <= 1) & (tt >= 0) & (tt <= 1)
        hit = cand[inside]
        out[hit] = bilinear(tex, s[inside], tt[inside])
        best[hit] = lc[inside]
    img = out.reshape(HEIGHT, WIDTH, ss, ss).mean(axis=(2, 3))
    if not return_depth:
        return img
    # d has unit z in the camera frame, so the ray parameter is the depth.
    return img, best.reshape(HEIGHT, WIDTH, ss, ss)[:, :, ss // 2, ss // 2]


def write_pgm(path, img):
    with open(path, "wb") as f:
        f.write(b"P5\n%d %d\n255\n" % (img.shape[1], img.shape[0]))
        f.write(np.ascontiguousarray(img).tobytes())


def main():
    if len(sys.argv) != 2:
        sys.exit("usage: gen_demo_scene.py OUT_DIR")
    out = sys.argv[1]
    os.makedirs(out, exist_ok=True)
    rng = np.random.default_rng(SEED)
    quads = scene()
    textures = [texture(rng, np.linalg.norm(qu), np.linalg.norm(qv)) for _, qu, qv in quads]
    poses = cameras()
    rows = ["sequence,timestamp_ns,file"]
    for i, (R, t) in enumerate(poses):
        img = render(quads, textures, R, t)
        img = img + rng.normal(0.0, NOISE_SIGMA, img.shape)
        img = np.clip(np.rint(img), 0, 255).astype(np.uint8)
        name = "view%d.pgm" % (i + 1)
        write_pgm(os.path.join(out, name), img)
        rows.append("%d,%d,%s" % (i, i * 100000000, name))
    with open(os.path.join(out, "manifest.csv"), "w") as f:
        f.write("\n".join(rows) + "\n")
    with open(os.path.join(out, "ground_truth.txt"), "w") as f:
        f.write("# libsfm demo ground truth (tools/gen_demo_scene.py, seed %d)\n" % SEED)
        f.write("# camera <view> fx fy cx cy; pose <view> R (row-major) t, x_cam = R X + t\n")
        for i, (R, t) in enumerate(poses):
            f.write("camera %d %.17g %.17g %.17g %.17g\n" % (i + 1, FX, FY, CX, CY))
        for i, (R, t) in enumerate(poses):
            f.write("pose %d %s\n" % (i + 1, " ".join("%.17g" % x for x in list(R.ravel()) + list(t))))
    print("wrote %s: 3 frames %dx%d, manifest.csv, ground_truth.txt" % (out, WIDTH, HEIGHT))


if __name__ == "__main__":
    main()
