"""Dense stereo against exact depth (rendered pairs), against OpenCV's
stereoRectify, StereoBM and StereoSGBM on the same inputs, and on Herz-Jesu-P8
against its ground-truth cameras."""
import os
import sys

import cv2
import numpy as np
import pytest

import libsfm

ROOT = os.path.join(os.path.dirname(__file__), "..", "..")
sys.path.insert(0, os.path.join(ROOT, "tools"))
import gen_demo_scene as scene  # noqa: E402

HERZ = os.path.join(ROOT, "..", "shared", "data", "herzjesu-p8")
K = np.array([[scene.FX, 0, scene.CX], [0, scene.FY, scene.CY], [0, 0, 1.0]])
ND = 64


def rot(axis, deg):
    return {"x": scene.rot_x, "y": scene.rot_y, "z": scene.rot_z}[axis](deg)


@pytest.fixture(scope="module")
def world():
    rng = np.random.default_rng(scene.SEED)
    quads = scene.scene()
    tex = [scene.texture(rng, np.linalg.norm(u), np.linalg.norm(v)) for _, u, v in quads]
    return quads, tex


def shoot(world, R, C, seed):
    quads, tex = world
    img, depth = scene.render(quads, tex, R, -R @ C, return_depth=True)
    noise = np.random.default_rng(seed).normal(0.0, scene.NOISE_SIGMA, img.shape)
    return np.clip(np.rint(img + noise), 0, 255).astype(np.uint8), depth


@pytest.fixture(scope="module")
def rectified_pair(world):
    """A pair already rectified (camera 2 0.3 m to the right): exact
    disparity f B / Z for every pixel of the left image."""
    C1 = np.array([0.0, 0.0, 0.5])
    L, Z = shoot(world, np.eye(3), C1, 1)
    R, _ = shoot(world, np.eye(3), C1 + [0.3, 0, 0], 2)
    return L, R, scene.FX * 0.3 / Z


def quality(d, truth):
    m = truth < ND
    v = np.isfinite(d) & m
    e = np.abs(d - truth)
    return v.sum() / m.sum(), (e[v] > 1).mean(), (e[v] > 2).mean()


def opencv_sgbm(L, R, block=5):
    cv2.setNumThreads(1)
    sg = cv2.StereoSGBM_create(minDisparity=0, numDisparities=ND, blockSize=block, P1=8 * block * block,
                               P2=32 * block * block, uniquenessRatio=10, disp12MaxDiff=1)
    d = sg.compute(L, R).astype(np.float32) / 16.0
    d[d < 0] = np.nan
    return d


def opencv_bm(L, R, block=7):
    cv2.setNumThreads(1)
    d = cv2.StereoBM_create(numDisparities=ND, blockSize=block).compute(L, R).astype(np.float32) / 16.0
    d[d < 0] = np.nan
    return d


def test_sgm_against_exact_depth_and_stereosgbm(rectified_pair):
    L, R, truth = rectified_pair
    ours = quality(libsfm.disparity_sgm(L, R, ND), truth)
    ours8 = quality(libsfm.disparity_sgm(L, R, ND, paths=8), truth)
    cv = quality(opencv_sgbm(L, R), truth)
    print("\nvalid / bad-1 / bad-2: libsfm SGM 5 paths %.3f %.4f %.4f, 8 paths %.3f %.4f %.4f, "
          "StereoSGBM %.3f %.4f %.4f" % (ours + ours8 + cv))
    assert ours[0] >= cv[0]
    assert ours[2] <= cv[2] * 1.05
    assert ours8[0] >= cv[0] and ours8[2] <= cv[2]


def test_block_matching_against_exact_depth_and_stereobm(rectified_pair):
    L, R, truth = rectified_pair
    # radius 2: a 5x5 centre window whose corner windows span 15x15
    ours = quality(libsfm.disparity_block(L, R, ND, radius=2), truth)
    cv = quality(opencv_bm(L, R, 7), truth)
    print("\nvalid / bad-1 / bad-2: libsfm block %.3f %.4f %.4f, StereoBM %.3f %.4f %.4f" % (ours + cv))
    assert ours[0] >= cv[0]
    assert ours[2] <= cv[2]


