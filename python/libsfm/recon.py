"""Uncalibrated reconstruction: projective factorization, self-calibration by
the absolute dual quadric, and the three- and two-view pipelines from pixels
of an unknown camera (zero skew, unit aspect, principal point at the image
centre, one focal length; with three views also up to two radial
distortion terms, Brown k1 and k2 about the centre). Poses are
world-to-camera, x_cam = R X + t, view 1 the world frame, |t[1]| = 1."""
import numpy as np

from ._ffi import SfmError, as_array, check, dptr, ffi, lib, to_float, to_int, to_seed, workspace

PATHS = {0: "none", 1: "linear", 2: "sweep"}
PRINCIPAL = {"centre": 0, "shared": 1, "per_view": 2}
STAGES = {1: "ransac", 2: "selfcal", 3: "sweep", 4: "ba", 5: "validate", 6: "done"}


def factorize_projective(tracks, max_iterations=None, tolerance=None, ba_iterations=None):
    """Sturm-Triggs projective factorization of (m, n, 2) pixel tracks, NaN
    where a view does not see a track.

    Returns dict(P (m,3,4), X (n,4) unit-norm homogeneous points (zero for
    tracks seen in fewer than 2 views), reproj_rms (px, after the projective
    bundle adjustment), factorization_rms (before it), ba_iterations, iterations,
    converged, monotone, first_residual, last_residual, block_views,
    block_points, points_recovered, n_observations), up to one projective
    transform of space.
    """
    x = np.ascontiguousarray(np.asarray(tracks, dtype=np.float64))
    if x.ndim != 3 or x.shape[2] != 2:
        raise ValueError("tracks must have shape (m, n, 2), got %s" % (x.shape,))
    m, n = x.shape[0], x.shape[1]
    need = lib.sfm_factorize_workspace_size(m, n)
    if need == 0:
        raise ValueError("need 2..%d views and at least %d tracks, got (%d, %d)"
                         % (lib.SFM_FACTORIZE_MAX_VIEWS, lib.SFM_FACTORIZE_MIN_BLOCK_POINTS, m, n))
    opt = ffi.new("sfm_factorize_options *")
    lib.sfm_factorize_default_options(opt)
    if max_iterations is not None:
        opt.max_iterations = int(max_iterations)
    if tolerance is not None:
        opt.tolerance = float(tolerance)
    if ba_iterations is not None:
        opt.ba_iterations = int(ba_iterations)
    P = np.empty((m, 3, 4))
    X = np.empty((n, 4))
    res = ffi.new("sfm_factorize_result *")
    buf, ws, size = workspace(need)
    check(lib.sfm_factorize_projective(m, n, dptr(x), opt, dptr(P), dptr(X), res, ws, size),
          "factorize_projective")
    out = dict(P=P, X=X)
    for k in ("reproj_rms", "factorization_rms", "ba_iterations", "ba_stop", "iterations", "converged", "monotone", "first_residual", "last_residual",
              "block_views", "block_points", "points_recovered", "n_observations"):
        out[k] = getattr(res, k)
    out["converged"] = bool(out["converged"])
    out["monotone"] = bool(out["monotone"])
    return out


def _selfcal_report(r, m):
    n = r.sweep_count
    return dict(path=PATHS.get(r.path, r.path), linear_status=r.linear_status, linear_flags=r.linear_flags,
                focal_linear=r.focal_linear, focal_sweep=r.focal_sweep, focal=r.focal,
                focal_view=np.array([r.focal_view[i] for i in range(m)]), per_view=bool(r.per_view),
                principal={v: k for k, v in PRINCIPAL.items()}.get(r.principal, r.principal),
                focal_sigma=r.focal_sigma, profile_rise=r.profile_rise, noise_sigma=r.noise_sigma,
                evaluations=r.evaluations, sweep_focal=np.array([r.sweep_focal[k] for k in range(n)]),
                sweep_cost=np.array([r.sweep_cost[k] for k in range(n)]), points=r.points,
                observations=r.observations, rms=r.rms, front_fraction=r.front_fraction)


