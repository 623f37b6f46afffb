"""Bundle adjustment (sfm_ba_solve) on numpy arrays.

Layout (float64, row-major, as in C):

* ``cameras``: a dict with
    - ``rotations``    (m, 3, 3) world-to-camera rotations, x_cam = R X + t
    - ``translations`` (m, 3)
    - either ``models``: m ``libsfm.Camera`` objects (pinhole, Brown-Conrady,
      Kannala-Brandt fisheye), refined in copies;
    - or ``intrinsics``: (m, 6) rows {fx, fy, cx, cy, k1, k2} (Brown-Conrady
      cameras with p1 = p2 = k3 = 0); (m, 4) rows {fx, fy, cx, cy} are taken
      with k1 = k2 = 0
* ``points``: (n, 3) world points
* ``observations``: (k, 4) rows (camera index, point index, x, y) in pixels;
  the indices must be integers

Each camera projects through its model (sfm_camera.h). Cost =
1/2 sum rho(w |r|^2).

``options`` (all optional):

* ``mode``: "full" | "pose_only" | "points_only"
* ``intrinsics``: "fixed" | "shared" | "per_camera"
* ``refine``: iterable of "focal", "principal", "radial" (k1, k2), "k1" (k1 alone),
  "distortion" (every coefficient of the model)
* ``loss``: "squared" | "huber" | "cauchy" | "truncated"; ``loss_scale`` (a)
* ``gauge``: "first_camera" | "none"
* ``scale_gauge``: "none" | "coordinate" | "distance", with ``scale_camera``,
  ``scale_coordinate``, ``scale_distance``
* ``max_iterations``, ``function_tolerance``, ``gradient_tolerance``,
  ``parameter_tolerance``, ``initial_trust_radius``
* ``weights``: (k,) per-observation weights (inverse variances)
* ``fixed_cameras``: indices whose pose is held; ``fixed_intrinsics``: camera
  indices whose intrinsics are held (per_camera mode); ``fixed_points``
* ``covariance``: True to return the (m, 6, 6) pose covariances

Returns a dict: ``cameras`` (same layout: ``models`` as Camera objects, or
``intrinsics`` (m, 6)), ``points``,
``cost``, ``initial_cost``, ``iterations``, ``successful_steps``,
``stop_reason`` (a string), ``workspace_bytes`` and, when asked,
``covariance`` ((m, 6, 6), rows (w, t), or None when the undamped system is
singular).
"""
import numpy as np

from ._ffi import as_array, check, dptr, ffi, iptr, lib, workspace
from .geometry import Camera

_MODES = {"full": 0, "pose_only": 1, "points_only": 2}
_INTR = {"fixed": 0, "shared": 1, "per_camera": 2}
_REFINE = {"focal": 1, "principal": 2, "radial": 4, "distortion": 8, "k1": 16}
_LOSS = {"squared": 0, "huber": 1, "cauchy": 2, "truncated": 3}
_GAUGE = {"none": 0, "first_camera": 1}
_SCALE = {"none": 0, "coordinate": 1, "distance": 2}
_STOP = {1: "gradient", 2: "function_tolerance", 3: "parameter_tolerance",
         4: "max_iterations", 5: "trust_region", 6: "no_parameters"}
_KNOWN = {"mode", "intrinsics", "refine", "loss", "loss_scale", "gauge", "scale_gauge",
          "scale_camera", "scale_coordinate", "scale_distance", "max_iterations",
          "function_tolerance", "gradient_tolerance", "parameter_tolerance",
          "initial_trust_radius", "weights", "fixed_cameras", "fixed_intrinsics",
          "fixed_points", "covariance"}


def _choice(table, value, name):
    if value not in table:
        raise ValueError("%s must be one of %s, got %r" % (name, sorted(table), value))
    return table[value]


def _indices(values, count, name):
    idx = np.asarray(list(values) if not isinstance(values, np.ndarray) else values)
    if idx.size and (idx.ndim != 1 or not np.issubdtype(idx.dtype, np.integer)):
        raise ValueError("%s must be a list of integer indices" % name)
    if idx.size and (idx.min() < 0 or idx.max() >= count):
        raise ValueError("%s: index out of range" % name)
    return idx.astype(np.int64)