def test_texture_poor_region_is_marked_not_guessed():
    rng = np.random.default_rng(5)
    tex = rng.integers(0, 256, (120, 212)).astype(np.uint8)
    tex[:, 106:] = 90  # flat right half
    L, R = tex[:, 6:206].copy(), tex[:, 12:212].copy()  # right(x) = left(x + 6)
    d = libsfm.disparity_block(L, R, 16)
    flat = d[10:-10, 120:-10]
    textured = d[10:-10, 30:90]
    assert np.isfinite(flat).mean() < 0.02
    assert np.nanmedian(np.abs(textured - 6)) < 0.2 and np.isfinite(textured).mean() > 0.9
    ds = libsfm.disparity_sgm(L, R, 16)
    wrong = np.isfinite(ds[10:-10, 130:-10]) & (np.abs(ds[10:-10, 130:-10] - 6) > 1)
    assert wrong.mean() < 0.05


def test_negative_min_disparity():
    rng = np.random.default_rng(6)
    L = cv2.GaussianBlur(rng.integers(0, 256, (100, 160)).astype(np.uint8), (3, 3), 0)
    R = np.roll(L, 3, axis=1)  # right(x) = left(x - 3): disparity -3
    d = libsfm.disparity_sgm(L, R, 16, min_disparity=-8)
    core = d[10:-10, 20:-20]
    assert np.isfinite(core).mean() > 0.9
    assert np.nanmedian(np.abs(core + 3)) < 0.2


def random_rig(rng):
    R = rot("y", rng.uniform(-4, 4)) @ rot("x", rng.uniform(-3, 3)) @ rot("z", rng.uniform(-3, 3))
    C2 = np.array([rng.uniform(0.2, 0.5), rng.uniform(-0.03, 0.03), rng.uniform(-0.05, 0.05)])
    return R, -R @ C2


def test_rectification_against_opencv_stereorectify():
    rng = np.random.default_rng(11)
    size = (640, 480)
    worst_ours = worst_cv = 0.0
    for _ in range(20):
        R, t = random_rig(rng)
        K2 = K.copy()
        K2[0, 0] = K2[1, 1] = rng.uniform(450, 550)
        dist = np.array([rng.uniform(-0.2, 0.0), rng.uniform(0.0, 0.05), 0, 0, 0])
        ours = libsfm.rectify_pair(K, K2, R, t, size, dist1=dist, dist2=dist)
        R1, R2, P1, P2, Q, _, _ = cv2.stereoRectify(K, dist, K2, dist, size, R, t.reshape(3, 1), alpha=-1)
        # Both put the rectified x axis along the baseline.
        assert abs(ours["R1"][0] @ R1[0]) > 1 - 1e-9
        # Matches of random points: rows aligned after rectification.
        X = np.column_stack([rng.uniform(-2, 2, 200), rng.uniform(-1.5, 1.5, 200), rng.uniform(3, 9, 200)])
        x1 = cv2.projectPoints(X, np.zeros(3), np.zeros(3), K, dist)[0].reshape(-1, 2)
        x2 = cv2.projectPoints(X, cv2.Rodrigues(R)[0], t, K2, dist)[0].reshape(-1, 2)
        inside = np.all((x1 >= 0) & (x1 < size) & (x2 >= 0) & (x2 < size), axis=1)
        x1, x2 = x1[inside], x2[inside]
        med, mx, n = libsfm.rectification_error(x1, x2, rect=ours, K1=K, K2=K2, dist1=dist, dist2=dist)
        assert n == len(x1)
        r1 = cv2.undistortPoints(x1.reshape(-1, 1, 2), K, dist, R=R1, P=P1).reshape(-1, 2)
        r2 = cv2.undistortPoints(x2.reshape(-1, 1, 2), K2, dist, R=R2, P=P2).reshape(-1, 2)
        worst_ours = max(worst_ours, mx)
        worst_cv = max(worst_cv, np.abs(r1[:, 1] - r2[:, 1]).max())
    print("\nmax vertical disparity of true matches: libsfm %.2e px, OpenCV %.2e px" % (worst_ours, worst_cv))
    assert worst_ours < 1e-3
    assert worst_ours <= worst_cv + 1e-6