def self_calibrate(P, image_sizes, X=None, tracks=None, per_view_focal=False, principal="centre", sweep="always",
                   sweep_steps=None, focal_range=None, max_rms=None, loss_scale=None, max_focal_sigma=None,
                   min_profile=None):
    """Self-calibration of m >= 3 projective cameras P (m,3,4) in pixels;
    image_sizes (m,2) or one (width, height). X (n,4) homogeneous points of
    the same frame (zero rows unused).

    Without tracks: the linear absolute dual quadric only (principal point
    at the centre, zero skew, unit aspect); X, optional, resolves the mirror
    by cheirality. Returns dict(K (m,3,3), H (4,4) with P_i H ~ K_i [R_i |
    t_i], path "linear", flags, null_ratio, weak_ratio, front_fraction);
    raises SfmError
    when the linear solution is unusable (the error's .flags says why: 1 not
    semi-definite, 2 a w*_i not definite, 4 cheirality, 8 critical motion).

    With tracks (m,n,2) pixels, NaN where a view does not see point j (the
    observations a metric bundle adjustment needs; X required): the linear
    start, then a search over one shared focal length (sweep="always", or
    "when_needed": only when the linear solution is unusable), each
    candidate scored by a metric bundle adjustment with f held; the better
    start refined with f free; then, each kept when it passes the checks,
    principal="shared" frees one principal point for all views,
    per_view_focal=True a focal length per view, principal="per_view" a
    focal length and a principal point per view ("centre": held at the
    image centre). Returns dict(K (m,3,3), H (4,4), R (m,3,3),
    t (m,3) with x_cam = R X + t (view 1 the identity, farthest centre at
    distance 1), X (n,3) metric points (zero where not adjusted), path
    "linear" or "sweep", focal, focal_view (m,), per_view, principal (the
    model kept), focal_sigma (relative
    standard deviation of f from the profile), profile_rise, sweep_focal,
    sweep_cost, rms, front_fraction, ...). Raises SfmError when f is not
    determined (a flat profile: SFM_E_SINGULAR) or the answer fails a
    physical check (SFM_E_NO_CONVERGENCE); the error carries .report.
    focal_range: (min, max) multiples of (width + height) / 2.
    """
    P = as_array(P, (None, 3, 4), "P")
    m = P.shape[0]
    if not 3 <= m <= lib.SFM_SELFCAL_MAX_VIEWS:
        raise ValueError("P must hold 3..%d views, got %d" % (lib.SFM_SELFCAL_MAX_VIEWS, m))
    if np.ndim(image_sizes) == 1:
        wh = np.tile(as_array(image_sizes, (2,), "image_sizes"), (m, 1))
    else:
        wh = as_array(image_sizes, (m, 2), "image_sizes")
    if not np.all(np.isfinite(wh)):
        raise SfmError(lib.SFM_E_NONFINITE, "self_calibrate", "image_sizes")
    if not np.all(wh > 0):
        raise ValueError("image_sizes must be > 0, got %s" % (wh[~np.all(wh > 0, axis=1)][0],))
    if X is None:
        n, Xa, Xp = 0, None, ffi.NULL
    else:
        Xa = as_array(X, (None, 4), "X")
        n, Xp = Xa.shape[0], dptr(Xa)
    K = np.empty((m, 3, 3))
    H = np.empty((4, 4))
    if tracks is not None:
        if Xa is None:
            raise ValueError("tracks need the points X")
        x = as_array(tracks, (m, n, 2), "tracks")
        missing = np.isnan(x)
        if np.any(missing[:, :, 0] != missing[:, :, 1]):
            raise ValueError("tracks: an observation has one coordinate NaN and not the other")
        cam, pt = np.nonzero(~missing[:, :, 0])
        oc = np.ascontiguousarray(cam, dtype=np.intc)
        op = np.ascontiguousarray(pt, dtype=np.intc)
        oxy = np.ascontiguousarray(x[cam, pt], dtype=np.float64)
        o = ffi.new("sfm_selfcal_options *")
        lib.sfm_selfcal_default_options(o)
        if sweep not in ("always", "when_needed"):
            raise ValueError("sweep must be 'always' or 'when_needed', got %r" % (sweep,))
        o.sweep = lib.SFM_SELFCAL_SWEEP_ALWAYS if sweep == "always" else lib.SFM_SELFCAL_SWEEP_WHEN_NEEDED
        o.per_view_focal = 1 if per_view_focal else 0
        if principal not in PRINCIPAL:
            raise ValueError("principal must be one of %s, got %r" % (sorted(PRINCIPAL), principal))
        o.principal = PRINCIPAL[principal]
        if sweep_steps is not None:
            o.sweep_steps = to_int(sweep_steps, "sweep_steps", 3, lib.SFM_SELFCAL_MAX_SWEEP)
        if focal_range is not None:
            if np.ndim(focal_range) != 1 or len(focal_range) != 2:
                raise TypeError("focal_range must be a pair (min, max), got %r" % (focal_range,))
            lo, hi = to_float(focal_range[0], "focal_range"), to_float(focal_range[1], "focal_range")
            if not 0 < lo < hi:
                raise ValueError("focal_range must satisfy 0 < min < max, got (%r, %r)" % (lo, hi))
            o.focal_min, o.focal_max = lo, hi
        # the C ranges (sfm_selfcal.h): max_rms and max_focal_sigma may be
        # infinite (no check), loss_scale and min_profile not
        for name, v, finite, lo in (("max_rms", max_rms, False, 0), ("loss_scale", loss_scale, True, 0),
                                    ("max_focal_sigma", max_focal_sigma, False, 0),
                                    ("min_profile", min_profile, True, None)):
            if v is None:
                continue
            v = to_float(v, name, finite)
            if np.isnan(v) or (v <= 0 if lo is not None else v < 0):
                raise ValueError("%s must be %s, got %r" % (name, "> 0" if lo is not None else ">= 0", v))
            setattr(o, name, v)
        need = lib.sfm_selfcal_workspace_size(m, n, len(oc))
        if need == 0:
            raise ValueError("need 3..%d views, points and observations" % lib.SFM_SELFCAL_MAX_VIEWS)
        poses = ffi.new("sfm_pose[]", m)
        Xm = np.zeros((n, 3))
        rep = ffi.new("sfm_selfcal_report *")
        buf, ws, size = workspace(need)
        st = lib.sfm_selfcal_solve(m, dptr(P), dptr(wh), n, Xp, len(oc), ffi.cast("int *", ffi.from_buffer(oc)),
                                   ffi.cast("int *", ffi.from_buffer(op)), dptr(oxy), o, dptr(K), dptr(H),
                                   poses, dptr(Xm), rep, ws, size)
        try:
            check(st, "self_calibrate", inputs={"P": P, "image_sizes": wh, "X": Xa, "tracks": oxy})
        except SfmError as e:
            e.report = _selfcal_report(rep, m)
            raise
        R = np.array([list(poses[i].R) for i in range(m)]).reshape(m, 3, 3)
        t = np.array([list(poses[i].t) for i in range(m)])
        out = dict(K=K, H=H, R=R, t=t, X=Xm)
        out.update(_selfcal_report(rep, m))
        return out
    res = ffi.new("sfm_selfcal_result *")
    st = lib.sfm_selfcal_linear(m, dptr(P), dptr(wh), n, Xp, dptr(K), dptr(H), res)
    try:
        check(st, "self_calibrate", inputs={"P": P, "image_sizes": wh, "X": Xa})
    except SfmError as e:
        e.flags = res.flags
        e.null_ratio = res.null_ratio
        e.weak_ratio = res.weak_ratio
        raise
    return dict(K=K, H=H, path="linear", flags=res.flags, null_ratio=res.null_ratio,
                weak_ratio=res.weak_ratio, front_fraction=res.front_fraction)


