"""Frame-to-frame relative pose on the shared KITTI excerpt (kitti-seq1).

libsfm's own features (2000 per frame) and matcher (mutual, ratio 0.8) give
the pairs of frames i, i+1; the relative pose comes from
libsfm.estimate_relative_pose at its defaults (1 px threshold) and, beside
it, from OpenCV's findEssentialMat (RANSAC and USAC_MAGSAC, 1 px,
confidence 0.999) + recoverPose on the same pairs. Each step is scaled to
the ground-truth step length, the steps are chained, and the trajectory is
aligned to the ground truth by a similarity (Umeyama 1991); ATE is the RMS
of the aligned position errors. Per run (one seed): ATE, the largest
per-frame rotation error and translation-direction error against the ground
truth relative pose, and the time of the estimator calls.

Usage: python bench/kitti_f2f.py [--seeds 20] [--data ../shared/data/kitti-seq1]
"""
import argparse
import os
import sys
import time

import numpy as np

HERE = os.path.dirname(os.path.abspath(__file__))
sys.path.insert(0, os.path.join(HERE, "..", "python"))
import libsfm  # noqa: E402

DEFAULT_DATA = os.path.join(HERE, "..", "..", "shared", "data", "kitti-seq1")


def read_gray(path):
    import cv2
    img = cv2.imread(path, cv2.IMREAD_GRAYSCALE)
    if img is None:
        raise IOError("cannot read %s" % path)
    return img


def load(data_dir, n_frames=None):
    """K, ground-truth camera-to-world poses (n, 4, 4) and, per frame pair,
    the matched pixel coordinates (p1, p2)."""
    P0 = np.loadtxt(os.path.join(data_dir, "calib.txt"))[0].reshape(3, 4)
    K = P0[:, :3].copy()
    rows = np.loadtxt(os.path.join(data_dir, "poses.txt"))
    T = np.tile(np.eye(4), (rows.shape[0], 1, 1))
    T[:, :3, :] = rows.reshape(-1, 3, 4)
    files = sorted(f for f in os.listdir(os.path.join(data_dir, "image_l")) if f.endswith(".png"))
    if n_frames is not None:
        files = files[:n_frames]
    T = T[:len(files)]
    feats = [libsfm.detect_and_describe(read_gray(os.path.join(data_dir, "image_l", f)),
                                        max_features=2000) for f in files]
    pairs = []
    for i in range(len(files) - 1):
        (k1, d1), (k2, d2) = feats[i], feats[i + 1]
        m = libsfm.match(d1, d2, ratio=0.8, mutual=True)
        pairs.append((np.ascontiguousarray(k1[m[:, 0], :2]), np.ascontiguousarray(k2[m[:, 1], :2])))
    return K, T, pairs


def gt_relative(T, i):
    """x_{i+1} = R x_i + t from the camera-to-world poses."""
    M = np.linalg.inv(T[i + 1]) @ T[i]
    return M[:3, :3], M[:3, 3]


def rot_err_deg(Ra, Rb):
    return float(np.degrees(np.arccos(np.clip((np.trace(Ra.T @ Rb) - 1) / 2, -1, 1))))


def dir_err_deg(a, b):
    c = a @ b / (np.linalg.norm(a) * np.linalg.norm(b))
    return float(np.degrees(np.arccos(np.clip(c, -1, 1))))


def umeyama_ate(est, gt):
    """RMS position error after the best similarity est -> gt."""
    mu_e, mu_g = est.mean(0), gt.mean(0)
    E, G = est - mu_e, gt - mu_g
    U, S, Vt = np.linalg.svd(G.T @ E / len(est))
    D = np.eye(3)
    if np.linalg.det(U) * np.linalg.det(Vt) < 0:
        D[2, 2] = -1
    R = U @ D @ Vt
    s = np.trace(np.diag(S) @ D) / (E ** 2).sum(1).mean()
    aligned = s * E @ R.T + mu_g
    return float(np.sqrt(((aligned - gt) ** 2).sum(1).mean()))


def run(estimate, K, T, pairs, seed):
    """Chains the relative poses of estimate(p1, p2, K, seed) -> (R, t)."""
    pos = [T[0][:3, 3].copy()]
    C = T[0].copy()  # camera-to-world of the current frame (estimated)
    worst_r = worst_t = 0.0
    elapsed = 0.0
    for i, (p1, p2) in enumerate(pairs):
        Rg, tg = gt_relative(T, i)
        t0 = time.perf_counter()
        R, t = estimate(p1, p2, K, seed + 1000 * i)
        elapsed += time.perf_counter() - t0
        worst_r = max(worst_r, rot_err_deg(R, Rg))
        worst_t = max(worst_t, dir_err_deg(t, tg))
        t = t / np.linalg.norm(t) * np.linalg.norm(tg)
        M = np.eye(4)
        M[:3, :3], M[:3, 3] = R, t
        C = C @ np.linalg.inv(M)
        pos.append(C[:3, 3].copy())
    ate = umeyama_ate(np.array(pos), T[:len(pos), :3, 3])
    return ate, worst_r, worst_t, elapsed


def est_libsfm(p1, p2, K, seed, **kw):
    r = libsfm.estimate_relative_pose(p1, p2, K, K, threshold_px=1.0, seed=seed, **kw)
    return r["R"], r["t"]


def est_cv2(method):
    import cv2

    def f(p1, p2, K, seed):
        cv2.setRNGSeed(seed)
        E, mask = cv2.findEssentialMat(p1, p2, K, method=method, prob=0.999, threshold=1.0)
        if E is None or E.shape != (3, 3):
            return np.eye(3), np.array([0.0, 0.0, -1.0])
        _, R, t, _ = cv2.recoverPose(E, p1, p2, K, mask=mask)
        return R, t.ravel()
    return f


def summary(name, runs):
    a = np.array(runs)
    bad = int((a[:, 1] > 2.0).sum())
    print("| %s | %.3f | %.3f - %.3f | %.2f | %.1f | %d of %d | %.1f |" %
          (name, np.median(a[:, 0]), a[:, 0].min(), a[:, 0].max(), a[:, 1].max(), a[:, 2].max(),
           bad, len(a), 1e3 * np.median(a[:, 3]) / 50), flush=True)


def main():
    ap = argparse.ArgumentParser()
    ap.add_argument("--seeds", type=int, default=20)
    ap.add_argument("--data", default=DEFAULT_DATA)
    ap.add_argument("--no-opencv", action="store_true")
    args = ap.parse_args()
    if not os.path.isdir(args.data):
        print("SKIP: %s not found" % args.data)
        return
    import cv2
    cv2.setNumThreads(1)
    K, T, pairs = load(args.data)
    methods = [("libsfm (defaults)", est_libsfm)]
    if not args.no_opencv:
        methods += [("cv2 RANSAC", est_cv2(cv2.RANSAC)), ("cv2 USAC_MAGSAC", est_cv2(cv2.USAC_MAGSAC))]
    print("kitti-seq1, %d frame pairs, %d seeds, median matches per pair %d" %
          (len(pairs), args.seeds, int(np.median([len(p[0]) for p in pairs]))))
    print("| method | median ATE m | ATE range m | worst R err deg | worst t dir err deg | "
          "runs with a frame R err > 2 deg | ms per frame |")
    print("|---|---|---|---|---|---|---|")
    for name, f in methods:
        summary(name, [run(f, K, T, pairs, s) for s in range(args.seeds)])


if __name__ == "__main__":
    main()
