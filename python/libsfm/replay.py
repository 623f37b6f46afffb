"""Visual odometry on a recording: python -m libsfm.replay DIR [options].

Reads, directly:
  * the project's replay directories (manifest.csv: sequence,timestamp_ns,file
    or timestamp_ns,file; a ground_truth.txt or camera.txt beside it gives K),
  * EuRoC folders (mav0/cam0/data.csv + data/, sensor.yaml for K and the
    radial-tangential distortion; DIR may be the folder holding mav0 or cam0),
  * KITTI odometry folders (image_0, image_2 or image_l, calib.txt for K,
    times.txt when present, else frame i at i x 0.1 s, KITTI's 10 Hz).
--camera fx,fy,cx,cy[,k1,k2,p1,p2,k3] overrides K; without a camera (none
given, none in the recording) or with --self-calibrate (the recording's
ignored) the pipeline self-calibrates a pinhole camera on the first good
keyframe triple and prints the focal length found; --gt FILE (KITTI poses.txt,
TUM, or the project's ground_truth.txt) adds the error report: ATE after a
similarity (Sim3, Umeyama) alignment and the relative pose error between
consecutive frames; --trajectory OUT.tum writes one row per frame with a pose
(timestamp tx ty tz qx qy qz qw, camera-to-world, seconds), --points OUT.ply
the sparse map, --plot OUT.png estimated against true trajectory.
Exit status 1 with the status named on failure, 2 on bad usage.

Many recordings: `python -m libsfm.replay DIR1 DIR2 ... --dask ADDRESS`
(or replay_many(dirs, client=None)) runs one Dask task per recording, on a
local cluster by default, and gathers the reports into one CSV table
(--csv OUT.csv, else stdout). A task whose worker dies is retried by Dask.
"""
import argparse
import csv
import glob
import io
import os
import sys
import time

import numpy as np

# --------------------------------------------------------------------------
# recordings


class Recording:
    """frames: list of (timestamp_ns, path); camera: (fx, fy, cx, cy[, dist]) or
    None; gt: ground-truth camera-to-world poses, a dict timestamp_ns ->
    (R_wc 3x3, c 3) or None; gt_by_index: list aligned with frames or None;
    gravity: per-frame gravity in camera coordinates or None."""

    def __init__(self, name, frames, camera=None, gt_index=None, gravity=None, kind="",
                 model="pinhole"):
        self.name = name
        self.model = model  # camera model of camera: "pinhole" (Brown with dist), "fisheye"
        self.frames = frames
        self.camera = camera
        self.gt_index = gt_index
        self.gravity = gravity
        self.kind = kind


def _read_manifest(path):
    rows = []
    with open(path) as f:
        for line in f:
            line = line.strip()
            if not line or line.startswith("#"):
                continue
            parts = [p.strip() for p in line.split(",")]
            if not parts[0].lstrip("-").isdigit():
                continue  # header
            if len(parts) >= 3:
                rows.append((int(parts[1]), parts[2]))
            else:
                rows.append((int(parts[0]), parts[1]))
    return rows


def read_project_gt(path):
    """The demo's ground_truth.txt: camera lines and world-to-camera pose
    lines. Returns (camera tuple or None, {view: (R_cw, t_cw)}, gravity dict);
    read_project_model names the camera model."""
    cam, poses, grav = None, {}, {}
    with open(path) as f:
        for line in f:
            p = line.split()
            if not p or p[0].startswith("#"):
                continue
            if p[0] == "camera" and cam is None:
                cam = tuple(float(v) for v in p[2:])
            elif p[0] == "pose":
                v = np.array([float(x) for x in p[2:14]])
                poses[int(p[1])] = (v[:9].reshape(3, 3), v[9:12])
            elif p[0] == "gravity":
                grav[int(p[1])] = np.array([float(x) for x in p[2:5]])
    return cam, poses, grav


