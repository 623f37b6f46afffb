#!/usr/bin/env python3
"""Elimination-template (action-matrix) generator for small polynomial systems.

Usage: gen_r2r_templates.py OUTDIR   writes OUTDIR/r2r_tmpl_<name>.c and
OUTDIR/r2r_tmpl.h for every problem in PROBLEMS (the committed copies live in
libsfm/solvers/generated/; `make test-r2r-generated` regenerates into a
temporary directory and fails on any difference).

Method (the automatic generator of Kukelova, Bujnak & Pajdla, ECCV 2008, in
its plain form). A problem is a list of polynomial equations in unknowns x
whose coefficients are polynomials in input data (SymPy expressions).
 1. A random instance over the prime field GF(P) stands for the generic one:
    its grevlex Groebner basis gives the standard monomials B (a basis of the
    quotient ring; |B| is the number of complex solutions).
 2. The equations are multiplied by every monomial up to a total degree D
    (D raised until it works). For an action variable a, R = a*B \\ B are
    the monomials to reduce and E the rest. Rows are chosen that are
    independent on E u R; E columns that are not pivots are dropped, which is
    valid only when they do not feed the R rows ((A^-1 N)_R = 0 is checked).
 3. At run time the emitted C fills A (square, over the kept E and R
    columns) and the B block, solves A X = B_block by LU, so NF(r) = -X_r on
    B, forms the |B| x |B| action matrix of a and reads every solution from
    an eigenvector v = B(x): x_i = v[x_i] / v[1], a from the eigenvalue.
 4. The template's action matrix is checked against SymPy's normal forms on
    a second GF(P) instance before anything is written.

Feeding it another system: add a Problem(name, unknowns, data, equations,
doc[, max_extra]) to PROBLEMS (max_extra: how many degrees above the
equations' own the expansion may go, 4 unless said; each degree and action
variable tried is reported on stderr, so a failing search shows how far it
got). The row reduction over GF(P) runs in numpy, so templates of a few
hundred rows cost seconds. Requirements: a zero-dimensional system for generic data;
every unknown other than the action variable must be a standard monomial
(true when no equation is linear in a leading unknown); the data symbols are
the inputs of the generated function in the order given.
"""
import random
import sys
from pathlib import Path

import numpy as np
import sympy as sp

P = 30011  # prime for the generic instances
MAX_EXTRA_DEGREE = 4


class Problem:
    def __init__(self, name, unknowns, data, equations, doc, max_extra=MAX_EXTRA_DEGREE):
        self.name, self.x, self.data, self.eqs, self.doc = name, unknowns, data, equations, doc
        self.max_extra = max_extra  # how far above the equations' degree to expand


