"""Scene generator of the degenerate-scene suite (test_degenerate.py): two
and three views of one synthetic camera (f = 500, 640 x 480), with a scene
class that makes the estimators' support degenerate or not.

Classes: general (points 4-10 units deep, baseline 1), collinear (one 3D
line), clustered (80 % of the points in one ball of radius 0.1 at 6 units,
20 % random matches), planar (one plane), pure_rotation (no translation),
zero_parallax (baseline 1e-4 at 4-10 units) and outliers (random matches
only). Every class but collinear and outliers has 20 % random matches. The
cameras' truth and noise-free probe correspondences of a general scene are
returned, so a model can be checked where its support did not reach.
"""
import numpy as np

F = 500.0
W, H = 640.0, 480.0
K = np.array([[F, 0, 320.0], [0, F, 240.0], [0, 0, 1]])
CLASSES = ("general", "collinear", "clustered", "planar", "pure_rotation", "zero_parallax",
           "outliers")


def rodrigues(w):
    th = np.linalg.norm(w)
    if th < 1e-15:
        return np.eye(3)
    k = w / th
    Kx = np.array([[0, -k[2], k[1]], [k[2], 0, -k[0]], [-k[1], k[0], 0]])
    return np.eye(3) + np.sin(th) * Kx + (1 - np.cos(th)) * Kx @ Kx


def project(R, t, X):
    Xc = X @ R.T + t
    return Xc[:, :2] / Xc[:, 2:3] * F + K[:2, 2], Xc[:, 2]


def visible(q, z):
    return (z > 0.5) & (q[:, 0] >= 0) & (q[:, 0] < W) & (q[:, 1] >= 0) & (q[:, 1] < H)


def random_pixels(rng, m):
    return np.column_stack([rng.uniform(0, W, m), rng.uniform(0, H, m)])


def cameras(rng, views, cls):
    """Poses x_cam = R X + t of `views` cameras, the first at the origin."""
    poses = [(np.eye(3), np.zeros(3))]
    for v in range(1, views):
        R = rodrigues(rng.normal(size=3) * np.radians(5))
        if cls == "pure_rotation":
            c = np.zeros(3)
        else:
            d = rng.normal(size=3)
            d[2] *= 0.3
            c = d / np.linalg.norm(d) * (1e-4 if cls == "zero_parallax" else 1.0) * v
        poses.append((R, -R @ c))
    return poses


def structure(rng, m, cls):
    """m world points of the class (in the first camera's frame)."""
    px = random_pixels(rng, m)
    rays = np.column_stack([(px - K[:2, 2]) / F, np.ones(m)])
    if cls == "collinear":
        a = np.array([rng.uniform(-2, 2), rng.uniform(-1.5, 1.5), rng.uniform(5, 8)])
        d = rng.normal(size=3)
        d /= np.linalg.norm(d)
        return a + rng.uniform(-3, 3, m)[:, None] * d
    if cls == "clustered":
        c = np.array([rng.uniform(-1, 1), rng.uniform(-0.8, 0.8), 6.0])
        u = rng.normal(size=(m, 3))
        u /= np.linalg.norm(u, axis=1, keepdims=True)
        return c + u * 0.1 * rng.uniform(0, 1, m)[:, None] ** (1 / 3)
    if cls == "planar":
        nrm = np.array([rng.uniform(-0.3, 0.3), rng.uniform(-0.3, 0.3), 1.0])
        return rays * (6.0 / (rays @ nrm))[:, None]
    return rays * rng.uniform(4, 10, m)[:, None]


def scene(rng, cls, n=200, views=2, sigma=0.3, outlier_share=0.2):
    """Returns dict(x: list of (n,2) pixels per view, poses, truth (n,) bool
    inlier mask, X (n,3), probe: list of (p,2) noise-free pixels per view of
    a general scene seen by the same cameras)."""
    poses = cameras(rng, views, cls)
    share = 0.0 if cls == "collinear" else (1.0 if cls == "outliers" else outlier_share)
    while True:  # one line, cluster or plane per scene: redraw it whole
        X = structure(rng, 20 * n, cls)
        ok = np.ones(len(X), dtype=bool)
        for R, t in poses:
            q, z = project(R, t, X)
            ok &= visible(q, z)
        if ok.sum() >= n:
            break
    X = X[ok][:n]
    x = [project(R, t, X)[0] + rng.normal(scale=sigma, size=(n, 2)) for R, t in poses]
    truth = rng.uniform(size=n) >= share
    for v in range(1, views):
        x[v][~truth] = random_pixels(rng, int((~truth).sum()))
    if cls == "outliers":
        x[0] = random_pixels(rng, n)
    Xp = structure(rng, 2000, "general")
    ok = np.ones(len(Xp), dtype=bool)
    for R, t in poses:
        q, z = project(R, t, Xp)
        ok &= visible(q, z)
    Xp = Xp[ok][:100]
    probe = [project(R, t, Xp)[0] for R, t in poses]
    return dict(x=x, poses=poses, truth=truth, X=X, probe=probe)


def rot_err(Ra, Rb):
    return float(np.degrees(np.arccos(np.clip((np.trace(Ra.T @ Rb) - 1) / 2, -1, 1))))


def dir_err(a, b):
    na, nb = np.linalg.norm(a), np.linalg.norm(b)
    if na < 1e-12 or nb < 1e-12:
        return 0.0
    return float(np.degrees(np.arccos(np.clip(a @ b / na / nb, -1, 1))))