def read_project_model(path):
    """The camera model of a ground_truth.txt: its `camera_model <view> NAME`
    line (the fisheye sequence writes one), else "pinhole"."""
    with open(path) as f:
        for line in f:
            p = line.split()
            if len(p) >= 3 and p[0] == "camera_model":
                return p[2]
    return "pinhole"


def _kitti_calib(path):
    with open(path) as f:
        line = f.readline().split()
    vals = [float(v) for v in (line[1:] if line[0].endswith(":") else line)]
    P = np.array(vals[:12]).reshape(3, 4)
    return (P[0, 0], P[1, 1], P[0, 2], P[1, 2])


def read_kitti_poses(path):
    """KITTI poses.txt: 3x4 camera-to-world rows. Returns a list of (R_wc, c)."""
    out = []
    with open(path) as f:
        for line in f:
            v = [float(x) for x in line.split()]
            if len(v) == 12:
                M = np.array(v).reshape(3, 4)
                out.append((M[:, :3], M[:, 3]))
    return out


def read_tum(path):
    """TUM trajectory: timestamp tx ty tz qx qy qz qw (camera-to-world).
    Returns (timestamps seconds array, list of (R_wc, c))."""
    ts, poses = [], []
    with open(path) as f:
        for line in f:
            p = line.split()
            if not p or p[0].startswith("#") or len(p) < 8:
                continue
            v = [float(x) for x in p[:8]]
            ts.append(v[0])
            poses.append((quat_to_rot(v[7], v[4], v[5], v[6]), np.array(v[1:4])))
    return np.array(ts), poses


def _euroc_camera(yaml_path):
    intr, dist = None, None
    with open(yaml_path) as f:
        text = f.read()
    for line in text.splitlines():
        s = line.strip()
        if s.startswith("intrinsics:"):
            intr = [float(x) for x in s.split("[")[1].split("]")[0].split(",")]
        if s.startswith("distortion_coefficients:"):
            dist = [float(x) for x in s.split("[")[1].split("]")[0].split(",")]
    if intr is None:
        return None
    cam = tuple(intr)
    if dist:
        d = list(dist) + [0.0] * (5 - len(dist))
        cam = cam + tuple(d[:5])
    return cam


def open_recording(path, camera=None):
    """Recognises the layout of path and lists its frames."""
    path = os.path.abspath(path)
    name = os.path.basename(path.rstrip("/"))
    if not os.path.isdir(path):
        raise FileNotFoundError("no such directory: %s" % path)
    # KITTI odometry
    for sub in ("image_0", "image_2", "image_l"):
        d = os.path.join(path, sub)
        if os.path.isdir(d):
            files = sorted(glob.glob(os.path.join(d, "*.png")))
            if not files:
                raise FileNotFoundError("no PNG frames in %s" % d)
            times = os.path.join(path, "times.txt")
            if os.path.exists(times):
                ts = [int(round(float(x) * 1e9)) for x in open(times).read().split()]
            else:
                ts = [i * 100000000 for i in range(len(files))]
            cam = camera
            if cam is None and os.path.exists(os.path.join(path, "calib.txt")):
                cam = _kitti_calib(os.path.join(path, "calib.txt"))
            gt = None
            if os.path.exists(os.path.join(path, "poses.txt")):
                gt = read_kitti_poses(os.path.join(path, "poses.txt"))
            return Recording(name, list(zip(ts, files)), cam, gt, None, "kitti")
    # EuRoC
    for base in (os.path.join(path, "mav0", "cam0"), os.path.join(path, "cam0"), path):
        csvp = os.path.join(base, "data.csv")
        if os.path.exists(csvp) and os.path.isdir(os.path.join(base, "data")):
            rows = _read_manifest(csvp)
            frames = [(t, os.path.join(base, "data", f)) for t, f in rows]
            cam = camera
            if cam is None and os.path.exists(os.path.join(base, "sensor.yaml")):
                cam = _euroc_camera(os.path.join(base, "sensor.yaml"))
            return Recording(name, frames, cam, None, None, "euroc")
    # project replay directory
    man = os.path.join(path, "manifest.csv")
    if os.path.exists(man):
        rows = _read_manifest(man)
        frames = []
        for t, f in rows:
            full = os.path.join(path, f)
            if not os.path.exists(full):
                full = os.path.join(path, "data", f)
            frames.append((t, full))
        cam, gt, grav, model = camera, None, None, "pinhole"
        gtp = os.path.join(path, "ground_truth.txt")
        if os.path.exists(gtp):
            c, poses, g = read_project_gt(gtp)
            if cam is None:
                cam, model = c, read_project_model(gtp)
            if poses:
                gt = []
                for i in range(len(frames)):
                    if i + 1 in poses:
                        R, t = poses[i + 1]
                        gt.append((R.T, -R.T @ t))
                    else:
                        gt.append(None)
            if g:
                grav = [g.get(i + 1) for i in range(len(frames))]
        camp = os.path.join(path, "camera.txt")
        if cam is None and os.path.exists(camp):
            cam = tuple(float(v) for v in open(camp).read().replace(",", " ").split())
        return Recording(name, frames, cam, gt, grav, "replay", model)
    raise FileNotFoundError("%s: not a replay directory (manifest.csv), EuRoC or KITTI folder" % path)