def problems():
    out = []
    # --- 3 points + 1 known direction (upright relative pose, y axis up) ---
    q, tx, ty = sp.symbols("q tx ty")
    X1 = sp.Matrix(3, 3, sp.symbols("a0:9"))  # row i: bearing i in camera 1
    X2 = sp.Matrix(3, 3, sp.symbols("b0:9"))  # row i: bearing i in camera 2
    Rq = sp.Matrix([[1 - q**2, 0, 2 * q], [0, 1 + q**2, 0], [-2 * q, 0, 1 - q**2]])
    t = sp.Matrix([tx, ty, 1])
    tx_ = sp.Matrix([[0, -t[2], t[1]], [t[2], 0, -t[0]], [-t[1], t[0], 0]])
    eqs = [sp.expand((X2[i, :] * tx_ * Rq * X1[i, :].T)[0]) for i in range(3)]
    out.append(Problem(
        "upright3pt", [q, tx, ty], list(X1) + list(X2), eqs,
        "Upright relative pose: x_cam2 = Ry(theta) x_cam1 + t, t = (tx, ty, 1),\n"
        " * q = tan(theta/2), (1+q^2) Ry(theta) = [[1-q^2,0,2q],[0,1+q^2,0],[-2q,0,1-q^2]].\n"
        " * Inputs: a[9] bearings in camera 1 (rows), b[9] in camera 2. The system\n"
        " * also has the two spurious roots q = +-i of 1+q^2, never real."))
    # --- r2r System 10: relative position known, three distances for C ---
    s = sp.symbols("s1:4")
    sv = sp.Matrix(s)
    S = sp.Matrix([[0, -s[2], s[1]], [s[2], 0, -s[0]], [-s[1], s[0], 0]])
    ss = (sv.T * sv)[0]
    Cc = (1 - ss) * sp.eye(3) + 2 * S + 2 * sv * sv.T  # (1 + s's) C
    data, eqs = [], []
    for k in range(3):
        u = sp.Matrix(sp.symbols("u%d_0:3" % k))
        v = sp.Matrix(sp.symbols("v%d_0:3" % k))
        c = sp.Symbol("c%d" % k)
        data += list(u) + list(v) + [c]
        eqs.append(sp.expand((u.T * Cc * v)[0] - c * (1 + ss)))
    out.append(Problem(
        "sys10", list(s), data, eqs,
        "Three equations u_k^T C v_k = c_k on a rotation C in Cayley form,\n"
        " * (1 + s's) C = (1 - s's) I + 2 [s]x + 2 s s^T (8 solutions, Bezout bound).\n"
        " * Inputs per equation k: u_k[3], v_k[3], c_k."))
    # --- r2r B1_B1_B1: bearings b1 at three steps (p = l u0) ---
    l, m1, m2 = sp.symbols("l m1 m2")
    a = sp.symbols("a0:4")
    b = sp.symbols("b0:4")
    c = sp.symbols("c0:7")
    eqs = [m1**2 + l**2 + a[0] * l * m1 + a[1] * l + a[2] * m1 + a[3],
           m2**2 + l**2 + b[0] * l * m2 + b[1] * l + b[2] * m2 + b[3],
           l**2 + c[0] * l * m1 + c[1] * l * m2 + c[2] * m1 * m2 + c[3] * l + c[4] * m1 +
           c[5] * m2 + c[6]]
    out.append(Problem(
        "b1_b1_b1", [l, m1, m2], list(a) + list(b) + list(c), eqs,
        "Robot-to-robot B1_B1_B1 after eliminating C: with p = l u0 and\n"
        " * a_k = t1_k - l u0 + m_k u_k = C t2_k, the equations |a_1|^2 = |t2_1|^2,\n"
        " * |a_2|^2 = |t2_2|^2, a_1.a_2 = t2_1.t2_2 (unit u's), coefficients as inputs:\n"
        " * m1^2 + l^2 + a0 l m1 + a1 l + a2 m1 + a3, m2^2 + l^2 + b0 l m2 + b1 l + b2 m2 + b3,\n"
        " * l^2 + c0 l m1 + c1 l m2 + c2 m1 m2 + c3 l + c4 m1 + c5 m2 + c6."))
    # --- r2r B1_B1_B2: b1 at steps 0 and 1, b2 at step 2 ---
    l, m, n_ = sp.symbols("l m n")
    a = sp.symbols("a0:4")
    b = sp.symbols("b0:3")
    c = sp.symbols("c0:5")
    eqs = [m**2 + l**2 + a[0] * l * m + a[1] * l + a[2] * m + a[3],
           l**2 - n_**2 + b[0] * l + b[1] * n_ + b[2],
           l**2 + c[0] * l * m + c[1] * l + c[2] * m + c[3] * n_ + c[4]]
    out.append(Problem(
        "b1_b1_b2", [l, m, n_], list(a) + list(b) + list(c), eqs,
        "Robot-to-robot B1_B1_B2 after eliminating C: with p = l u0,\n"
        " * a = t1_1 - l u0 + m u1 = C t2_1 and b = t1_2 - l u0 = C (t2_2 + n w),\n"
        " * the equations |a|^2 = |t2_1|^2, |b|^2 = |t2_2 + n w|^2, a.b = t2_1.(t2_2 + n w)\n"
        " * (unit u's and w), coefficients as inputs: m^2 + l^2 + a0 l m + a1 l + a2 m + a3,\n"
        " * l^2 - n^2 + b0 l + b1 n + b2, l^2 + c0 l m + c1 l + c2 m + c3 n + c4."))
    return out


