#!/usr/bin/env python3
"""Renders the demo's bundled data: a textured room (floor, ceiling, three
walls and two boxes) seen by three calibrated pinhole cameras, written as a
replay directory (manifest.csv + three 640x480 PGM frames) and a ground-truth
file the demo program reads.

    python3 tools/gen_demo_scene.py OUT_DIR
    python3 tools/gen_demo_scene.py --sequence N OUT_DIR
    python3 tools/gen_demo_scene.py --sequence N --fisheye OUT_DIR

Sequence mode renders N frames (30 Hz timestamps) along a known smooth
trajectory through the same room (a loop that sways left and right and
forward and back while the camera turns to keep the boxes in view, with a
little roll and pitch), one sample per pixel plus a slight blur to stand in
for the optics, and writes the pose and the gravity direction (in camera
coordinates, the world's +y) of every frame to ground_truth.txt, plus the
trajectory as a TUM file (camera-to-world) in ground_truth.tum.

--fisheye renders the same loop through an equidistant fisheye lens with
Kannala-Brandt distortion (J. Kannala, S. Brandt, "A generic camera model and
calibration method for conventional, wide-angle, and fish-eye lenses", PAMI
2006: theta_d = theta (1 + k1 theta^2 + k2 theta^4 + k3 theta^6 + k4 theta^8),
pixel = f theta_d (x, y) / r + c, OpenCV's fisheye model), FISHEYE_F and
FISHEYE_K below, about 150 degrees across the diagonal; each pixel's ray is
found by inverting theta_d(theta) with Newton's method here, independently of
the library's camera model. ground_truth.txt then carries a
`camera_model 1 fisheye` line and the camera line lists fx fy cx cy k1..k4.

Deterministic: the textures come from a fixed seed and the rendering is plain
ray casting (nearest quad per ray, bilinear texture lookup, 3x3 supersampling
per pixel, then a little Gaussian sensor noise from the same seed).

Conventions, as the library's: pixel origin at the centre of the top-left
pixel, y down; camera axes x right, y down, z forward; poses are
world-to-camera, x_cam = R X + t; the world frame is camera 1's.

Ground-truth file (text, '#' comments):
    camera <view> fx fy cx cy
    pose <view> r00 r01 r02 r10 r11 r12 r20 r21 r22 t0 t1 t2
    gravity <view> gx gy gz        (sequence mode: unit, camera coordinates)
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
FISHEYE_F = 300.0
FISHEYE_K = (0.03, -0.01, 0.002, 0.0)
LENS = {"fisheye": False}


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


def _quad_bbox(o, qu, qv, R, t, normalised=False):
    """Pixel box (x0, x1, y0, y1) holding the quad's image when all its
    corners are in front of the camera, else None (test every ray)."""
    corners = np.array([o, o + qu, o + qv, o + qu + qv])
    xc = corners @ R.T + t
    if np.any(xc[:, 2] < 0.05):
        return None
    if normalised:
        x, y = xc[:, 0] / xc[:, 2], xc[:, 1] / xc[:, 2]
        return x.min() - 0.01, x.max() + 0.01, y.min() - 0.01, y.max() + 0.01
    u = FX * xc[:, 0] / xc[:, 2] + CX
    v = FY * xc[:, 1] / xc[:, 2] + CY
    return u.min() - 2, u.max() + 2, v.min() - 2, v.max() + 2


def render(quads, textures, R, t, return_depth=False):
    """Gray image of the scene from pose (R, t); with return_depth also the
    exact depth (camera z) of the ray through each pixel's centre."""
    ss = SUPERSAMPLE
    offs = (np.arange(ss) + 0.5) / ss - 0.5
    u = (np.arange(WIDTH)[None, :, None, None] + offs[None, None, None, :])
    v = (np.arange(HEIGHT)[:, None, None, None] + offs[None, None, :, None])
    u, v = [a.ravel() for a in np.broadcast_arrays(u, v)]
    # World ray directions R^T [(u - cx) / fx, (v - cy) / fy, 1] from the centre C.
    if LENS["fisheye"]:
        xn, yn = fisheye_rays(u, v)
    else:
        xn, yn = (u - CX) / FX, (v - CY) / FY
    d = [R[0, k] * xn + R[1, k] * yn + R[2, k] for k in range(3)]
    C = -R.T @ t
    best = np.full(u.shape, np.inf)
    out = np.full(u.shape, 128.0, np.float32)
    for (o, qu, qv), tex in zip(quads, textures):
        n = np.cross(qu, qv)
        if LENS["fisheye"]:
            # perspective keeps lines straight: a quad in front of the camera
            # covers the box of its corners on the z = 1 plane, where the
            # fisheye pixels' rays are given
            bb = _quad_bbox(o, qu, qv, R, t, normalised=True)
            uu, vv = xn, yn
        else:
            bb = _quad_bbox(o, qu, qv, R, t)
            uu, vv = u, v
        if bb is not None:
            sel = np.flatnonzero((uu >= bb[0]) & (uu <= bb[1]) & (vv >= bb[2]) & (vv <= bb[3]))
            if sel.size == 0:
                continue
        else:
            sel = np.arange(u.size)
        den = d[0][sel] * n[0] + d[1][sel] * n[1] + d[2][sel] * n[2]
        with np.errstate(divide="ignore", invalid="ignore"):
            lam = (n @ (o - C)) / den
        keep = (lam > 1e-6) & (lam < best[sel])
        cand = sel[keep]
        lc = lam[keep]
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