# --------------------------------------------------------------------------
# metrics


def quat_to_rot(w, x, y, z):
    n = np.sqrt(w * w + x * x + y * y + z * z)
    w, x, y, z = w / n, x / n, y / n, z / n
    return np.array([[1 - 2 * (y * y + z * z), 2 * (x * y - z * w), 2 * (x * z + y * w)],
                     [2 * (x * y + z * w), 1 - 2 * (x * x + z * z), 2 * (y * z - x * w)],
                     [2 * (x * z - y * w), 2 * (y * z + x * w), 1 - 2 * (x * x + y * y)]])


def rot_to_quat(R):
    """(qx, qy, qz, qw) of a rotation matrix (Shepperd's method)."""
    tr = np.trace(R)
    if tr > 0:
        s = np.sqrt(tr + 1.0) * 2
        w, x, y, z = 0.25 * s, (R[2, 1] - R[1, 2]) / s, (R[0, 2] - R[2, 0]) / s, (R[1, 0] - R[0, 1]) / s
    elif R[0, 0] > R[1, 1] and R[0, 0] > R[2, 2]:
        s = np.sqrt(1.0 + R[0, 0] - R[1, 1] - R[2, 2]) * 2
        w, x, y, z = (R[2, 1] - R[1, 2]) / s, 0.25 * s, (R[0, 1] + R[1, 0]) / s, (R[0, 2] + R[2, 0]) / s
    elif R[1, 1] > R[2, 2]:
        s = np.sqrt(1.0 + R[1, 1] - R[0, 0] - R[2, 2]) * 2
        w, x, y, z = (R[0, 2] - R[2, 0]) / s, (R[0, 1] + R[1, 0]) / s, 0.25 * s, (R[1, 2] + R[2, 1]) / s
    else:
        s = np.sqrt(1.0 + R[2, 2] - R[0, 0] - R[1, 1]) * 2
        w, x, y, z = (R[1, 0] - R[0, 1]) / s, (R[0, 2] + R[2, 0]) / s, (R[1, 2] + R[2, 1]) / s, 0.25 * s
    q = np.array([x, y, z, w])
    return q if w >= 0 else -q


def umeyama(src, dst, with_scale=True):
    """s, R, t minimising |dst - (s R src + t)|^2 (Umeyama, PAMI 1991)."""
    src, dst = np.asarray(src, float), np.asarray(dst, float)
    mu_s, mu_d = src.mean(0), dst.mean(0)
    a, b = src - mu_s, dst - mu_d
    C = b.T @ a / len(src)
    U, S, Vt = np.linalg.svd(C)
    D = np.eye(3)
    if np.linalg.det(U) * np.linalg.det(Vt) < 0:
        D[2, 2] = -1
    R = U @ D @ Vt
    var = (a ** 2).sum() / len(src)
    s = (S * np.diag(D)).sum() / var if with_scale and var > 0 else 1.0
    t = mu_d - s * R @ mu_s
    return s, R, t


