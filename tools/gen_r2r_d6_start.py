#!/usr/bin/env python3
"""Start system of the D6 robot-to-robot solver (six distances): a generic
complex parameter point and all 40 of its solutions, found by monodromy.

Usage: gen_r2r_d6_start.py OUTDIR   writes OUTDIR/r2r_d6_start.c and
OUTDIR/r2r_d6_start.h (the committed copies live in libsfm/solvers/generated/;
`make test-r2r-generated` regenerates into a temporary directory and fails on
any difference).

The problem. |C t2_k + p - t1_k| = d_k, k = 0..5, t1_0 = t2_0 = 0, is the
forward kinematics of the general Stewart-Gough platform (base points t1_k,
platform points t2_k, leg lengths d_k): 40 complex solutions for generic data
(Raghavan 1993; Wampler 1996; Husty 1996).

Formulation (Study parameters, as in Wampler, "Forward displacement analysis
of general six-in-parallel SPS (Stewart) platform manipulators using soma
coordinates", Mech. Mach. Theory 1996; in our notation). With
quaternions w-first, e the rotation's (unnormalised) quaternion and
g = (1/2) p e, so that C = R(e) / e.e and p = 2 vec(g conj(e)) / e.e, each
distance reads |e t2 - t1 e + 2 g|^2 = d^2 e.e, i.e. with m = t2 - t1,
n = t1 + t2:
    u0 = -e_v . m + 2 g0,   u_v = e0 m + e_v x n + 2 g_v,
    f_k = u0^2 + u_v . u_v - d_k^2 e.e                       (k = 0..5)
    f_6 = e . g            (the Study quadric: p is a pure quaternion)
    f_7 = c . (e, g) - 1   (one random complex chart of P^7)
Eight equations in the eight unknowns x = (e, g), bilinear products (no
conjugation) over the complex numbers. Each real (C, p) is one point of P^7
((e, g) and (-e, -g) coincide), so it appears once.

Parameters: t1_k, t2_k (k = 1..5) and d_k^2 (k = 0..5), complex.

Method.
 1. Choose x0 first (random complex e, g, projected onto e . g = 0, scaled
    onto the chart) and random complex t1_k, t2_k; d_k^2 then follows from
    f_k = 0 (it is linear in d_k^2). This is the start point P0 with one
    known solution.
 2. Monodromy: loops P0 -> P1 -> P2 -> P0 through two random complex points,
    each leg a straight segment tracked by the same predictor-corrector the C
    solver uses (RK4 on the Davidenko equation, Newton, adaptive step); every
    end point is Newton-checked against P0's system and new ones are kept.
    Repeated until 40 are known, then SATURATION further loops must bring no
    new one (the count is 40 and no more).
 3. Every solution is polished in 50-digit arithmetic (mpmath) on the exact
    double parameters, checked nonsingular and distinct, and printed to 17
    significant digits in a fixed order (sorted by value), so regenerating
    gives the same file whatever the float details of the tracking.
Fixed seeds: the output depends on nothing but this file.
"""
import sys
from pathlib import Path

import mpmath as mp
import numpy as np

SEED = 20261202
NSOL = 40          # Stewart-Gough forward kinematics, generic
SATURATION = 8     # loops with no new solution after the 40th
MAX_LOOPS = 200
# Sizes of the start point: positions (t) and g = p e / 2 at about the size
# of the solver's data after its scaling (largest coordinate or distance 1),
# which shortens the paths to typical data (measured: 29 % fewer linear
# solves per call than with unit-variance draws).
T_SCALE = 0.4
G_SCALE = 0.2

# ---- the system, batched over paths (numpy, complex128) --------------------


def unpack(P):
    """P (..., 42): per k = 0..5, t1 (3), t2 (3), d^2 (1)."""
    P = P.reshape(P.shape[:-1] + (6, 7))
    return P[..., 0:3], P[..., 3:6], P[..., 6]