def fisheye_rays(u, v):
    """Normalised ray (x/z, y/z) of each fisheye pixel: theta_d = r_d / f
    inverted for theta by Newton's method (theta_d(theta) is increasing over
    the image for FISHEYE_K), then tan(theta) along the pixel's direction."""
    xd, yd = (u - CX) / FISHEYE_F, (v - CY) / FISHEYE_F
    td = np.hypot(xd, yd)
    k1, k2, k3, k4 = FISHEYE_K
    th = td.copy()
    for _ in range(20):
        t2 = th * th
        f = th * (1 + t2 * (k1 + t2 * (k2 + t2 * (k3 + t2 * k4)))) - td
        df = 1 + t2 * (3 * k1 + t2 * (5 * k2 + t2 * (7 * k3 + t2 * 9 * k4)))
        th = th - f / df
    assert float(th.max()) < np.radians(86.0), "fisheye rays beyond the forward half-space"
    with np.errstate(invalid="ignore", divide="ignore"):
        s = np.where(td > 1e-12, np.tan(th) / td, 1.0)
    return xd * s, yd * s


def write_pgm(path, img):
    with open(path, "wb") as f:
        f.write(b"P5\n%d %d\n255\n" % (img.shape[1], img.shape[0]))
        f.write(np.ascontiguousarray(img).tobytes())


def look_at(C, target, roll_deg=0.0):
    """World-to-camera rotation of a camera at C looking at target, y down
    (the world's +y), rolled about its optical axis."""
    z = np.asarray(target, float) - C
    z /= np.linalg.norm(z)
    x = np.cross([0.0, 1.0, 0.0], z)
    x /= np.linalg.norm(x)
    y = np.cross(z, x)
    R = np.stack([x, y, z])  # rows: camera axes in world coordinates
    return rot_z(roll_deg) @ R


def trajectory(n):
    """Room-frame poses (R, t) of n frames along one closed loop."""
    poses = []
    for i in range(n):
        s = 2 * np.pi * i / n
        C = np.array([1.1 * np.sin(s), -0.25 + 0.15 * np.sin(2 * s),
                      1.2 * (1 - np.cos(s)) + 0.3 * np.sin(2 * s)])
        target = np.array([0.4 * np.sin(s + 0.5), 0.0, 4.6])
        R = look_at(C, target, 3.0 * np.sin(3 * s))
        poses.append((R, -R @ C))
    return poses


def quat_wxyz(R):
    w = np.sqrt(max(0.0, 1 + R[0, 0] + R[1, 1] + R[2, 2])) / 2
    x = np.copysign(np.sqrt(max(0.0, 1 + R[0, 0] - R[1, 1] - R[2, 2])) / 2, R[2, 1] - R[1, 2])
    y = np.copysign(np.sqrt(max(0.0, 1 - R[0, 0] + R[1, 1] - R[2, 2])) / 2, R[0, 2] - R[2, 0])
    z = np.copysign(np.sqrt(max(0.0, 1 - R[0, 0] - R[1, 1] + R[2, 2])) / 2, R[1, 0] - R[0, 1])
    return w, x, y, z


