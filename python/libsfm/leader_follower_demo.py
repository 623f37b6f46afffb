"""Monte-Carlo simulation of the leader-follower motion strategies.

    python -m libsfm.leader_follower_demo [--trials 50] [--steps 100] [--seed 1] [--out build]

The leader drives a straight line at constant speed; the follower estimates
the leader's relative pose (position and heading) with the EKF of
sfm_r2r_motion.h from its odometry, the leader's communicated odometry and
one range (or bearing) measurement per step. At every step the follower's
next relative position must stay within `tolerance` of the desired formation
position q_des (the admissible disk of sfm_r2r_motion_next, centred on the
formation-keeping motion). Three strategies choose the follower's
translation inside that disk:

  keep      maintaining the formation: the disk's centre (the relative pose
            is then unobservable along the directions the sensor does not
            see, and the uncertainty grows without bound);
  random    a uniformly random point of the disk;
  optimal   sfm_r2r_motion_next: the next-step minimum of the trace of the
            posterior covariance.

It prints the mean trace of the covariance over the trials at a few steps
and writes a plot of the mean trace over time for both sensors, beside the
paths of the first range-only trial (OUT/leader_follower.png, and the
figures to OUT/leader_follower.txt).
"""
import argparse
import os

import numpy as np

from .formation import (leader_follower_next_motion, leader_follower_propagate,
                        leader_follower_update)

STRATEGIES = ("keep", "random", "optimal")

#: The scenario: speeds per step, formation offset, noise, initial covariance.
SCENARIO = dict(
    leader_speed=0.2,                 # m per step, along the leader's x axis
    q_des=(2.0, 1.5),                 # leader 2 m ahead, 1.5 m left of the follower
    tolerance=0.5,                    # m: next relative position within this of q_des
    noise_range=dict(sigma_leader_d=0.01, sigma_leader_w=0.004, sigma_follower_d=0.01,
                     sigma_follower_w=0.004, sigma_meas=0.05),
    noise_bearing=dict(sigma_leader_d=0.01, sigma_leader_w=0.004, sigma_follower_d=0.01,
                       sigma_follower_w=0.004, sigma_meas=0.02),
    P0=np.diag([0.2 ** 2, 0.2 ** 2, 0.1 ** 2]),
)


def _rot(a):
    c, s = np.cos(a), np.sin(a)
    return np.array([[c, -s], [s, c]])


def _wrap(a):
    return (a + np.pi) % (2 * np.pi) - np.pi


def simulate(strategy, sensor="range", trials=50, steps=100, seed=1, scenario=None,
             paths=False):
    """Runs `trials` Monte-Carlo trials of one strategy. Returns
    (trace, err): arrays (trials, steps + 1) of the trace of the EKF
    covariance and of the squared estimation error (position and heading);
    with paths=True also the true follower and leader positions in the world
    (the leader's start frame), arrays (trials, steps + 1, 2) each."""
    if strategy not in STRATEGIES:
        raise ValueError("strategy must be one of %s" % (STRATEGIES,))
    sc = dict(SCENARIO)
    sc.update(scenario or {})
    noise = sc["noise_range"] if sensor == "range" else sc["noise_bearing"]
    q_des = np.asarray(sc["q_des"], float)
    rho = float(sc["tolerance"])
    P0 = np.asarray(sc["P0"], float)
    ld_cmd = np.array([sc["leader_speed"], 0.0])
    trace = np.empty((trials, steps + 1))
    err = np.empty((trials, steps + 1))
    fpath = np.empty((trials, steps + 1, 2))
    lpath = np.empty((trials, steps + 1, 2))
    # one generator per trial, shared by the three strategies' noise draws, so
    # the strategies meet the same initial errors
    for k in range(trials):
        rng = np.random.default_rng([seed, k])
        pick = np.random.default_rng([seed, k, 1 + STRATEGIES.index(strategy)])
        xt = np.array([q_des[0], q_des[1], 0.0])        # true relative pose
        xe = xt + rng.multivariate_normal(np.zeros(3), P0)  # estimate
        P = P0.copy()
        trace[k, 0] = np.trace(P)
        e = xe - xt
        e[2] = _wrap(e[2])
        err[k, 0] = e @ e
        # world frame: the leader's start; the follower's pose in it
        th_f = -xt[2]
        pos_f = -_rot(th_f) @ xt[:2]
        fpath[k, 0] = pos_f
        lpath[k, 0] = pos_f + _rot(th_f) @ xt[:2]
        for s in range(steps):
            # where the leader would be seen if the follower did not translate
            c = xe[:2] + _rot(xe[2]) @ ld_cmd
            d0 = c - q_des
            if strategy == "keep":
                fd = d0
            elif strategy == "random":
                a = pick.uniform(-np.pi, np.pi)
                r = rho * np.sqrt(pick.uniform())
                fd = d0 + r * np.array([np.cos(a), np.sin(a)])
            else:
                plan = leader_follower_next_motion(xe, P, ld_cmd, rho, d0=d0,
                                                   sensor=sensor, noise=noise)
                fd = plan["follower_d"]
            # truth: the commanded motions plus odometry noise
            ld_t = ld_cmd + rng.normal(0.0, noise["sigma_leader_d"], 2)
            lw_t = rng.normal(0.0, noise["sigma_leader_w"])
            fw_t = rng.normal(0.0, noise["sigma_follower_w"])
            fd_t = fd + rng.normal(0.0, noise["sigma_follower_d"], 2)
            pt = _rot(-fw_t) @ (xt[:2] + _rot(xt[2]) @ ld_t) - fd_t
            xt = np.array([pt[0], pt[1], _wrap(xt[2] + lw_t - fw_t)])
            th_f += fw_t
            pos_f = pos_f + _rot(th_f) @ fd_t
            fpath[k, s + 1] = pos_f
            lpath[k, s + 1] = pos_f + _rot(th_f) @ xt[:2]
            # estimate: propagate with the commanded motions, then measure
            xe, P = leader_follower_propagate(xe, P, ld_cmd, 0.0, 0.0, fd, noise=noise)
            if sensor == "range":
                z = np.hypot(xt[0], xt[1]) + rng.normal(0.0, noise["sigma_meas"])
                z = abs(z)
            else:
                z = _wrap(np.arctan2(xt[1], xt[0]) + rng.normal(0.0, noise["sigma_meas"]))
            xe, P = leader_follower_update(xe, P, z, sensor=sensor, noise=noise)
            trace[k, s + 1] = np.trace(P)
            e = xe - xt
            e[2] = _wrap(e[2])
            err[k, s + 1] = e @ e
    if paths:
        return trace, err, fpath, lpath
    return trace, err