def cross(a, b):
    return np.stack([a[..., 1] * b[..., 2] - a[..., 2] * b[..., 1],
                     a[..., 2] * b[..., 0] - a[..., 0] * b[..., 2],
                     a[..., 0] * b[..., 1] - a[..., 1] * b[..., 0]], axis=-1)


def system(x, P, c, dP=None):
    """H (n, 8), H_x (n, 8, 8) and, when dP is given, H_s = dH/dP . dP (n, 8)
    for x (n, 8) at parameters P (n, 42)."""
    n = x.shape[0]
    e0, ev, g0, gv = x[:, 0], x[:, 1:4], x[:, 4], x[:, 5:8]
    t1, t2, d2 = unpack(P)
    m, nn = t2 - t1, t1 + t2
    ee = e0 * e0 + np.sum(ev * ev, axis=1)
    u0 = -np.einsum("pi,pki->pk", ev, m) + 2.0 * g0[:, None]
    uv = e0[:, None, None] * m + cross(ev[:, None, :], nn) + 2.0 * gv[:, None, :]
    H = np.zeros((n, 8), complex)
    J = np.zeros((n, 8, 8), complex)
    H[:, :6] = u0 * u0 + np.sum(uv * uv, axis=2) - d2 * ee[:, None]
    J[:, :6, 0] = 2.0 * np.sum(uv * m, axis=2) - 2.0 * d2 * e0[:, None]
    J[:, :6, 1:4] = 2.0 * (-u0[..., None] * m + cross(nn, uv)) - 2.0 * d2[..., None] * ev[:, None, :]
    J[:, :6, 4] = 4.0 * u0
    J[:, :6, 5:8] = 4.0 * uv
    H[:, 6] = np.sum(x[:, :4] * x[:, 4:], axis=1)
    J[:, 6, :4] = x[:, 4:]
    J[:, 6, 4:] = x[:, :4]
    H[:, 7] = x @ c - 1.0
    J[:, 7, :] = c
    if dP is None:
        return H, J
    a1, a2, dd = unpack(dP)
    dm, dn = a2 - a1, a1 + a2
    du0 = -np.einsum("pi,pki->pk", ev, dm)
    duv = e0[:, None, None] * dm + cross(ev[:, None, :], dn)
    Hs = np.zeros((n, 8), complex)
    Hs[:, :6] = 2.0 * (u0 * du0 + np.sum(uv * duv, axis=2)) - dd * ee[:, None]
    return H, J, Hs


def track(x, Pa, Pb, c, max_steps=3000):
    """Tracks the solutions x (n, 8) of P(s) = Pa + s (Pb - Pa) from s = 0 to
    1. Returns the end points and a success flag per path."""
    n = x.shape[0]
    dP = np.broadcast_to(Pb - Pa, (n, 42))
    x = x.copy()
    s = np.zeros(n)
    h = np.full(n, 0.02)
    ok = np.ones(n, bool)
    done = np.zeros(n, bool)

    def vel(xx, ss, idx):
        _, J, Hs = system(xx, Pa + ss[:, None] * (Pb - Pa), c, dP[idx])
        return -np.linalg.solve(J, Hs[..., None])[..., 0]

    for _ in range(max_steps):
        act = np.nonzero(~done & ok)[0]
        if act.size == 0:
            break
        xa, sa, ha = x[act], s[act], np.minimum(h[act], 1.0 - s[act])
        k1 = vel(xa, sa, act)
        k2 = vel(xa + 0.5 * ha[:, None] * k1, sa + 0.5 * ha, act)
        k3 = vel(xa + 0.5 * ha[:, None] * k2, sa + 0.5 * ha, act)
        k4 = vel(xa + ha[:, None] * k3, sa + ha, act)
        xp = xa + ha[:, None] / 6.0 * (k1 + 2.0 * k2 + 2.0 * k3 + k4)
        sn = sa + ha
        Pn = Pa + sn[:, None] * (Pb - Pa)
        conv = np.zeros(act.size, bool)
        for it in range(3):
            H, J = system(xp, Pn, c)
            dx = np.linalg.solve(J, H[..., None])[..., 0]
            xp = xp - dx
            rel = np.abs(dx).max(axis=1) / (1.0 + np.abs(xp).max(axis=1))
            if it == 0:
                big = rel > 1e-3
            conv |= rel < 1e-9
        good = conv & ~big & np.all(np.isfinite(xp), axis=1)
        gi, bi = act[good], act[~good]
        x[gi], s[gi] = xp[good], sn[good]
        h[gi] = np.minimum(ha[good] * 1.6, 0.1)
        h[bi] = ha[~good] * 0.5
        ok[bi[h[bi] < 1e-9]] = False
        done[gi[s[gi] >= 1.0]] = True
    ok &= done
    return x, ok