def bundle_adjust(cameras, points, observations, options=None):
    options = dict(options or {})
    unknown = set(options) - _KNOWN
    if unknown:
        raise ValueError("unknown options: %s" % ", ".join(sorted(unknown)))
    R = as_array(cameras["rotations"], (None, 3, 3), "rotations").copy()
    m = R.shape[0]
    t = as_array(cameras["translations"], (m, 3), "translations").copy()
    models = cameras.get("models")
    cams = ffi.new("sfm_camera[]", m)
    if models is not None:
        models = list(models)
        if len(models) != m or not all(isinstance(c, Camera) for c in models):
            raise ValueError("models must be %d libsfm.Camera objects" % m)
        for i, c in enumerate(models):
            ffi.memmove(ffi.addressof(cams, i), c._c, ffi.sizeof("sfm_camera"))
    else:
        K_in = np.ascontiguousarray(np.asarray(cameras["intrinsics"], dtype=np.float64))
        if K_in.ndim != 2 or K_in.shape[0] != m or K_in.shape[1] not in (4, 6):
            raise ValueError("intrinsics must have shape (m, 6) or (m, 4), got %s" % (K_in.shape,))
        K = np.zeros((m, 6))
        K[:, :K_in.shape[1]] = K_in
        for i in range(m):
            cams[i].model = lib.SFM_CAMERA_BROWN
            cams[i].fx, cams[i].fy, cams[i].cx, cams[i].cy = (float(v) for v in K[i, :4])
            cams[i].dist[0], cams[i].dist[1] = float(K[i, 4]), float(K[i, 5])
    X = as_array(points, (None, 3), "points").copy()
    n = X.shape[0]
    obs = as_array(observations, (None, 4), "observations")
    k = obs.shape[0]
    if m < 1 or k < 1:
        raise ValueError("need at least one camera and one observation")
    if not np.all(np.isfinite(obs[:, :2])) or np.any(obs[:, :2] != np.round(obs[:, :2])):
        raise ValueError("observation camera and point indices must be integers")
    oc = np.ascontiguousarray(obs[:, 0].astype(np.int32))
    op = np.ascontiguousarray(obs[:, 1].astype(np.int32))
    xy = np.ascontiguousarray(obs[:, 2:4])

    o = ffi.new("sfm_ba_options *")
    lib.sfm_ba_default_options(o)
    o.mode = _choice(_MODES, options.get("mode", "full"), "mode")
    o.intrinsics = _choice(_INTR, options.get("intrinsics", "fixed"), "intrinsics")
    mask = 0
    for r in options.get("refine", ()):
        mask |= _choice(_REFINE, r, "refine entry")
    o.refine_intrinsics = mask
    o.loss = _choice(_LOSS, options.get("loss", "squared"), "loss")
    o.gauge = _choice(_GAUGE, options.get("gauge", "first_camera"), "gauge")
    o.scale_gauge = _choice(_SCALE, options.get("scale_gauge", "none"), "scale_gauge")
    for key in ("loss_scale", "scale_distance", "function_tolerance", "gradient_tolerance",
                "parameter_tolerance", "initial_trust_radius"):
        if key in options:
            setattr(o, key, float(options[key]))
    for key in ("scale_camera", "scale_coordinate", "max_iterations"):
        if key in options:
            setattr(o, key, int(options[key]))
    want_cov = bool(options.get("covariance", False))
    o.want_covariance = 1 if want_cov else 0

    p = ffi.new("sfm_ba_problem *")
    p.n_cameras = m
    p.n_points = n
    p.n_observations = k
    p.rotations = dptr(R)
    p.translations = dptr(t)
    p.cameras = cams
    p.points = dptr(X) if n else ffi.NULL
    p.obs_camera = iptr(oc)
    p.obs_point = iptr(op)
    p.obs_xy = dptr(xy)
    keep = []
    if options.get("weights") is not None:
        w = as_array(options["weights"], (k,), "weights")
        keep.append(w)
        p.obs_weight = dptr(w)
    flags = np.zeros(m, dtype=np.uint8)
    flags[_indices(options.get("fixed_cameras", ()), m, "fixed_cameras")] |= 1
    flags[_indices(options.get("fixed_intrinsics", ()), m, "fixed_intrinsics")] |= 2
    p.camera_flags = ffi.cast("unsigned char *", ffi.from_buffer(flags))
    pfix = np.zeros(max(n, 1), dtype=np.uint8)
    pfix[_indices(options.get("fixed_points", ()), n, "fixed_points")] = 1
    p.point_fixed = ffi.cast("unsigned char *", ffi.from_buffer(pfix))

    dims = ffi.new("sfm_ba_dims *")
    dims.n_cameras = m
    dims.n_points = n
    dims.n_observations = k
    dims.intrinsics = o.intrinsics
    dims.refine_intrinsics = o.refine_intrinsics
    nbytes = lib.sfm_ba_workspace_size(dims)
    if nbytes == 0:
        raise ValueError("problem dimensions or intrinsics options are invalid")
    _buf, ws, ws_size = workspace(nbytes)
    cov = np.zeros((m, 6, 6)) if want_cov else None
    res = ffi.new("sfm_ba_result *")
    check(lib.sfm_ba_solve(p, o, res, dptr(cov) if want_cov else ffi.NULL,
                           36 * m if want_cov else 0, ws, ws_size), "sfm_ba_solve")
    cams_out = {"rotations": R, "translations": t}
    if models is not None:
        names = {v: k for k, v in Camera.MODELS.items()}
        cams_out["models"] = [
            Camera(names[cams[i].model], cams[i].fx, cams[i].fy, cams[i].cx, cams[i].cy,
                   [cams[i].dist[e] for e in range(Camera.NDIST[names[cams[i].model]])])
            for i in range(m)]
    else:
        for i in range(m):
            K[i] = (cams[i].fx, cams[i].fy, cams[i].cx, cams[i].cy, cams[i].dist[0], cams[i].dist[1])
        cams_out["intrinsics"] = K
    out = {
        "cameras": cams_out,
        "points": X,
        "cost": res.final_cost,
        "initial_cost": res.initial_cost,
        "iterations": res.iterations,
        "successful_steps": res.successful_steps,
        "stop_reason": _STOP.get(res.stop_reason, str(res.stop_reason)),
        "workspace_bytes": int(nbytes),
    }
    if want_cov:
        out["covariance"] = cov if res.covariance_status == 0 else None
    return out