def main_sequence(n, out):
    global SUPERSAMPLE
    SUPERSAMPLE = 1
    os.makedirs(out, exist_ok=True)
    rng = np.random.default_rng(SEED)
    quads = scene()
    textures = [texture(rng, np.linalg.norm(qu), np.linalg.norm(qv)) for _, qu, qv in quads]
    room = trajectory(n)
    R0, t0 = room[0]
    rows = ["sequence,timestamp_ns,file"]
    gts = []
    for i, (Rr, tr) in enumerate(room):
        img = render(quads, textures, Rr, tr)
        img = cv2.GaussianBlur(img.astype(np.float32), (0, 0), 0.6)
        img = img + rng.normal(0.0, NOISE_SIGMA, img.shape)
        img = np.clip(np.rint(img), 0, 255).astype(np.uint8)
        name = "frame%04d.pgm" % i
        write_pgm(os.path.join(out, name), img)
        rows.append("%d,%d,%s" % (i, i * 33333333, name))
        # world = view 1: X1 = R0 X + t0, so x = Rr R0^T X1 + (tr - Rr R0^T t0)
        R = Rr @ R0.T
        gts.append((R, tr - R @ t0, Rr @ np.array([0.0, 1.0, 0.0])))
        if i % 50 == 0:
            print("rendered %d / %d" % (i, n), flush=True)
    with open(os.path.join(out, "manifest.csv"), "w") as f:
        f.write("\n".join(rows) + "\n")
    with open(os.path.join(out, "ground_truth.txt"), "w") as f:
        f.write("# libsfm demo sequence ground truth (tools/gen_demo_scene.py --sequence %d, seed %d)\n" % (n, SEED))
        f.write("# camera <view> fx fy cx cy; pose <view> R (row-major) t, x_cam = R X + t (world = view 1);\n")
        f.write("# gravity <view> g: the direction of gravity in that camera's coordinates\n")
        if LENS["fisheye"]:
            f.write("camera_model 1 fisheye\n")
            f.write("camera 1 %.17g %.17g %.17g %.17g %s\n" % (FISHEYE_F, FISHEYE_F, CX, CY,
                                                           " ".join("%.17g" % k for k in FISHEYE_K)))
        else:
            f.write("camera 1 %.17g %.17g %.17g %.17g\n" % (FX, FY, CX, CY))
        for i, (R, t, g) in enumerate(gts):
            f.write("pose %d %s\n" % (i + 1, " ".join("%.17g" % x for x in list(R.ravel()) + list(t))))
        for i, (R, t, g) in enumerate(gts):
            f.write("gravity %d %.17g %.17g %.17g\n" % (i + 1, g[0], g[1], g[2]))
    with open(os.path.join(out, "ground_truth.tum"), "w") as f:
        f.write("# timestamp tx ty tz qx qy qz qw (camera-to-world, world = view 1)\n")
        for i, (R, t, g) in enumerate(gts):
            C = -R.T @ t
            w, x, y, z = quat_wxyz(R.T)
            f.write("%.9f %.9f %.9f %.9f %.9f %.9f %.9f %.9f\n" % (i * 0.033333333, C[0], C[1], C[2], x, y, z, w))
    print("wrote %s: %d frames %dx%d, manifest.csv, ground_truth.txt, ground_truth.tum" % (out, n, WIDTH, HEIGHT))


def main():
    if len(sys.argv) == 4 and sys.argv[1] == "--sequence":
        return main_sequence(int(sys.argv[2]), sys.argv[3])
    if len(sys.argv) == 5 and sys.argv[1] == "--sequence" and sys.argv[3] == "--fisheye":
        LENS["fisheye"] = True
        return main_sequence(int(sys.argv[2]), sys.argv[4])
    if len(sys.argv) != 2:
        sys.exit("usage: gen_demo_scene.py OUT_DIR | --sequence N [--fisheye] OUT_DIR")
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