# ---------------------------------------------------------------- GF(P) tools
def inv(a):
    return pow(a % P, P - 2, P)


def to_mod(r):
    r = sp.Rational(r)
    return int(r.p) % P * inv(int(r.q)) % P


def grevlex_key(m):
    return (sum(m), tuple(-e for e in reversed(m)))


def monomials_upto(n, D):
    res = []
    def rec(i, left, cur):
        if i == n:
            res.append(tuple(cur))
            return
        for e in range(left + 1):
            rec(i + 1, left - e, cur + [e])
    rec(0, D, [])
    return sorted(res, key=grevlex_key, reverse=True)


def mul(m1, m2):
    return tuple(a + b for a, b in zip(m1, m2))


def divides(a, b):
    return all(x <= y for x, y in zip(a, b))


def instance(prob, polys, rng):
    vals = {d: rng.randrange(1, P) for d in prob.data}
    inst = []
    for pl in polys:
        inst.append({m: to_mod(c.subs(vals)) for m, c in zip(pl.monoms(), pl.coeffs())})
    return inst


def rref_pivots(M, ncols_elim):
    """Row-reduce M (list of rows, mod P) on its first ncols_elim columns;
    return (pivot columns, pivot rows as original indices). Gauss-Jordan with
    the first nonzero row as pivot, vectorised with numpy (P^2 < 2^63)."""
    A = np.array(M, dtype=np.int64) % P
    nrows = A.shape[0]
    idx = list(range(nrows))
    piv_cols, piv_rows = [], []
    r0 = 0
    for c in range(ncols_elim):
        if r0 == nrows:
            break
        nz = np.nonzero(A[r0:, c])[0]
        if len(nz) == 0:
            continue
        pr = r0 + int(nz[0])
        if pr != r0:
            A[[r0, pr]] = A[[pr, r0]]
            idx[r0], idx[pr] = idx[pr], idx[r0]
        A[r0] = A[r0] * inv(int(A[r0, c])) % P
        f = A[:, c].copy()
        f[r0] = 0
        rows = np.nonzero(f)[0]
        if len(rows):
            A[rows] = (A[rows] - f[rows, None] * A[r0][None, :]) % P
        piv_cols.append(c)
        piv_rows.append(idx[r0])
        r0 += 1
    return piv_cols, piv_rows


def solve_mod(A, Bm):
    """X = A^-1 Bm mod P (A square nonsingular)."""
    n = len(A)
    M = [list(A[i]) + list(Bm[i]) for i in range(n)]
    for c in range(n):
        pr = next(i for i in range(c, n) if M[i][c] % P)
        M[c], M[pr] = M[pr], M[c]
        iv = inv(M[c][c])
        M[c] = [v * iv % P for v in M[c]]
        for i in range(n):
            if i != c and M[i][c] % P:
                f = M[i][c]
                M[i] = [(v - f * w) % P for v, w in zip(M[i], M[c])]
    return [row[n:] for row in M]


class Template:
    pass