def rot_angle_deg(R):
    return float(np.degrees(np.arccos(np.clip((np.trace(R) - 1) / 2, -1, 1))))


def evaluate(est, gt):
    """est, gt: lists of (R_wc, c) for the same frames (pairs where both have a
    pose). Returns a dict: ate_rmse and ate_median after Sim3 alignment (in
    the ground truth's units), scale, RPE between consecutive entries
    (translation after the Sim3 scale, rotation in degrees), count."""
    if len(est) < 3:
        return {"count": len(est)}
    P = np.array([c for _, c in est])
    G = np.array([c for _, c in gt])
    s, R, t = umeyama(P, G)
    A = (s * (R @ P.T)).T + t
    err = np.linalg.norm(A - G, axis=1)
    rt, rr = [], []
    for k in range(len(est) - 1):
        Re0, ce0 = est[k]
        Re1, ce1 = est[k + 1]
        Rg0, cg0 = gt[k]
        Rg1, cg1 = gt[k + 1]
        # relative motion of frame k+1 in frame k's camera coordinates
        de = Re0.T @ (ce1 - ce0) * s
        dg = Rg0.T @ (cg1 - cg0)
        rt.append(np.linalg.norm(de - dg))
        rr.append(rot_angle_deg((Re0.T @ Re1).T @ (Rg0.T @ Rg1)))
    return {"count": len(est), "ate_rmse": float(np.sqrt((err ** 2).mean())),
            "ate_median": float(np.median(err)), "ate_max": float(err.max()), "scale": float(s),
            "rpe_trans_rmse": float(np.sqrt(np.mean(np.square(rt)))),
            "rpe_rot_median_deg": float(np.median(rr)), "rpe_rot_mean_deg": float(np.mean(rr)),
            "aligned": A, "gt": G}


# --------------------------------------------------------------------------
# writers


def write_tum(path, rows):
    """rows: (timestamp_ns, R_wc, c_w)."""
    with open(path, "w") as f:
        f.write("# timestamp tx ty tz qx qy qz qw (camera-to-world)\n")
        for ts, R, c in rows:
            q = rot_to_quat(R)
            f.write("%.9f %.9f %.9f %.9f %.9f %.9f %.9f %.9f\n" % ((ts / 1e9,) + tuple(c) + tuple(q)))


def write_ply(path, xyz, rgb=None):
    xyz = np.asarray(xyz, float).reshape(-1, 3)
    with open(path, "w") as f:
        f.write("ply\nformat ascii 1.0\nelement vertex %d\n" % len(xyz))
        f.write("property float x\nproperty float y\nproperty float z\n")
        if rgb is not None:
            f.write("property uchar red\nproperty uchar green\nproperty uchar blue\n")
        f.write("end_header\n")
        for i, p in enumerate(xyz):
            if rgb is not None:
                f.write("%.6f %.6f %.6f %d %d %d\n" % (p[0], p[1], p[2], rgb[i][0], rgb[i][1], rgb[i][2]))
            else:
                f.write("%.6f %.6f %.6f\n" % tuple(p))


def write_points(path, rep):
    """The run's points as PLY: with RGB (from the frame where each point was
    first seen) when the frames were colour; a point that never got a
    colour (first seen outside the image after the camera model) is gray."""
    ids = list(rep["points"].keys())
    xyz = np.array([rep["points"][k] for k in ids]) if ids else np.zeros((0, 3))
    rgb = None
    if rep.get("colours") is not None:
        rgb = [rep["colours"].get(k, (128, 128, 128)) for k in ids]
    write_ply(path, xyz, rgb)