def random_params(rng):
    t = rng.normal(size=(6, 6)) + 1j * rng.normal(size=(6, 6))
    t[0] = 0.0
    d2 = rng.normal(size=6) + 1j * rng.normal(size=6)
    return np.concatenate([t, d2[:, None]], axis=1).reshape(42)


# ---- exact start point and polishing (mpmath) ------------------------------

def mp_system(x, P, c):
    t = [[P[7 * k + i] for i in range(7)] for k in range(6)]
    e0, ev, g0, gv = x[0], x[1:4], x[4], x[5:8]
    ee = e0 * e0 + sum(v * v for v in ev)
    H, J = [], []
    for k in range(6):
        a, b, d2 = t[k][0:3], t[k][3:6], t[k][6]
        m = [b[i] - a[i] for i in range(3)]
        nn = [a[i] + b[i] for i in range(3)]
        cr = [ev[1] * nn[2] - ev[2] * nn[1], ev[2] * nn[0] - ev[0] * nn[2], ev[0] * nn[1] - ev[1] * nn[0]]
        u0 = -sum(ev[i] * m[i] for i in range(3)) + 2 * g0
        uv = [e0 * m[i] + cr[i] + 2 * gv[i] for i in range(3)]
        H.append(u0 * u0 + sum(v * v for v in uv) - d2 * ee)
        nu = [nn[1] * uv[2] - nn[2] * uv[1], nn[2] * uv[0] - nn[0] * uv[2], nn[0] * uv[1] - nn[1] * uv[0]]
        row = [2 * sum(uv[i] * m[i] for i in range(3)) - 2 * d2 * e0]
        row += [2 * (-u0 * m[i] + nu[i]) - 2 * d2 * ev[i] for i in range(3)]
        row += [4 * u0] + [4 * uv[i] for i in range(3)]
        J.append(row)
    H.append(sum(x[i] * x[4 + i] for i in range(4)))
    J.append([x[4 + i] for i in range(4)] + [x[i] for i in range(4)])
    H.append(sum(c[i] * x[i] for i in range(8)) - 1)
    J.append(list(c))
    return H, J


def mp_polish(x, P, c):
    x = [mp.mpc(v) for v in x]
    for _ in range(60):
        H, J = mp_system(x, P, c)
        dx = mp.lu_solve(mp.matrix(J), mp.matrix(H))
        x = [x[i] - dx[i] for i in range(8)]
        if max(abs(v) for v in dx) < mp.mpf(10) ** (-45):
            break
    H, J = mp_system(x, P, c)
    res = max(abs(v) for v in H)
    sv = mp.svd_c(mp.matrix(J), compute_uv=False)
    return x, res, min(sv[i] for i in range(8)) / max(sv[i] for i in range(8))