def build(prob):
    n = len(prob.x)
    polys = [sp.Poly(e, *prob.x) for e in prob.eqs]
    rng = random.Random(1)
    inst = instance(prob, polys, rng)
    exprs = [sum(c * sp.prod([v**e for v, e in zip(prob.x, m)]) for m, c in f.items())
             for f in inst]
    G = sp.groebner(exprs, *prob.x, modulus=P, order="grevlex")
    lms = [sp.Poly(g, *prob.x, modulus=P).monoms(order="grevlex")[0] for g in G.exprs]
    for i in range(n):  # zero-dimensional: a pure power of every unknown leads
        if not any(all(e == 0 for j, e in enumerate(lm) if j != i) for lm in lms):
            raise SystemExit("%s: not zero-dimensional" % prob.name)
    B = [m for m in monomials_upto(n, 12) if not any(divides(lm, m) for lm in lms)]
    one = tuple([0] * n)
    maxdeg = max(pl.total_degree() for pl in polys)
    for D in range(maxdeg, maxdeg + prob.max_extra + 1):
        for ai in range(n):
            unit = lambda i: tuple(1 if j == i else 0 for j in range(n))
            if any(unit(i) not in B for i in range(n) if i != ai) or one not in B:
                continue
            t = try_template(prob, polys, inst, B, ai, D)
            print("%s: degree %d, action %s: %s" % (prob.name, D, prob.x[ai],
                  "template" if t is not None else "no"), file=sys.stderr, flush=True)
            if t is not None:
                t.B, t.ai, t.polys, t.G = B, ai, polys, G
                verify(prob, t, rng)
                return t
    raise SystemExit("%s: no template up to degree %d" % (prob.name, maxdeg + prob.max_extra))


def try_template(prob, polys, inst, B, ai, D):
    n = len(prob.x)
    a = tuple(1 if j == ai else 0 for j in range(n))
    rows = []  # (equation, multiplier)
    for i, pl in enumerate(polys):
        for m in monomials_upto(n, D - pl.total_degree()):
            rows.append((i, m))
    mons = set()
    for i, m in rows:
        for pm in polys[i].monoms():
            mons.add(mul(pm, m))
    Bset = set(B)
    R = sorted({mul(a, b) for b in B} - Bset, key=grevlex_key, reverse=True)
    if any(r not in mons for r in R):
        return None
    E = sorted(mons - Bset - set(R), key=grevlex_key, reverse=True)
    cols = E + R + B
    cidx = {m: k for k, m in enumerate(cols)}
    M = []
    for i, m in rows:
        row = [0] * len(cols)
        for pm, c in inst[i].items():
            row[cidx[mul(pm, m)]] = c
        M.append(row)
    pc, pr = rref_pivots(M, len(E) + len(R))
    if any(cidx[r] not in pc for r in R):
        return None
    keep = [c for c in pc]  # kept E columns then R columns, all pivots
    drop = [c for c in range(len(E)) if c not in pc]
    A = [[M[r][c] for c in keep] for r in pr]
    N = [[M[r][c] for c in drop] for r in pr]
    if drop:
        X = solve_mod(A, N)
        for r in R:
            if any(X[keep.index(cidx[r])]):
                return None
    t = Template()
    t.rows = [rows[r] for r in pr]
    t.keep_mons = [cols[c] for c in keep]
    t.R, t.E, t.D = R, E, D
    return t


def action_from_template(t, inst):
    """Action matrix mod P of the template on one instance (rows: a*b_j)."""
    n_keep = len(t.keep_mons)
    kidx = {m: k for k, m in enumerate(t.keep_mons)}
    bidx = {m: k for k, m in enumerate(t.B)}
    A = [[0] * n_keep for _ in t.rows]
    Bm = [[0] * len(t.B) for _ in t.rows]
    for r, (i, m) in enumerate(t.rows):
        for pm, c in inst[i].items():
            mm = mul(pm, m)
            if mm in kidx:
                A[r][kidx[mm]] = c
            elif mm in bidx:
                Bm[r][bidx[mm]] = c
    X = solve_mod(A, Bm)
    n = len(t.B[0])
    a = tuple(1 if j == t.ai else 0 for j in range(n))
    act = []
    for b in t.B:
        ab = mul(a, b)
        if ab in bidx:
            act.append([1 if k == bidx[ab] else 0 for k in range(len(t.B))])
        else:
            act.append([(-v) % P for v in X[kidx[ab]]])
    return act