def run(trials=50, steps=100, seed=1):
    """{sensor: {strategy: (mean trace over time, median error norm over
    time, trials lost, the first trial's follower path, its leader path)}}"""
    out = {}
    for sensor in ("range", "bearing"):
        out[sensor] = {}
        for st in STRATEGIES:
            tr, er, fp, lp = simulate(st, sensor, trials, steps, seed, paths=True)
            out[sensor][st] = (tr.mean(axis=0), np.sqrt(np.median(er, axis=0)),
                               int(np.sum(er[:, -1] > 1.0)), fp[0], lp[0])
    return out


def main(argv=None):
    ap = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    ap.add_argument("--trials", type=int, default=50)
    ap.add_argument("--steps", type=int, default=100)
    ap.add_argument("--seed", type=int, default=1)
    ap.add_argument("--out", default="build")
    a = ap.parse_args(argv)
    res = run(a.trials, a.steps, a.seed)
    os.makedirs(a.out, exist_ok=True)
    lines = ["leader-follower Monte-Carlo: %d trials, %d steps, seed %d" % (a.trials, a.steps, a.seed),
             "mean trace of the covariance (m^2 + rad^2) / median error norm at steps;",
             "lost: trials whose final error norm exceeds 1"]
    marks = sorted({10, a.steps // 4, a.steps // 2, a.steps})
    for sensor, r in res.items():
        lines.append("%s:" % sensor)
        lines.append("  %-8s " % "strategy" + " ".join("%17s" % ("k=%d" % m) for m in marks)
                     + "  lost")
        for st in STRATEGIES:
            tr, med, lost = r[st][:3]
            lines.append("  %-8s " % st + " ".join("%8.4f / %6.3f" % (tr[m], med[m]) for m in marks)
                         + "  %4d" % lost)
    text = "\n".join(lines)
    print(text)
    with open(os.path.join(a.out, "leader_follower.txt"), "w") as f:
        f.write(text + "\n")
    import matplotlib
    matplotlib.use("Agg")
    import matplotlib.pyplot as plt
    fig, axes = plt.subplots(1, 3, figsize=(16, 4.2))
    names = {"keep": "maintain formation", "random": "constrained random", "optimal": "optimal (KKT)"}
    ax = axes[2]
    r = res["range"]
    ax.plot(r["keep"][4][:, 0], r["keep"][4][:, 1], "k-", lw=2, label="leader")
    for st in STRATEGIES:
        ax.plot(r[st][3][:, 0], r[st][3][:, 1], ".-", ms=3, lw=0.8, label="follower, " + names[st])
    ax.set_title("range-only, trial 1: paths (m)")
    ax.set_aspect("equal", adjustable="datalim")
    ax.grid(True, alpha=0.3)
    ax.legend(fontsize=8)
    for ax, (sensor, r) in zip(axes[:2], res.items()):
        for st in STRATEGIES:
            ax.plot(r[st][0], label=names[st])
        ax.set_title("%s-only, mean of %d trials" % (sensor, a.trials))
        ax.set_xlabel("step")
        ax.set_ylabel("trace of covariance")
        ax.set_yscale("log")
        ax.grid(True, which="both", alpha=0.3)
        ax.legend()
    fig.tight_layout()
    path = os.path.join(a.out, "leader_follower.png")
    fig.savefig(path, dpi=120)
    print("wrote", path)


if __name__ == "__main__":
    main()