def write_plot(path, report, title=""):
    import matplotlib
    matplotlib.use("Agg")
    import matplotlib.pyplot as plt
    fig, ax = plt.subplots(1, 2, figsize=(11, 5))
    A, G = report.get("aligned"), report.get("gt")
    E = report.get("est_raw")
    for k, (i, j, lab) in enumerate(((0, 2, "x-z (top view)"), (0, 1, "x-y"))):
        if G is not None:
            ax[k].plot(G[:, i], G[:, j], "k-", lw=2, label="ground truth")
        if A is not None:
            ax[k].plot(A[:, i], A[:, j], "r.-", ms=3, lw=1, label="libsfm VO (Sim3-aligned)")
        elif E is not None:
            ax[k].plot(E[:, i], E[:, j], "r.-", ms=3, lw=1, label="libsfm VO")
        ax[k].set_title(lab)
        ax[k].axis("equal")
        ax[k].grid(True)
        ax[k].legend()
    if "ate_rmse" in report:
        title += "  ATE (Sim3) RMSE %.3f, median %.3f" % (report["ate_rmse"], report["ate_median"])
    fig.suptitle(title)
    fig.tight_layout()
    fig.savefig(path, dpi=90)
    plt.close(fig)


# --------------------------------------------------------------------------
# running


def _load_gray(path):
    import cv2
    img = cv2.imread(path, cv2.IMREAD_GRAYSCALE)
    if img is None:
        raise OSError("cannot read image %s" % path)
    return img


def _load_frame(path):
    """(gray, colour or None): colour (RGB, uint8) only when the file has
    three channels; the pipeline sees the gray image either way."""
    import cv2
    img = cv2.imread(path, cv2.IMREAD_UNCHANGED)
    if img is None:
        raise OSError("cannot read image %s" % path)
    if img.ndim == 3 and img.shape[2] >= 3:
        bgr = np.ascontiguousarray(img[:, :, :3])
        if bgr.dtype != np.uint8:
            bgr = (bgr >> 8).astype(np.uint8) if bgr.dtype == np.uint16 else bgr.astype(np.uint8)
        return cv2.cvtColor(bgr, cv2.COLOR_BGR2GRAY), bgr[:, :, ::-1]
    return _load_gray(path), None


def _sample_colours(vo, keep, colours, images):
    """Colour of every live point not coloured yet, from the frame where it
    was first seen (its image in images, keyed by frame index)."""
    ids, px, frame = vo.map_points_first_seen()
    for k, (u, v), f in zip(ids.tolist(), px, frame.tolist()):
        if k in colours or f not in images or not np.all(np.isfinite((u, v))):
            continue
        img = images[f]
        x, y = int(round(u)), int(round(v))
        if 0 <= x < img.shape[1] and 0 <= y < img.shape[0]:
            colours[k] = tuple(int(c) for c in img[y, x])
    # images of frames no live point can still name are dropped
    for f in [f for f in images if f < keep]:
        del images[f]


