"""Leader-follower formations (sfm_r2r_motion.h): the follower's EKF of the
leader's relative pose and its next-step motion minimising the trace of the
posterior covariance (Zhou, Zhou, Roumeliotis, IROS 2011).

Planar; metres and radians. The state x = (p_x, p_y, phi) is the leader's
position in the follower's frame and its heading relative to the follower;
P is its 3x3 covariance. One step: the leader translates by leader_d (in its
own frame) and turns by leader_w; the follower turns by follower_w, then
translates by follower_d in its turned frame. The sensor is "range"
(|p|, metres) or "bearing" (atan2(p_y, p_x), radians). Noise is a dict (or
keyword arguments) of per-step standard deviations: sigma_leader_d,
sigma_leader_w, sigma_follower_d, sigma_follower_w, sigma_meas.
"""
import numpy as np

from ._ffi import as_array, check, dptr, ffi, lib, to_float

__all__ = ["leader_follower_next_motion", "leader_follower_propagate",
           "leader_follower_update", "leader_follower_cost", "NOISE_DEFAULTS"]

#: Per-step standard deviations used when a key is not given.
NOISE_DEFAULTS = dict(sigma_leader_d=0.01, sigma_leader_w=0.005, sigma_follower_d=0.01,
                      sigma_follower_w=0.005, sigma_meas=0.05)

_SENSORS = {"range": 1, "bearing": 2}


def _sensor(sensor):
    if sensor not in _SENSORS:
        raise ValueError("sensor must be 'range' or 'bearing', got %r" % (sensor,))
    return _SENSORS[sensor]


def _noise(noise):
    n = dict(NOISE_DEFAULTS)
    if noise:
        unknown = set(noise) - set(n)
        if unknown:
            raise ValueError("unknown noise keys: %s" % ", ".join(sorted(unknown)))
        n.update(noise)
    c = ffi.new("sfm_r2r_motion_noise *")
    for k, v in n.items():
        setattr(c, k, to_float(v, k, finite=False))
    return c


def _step(leader_d, leader_w, follower_w, follower_d=(0.0, 0.0)):
    u = ffi.new("sfm_r2r_motion_step *")
    ld = as_array(leader_d, (2,), "leader_d")
    fd = as_array(follower_d, (2,), "follower_d")
    u.leader_d.v[0], u.leader_d.v[1] = float(ld[0]), float(ld[1])
    u.leader_w = to_float(leader_w, "leader_w", finite=False)
    u.follower_w = to_float(follower_w, "follower_w", finite=False)
    u.follower_d.v[0], u.follower_d.v[1] = float(fd[0]), float(fd[1])
    return u


def _state(x, P):
    return as_array(x, (3,), "x"), as_array(P, (3, 3), "P")


def leader_follower_propagate(x, P, leader_d, leader_w=0.0, follower_w=0.0,
                              follower_d=(0.0, 0.0), noise=None):
    """EKF propagation through one step: (x', P') (sfm_r2r_motion_propagate)."""
    x, P = _state(x, P)
    u = _step(leader_d, leader_w, follower_w, follower_d)
    xo, Po = np.empty(3), np.empty((3, 3))
    check(lib.sfm_r2r_motion_propagate(dptr(x), dptr(P), u, _noise(noise), dptr(xo), dptr(Po)),
          "sfm_r2r_motion_propagate", {"x": x, "P": P})
    return xo, Po


def leader_follower_update(x, P, z, sensor="range", noise=None):
    """EKF update with one range or bearing measurement z: (x+, P+)
    (sfm_r2r_motion_update)."""
    x, P = _state(x, P)
    xo, Po = np.empty(3), np.empty((3, 3))
    check(lib.sfm_r2r_motion_update(dptr(x), dptr(P), _sensor(sensor),
                                    to_float(z, "z", finite=False), _noise(noise),
                                    dptr(xo), dptr(Po)),
          "sfm_r2r_motion_update", {"x": x, "P": P})
    return xo, Po


def leader_follower_cost(x, P, leader_d, follower_d, leader_w=0.0, follower_w=0.0,
                         sensor="range", noise=None):
    """Trace of the covariance after the step (follower translating by
    follower_d) and one update (sfm_r2r_motion_cost)."""
    x, P = _state(x, P)
    u = _step(leader_d, leader_w, follower_w, follower_d)
    out = ffi.new("double *")
    check(lib.sfm_r2r_motion_cost(dptr(x), dptr(P), u, _noise(noise), _sensor(sensor), out),
          "sfm_r2r_motion_cost", {"x": x, "P": P})
    return float(out[0])


def leader_follower_next_motion(x, P, leader_d, radius, leader_w=0.0, follower_w=0.0,
                                d0=None, sensor="range", noise=None, min_distance=0.0):
    """The follower's next translation minimising the posterior covariance
    trace, among |follower_d - d0| <= radius (d0 None: the origin, a speed
    bound) keeping the next relative position q at |q| >= min_distance.
    Returns a dict: follower_d (2,), q (2,) the predicted relative position,
    trace, trace_prior, multiplier (KKT, >= 0), on_boundary (0 inside, 1 on
    the disk's circle, 2 on the distance circle, 3 at a corner), n_critical
    (sfm_r2r_motion_next)."""
    x, P = _state(x, P)
    u = _step(leader_d, leader_w, follower_w)
    d0p = ffi.NULL
    if d0 is not None:
        d0a = as_array(d0, (2,), "d0")
        d0p = dptr(d0a)
    plan = ffi.new("sfm_r2r_motion_plan *")
    check(lib.sfm_r2r_motion_next(dptr(x), dptr(P), u, d0p, to_float(radius, "radius", finite=False),
                                  to_float(min_distance, "min_distance", finite=False),
                                  _noise(noise), _sensor(sensor), plan),
          "sfm_r2r_motion_next", {"x": x, "P": P})
    return dict(follower_d=np.array([plan.follower_d.v[0], plan.follower_d.v[1]]),
                q=np.array([plan.q.v[0], plan.q.v[1]]), trace=plan.trace,
                trace_prior=plan.trace_prior, multiplier=plan.multiplier,
                on_boundary=int(plan.on_boundary), n_critical=plan.n_critical)