def _threshold(threshold_px):
    v = to_float(threshold_px, "threshold_px")
    if not v > 0:
        raise ValueError("threshold_px must be > 0, got %r" % v)
    return v


def _real(value, name, positive=False):
    """A real option of the uncalibrated pipelines: > 0, or >= 0 (0: off)."""
    v = to_float(value, name, finite=False)
    if np.isnan(v) or (v <= 0 if positive else v < 0):
        raise ValueError("%s must be %s, got %r" % (name, "> 0" if positive else ">= 0", v))
    return v


def _uncal_options(threshold_px, seed, max_iterations, max_focal_sigma, min_parallax_deg, per_view_focal,
                   radial=2, principal_sigma=None, aspect_sigma=None, sweep_iterations=None):
    o = ffi.new("sfm_uncal_options *")
    lib.sfm_uncal_default_options(o)
    o.ransac.threshold = _threshold(threshold_px)
    o.ransac.seed = to_seed(seed)
    if max_iterations is not None:
        o.ransac.max_iterations = to_int(max_iterations, "max_iterations", 1)
    if max_focal_sigma is not None:
        o.max_focal_sigma = _real(max_focal_sigma, "max_focal_sigma", positive=True)
    if min_parallax_deg is not None:
        o.min_parallax_deg = _real(min_parallax_deg, "min_parallax_deg")
    o.per_view_focal = 1 if per_view_focal else 0
    radial = int(radial)
    if radial not in (0, 1, 2):
        raise ValueError("radial must be 0, 1 or 2, got %r" % radial)
    o.radial = radial
    if principal_sigma is not None:
        o.principal_sigma = _real(principal_sigma, "principal_sigma")
    if aspect_sigma is not None:
        o.aspect_sigma = _real(aspect_sigma, "aspect_sigma")
    if sweep_iterations is not None:
        o.sweep_iterations = to_int(sweep_iterations, "sweep_iterations", 1, 50)
    return o