def test_end_to_end_rectify_remap_sgm_depth(world):
    """A pair that is not rectified (camera 2 turned and raised): rectify,
    remap, SGM, depth, and compare with the exact depth of view 1."""
    C1 = np.array([0.0, 0.0, 0.5])
    R2 = rot("y", -3.0) @ rot("x", 1.0)
    C2 = C1 + np.array([0.3, 0.02, 0.03])
    L, Z = shoot(world, np.eye(3), C1, 3)
    Rimg, _ = shoot(world, R2, C2, 4)
    rect = libsfm.rectify_pair(K, K, R2, -R2 @ (C2 - C1), (640, 480))
    Lr = libsfm.remap(L, rect["maps"], 1)
    Rr = libsfm.remap(Rimg, rect["maps"], 2)
    # The rectified principal points differ (cx1 - cx2): disparities are
    # f B / Z plus that offset, so the searched range starts there.
    doff = rect["K1"][0, 2] - rect["K2"][0, 2]
    d = libsfm.disparity_sgm(Lr, Rr, ND, min_disparity=int(np.floor(doff)))
    pts, idx = libsfm.disparity_to_points(d, rect=rect)
    # Exact depth of those points: project each into view 1 and read Z there.
    u = pts[:, 0] / pts[:, 2] * scene.FX + scene.CX
    v = pts[:, 1] / pts[:, 2] * scene.FY + scene.CY
    ok = (u >= 0) & (u <= 639) & (v >= 0) & (v <= 479)
    zt = Z[np.rint(v[ok]).astype(int), np.rint(u[ok]).astype(int)]
    rel = np.abs(pts[ok, 2] - zt) / zt
    print("\nend to end: %d points, median relative depth error %.4f, share > 5%% %.4f"
          % (len(rel), np.median(rel), (rel > 0.05).mean()))
    assert len(rel) > 0.6 * 640 * 480
    assert np.median(rel) < 0.01
    assert (rel > 0.05).mean() < 0.03


def test_bad_input_is_a_status():
    a = np.zeros((50, 60), np.uint8)
    with pytest.raises(ValueError):
        libsfm.disparity_sgm(a, np.zeros((50, 61), np.uint8))
    with pytest.raises(ValueError):  # range wider than the image
        libsfm.disparity_sgm(a, a, num_disparities=128)
    with pytest.raises(ValueError):
        libsfm.disparity_block(a, a, num_disparities=12)
    with pytest.raises(libsfm.SfmError):  # forward motion: no planar rectification
        libsfm.rectify_pair(K, K, np.eye(3), [0, 0, -0.5], (640, 480))


def load_strecha(stem):
    v = np.array([float(x) for x in open(os.path.join(HERZ, "gt_dense_cameras", stem + ".jpg.camera")).read().split()[:24]])
    Kc = v[:9].reshape(3, 3)
    Rw = v[12:21].reshape(3, 3)  # camera-to-world
    C = v[21:24]
    return Kc, Rw.T, -Rw.T @ C


