"""Robot-to-robot relative pose from distances and bearings (sfm_r2r.h).

Conventions (as in the C header): frame {1} is robot 1 at the first step,
{2} robot 2 at the first step; the unknown (C, p) maps x_{1} = C x_{2} + p.
A step is a dict with the ego-motions R1, t1 (robot 1 in {1}), R2, t2
(robot 2 in {2}) and any of d (distance), b1 (bearing from robot 1 to robot
2 in robot 1's frame), b2 (from robot 2 to robot 1 in robot 2's frame).
R1/t1/R2/t2 may be left out of the first step only (the identity there).
"""
import numpy as np

from ._ffi import as_array, check, ffi, lib, to_float, workspace

__all__ = ["r2r_solve", "r2r_predict", "r2r_classify", "R2R_SYSTEMS", "R2R_MAX_SOLUTIONS"]

R2R_MAX_SOLUTIONS = lib.SFM_R2R_MAX_SOLUTIONS
# sfm_r2r_system value -> name, in the C enum's order
R2R_SYSTEMS = dict(sorted((v, n) for n, v in (
    (name[len("SFM_R2R_SYS_"):], getattr(lib, name)) for name in dir(lib)
    if name.startswith("SFM_R2R_SYS_") and not name.endswith("_") and name != "SFM_R2R_SYS_NONE")))

_KEYS = {"R1", "t1", "R2", "t2", "d", "b1", "b2"}
_EYE = np.eye(3)
_ZERO = np.zeros(3)


def _steps(steps):
    """A cffi sfm_r2r_step[] from a list of step dicts (shapes and types
    checked here, values by the C library)."""
    if isinstance(steps, dict):
        raise TypeError("steps must be a list of dicts, got one dict")
    steps = list(steps)
    if not steps:
        raise ValueError("steps must not be empty")
    arr = ffi.new("sfm_r2r_step[]", len(steps))
    for k, st in enumerate(steps):
        if not isinstance(st, dict):
            raise TypeError("steps[%d] must be a dict, got %s" % (k, type(st).__name__))
        extra = set(st) - _KEYS
        if extra:
            raise ValueError("steps[%d]: unknown keys %s" % (k, sorted(extra)))
        s = arr[k]
        for key, shape, default in (("R1", (3, 3), _EYE), ("t1", (3,), _ZERO),
                                    ("R2", (3, 3), _EYE), ("t2", (3,), _ZERO)):
            if key in st:
                v = as_array(st[key], shape, "steps[%d][%r]" % (k, key))
            elif k == 0:
                v = default
            else:
                raise ValueError("steps[%d] needs %r (only the first step defaults to the identity)" % (k, key))
            field = getattr(s, key)
            target = field.m if len(shape) == 2 else field.v
            target[0:v.size] = v.ravel().tolist()
        has = 0
        if st.get("d") is not None:
            s.d = to_float(st["d"], "steps[%d]['d']" % k, finite=False)
            has |= lib.SFM_R2R_D
        for key, bit in (("b1", lib.SFM_R2R_B1), ("b2", lib.SFM_R2R_B2)):
            if st.get(key) is not None:
                v = as_array(st[key], (3,), "steps[%d][%r]" % (k, key))
                getattr(s, key).v[0:3] = v.tolist()
                has |= bit
        s.has = has
    return arr


def _step_inputs(steps):
    """{name: values} of every float field of the steps, so that an
    SFM_E_NONFINITE from the C library names the step and field at fault."""
    out = {}
    if not isinstance(steps, (list, tuple)):
        return out
    for k, st in enumerate(steps):
        if not isinstance(st, dict):
            continue
        for key in ("R1", "t1", "R2", "t2", "d", "b1", "b2"):
            if st.get(key) is not None:
                out["steps[%d][%r]" % (k, key)] = np.asarray(st[key], dtype=np.float64)
    return out


def _check_steps(status, where, steps, **extra):
    """check(), naming the step field that holds a NaN/Inf on
    SFM_E_NONFINITE (built only then: steps may be long)."""
    if status == lib.SFM_E_NONFINITE:
        return check(status, where, dict(_step_inputs(steps), **extra))
    return check(status, where)


def _transform(C, p):
    C = as_array(C, (3, 3), "C")
    p = as_array(p, (3,), "p")
    T = ffi.new("sfm_r2r_transform *")
    T.C.m[0:9] = C.ravel().tolist()
    T.p.v[0:3] = p.tolist()
    return T


def r2r_predict(step, C, p):
    """The measurement model of one step under (C, p): (d, b1, b2) with
    unit bearings (sfm_r2r_predict). The step's own measurements are
    ignored."""
    arr = _steps([step])
    T = _transform(C, p)
    d = ffi.new("double *")
    b1 = ffi.new("sfm_vec3 *")
    b2 = ffi.new("sfm_vec3 *")
    _check_steps(lib.sfm_r2r_predict(arr, T, d, b1, b2), "sfm_r2r_predict", [step], C=C, p=p)
    return float(d[0]), np.array(list(b1.v)), np.array(list(b2.v))


def r2r_classify(steps):
    """The base system (name, e.g. "DB1_D_D_D") a sequence of exactly six
    scalar equations reduces to (sfm_r2r_classify)."""
    arr = _steps(steps)
    return R2R_SYSTEMS[_check_steps(lib.sfm_r2r_classify(arr, len(arr)), "sfm_r2r_classify",
                                        steps)]


def r2r_solve(steps):
    """Every real (C, p) consistent with the measurements, best first
    (sfm_r2r_solve): a list of (C (3, 3), p (3,)). Six scalar equations give
    the base system's solutions; more are solved on a minimal subset and
    verified on the rest. Degenerate motion raises SfmError
    (SFM_E_DEGENERATE)."""
    arr = _steps(steps)
    n = len(arr)
    buf, ptr, size = workspace(lib.sfm_r2r_solve_workspace_size(n))
    out = np.empty((R2R_MAX_SOLUTIONS, 12), dtype=np.float64)
    outp = ffi.cast("sfm_r2r_transform *", ffi.from_buffer(out))
    k = _check_steps(lib.sfm_r2r_solve(arr, n, outp, ptr, size), "sfm_r2r_solve", steps)
    return [(out[i, :9].reshape(3, 3).copy(), out[i, 9:].copy()) for i in range(k)]