def _report(r):
    return dict(stage=STAGES.get(r.stage, r.stage), attempts=r.attempts, n_input=r.n_input, ransac_inliers=r.ransac_inliers,
                ransac_iterations=r.ransac.iterations, projective_rms=r.projective_rms,
                linear_status=r.linear_status, linear_flags=r.linear_flags, focal_linear=r.focal_linear,
                focal_sweep=r.focal_sweep, evaluations=r.evaluations, path=PATHS.get(r.path, r.path),
                focal_view=[r.focal_view[v] for v in range(3)], profile_rise=r.profile_rise, focal_sigma=r.focal_sigma,
                focal_sigma_noise=r.focal_sigma_noise, focal=r.focal, inliers=r.inliers,
                rms=r.rms, front_fraction=r.front_fraction, parallax_deg=r.parallax_deg, k1=r.k1, k2=r.k2,
                radial_rise=[r.radial_rise[0], r.radial_rise[1]])


def _run(nv, xs, width, height, threshold_px, seed, max_iterations, max_focal_sigma, min_parallax_deg,
         per_view_focal, radial=0, principal_sigma=None, aspect_sigma=None, sweep_iterations=None):
    width, height = to_int(width, "width", 1), to_int(height, "height", 1)
    x1 = as_array(xs[0], (None, 2), "x1")
    n = x1.shape[0]
    xs = [x1] + [as_array(x, (n, 2), "x%d" % (k + 2)) for k, x in enumerate(xs[1:])]
    o = _uncal_options(threshold_px, seed, max_iterations, max_focal_sigma, min_parallax_deg, per_view_focal,
                       radial, principal_sigma, aspect_sigma, sweep_iterations)
    size_fn = (lib.sfm_recon_three_view_uncalibrated_workspace_size if nv == 3
               else lib.sfm_recon_two_view_uncalibrated_workspace_size)
    need = size_fn(n)
    if need == 0:
        raise ValueError("need at least %d correspondences, got %d" % (7 if nv == 3 else 8, n))
    K = np.zeros((nv, 3, 3))
    poses = ffi.new("sfm_pose[3]")
    X = np.zeros((n, 3))
    mask = np.zeros(n, dtype=np.uint8)
    rep = ffi.new("sfm_uncal_report *")
    buf, ws, size = workspace(need)
    mp = ffi.cast("uint8_t *", ffi.from_buffer(mask))
    if nv == 3:
        st = lib.sfm_recon_three_view_uncalibrated(dptr(xs[0]), dptr(xs[1]), dptr(xs[2]), n, width, height, o,
                                                   dptr(K), poses, dptr(X), mp, rep, ws, size)
    else:
        st = lib.sfm_recon_two_view_uncalibrated(dptr(xs[0]), dptr(xs[1]), n, width, height, o, dptr(K), poses,
                                                 dptr(X), mp, rep, ws, size)
    try:
        check(st, "reconstruct_%s_view" % ("three" if nv == 3 else "two"))
    except Exception as e:
        e.report = _report(rep)
        raise
    R = np.array([list(poses[v].R) for v in range(nv)]).reshape(nv, 3, 3)
    t = np.array([list(poses[v].t) for v in range(nv)])
    dist = np.array([rep.k1, rep.k2, 0.0, 0.0, 0.0])
    return dict(K=K, dist=dist, R=R, t=t, X=X, inliers=mask.astype(bool), report=_report(rep))