def run(rec, max_features=1000, window=5, progress=True, print_every=0, seed=None,
        frame_budget=0.0, use_gravity=True, max_frames=None, **params):
    """Runs the pipeline over a Recording. Returns a dict report (metrics
    when ground truth is there) plus 'rows' (timestamp_ns, R_wc, c_w) and
    'points' (ids -> xyz) and per-frame results."""
    from .vo import STAGES, VisualOdometry
    # No intrinsics (none given, none in the recording, or --self-calibrate):
    # the pipeline self-calibrates a pinhole camera.
    frames = rec.frames[:max_frames] if max_frames else rec.frames
    first, first_rgb = _load_frame(frames[0][1])
    h, w = first.shape
    if seed is not None:
        params["seed"] = int(seed)
    if frame_budget:
        params["frame_budget"] = float(frame_budget)
    vo = VisualOdometry(w, h, rec.camera, max_features=max_features, window=window,
                        model=getattr(rec, "model", "pinhole"), **params)
    it = range(len(frames))
    bar = None
    if progress:
        try:
            from tqdm import tqdm
            bar = tqdm(total=len(frames), file=sys.stderr, desc=rec.name, unit="frame", leave=False)
        except ImportError:
            bar = None
    rows, results, points = [], [], {}
    colours, images = {}, {}  # point id -> RGB; keyframe index -> RGB image
    ms, stage = [], {s: 0.0 for s in STAGES}
    est_pairs, gt_pairs = [], []
    for i in it:
        ts, path = frames[i]
        img, rgb = (first, first_rgb) if i == 0 else _load_frame(path)
        g = rec.gravity[i] if (use_gravity and rec.gravity is not None) else None
        t0 = time.perf_counter()
        r = vo.push(img, ts, gravity=g)
        dt = time.perf_counter() - t0
        ms.append(dt * 1e3)
        for s in STAGES:
            stage[s] += r.stage_seconds[s]
        results.append(r)
        if r.has_pose:
            rows.append((ts, r.R_wc, r.c_w))
            if rec.gt_index is not None and i < len(rec.gt_index) and rec.gt_index[i] is not None:
                est_pairs.append((r.R_wc, r.c_w))
                gt_pairs.append(rec.gt_index[i])
        if r.is_keyframe:
            ids, xyz = vo.map_points()
            for k, p in zip(ids.tolist(), xyz):
                points[k] = p
            if rgb is not None:
                images[i] = rgb
                _, _, seen = vo.map_points_first_seen()
                _sample_colours(vo, int(seen.min()) if len(seen) else i, colours, images)
        if print_every and (i % print_every == 0 or i == len(frames) - 1):
            print("frame %4d  %-22s %-8s features %4d matches %4d inliers %4d map %5d  %.1f ms"
                  % (i, r.state, r.quality, r.n_features, r.n_matches, r.n_inliers,
                     r.n_map_points, dt * 1e3))
        if bar is not None:
            bar.update(1)
    if bar is not None:
        bar.close()
    ids, xyz = vo.map_points()
    for k, p in zip(ids.tolist(), xyz):
        points[k] = p
    if images:
        _sample_colours(vo, 0, colours, images)
    states = [r.state for r in results]
    rep = {"name": rec.name, "frames": len(frames), "width": w, "height": h,
           "tracked": states.count("tracking"), "lost": states.count("lost"),
           "with_pose": len(rows), "keyframes": sum(r.is_keyframe for r in results),
           "ms_median": float(np.median(ms)), "ms_p95": float(np.percentile(ms, 95)),
           "stage_share": {s: stage[s] / max(sum(stage.values()), 1e-12) for s in STAGES},
           "rows": rows, "points": points, "results": results,
           "colours": colours if first_rgb is not None else None,
           "self_calibrated": rec.camera is None,
           "segments": (max(r.segment for r in results) + 1) if results else 0,
           "focal": float(results[-1].focal) if results else 0.0,
           "focal_first": next((float(r.focal) for r in results if r.focal > 0), 0.0),
           "focal_frame": next((r.frame_index for r in results if r.focal > 0), -1)}
    if est_pairs:
        rep.update(evaluate(est_pairs, gt_pairs))
    rep["est_raw"] = np.array([c for _, _, c in rows]) if rows else None
    return rep


def summary_lines(rep):
    out = ["%s: %d frames %dx%d, %d tracking, %d lost, %d with a pose, %d keyframes"
           % (rep["name"], rep["frames"], rep["width"], rep["height"], rep["tracked"], rep["lost"],
              rep["with_pose"], rep["keyframes"])]
    if rep.get("segments", 1) > 1:
        out.append("%d segments (re-initialised after a loss): scale and origin of each later segment "
                   "only continued from the motion before the gap" % rep["segments"])
    if "ate_rmse" in rep:
        out.append("ATE after Sim3 alignment: RMSE %.4f, median %.4f, max %.4f (scale %.4f, %d poses)"
                   % (rep["ate_rmse"], rep["ate_median"], rep["ate_max"], rep["scale"], rep["count"]))
        out.append("RPE between consecutive frames: translation RMSE %.4f, rotation median %.4f deg, mean %.4f deg"
                   % (rep["rpe_trans_rmse"], rep["rpe_rot_median_deg"], rep["rpe_rot_mean_deg"]))
    if rep.get("self_calibrated"):
        if rep["focal_frame"] >= 0:
            out.append("self-calibrated focal length: %.2f px at frame %d, %.2f px after the windowed BA"
                       % (rep["focal_first"], rep["focal_frame"], rep["focal"]))
        else:
            out.append("self-calibration: no focal length found (no frame tracked)")
    out.append("ms/frame: median %.2f, p95 %.2f" % (rep["ms_median"], rep["ms_p95"]))
    out.append("share per stage: " + ", ".join("%s %.0f%%" % (k, 100 * v) for k, v in rep["stage_share"].items()))
    return out