def start_point(rng):
    """P0 (42 complex doubles), chart c (8) and one solution (mp)."""
    c = rng.normal(size=8) + 1j * rng.normal(size=8)
    e = rng.normal(size=4) + 1j * rng.normal(size=4)
    g = G_SCALE * (rng.normal(size=4) + 1j * rng.normal(size=4))
    t = T_SCALE * (rng.normal(size=(6, 6)) + 1j * rng.normal(size=(6, 6)))
    t[0] = 0.0
    me = [mp.mpc(v) for v in e]
    mg = [mp.mpc(v) for v in g]
    r = sum(me[i] * mg[i] for i in range(4)) / sum(v * v for v in me)
    mg = [mg[i] - r * me[i] for i in range(4)]
    x = me + mg
    sc = sum(mp.mpc(c[i]) * x[i] for i in range(8))
    x = [v / sc for v in x]
    P = []
    for k in range(6):
        tk = [mp.mpc(v) for v in t[k]]
        a, b = tk[0:3], tk[3:6]
        m = [b[i] - a[i] for i in range(3)]
        nn = [a[i] + b[i] for i in range(3)]
        ev = x[1:4]
        cr = [ev[1] * nn[2] - ev[2] * nn[1], ev[2] * nn[0] - ev[0] * nn[2], ev[0] * nn[1] - ev[1] * nn[0]]
        u0 = -sum(ev[i] * m[i] for i in range(3)) + 2 * x[4]
        uv = [x[0] * m[i] + cr[i] + 2 * x[5 + i] for i in range(3)]
        d2 = (u0 * u0 + sum(v * v for v in uv)) / sum(v * v for v in x[:4])
        P += [complex(v) for v in tk] + [complex(d2)]  # rounded to doubles: P0 is exactly these
    return np.array(P), c, x


def monodromy(P0, c, x0, rng, log):
    sols = np.array([[complex(v) for v in x0]])
    quiet = 0
    for loop in range(MAX_LOOPS):
        P1, P2 = random_params(rng), random_params(rng)
        x, ok = track(sols, P0, P1, c)
        x, ok2 = track(x[ok], P1, P2, c)
        x, ok3 = track(x[ok2], P2, P0, c)
        x = x[ok3]
        H, J = system(x, np.broadcast_to(P0, (x.shape[0], 42)), c)
        for _ in range(3):
            x = x - np.linalg.solve(J, H[..., None])[..., 0]
            H, J = system(x, np.broadcast_to(P0, (x.shape[0], 42)), c)
        new = 0
        for y, r in zip(x, np.abs(H).max(axis=1)):
            if r > 1e-10:
                continue
            if np.abs(sols - y).max(axis=1).min() > 1e-6 * (1.0 + np.abs(y).max()):
                sols = np.vstack([sols, y])
                new += 1
        log("loop %d: %d paths, %d new, %d known" % (loop + 1, x.shape[0], new, len(sols)))
        if len(sols) > NSOL:
            raise SystemExit("more than %d solutions: the count is wrong" % NSOL)
        quiet = quiet + 1 if (new == 0 and len(sols) == NSOL) else 0
        if quiet >= SATURATION:
            return sols, loop + 1
    raise SystemExit("monodromy stopped at %d solutions" % len(sols))


# ---- emission ----------------------------------------------------------------

def fmt(v):
    s = mp.nstr(v, 17, min_fixed=-4, max_fixed=4, strip_zeros=False)
    return s if ("e" in s or "." in s) else s + ".0"