def verify(prob, t, rng):
    inst = instance(prob, t.polys, rng)
    exprs = [sum(c * sp.prod([v**e for v, e in zip(prob.x, m)]) for m, c in f.items())
             for f in inst]
    G = sp.groebner(exprs, *prob.x, modulus=P, order="grevlex")
    act = action_from_template(t, inst)
    n = len(prob.x)
    a = prob.x[t.ai]
    for j, b in enumerate(t.B):
        mono = sp.prod([v**e for v, e in zip(prob.x, b)])
        _, rem = G.reduce(a * mono)
        rp = sp.Poly(rem, *prob.x, modulus=P)
        want = [0] * len(t.B)
        for m, c in zip(rp.monoms(), rp.coeffs()):
            want[t.B.index(m)] = int(c) % P
        if want != act[j]:
            raise SystemExit("%s: template action matrix differs from the normal forms" % prob.name)


# ---------------------------------------------------------------- C emission
def mono_str(x, m):
    s = "*".join("%s^%d" % (v, e) if e > 1 else str(v) for v, e in zip(x, m) if e)
    return s or "1"


# Templates whose matrices fit in this many bytes keep them on the stack; larger
# ones take them from a caller workspace (a solver may use 16 KiB of stack).
STACK_LIMIT = 12 * 1024


def stack_bytes(nK, nB, nC):
    """Bytes of the generated function's own frame: c, A, X, M, V, wr, wi,
    the eigensolver workspace (SFMI_TMPL_EIG_WS) and the pivots."""
    return 8 * (nC + nK * nK + nK * nB + 2 * nB * nB + 2 * nB + 6 * nB * nB + 16 * nB + 16) + 4 * nK


def ws_doubles(nK, nB):
    """Doubles of workspace a large template takes (A, X, M, V, wr, wi, eig)."""
    return nK * nK + nK * nB + 2 * nB * nB + 2 * nB + (6 * nB * nB + 16 * nB + 16)