CSV_FIELDS = ("name", "frames", "tracked", "lost", "with_pose", "keyframes", "ate_rmse",
              "ate_median", "rpe_trans_rmse", "rpe_rot_median_deg", "ms_median", "ms_p95",
              "focal", "status", "error")


def _report_row(rep):
    return {k: rep.get(k, "") for k in CSV_FIELDS}


def replay_one(path, camera=None, **kw):
    """One recording to a flat report (the Dask task): never raises; a failure
    is reported in the row's status and error columns."""
    try:
        rec = open_recording(path, camera)
        rep = run(rec, progress=False, **kw)
        row = _report_row(rep)
        row["status"] = "ok"
        return row
    except Exception as e:  # reported, not lost: one bad recording must not sink the fleet run
        return {"name": os.path.basename(str(path).rstrip("/")), "status": "error",
                "error": "%s: %s" % (type(e).__name__, e)}


def replay_many(dirs, client=None, camera=None, retries=3, **kw):
    """Evaluates many recordings on Dask distributed, one task per recording.
    client: a distributed.Client, a scheduler address, or None (a local
    cluster for the call). Tasks are submitted with retries, so a worker that
    dies mid-task costs a rerun, not a row. Returns a list of report rows in
    the order of dirs."""
    from distributed import Client, LocalCluster
    own = None
    if client is None:
        own = LocalCluster(n_workers=2, threads_per_worker=1, processes=True,
                           dashboard_address=None, host="127.0.0.1")
        client = Client(own)
    elif isinstance(client, str):
        client = Client(client)
    try:
        futs = [client.submit(replay_one, d, camera, pure=False, retries=retries, key="replay-%d-%s" % (i, os.path.basename(str(d).rstrip("/"))), **kw)
                for i, d in enumerate(dirs)]
        return client.gather(futs)
    finally:
        if own is not None:
            client.close()
            own.close()


def rows_to_csv(rows, out=None):
    buf = io.StringIO() if out is None else out
    w = csv.DictWriter(buf, fieldnames=CSV_FIELDS, extrasaction="ignore")
    w.writeheader()
    for r in rows:
        w.writerow(r)
    return buf.getvalue() if out is None else None


def _parse_camera(s):
    vals = tuple(float(v) for v in s.split(","))
    if len(vals) not in (4, 5, 6, 7, 8, 9):
        raise argparse.ArgumentTypeError("--camera wants fx,fy,cx,cy[,k1,k2,p1,p2,k3]")
    return vals