@pytest.mark.skipif(not os.path.isdir(HERZ), reason="../shared/data/herzjesu-p8 not present")
def test_herzjesu_dense_depth_against_triangulated_matches():
    """Views 0003 and 0004 (a sideways step of 2.7 m, the best-conditioned
    neighbours: 0000-0001 moves mostly forward, its epipoles lie inside the
    images), reduced 4x, rectified from the true cameras; the dense depth
    against SIFT triplet matches of views 3, 4, 5 triangulated with the true
    cameras."""
    s = 4
    cams = [load_strecha(v) for v in ("0003", "0004", "0005")]
    K0 = cams[0][0]
    Ks = np.diag([1.0 / s, 1.0 / s, 1.0]) @ K0
    Ks[0, 2] = (K0[0, 2] + 0.5) / s - 0.5
    Ks[1, 2] = (K0[1, 2] + 0.5) / s - 0.5
    imgs = [cv2.imread(os.path.join(HERZ, "images", "%04d.jpg" % i), cv2.IMREAD_GRAYSCALE) for i in (3, 4)]
    imgs = [cv2.resize(im, (im.shape[1] // s, im.shape[0] // s), interpolation=cv2.INTER_AREA) for im in imgs]
    h, w = imgs[0].shape
    (_, R0, t0), (_, R1, t1), (_, R2, t2) = cams
    Rrel = R1 @ R0.T
    trel = t1 - Rrel @ t0
    rect = libsfm.rectify_pair(Ks, Ks, Rrel, trel, (w, h))
    Lr = libsfm.remap(imgs[0], rect["maps"], 1)
    Rr = libsfm.remap(imgs[1], rect["maps"], 2)
    # Sparse truth: triplet matches triangulated with the true cameras, kept
    # where they reproject within 1 px in all three views.
    m = np.loadtxt(os.path.join(HERZ, "triplets", "triplet_0003_0004_0005.txt"))
    Ps = [c[0] @ np.column_stack([c[1], c[2]]) for c in cams]
    X = cv2.triangulatePoints(Ps[0], Ps[1], m[:, 0:2].T, m[:, 2:4].T)
    X = (X[:3] / X[3]).T
    err = [np.linalg.norm((lambda p: p[:, :2] / p[:, 2:])((P @ np.column_stack([X, np.ones(len(X))]).T).T)
                          - m[:, c:c + 2], axis=1) for P, c in zip(Ps, (0, 2, 4))]
    good = np.max(err, axis=0) < 1.0
    xr = (rect["R1"] @ ((R0 @ X[good].T).T + t0).T).T  # rectified camera 1
    f, B = rect["K1"][0, 0], rect["baseline"]
    doff = rect["K1"][0, 2] - rect["K2"][0, 2]
    u = f * xr[:, 0] / xr[:, 2] + rect["K1"][0, 2]
    v = f * xr[:, 1] / xr[:, 2] + rect["K1"][1, 2]
    inside = (u >= 0) & (u <= w - 1) & (v >= 0) & (v <= h - 1) & (xr[:, 2] > 0)
    # The disparity range a user would take from the sparse reconstruction.
    dsp = f * B / xr[inside, 2] + doff
    dmin = int(np.floor(dsp.min() - 16)) // 8 * 8
    num = min(256, int(np.ceil((dsp.max() + 16 - dmin) / 8.0)) * 8)
    d = libsfm.disparity_sgm(Lr, Rr, num_disparities=num, min_disparity=dmin)
    depth = libsfm.disparity_to_depth(d, rect=rect)
    dz = depth[np.rint(v[inside]).astype(int), np.rint(u[inside]).astype(int)]
    zt = xr[inside, 2]
    have = np.isfinite(dz)
    rel = np.abs(dz[have] - zt[have]) / zt[have]
    print("\nHerz-Jesu 0003-0004 at 1/4 (%dx%d), disparities %d..%d: %d sparse points, %d with a dense "
          "depth, median relative depth error %.4f, share > 5%% %.3f, dense valid %.3f"
          % (w, h, dmin, dmin + num - 1, inside.sum(), have.sum(), np.median(rel), (rel > 0.05).mean(),
             np.isfinite(d).mean()))
    assert inside.sum() > 100
    assert have.sum() >= 0.6 * inside.sum()
    assert np.median(rel) < 0.01
    assert (rel > 0.05).mean() < 0.1


def test_fisheye_pair_rectifies_through_the_camera_model():
    rng = np.random.default_rng(12)
    cam = libsfm.Camera("fisheye", 300.0, 300.0, 319.5, 239.5, dist=(0.05, -0.01, 0.002, 0.0))
    R, t = random_rig(rng)
    rect = libsfm.rectify_pair(cam, cam, R, t, (640, 480))
    X = np.column_stack([rng.uniform(-3, 3, 300), rng.uniform(-2, 2, 300), rng.uniform(2, 8, 300)])
    x1 = cam.project(X)
    x2 = cam.project((R @ X.T).T + t)
    ok = np.all((x1 >= 0) & (x1 < (640, 480)) & (x2 >= 0) & (x2 < (640, 480)), axis=1)
    med, mx, n = libsfm.rectification_error(x1[ok], x2[ok], rect=rect, K1=cam, K2=cam)
    assert n == ok.sum() > 50
    assert mx < 1e-6
    # The remap reads the source through the fisheye model: the map of a
    # rectified pixel is the fisheye projection of its ray.
    m = rect["maps"][0]
    v, u = 240, 320
    ray = rect["R1"].T @ np.array([(u - rect["K1"][0, 2]) / rect["K1"][0, 0],
                                   (v - rect["K1"][1, 2]) / rect["K1"][1, 1], 1.0])
    src = cam.project(ray[None, :])[0]
    assert np.abs(m[v, u] / 256.0 - src).max() < 1.0 / 256 + 1e-9


def test_three_uncalibrated_views_to_a_dense_cloud(world):
    """The seed's end to end (python -m libsfm.stereo_demo): the demo room's
    three views, no intrinsics given; the dense points against the exact
    depth of view 1, after fixing the reconstruction's free scale from the
    true baseline of view 2."""
    from libsfm import stereo_demo
    poses = scene.cameras()
    imgs, depth1 = [], None
    for k, (R, t) in enumerate(poses):
        img, z = shoot(world, R, -R.T @ t, 20 + k)
        imgs.append(img)
        depth1 = z if k == 0 else depth1
    r = stereo_demo.stereo_from_three_views(*imgs, seed=1)
    assert abs(r["K"][0, 0] / scene.FX - 1) < 0.05
    i, j = r["pair"]
    assert i == 0  # points in view 1's frame
    rec = r["recon"]
    s = np.linalg.norm(-poses[1][0].T @ poses[1][1]) / np.linalg.norm(-rec["R"][1].T @ rec["t"][1])
    P = r["points"] * s
    u = P[:, 0] / P[:, 2] * scene.FX + scene.CX
    v = P[:, 1] / P[:, 2] * scene.FY + scene.CY
    ok = (u >= 0) & (u <= 639) & (v >= 0) & (v <= 479)
    zt = depth1[np.rint(v[ok]).astype(int), np.rint(u[ok]).astype(int)]
    rel = np.abs(P[ok, 2] - zt) / zt
    print("\nthree uncalibrated views: f %.1f px, pair %d-%d, %d dense points, median relative depth error "
          "%.4f, share > 5%% %.3f" % (r["K"][0, 0], i + 1, j + 1, len(P), np.median(rel), (rel > 0.05).mean()))
    assert len(P) > 0.4 * 640 * 480
    assert np.median(rel) < 0.03
    assert (rel > 0.05).mean() < 0.15


def test_depth_from_q_matches_opencv_reprojection():
    rng = np.random.default_rng(13)
    R, t = random_rig(rng)
    rect = libsfm.rectify_pair(K, K, R, t, (640, 480))
    d = rng.uniform(20, 60, (48, 64)).astype(np.float32)
    d[::7, ::5] = np.nan
    ours = libsfm.disparity_to_depth(d, Q=rect["Q"])
    cv = cv2.reprojectImageTo3D(np.nan_to_num(d, nan=-1.0), rect["Q"])[..., 2]
    ok = np.isfinite(d)
    assert np.isnan(ours[~ok]).all()
    assert np.allclose(ours[ok], cv[ok], rtol=1e-5)
    assert np.allclose(ours, libsfm.disparity_to_depth(d, rect=rect), equal_nan=True)