def emit(prob, t):
    name = prob.name
    nB, nK, nx = len(t.B), len(t.keep_mons), len(prob.x)
    # coefficient expressions, one per (equation, monomial of its support)
    coef, cpos = [], {}
    for i, pl in enumerate(t.polys):
        for m, c in zip(pl.monoms(), pl.coeffs()):
            cpos[(i, m)] = len(coef)
            coef.append(c)
    repl, red = sp.cse(coef, symbols=sp.numbered_symbols("w"), optimizations=None)
    kidx = {m: k for k, m in enumerate(t.keep_mons)}
    bidx = {m: k for k, m in enumerate(t.B)}
    a_ent, b_ent = [], []
    for r, (i, m) in enumerate(t.rows):
        for pm in t.polys[i].monoms():
            mm = mul(pm, m)
            if mm in kidx:
                a_ent.append((r, kidx[mm], cpos[(i, pm)]))
            elif mm in bidx:
                b_ent.append((r, bidx[mm], cpos[(i, pm)]))
    a = tuple(1 if j == t.ai else 0 for j in range(nx))
    act_src = []
    for b in t.B:
        ab = mul(a, b)
        act_src.append(bidx[ab] if ab in bidx else -1 - kidx[ab])
    one = bidx[tuple([0] * nx)]
    var_src = [-1 if j == t.ai else bidx[tuple(1 if k == j else 0 for k in range(nx))]
               for j in range(nx)]
    L = []
    w = L.append
    w("/* DO NOT EDIT: generated by tools/gen_r2r_templates.py (problem \"%s\"). */" % name)
    w("/*")
    w(" * %s" % prob.doc)
    w(" * Unknowns: %s; action variable %s." % (", ".join(map(str, prob.x)), prob.x[t.ai]))
    w(" * Template: %d equations x monomials up to degree %d; %d kept rows, %d eliminated" % (len(prob.eqs), t.D, nK, nK))
    w(" * columns (%d excessive, %d reducible), %d basis monomials:" % (nK - len(t.R), len(t.R), nB))
    w(" * %s." % ", ".join(mono_str(prob.x, m) for m in t.B))
    if stack_bytes(nK, nB, len(coef)) <= STACK_LIMIT:
        w(" * Stack: the %dx%d template, its %dx%d right-hand side, the action matrix," % (nK, nK, nK, nB))
        w(" * its eigenvectors and the eigensolver's workspace (about %d bytes)." %
          stack_bytes(nK, nB, len(coef)))
    else:
        w(" * Work memory: the %dx%d template, its %dx%d right-hand side, the action" % (nK, nK, nK, nB))
        w(" * matrix, its eigenvectors and the eigensolver's workspace come from ws")
        w(" * (SFMI_TMPL_%s_WS doubles, 8-byte aligned); stack: the %d coefficients" %
          (name.upper(), len(coef)))
        w(" * and the pivots.")
    w(" */")
    w('#include "solvers/generated/r2r_tmpl.h"')
    w("")
    w("#define NK %d" % nK)
    w("#define NB %d" % nB)
    w("#define NX %d" % nx)
    w("#define NC %d" % len(coef))
    w("")
    w("static void coefficients(const double *in, double *c)")
    w("{")
    for k, d in enumerate(prob.data):
        w("    const double %s = in[%d];" % (d, k))
    for s_, e in repl:
        w("    const double %s = %s;" % (s_, sp.ccode(e)))
    for k, e in enumerate(red):
        w("    c[%d] = %s;" % (k, sp.ccode(e)))
    w("}")
    w("")
    w("/* (row, column, coefficient) of the template's eliminated block */")
    w("static const unsigned short A_ENT[%d][3] = {" % len(a_ent))
    for k in range(0, len(a_ent), 6):
        w("    " + " ".join("{%d, %d, %d}," % e for e in a_ent[k:k + 6]))
    w("};")
    w("/* (row, basis column, coefficient) of its basis block */")
    w("static const unsigned short B_ENT[%d][3] = {" % len(b_ent))
    for k in range(0, len(b_ent), 6):
        w("    " + " ".join("{%d, %d, %d}," % e for e in b_ent[k:k + 6]))
    w("};")
    w("/* a * b_j: basis index k >= 0, or reduced row -1 - k of the solve */")
    w("static const short ACT_SRC[NB] = {%s};" % ", ".join(map(str, act_src)))
    w("/* where each unknown is read from an eigenvector (-1: the eigenvalue) */")
    w("static const short VAR_SRC[NX] = {%s};" % ", ".join(map(str, var_src)))
    w("")
    w("static const sfmi_tmpl TMPL = {")
    w("    NK, NB, NX, %d, A_ENT, %d, B_ENT, %d, ACT_SRC, VAR_SRC," % (one, len(a_ent), len(b_ent)))
    w("};")
    w("")
    if stack_bytes(nK, nB, len(coef)) <= STACK_LIMIT:
        w("int sfmi_tmpl_%s(const double *in, double *sol)" % name)
        w("{")
        w("    double c[NC], A[NK * NK], X[NK * NB], M[NB * NB], V[NB * NB], wr[NB], wi[NB];")
        w("    double ews[SFMI_TMPL_EIG_WS(NB)];")
        w("    int piv[NK];")
        w("    coefficients(in, c);")
        w("    return sfmi_tmpl_run(&TMPL, c, A, piv, X, M, V, wr, wi, ews, sizeof ews, sol);")
        w("}")
    else:
        w("int sfmi_tmpl_%s(const double *in, double *sol, double *ws)" % name)
        w("{")
        w("    double c[NC], *A = ws, *X = A + NK * NK, *M = X + NK * NB, *V = M + NB * NB;")
        w("    double *wr = V + NB * NB, *wi = wr + NB, *ews = wi + NB;")
        w("    int piv[NK];")
        w("    coefficients(in, c);")
        w("    return sfmi_tmpl_run(&TMPL, c, A, piv, X, M, V, wr, wi, ews,")
        w("                         SFMI_TMPL_EIG_WS(NB) * sizeof(double), sol);")
        w("}")
    return "\n".join(L) + "\n"