def main(argv=None):
    ap = argparse.ArgumentParser(prog="python -m libsfm.replay", description=__doc__.split("\n")[0])
    ap.add_argument("dirs", nargs="+", help="recording directories")
    ap.add_argument("--camera", type=_parse_camera, help="fx,fy,cx,cy[,k1,k2,p1,p2,k3]")
    ap.add_argument("--calib", help="file with fx fy cx cy [dist...] (or a KITTI calib.txt)")
    ap.add_argument("--model", choices=("pinhole", "fisheye"),
                    help="camera model of --camera / --calib (fisheye: fx,fy,cx,cy,k1,k2,k3,k4)")
    ap.add_argument("--self-calibrate", action="store_true",
                    help="ignore the recording's intrinsics: self-calibrate a pinhole camera")
    ap.add_argument("--gt", help="ground truth: KITTI poses.txt or TUM")
    ap.add_argument("--trajectory", help="write the trajectory (TUM, camera-to-world)")
    ap.add_argument("--points", help="write the sparse points (PLY)")
    ap.add_argument("--plot", help="write a PNG of estimated vs true trajectory")
    ap.add_argument("--features", type=int, default=1000)
    ap.add_argument("--window", type=int, default=5)
    ap.add_argument("--seed", type=int)
    ap.add_argument("--budget-ms", type=float, default=0.0, help="per-frame time budget")
    ap.add_argument("--every", type=int, default=0, help="print a status line every N frames")
    ap.add_argument("--no-progress", action="store_true")
    ap.add_argument("--set", action="append", default=[], metavar="KEY=VALUE",
                    help="a pipeline parameter (sfm_vo_params field, or n_levels / fast_threshold)")
    ap.add_argument("--dask", nargs="?", const="local", help="scheduler address, or none for a local cluster")
    ap.add_argument("--csv", help="fleet runs: write the table here (else stdout)")
    a = ap.parse_args(argv)
    from ._ffi import SfmError
    cam = a.camera
    if cam is None and a.calib:
        txt = open(a.calib).read().split()
        try:
            cam = _kitti_calib(a.calib) if len(txt) >= 12 else tuple(float(v) for v in txt)
        except ValueError:
            cam = _kitti_calib(a.calib)
    kw = {"max_features": a.features, "window": a.window, "seed": a.seed,
          "frame_budget": a.budget_ms / 1e3}
    for item in a.set:
        key, _, val = item.partition("=")
        try:
            kw[key] = int(val)
        except ValueError:
            try:
                kw[key] = float(val)
            except ValueError:
                ap.error("--set %s: not a number" % item)
    if a.dask is not None or len(a.dirs) > 1:
        client = None if a.dask in (None, "local") else a.dask
        rows = replay_many(a.dirs, client=client, camera=cam, **kw)
        if a.csv:
            with open(a.csv, "w", newline="") as f:
                rows_to_csv(rows, f)
        else:
            sys.stdout.write(rows_to_csv(rows))
        return 1 if any(r.get("status") != "ok" for r in rows) else 0
    try:
        rec = open_recording(a.dirs[0], cam)
        if a.model is not None:
            rec.model = a.model
        if a.self_calibrate:
            if cam is not None:
                ap.error("--self-calibrate excludes --camera / --calib")
            rec.camera = None
        if a.gt:
            if a.gt.endswith(".txt") and open(a.gt).readline().count(" ") >= 11 and not a.gt.endswith(".tum"):
                rec.gt_index = read_kitti_poses(a.gt)
            else:
                ts, poses = read_tum(a.gt)
                rec.gt_index = []
                for t_ns, _ in rec.frames:
                    k = int(np.argmin(np.abs(ts - t_ns / 1e9))) if len(ts) else -1
                    rec.gt_index.append(poses[k] if k >= 0 and abs(ts[k] - t_ns / 1e9) < 0.02 else None)
        rep = run(rec, progress=not a.no_progress, print_every=a.every, **kw)
    except SfmError as e:
        print("replay: failed: %s" % e, file=sys.stderr)
        return 1
    except (OSError, ValueError) as e:
        print("replay: failed: %s" % e, file=sys.stderr)
        return 1
    for line in summary_lines(rep):
        print(line)
    if a.trajectory:
        write_tum(a.trajectory, rep["rows"])
    if a.points:
        write_points(a.points, rep)
    if a.plot:
        write_plot(a.plot, rep, rec.name)
    if rep["with_pose"] < 2:
        print("replay: failed: no trajectory (%d frames with a pose)" % rep["with_pose"], file=sys.stderr)
        return 1
    return 0


if __name__ == "__main__":
    sys.exit(main())