def reconstruct_three_view(x1, x2, x3, width, height, seed=0, threshold_px=1.0, max_iterations=None,
                           max_focal_sigma=None, min_parallax_deg=None, per_view_focal=False, radial=2,
                           principal_sigma=None, aspect_sigma=None, sweep_iterations=None):
    """Metric cameras and points from (n,2) pixel triplets of one unknown
    camera of image size width x height.

    per_view_focal: after the shared answer, one focal length per view
    (kept when it passes the same checks). radial: radial distortion terms
    estimated with the focal length (Brown k1, k2 about the image centre):
    0 pinhole, 1 k1, 2 k1 and k2; a term is dropped when the data do not
    reject it being 0. principal_sigma (of max(width, height), per axis) and
    aspect_sigma: the prior standard deviations of the principal point about
    the centre and of the aspect ratio about 1 that focal_sigma includes
    (defaults 0.01 and 0.0025; 0: the noise alone, focal_sigma_noise).
    Returns dict(K (3,3,3), dist (5,) OpenCV distortion vector (k1, k2, 0,
    0, 0), R (3,3,3), t (3,3), X (n,3) (zero off the inliers), inliers (n,)
    bool, report dict (stage, path "linear" or "sweep", focal_linear,
    focal_sweep, focal, focal_sigma, k1, k2, radial_rise, rms, ...)).
    Raises SfmError when the data do not determine the answer or it fails a
    physical check; the exception carries .report.
    """
    return _run(3, (x1, x2, x3), width, height, threshold_px, seed, max_iterations, max_focal_sigma,
                min_parallax_deg, per_view_focal, radial, principal_sigma, aspect_sigma, sweep_iterations)


def reconstruct_two_view(x1, x2, width, height, seed=0, threshold_px=1.0, max_iterations=None,
                         max_focal_sigma=None, min_parallax_deg=None, per_view_focal=False, principal_sigma=None,
                         aspect_sigma=None, sweep_iterations=None):
    """The same from (n,2) pixel pairs: K (2,3,3), R (2,3,3), t (2,3), ..."""
    return _run(2, (x1, x2), width, height, threshold_px, seed, max_iterations, max_focal_sigma,
                min_parallax_deg, per_view_focal, 0, principal_sigma, aspect_sigma, sweep_iterations)


def _gray(img, name):
    a = np.asarray(img)
    if a.ndim == 3 and a.shape[2] in (3, 4):
        a = (a[..., :3].astype(np.float64) @ np.array([0.299, 0.587, 0.114])).round().clip(0, 255)
        a = a.astype(np.uint8)
    if a.ndim != 2 or a.dtype != np.uint8:
        raise ValueError("%s must be a 2-D uint8 gray image (or RGB), got %s %s" % (name, a.shape, a.dtype))
    return np.ascontiguousarray(a)


def reconstruct_three_view_images(img1, img2, img3, seed=0, max_features=5000, threshold_px=1.0, align=True, **kw):
    """reconstruct_three_view on three images of one size: features
    (detect_and_describe), matching of the pairs 1-2, 2-3, 3-1 and the cyclic
    three-view association in front of it, then (align=True) each triplet's
    view-2 and view-3 points aligned photometrically onto its view-1 patch
    (align_points): the detector's positions lie on their pyramid level's
    pixel grid, the aligned ones within about a tenth of a pixel. The result
    also has x (3, t, 2), the pixel triplets passed on, and aligned (t,), the
    triplets whose two points were both aligned (the others keep the
    detector's positions)."""
    from .features import align_points, associate_three_views, detect_and_describe, match
    # checked before the detector runs: images without features would
    # otherwise end the call before a bad seed or threshold is seen
    seed = to_seed(seed)
    threshold_px = _threshold(threshold_px)
    imgs = [_gray(im, "img%d" % (k + 1)) for k, im in enumerate((img1, img2, img3))]
    if not (imgs[0].shape == imgs[1].shape == imgs[2].shape):
        raise ValueError("the three images must have one size")
    feats = [detect_and_describe(im, max_features=max_features) for im in imgs]
    m12 = match(feats[0][1], feats[1][1])
    m23 = match(feats[1][1], feats[2][1])
    m31 = match(feats[2][1], feats[0][1])
    tri = associate_three_views(m12, m23, m31, len(feats[0][0]), len(feats[1][0]), len(feats[2][0]))
    x = np.stack([feats[v][0][tri[:, v], :2] for v in range(3)])
    aligned = np.zeros(x.shape[1], dtype=bool)
    if align:
        x[1], ok2 = align_points(imgs[0], x[0], imgs[1], x[1])
        x[2], ok3 = align_points(imgs[0], x[0], imgs[2], x[2])
        aligned = ok2 & ok3
    h, w = imgs[0].shape
    out = reconstruct_three_view(x[0], x[1], x[2], w, h, seed=seed, threshold_px=threshold_px, **kw)
    out["x"] = x
    out["aligned"] = aligned
    return out