def emit_header(probs, temps):
    L = ["/* DO NOT EDIT: generated by tools/gen_r2r_templates.py. */",
         "/*",
         " * Internal: action-matrix solvers emitted from elimination templates.",
         " * sfmi_tmpl_<name>(in, sol) takes the problem's inputs (see its file) and",
         " * writes each real solution's unknowns to sol[k * NX ...]; it returns the",
         " * count (<= its basis size), or a negative sfm_status (SFM_E_SINGULAR when",
         " * the template matrix is singular for these data).",
         " */",
         "#ifndef SFM_SOLVERS_GENERATED_R2R_TMPL_H",
         "#define SFM_SOLVERS_GENERATED_R2R_TMPL_H",
         "",
         "#include <stddef.h>",
         "",
         "/* doubles of eigensolver workspace for an n x n action matrix */",
         "#define SFMI_TMPL_EIG_WS(n) (6 * (n) * (n) + 16 * (n) + 16)",
         ""]
    for p, t in zip(probs, temps):
        nK, nB = len(t.keep_mons), len(t.B)
        nC = sum(len(pl.monoms()) for pl in t.polys)
        L.append("#define SFMI_TMPL_%s_NSOL %d /* basis size */" % (p.name.upper(), nB))
        L.append("#define SFMI_TMPL_%s_NX %d" % (p.name.upper(), len(p.x)))
        L.append("#define SFMI_TMPL_%s_NIN %d" % (p.name.upper(), len(p.data)))
        if stack_bytes(nK, nB, nC) <= STACK_LIMIT:
            L.append("int sfmi_tmpl_%s(const double *in, double *sol);" % p.name)
        else:
            L.append("#define SFMI_TMPL_%s_WS %d /* doubles of ws */" % (p.name.upper(), ws_doubles(nK, nB)))
            L.append("int sfmi_tmpl_%s(const double *in, double *sol, double *ws);" % p.name)
        L.append("")
    L += ["/* A template as the generator lays it out: (row, column, coefficient index)",
          " * entries of its eliminated block A (nk x nk) and of its basis block X",
          " * (nk x nb), where a * b_j comes from in the action matrix (act_src: basis",
          " * index >= 0, or -1 - reduced row), where each unknown is read from an",
          " * eigenvector (var_src: basis index, -1 for the eigenvalue), and the",
          " * basis index of the monomial 1. */",
          "typedef struct sfmi_tmpl {",
          "    int nk, nb, nx, one;",
          "    const unsigned short (*a_ent)[3];",
          "    int n_a;",
          "    const unsigned short (*b_ent)[3];",
          "    int n_b;",
          "    const short *act_src, *var_src;",
          "} sfmi_tmpl;",
          "",
          "/* The shared back end (libsfm/solvers/r2r_template.c). sfmi_tmpl_run fills",
          " * A and X from the coefficients c, then finishes: LU-solve the template,",
          " * form the action matrix, eigendecompose, read the real solutions. */",
          "int sfmi_tmpl_run(const sfmi_tmpl *T, const double *c, double *A, int *piv, double *X,",
          "                  double *M, double *V, double *wr, double *wi, double *ews,",
          "                  size_t ews_size, double *sol);",
          "int sfmi_tmpl_finish(double *A, int *piv, int nk, double *X, int nb,",
          "                     const short *act_src, const short *var_src, int nx, int one,",
          "                     double *M, double *V, double *wr, double *wi, double *ews,",
          "                     size_t ews_size, double *sol);",
          "",
          "#endif"]
    return "\n".join(L) + "\n"


def main():
    if len(sys.argv) != 2:
        raise SystemExit("usage: gen_r2r_templates.py OUTDIR")
    out = Path(sys.argv[1])
    out.mkdir(parents=True, exist_ok=True)
    probs = problems()
    temps = [build(p) for p in probs]
    for p, t in zip(probs, temps):
        (out / ("r2r_tmpl_%s.c" % p.name)).write_text(emit(p, t))
        print("%s: %d solutions, template %d x %d (degree %d)" %
              (p.name, len(t.B), len(t.keep_mons), len(t.keep_mons) + len(t.B), t.D), file=sys.stderr)
    (out / "r2r_tmpl.h").write_text(emit_header(probs, temps))


if __name__ == "__main__":
    main()