def emit(P0, c, sols, stats):
    L = ["/* DO NOT EDIT: generated by tools/gen_r2r_d6_start.py. */",
         "/*",
         " * Start system of the D6 parameter homotopy (libsfm/solvers/r2r_d6.c): a",
         " * generic complex parameter point P0 of the Stewart-Gough forward kinematics",
         " * in Study coordinates and all 40 of its solutions, found by monodromy",
         " * (%d loops, the last %d without a new solution) and polished to 50 digits." % stats,
         " * See the generator for the formulation. Complex numbers as {re, im}.",
         " */",
         '#include "solvers/generated/r2r_d6_start.h"',
         "",
         "/* per k = 0..5: t1_k (3), t2_k (3), d_k^2 */",
         "const double sfmi_r2r_d6_start_par[SFMI_R2R_D6_NPAR][2] = {"]
    for k in range(6):
        L.append("    " + " ".join("{%s, %s}," % (fmt(mp.mpf(v.real)), fmt(mp.mpf(v.imag)))
                                   for v in P0[7 * k:7 * k + 3]))
        L.append("    " + " ".join("{%s, %s}," % (fmt(mp.mpf(v.real)), fmt(mp.mpf(v.imag)))
                                   for v in P0[7 * k + 3:7 * k + 7]))
    L += ["};", "", "/* the chart: c . (e, g) = 1 */",
          "const double sfmi_r2r_d6_chart[8][2] = {"]
    for i in range(0, 8, 4):
        L.append("    " + " ".join("{%s, %s}," % (fmt(mp.mpf(v.real)), fmt(mp.mpf(v.imag)))
                                   for v in c[i:i + 4]))
    L += ["};", "", "/* the 40 solutions (e0, e1, e2, e3, g0, g1, g2, g3) at P0 */",
          "const double sfmi_r2r_d6_start_sol[SFMI_R2R_D6_NSOL][8][2] = {"]
    for x in sols:
        L.append("    {")
        for i in range(0, 8, 2):
            L.append("        " + " ".join("{%s, %s}," % (fmt(v.real), fmt(v.imag)) for v in x[i:i + 2]))
        L.append("    },")
    L += ["};"]
    return "\n".join(L) + "\n"


def emit_header():
    return "\n".join([
        "/* DO NOT EDIT: generated by tools/gen_r2r_d6_start.py. */",
        "/*",
        " * Internal: the start system of the D6 parameter homotopy (see",
        " * r2r_d6_start.c and the generator): parameters P0, the chart and the 40",
        " * start solutions, complex numbers as {re, im}.",
        " */",
        "#ifndef SFM_SOLVERS_GENERATED_R2R_D6_START_H",
        "#define SFM_SOLVERS_GENERATED_R2R_D6_START_H",
        "",
        "#define SFMI_R2R_D6_NSOL %d" % NSOL,
        "#define SFMI_R2R_D6_NPAR 42",
        "",
        "extern const double sfmi_r2r_d6_start_par[SFMI_R2R_D6_NPAR][2];",
        "extern const double sfmi_r2r_d6_chart[8][2];",
        "extern const double sfmi_r2r_d6_start_sol[SFMI_R2R_D6_NSOL][8][2];",
        "",
        "#endif"]) + "\n"


def main():
    if len(sys.argv) != 2:
        raise SystemExit("usage: gen_r2r_d6_start.py OUTDIR")
    out = Path(sys.argv[1])
    out.mkdir(parents=True, exist_ok=True)
    mp.mp.dps = 50
    log = lambda s: print("d6: " + s, file=sys.stderr)  # noqa: E731
    rng = np.random.default_rng(SEED)
    P0, c, x0 = start_point(rng)
    sols, loops = monodromy(P0, c, x0, rng, log)
    mP = [mp.mpc(v) for v in P0]
    mc = [mp.mpc(v) for v in c]
    pol = []
    for y in sols:
        x, res, rc = mp_polish(y, mP, mc)
        if res > mp.mpf(10) ** (-40) or rc < 1e-10:
            raise SystemExit("start solution not regular: residual %s, 1/cond %s" % (res, rc))
        pol.append(x)
    for i in range(len(pol)):
        for j in range(i):
            if max(abs(pol[i][q] - pol[j][q]) for q in range(8)) < 1e-8:
                raise SystemExit("two start solutions coincide")
    pol.sort(key=lambda x: [(float(v.real), float(v.imag)) for v in x])
    (out / "r2r_d6_start.c").write_text(emit(P0, c, pol, (loops, SATURATION)))
    (out / "r2r_d6_start.h").write_text(emit_header())
    log("%d solutions written" % len(pol))


if __name__ == "__main__":
    main()
