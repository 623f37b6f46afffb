/*
 * Robot-to-robot base system D6: six distances over six steps,
 * |C t2_k + p - t1_k| = d_k, k = 0..5 (t1_0 = t2_0 = 0). This is the forward
 * kinematics of the general Stewart-Gough platform (base points t1_k,
 * platform points t2_k, leg lengths d_k): 40 complex solutions (Raghavan
 * 1993; Husty 1996; Wampler, "Forward displacement analysis of general
 * six-in-parallel SPS (Stewart) platform manipulators using soma
 * coordinates", Mech. Mach. Theory 1996); the base system of six distances
 * of Zhou & Roumeliotis (T-RO 2013).
 *
 * Formulation (Study parameters; derivation in tools/gen_r2r_d6_start.py):
 * x = (e, g) in C^8, e the rotation's quaternion (w first), g = (1/2) p e;
 * with m = t2_k - t1_k, n = t1_k + t2_k,
 *   u0 = -e_v . m + 2 g0,   u_v = e0 m + e_v x n + 2 g_v,
 *   f_k = u0^2 + u_v . u_v - d_k^2 e.e = 0      (k = 0..5)
 *   f_6 = e . g = 0  (Study quadric),  f_7 = c . x - 1 = 0  (a random chart),
 * products bilinear (no conjugation). Then C = R(e) / e.e and
 * p = 2 vec(g conj(e)) / e.e, and each real (C, p) is one point of P^7.
 *
 * Method: parameter homotopy. The generated start system
 * (solvers/generated/r2r_d6_start.c: a generic complex parameter point P0
 * and its 40 solutions, found offline by monodromy) is deformed along the
 * straight segment P(s) = (1 - s) P0 + s P1 to the caller's data P1 (t1_k,
 * t2_k, d_k^2, scaled to unit size). As P0 is generic and complex, the
 * segment misses the discriminant (where solutions meet) with probability
 * one (the "gamma trick" of Morgan & Sommese, 1989), so the 40 paths are
 * smooth and end at every isolated solution of P1. Each path is tracked
 * with an RK4 predictor on the Davidenko equation H_x x' = -H_s and up to
 * NEWTON_ITERS Newton corrections: a step is accepted when Newton's correction
 * falls below NEWTON_TOL (relative) and its first one is below JUMP_TOL,
 * else it is halved; the step doubles after GROW_AFTER successes in a row
 * (at most H_MAX). At most MAX_STEPS steps per path; a step below MIN_STEP
 * gives the path up, except within END_ZONE of s = 1, where the end point
 * is ill-conditioned (a near-double root: the truth close to a singular
 * configuration) and Newton at s = 1 takes over. A path given up, and both
 * of two paths that end at one point (one jumped onto the other: the 40
 * end points of generic data are distinct), are tracked again with steps
 * of at most H_MAX_CAREFUL and the stricter JUMP_TOL_CAREFUL. Complex
 * arithmetic in a two-double struct, 8 x 8 complex Gaussian elimination
 * with partial pivoting.
 *
 * At s = 1: Newton to full accuracy. An end point is a candidate real
 * solution when, divided by its largest e component, every imaginary part
 * is below REAL_TOL of its size (loose: an ill-conditioned real end point
 * carries imaginary noise of 1e-6..1e-4; the real Newton and the residual
 * test below are what decide). Candidates become (C, p), are polished by
 * Newton on the six real equations in (C, p) (C updated on the left by a
 * rotation vector), kept when every equation is met to RES_TOL (unit
 * scale) and deduplicated. C is a proper rotation by construction (the
 * quaternion's matrix, then exponential updates).
 *
 * Degenerate data (SFM_E_DEGENERATE): either robot's positions on one
 * straight line (standing still included): C may turn about that line
 * unseen. Non-finite data: SFM_E_NONFINITE.
 * Work memory: the 40 end points, 16 * 40 doubles of ws (descriptor). Stack:
 * about 5 KiB (x86-64 gcc -O2: 3.1 KiB in solve with the tracker inlined,
 * 1.2 KiB a Newton step, 0.6 KiB the evaluation).
 * Cost (random scenes, bench/README.md): about 7,400 complex 8 x 8 solves
 * per call, 29 tries of a step per path of which 4 rejected; 67 M
 * instructions on x86-64, about half in the eliminations, half in eval.
 */
#include <math.h>
#include <string.h>

#include "sfm/sfm_linalg.h"
#include "sfm/sfm_rotation.h"
#include "solvers/generated/r2r_d6_start.h"
#include "solvers/r2r_align.h"
#include "solvers/r2r_internal.h"
#include "solvers/r2r_solve_internal.h"
#include "solvers/small_math.h"

#define MAX_STEPS 400     /* per path */
#define NEWTON_ITERS 4    /* corrections per step */
#define H_START 0.02
#define H_MAX 0.1
#define H_MAX_CAREFUL 0.01  /* the second pass, for failed or colliding paths */
#define H_GROW 2.0       /* after GROW_AFTER successes in a row */
#define GROW_AFTER 3
#define MIN_STEP 1e-9
#define END_ZONE 1e-4     /* a path stalled this close to s = 1 goes to Newton at 1 */
#define NEWTON_TOL 1e-7   /* relative correction of a converged step */
#define JUMP_TOL 3e-2     /* relative first correction: step too long */
#define JUMP_TOL_CAREFUL 1e-3
#define SAME_END 1e-7     /* relative: two paths ended at one point */
#define REAL_TOL 1e-3     /* relative imaginary part of a candidate real end point */
#define RES_TOL 1e-8      /* |f_k| of a kept solution, unit scale */
#define DUP_TOL 1e-8

typedef struct cx {
    double re, im;
} cx;

static inline cx cx_add(cx a, cx b) { return (cx){a.re + b.re, a.im + b.im}; }
static inline cx cx_sub(cx a, cx b) { return (cx){a.re - b.re, a.im - b.im}; }
/* The real part written as a sum with -b.im (the same bits): GCC 12's
 * vectorizer turns (a*b - c*d, a*e + c*f) into a fused multiply-add-subtract
 * under -march=x86-64-v3 even with -ffp-contract=off (mk/check-fma.mk). */
static inline cx cx_mul(cx a, cx b)
{
    const double nbi = -b.im;
    return (cx){a.re * b.re + a.im * nbi, a.re * b.im + a.im * b.re};
}
static inline cx cx_scale(double s, cx a) { return (cx){s * a.re, s * a.im}; }
static inline double cx_abs1(cx a) { return fabs(a.re) + fabs(a.im); }
static inline cx cx_inv(cx a)
{
    double d = a.re * a.re + a.im * a.im;
    return (cx){a.re / d, -a.im / d};
}

/* a . b (bilinear) of complex 3-vectors, a x b */
static inline cx cx_dot3(const cx *a, const cx *b)
{
    return cx_add(cx_add(cx_mul(a[0], b[0]), cx_mul(a[1], b[1])), cx_mul(a[2], b[2]));
}

static inline void cx_cross3(const cx *a, const cx *b, cx *c)
{
    c[0] = cx_sub(cx_mul(a[1], b[2]), cx_mul(a[2], b[1]));
    c[1] = cx_sub(cx_mul(a[2], b[0]), cx_mul(a[0], b[2]));
    c[2] = cx_sub(cx_mul(a[0], b[1]), cx_mul(a[1], b[0]));
}

/* The segment P(s) = P0 + s (P1 - P0), per step in the combinations the
 * equations use: m = t2 - t1 = m0 + s dm, n = t1 + t2 = n0 + s dn,
 * d^2 = d0 + s dd. Step 0 has t1 = t2 = 0 at both ends. */
typedef struct hom {
    cx m0[6][3], dm[6][3], n0[6][3], dn[6][3];
    cx d0[6], dd[6];
    cx c[8]; /* the chart */
} hom;

/* H(x, s) into H (may be NULL), H_x into J (row-major 8 x 8) and H_s into
 * Hs (may be NULL). */
static void eval(const hom *h, const cx *x, double s, cx *H, cx *J, cx *Hs)
{
    const cx e0 = x[0], *ev = x + 1, g0 = x[4], *gv = x + 5;
    cx ee = cx_add(cx_mul(e0, e0), cx_dot3(ev, ev));
    { /* step 0: u = 2 g */
        cx D = cx_add(h->d0[0], cx_scale(s, h->dd[0])), D2 = cx_scale(-2.0, D);
        if (H)
            H[0] = cx_sub(cx_scale(4.0, cx_add(cx_mul(g0, g0), cx_dot3(gv, gv))), cx_mul(D, ee));
        J[0] = cx_mul(D2, e0);
        for (int i = 0; i < 3; i++) {
            J[1 + i] = cx_mul(D2, ev[i]);
            J[5 + i] = cx_scale(8.0, gv[i]);
        }
        J[4] = cx_scale(8.0, g0);
        if (Hs)
            Hs[0] = cx_sub((cx){0.0, 0.0}, cx_mul(h->dd[0], ee));
    }
    for (int k = 1; k < 6; k++) {
        cx m[3], n[3], cr[3], uv[3], nu[3], D;
        for (int i = 0; i < 3; i++) {
            m[i] = cx_add(h->m0[k][i], cx_scale(s, h->dm[k][i]));
            n[i] = cx_add(h->n0[k][i], cx_scale(s, h->dn[k][i]));
        }
        D = cx_add(h->d0[k], cx_scale(s, h->dd[k]));
        cx u0 = cx_sub(cx_scale(2.0, g0), cx_dot3(ev, m));
        cx_cross3(ev, n, cr);
        for (int i = 0; i < 3; i++)
            uv[i] = cx_add(cx_add(cx_mul(e0, m[i]), cr[i]), cx_scale(2.0, gv[i]));
        if (H)
            H[k] = cx_sub(cx_add(cx_mul(u0, u0), cx_dot3(uv, uv)), cx_mul(D, ee));
        cx *Jr = J + 8 * k, D2 = cx_scale(2.0, D);
        Jr[0] = cx_sub(cx_scale(2.0, cx_dot3(uv, m)), cx_mul(D2, e0));
        cx_cross3(n, uv, nu);
        for (int i = 0; i < 3; i++) {
            Jr[1 + i] = cx_sub(cx_scale(2.0, cx_sub(nu[i], cx_mul(u0, m[i]))), cx_mul(D2, ev[i]));
            Jr[5 + i] = cx_scale(4.0, uv[i]);
        }
        Jr[4] = cx_scale(4.0, u0);
        if (Hs) {
            cx duv[3];
            cx du0 = cx_sub((cx){0.0, 0.0}, cx_dot3(ev, h->dm[k]));
            cx_cross3(ev, h->dn[k], cr);
            for (int i = 0; i < 3; i++)
                duv[i] = cx_add(cx_mul(e0, h->dm[k][i]), cr[i]);
            cx q = cx_add(cx_mul(u0, du0), cx_dot3(uv, duv));
            Hs[k] = cx_sub(cx_scale(2.0, q), cx_mul(h->dd[k], ee));
        }
    }
    cx st = {0.0, 0.0}, ch = {-1.0, 0.0};
    for (int i = 0; i < 4; i++) {
        st = cx_add(st, cx_mul(x[i], x[4 + i]));
        J[48 + i] = x[4 + i];
        J[52 + i] = x[i];
    }
    for (int i = 0; i < 8; i++) {
        ch = cx_add(ch, cx_mul(h->c[i], x[i]));
        J[56 + i] = h->c[i];
    }
    if (H) {
        H[6] = st;
        H[7] = ch;
    }
    if (Hs)
        Hs[6] = Hs[7] = (cx){0.0, 0.0};
}

/* b <- A^-1 b, 8 x 8 by elimination with partial pivoting (A destroyed).
 * 0 when A is singular to working precision. */
static int cx_solve8(cx *A, cx *b)
{
    for (int c = 0; c < 8; c++) {
        int p = c;
        double best = cx_abs1(A[8 * c + c]);
        for (int r = c + 1; r < 8; r++) {
            double v = cx_abs1(A[8 * r + c]);
            if (v > best) {
                best = v;
                p = r;
            }
        }
        if (!(best > 1e-300))
            return 0;
        if (p != c) {
            for (int j = c; j < 8; j++) {
                cx tmp = A[8 * c + j];
                A[8 * c + j] = A[8 * p + j];
                A[8 * p + j] = tmp;
            }
            cx tmp = b[c];
            b[c] = b[p];
            b[p] = tmp;
        }
        cx inv = cx_inv(A[8 * c + c]);
        for (int r = c + 1; r < 8; r++) {
            cx f = cx_mul(A[8 * r + c], inv);
            for (int j = c + 1; j < 8; j++)
                A[8 * r + j] = cx_sub(A[8 * r + j], cx_mul(f, A[8 * c + j]));
            b[r] = cx_sub(b[r], cx_mul(f, b[c]));
        }
    }
    for (int r = 7; r >= 0; r--) {
        cx acc = b[r];
        for (int j = r + 1; j < 8; j++)
            acc = cx_sub(acc, cx_mul(A[8 * r + j], b[j]));
        b[r] = cx_mul(acc, cx_inv(A[8 * r + r]));
    }
    for (int r = 0; r < 8; r++)
        if (!isfinite(b[r].re) || !isfinite(b[r].im))
            return 0;
    return 1;
}

/* dx/ds = -H_x^-1 H_s at (x, s) */
static int velocity(const hom *h, const cx *x, double s, cx *v)
{
    cx J[64], Hs[8];
    eval(h, x, s, NULL, J, Hs);
    if (!cx_solve8(J, Hs))
        return 0;
    for (int i = 0; i < 8; i++)
        v[i] = (cx){-Hs[i].re, -Hs[i].im};
    return 1;
}

static double cx_norm_inf(const cx *x)
{
    double m = 0.0;
    for (int i = 0; i < 8; i++)
        m = fmax(m, cx_abs1(x[i]));
    return m;
}

/* One Newton correction at s; writes the relative size of the step. */
static int newton(const hom *h, cx *x, double s, double *rel)
{
    cx J[64], H[8];
    eval(h, x, s, H, J, NULL);
    if (!cx_solve8(J, H))
        return 0;
    for (int i = 0; i < 8; i++)
        x[i] = cx_sub(x[i], H[i]);
    *rel = cx_norm_inf(H) / (1.0 + cx_norm_inf(x));
    return 1;
}

/* Tracks x from s = 0 to s = 1 (careful: the second pass's shorter steps
 * and stricter jump test). 1 on success. */
static int track(const hom *h, cx *x, int careful)
{
    const double hmax = careful ? H_MAX_CAREFUL : H_MAX, jump = careful ? JUMP_TOL_CAREFUL : JUMP_TOL;
    double s = 0.0, step = H_START;
    int run = 0;
    for (int it = 0; it < MAX_STEPS && s < 1.0; it++) {
        double hh = fmin(step, 1.0 - s);
        cx k1[8], k2[8], k3[8], k4[8], y[8];
        int ok = velocity(h, x, s, k1);
        for (int i = 0; ok && i < 8; i++)
            y[i] = cx_add(x[i], cx_scale(0.5 * hh, k1[i]));
        ok = ok && velocity(h, y, s + 0.5 * hh, k2);
        for (int i = 0; ok && i < 8; i++)
            y[i] = cx_add(x[i], cx_scale(0.5 * hh, k2[i]));
        ok = ok && velocity(h, y, s + 0.5 * hh, k3);
        for (int i = 0; ok && i < 8; i++)
            y[i] = cx_add(x[i], cx_scale(hh, k3[i]));
        ok = ok && velocity(h, y, s + hh, k4);
        for (int i = 0; ok && i < 8; i++) {
            cx sum = cx_add(cx_add(k1[i], k4[i]), cx_scale(2.0, cx_add(k2[i], k3[i])));
            y[i] = cx_add(x[i], cx_scale(hh / 6.0, sum));
        }
        int conv = 0;
        for (int n = 0; ok && n < NEWTON_ITERS && !conv; n++) {
            double rel;
            ok = newton(h, y, s + hh, &rel);
            if (ok && n == 0 && rel > jump)
                ok = 0;
            conv = ok && rel < NEWTON_TOL;
        }
        if (conv) {
            memcpy(x, y, sizeof y);
            s = hh == 1.0 - s ? 1.0 : s + hh;
            step = ++run >= GROW_AFTER ? fmin(hh * H_GROW, hmax) : hh;
            run = run >= GROW_AFTER ? 0 : run;
        } else {
            step = 0.5 * hh;
            run = 0;
            if (step < MIN_STEP && 1.0 - s < END_ZONE)
                s = 1.0; /* an ill-conditioned end point: Newton takes it from here */
            else if (step < MIN_STEP)
                return 0;
        }
    }
    if (s < 1.0)
        return 0;
    for (int n = 0; n < 6; n++) {
        double rel;
        if (!newton(h, x, 1.0, &rel))
            return 0;
        if (rel < 1e-15)
            break;
    }
    return 1;
}

/* Residuals |C t2_k + p - t1_k|^2 - d_k^2 of the scaled real data and
 * their Jacobian in (rotation vector on the left, p). */
typedef struct rdata {
    double t1[6][3], t2[6][3], d2[6];
} rdata;

static void real_resid(const rdata *dt, const double *C, const double *p, double *r, double *J)
{
    for (int k = 0; k < 6; k++) {
        double cb[3], w[3], q[3];
        sfmi_matvec3(C, dt->t2[k], cb);
        for (int i = 0; i < 3; i++)
            w[i] = cb[i] + p[i] - dt->t1[k][i];
        r[k] = sfmi_dot3(w, w) - dt->d2[k];
        if (J) {
            sfmi_cross3(cb, w, q);
            for (int i = 0; i < 3; i++) {
                J[6 * k + i] = 2.0 * q[i];
                J[6 * k + 3 + i] = 2.0 * w[i];
            }
        }
    }
}

static int solve(const sfm_r2r_step *s, sfm_r2r_transform *out, double *ws)
{
    for (int k = 0; k < 6; k++)
        if (!sfmi_all_finite3(s[k].t1.v) || !sfmi_all_finite3(s[k].t2.v) || !isfinite(s[k].d))
            return SFM_E_NONFINITE;
    if (sfmi_r2r_motion_degenerate(s, NULL, 6))
        return SFM_E_DEGENERATE;

    /* unit scale: the largest distance or position coordinate */
    double L = 0.0;
    rdata dt;
    for (int k = 0; k < 6; k++) {
        L = fmax(L, s[k].d);
        for (int i = 0; i < 3; i++)
            L = fmax(L, fmax(fabs(s[k].t1.v[i]), fabs(s[k].t2.v[i])));
    }
    if (!(L > 0.0))
        return SFM_E_DEGENERATE;
    hom h;
    for (int k = 0; k < 6; k++) {
        for (int i = 0; i < 3; i++) {
            dt.t1[k][i] = k ? s[k].t1.v[i] / L : 0.0; /* canonical: step 0 at the origins */
            dt.t2[k][i] = k ? s[k].t2.v[i] / L : 0.0;
        }
        dt.d2[k] = (s[k].d / L) * (s[k].d / L);
        const double(*P)[2] = sfmi_r2r_d6_start_par + 7 * k; /* t1, t2, d^2 at P0 */
        for (int i = 0; i < 3; i++) {
            cx a0 = {P[i][0], P[i][1]}, b0 = {P[3 + i][0], P[3 + i][1]};
            cx da = cx_sub((cx){dt.t1[k][i], 0.0}, a0), db = cx_sub((cx){dt.t2[k][i], 0.0}, b0);
            h.m0[k][i] = cx_sub(b0, a0);
            h.n0[k][i] = cx_add(a0, b0);
            h.dm[k][i] = cx_sub(db, da);
            h.dn[k][i] = cx_add(da, db);
        }
        h.d0[k] = (cx){P[6][0], P[6][1]};
        h.dd[k] = cx_sub((cx){dt.d2[k], 0.0}, h.d0[k]);
    }
    for (int i = 0; i < 8; i++)
        h.c[i] = (cx){sfmi_r2r_d6_chart[i][0], sfmi_r2r_d6_chart[i][1]};

    /* all 40 paths; a failed one, and both of two that ended at the same
     * point (one jumped onto the other's path), are tracked again with
     * shorter steps */
    cx *end = (cx *)(void *)ws;
    int ok[SFMI_R2R_D6_NSOL];
    for (int pass = 0; pass < 2; pass++) {
        int again[SFMI_R2R_D6_NSOL], any = 0;
        for (int j = 0; j < SFMI_R2R_D6_NSOL; j++) {
            again[j] = pass == 0 || !ok[j];
            for (int q = 0; pass == 1 && q < SFMI_R2R_D6_NSOL; q++)
                if (q != j && ok[j] && ok[q]) {
                    double d = 0.0;
                    for (int i = 0; i < 8; i++)
                        d = fmax(d, cx_abs1(cx_sub(end[8 * j + i], end[8 * q + i])));
                    again[j] |= d <= SAME_END * (1.0 + cx_norm_inf(end + 8 * j));
                }
            any |= again[j];
        }
        for (int j = 0; j < SFMI_R2R_D6_NSOL && any; j++) {
            if (!again[j])
                continue;
            cx *x = end + 8 * j;
            for (int i = 0; i < 8; i++)
                x[i] = (cx){sfmi_r2r_d6_start_sol[j][i][0], sfmi_r2r_d6_start_sol[j][i][1]};
            ok[j] = track(&h, x, pass);
        }
    }

    int n_out = 0;
    for (int j = 0; j < SFMI_R2R_D6_NSOL; j++) {
        const cx *x = end + 8 * j;
        if (!ok[j])
            continue;
        /* real up to the chart's complex factor: divide by the largest e_i */
        int im = 0;
        for (int i = 1; i < 4; i++)
            if (cx_abs1(x[i]) > cx_abs1(x[im]))
                im = i;
        if (!(cx_abs1(x[im]) > 1e-8 * cx_norm_inf(x)))
            continue; /* e = 0: not a rotation */
        cx inv = cx_inv(x[im]);
        double y[8], big = 0.0, imag = 0.0;
        for (int i = 0; i < 8; i++) {
            cx z = cx_mul(x[i], inv);
            y[i] = z.re;
            big = fmax(big, fabs(z.re));
            imag = fmax(imag, fabs(z.im));
        }
        if (!(imag <= REAL_TOL * big))
            continue;
        /* (C, p) from the real Study point */
        double w = y[0], a = y[1], b = y[2], c = y[3], ee = w * w + a * a + b * b + c * c;
        double C[9] = {w * w + a * a - b * b - c * c, 2 * (a * b - w * c), 2 * (a * c + w * b),
                       2 * (a * b + w * c), w * w - a * a + b * b - c * c, 2 * (b * c - w * a),
                       2 * (a * c - w * b), 2 * (b * c + w * a), w * w - a * a - b * b + c * c};
        double p[3], gxe[3];
        sfmi_cross3(y + 1, y + 5, gxe); /* e_v x g_v */
        for (int i = 0; i < 9; i++)
            C[i] /= ee;
        for (int i = 0; i < 3; i++)
            p[i] = 2.0 * (y[0] * y[5 + i] - y[4] * y[1 + i] + gxe[i]) / ee;
        /* Newton on the real equations */
        double r[6], J[36], res = HUGE_VAL;
        int piv[6];
        for (int n = 0; n < 8; n++) {
            real_resid(&dt, C, p, r, J);
            if (sfm_lu_factor(J, 6, piv) < 0 || sfm_lu_solve(J, piv, 6, r, 1) < 0)
                break;
            double aa[3] = {-r[0], -r[1], -r[2]}, R[9], dmax = 0.0;
            for (int i = 0; i < 6; i++)
                dmax = fmax(dmax, fabs(r[i]));
            if (!(dmax < 0.1))
                break;
            sfm_rot_from_axis_angle(aa, R);
            sfmi_matmul3(R, C, C);
            for (int i = 0; i < 3; i++)
                p[i] -= r[3 + i];
            if (dmax < 1e-15)
                break;
        }
        real_resid(&dt, C, p, r, NULL);
        res = 0.0;
        for (int k = 0; k < 6; k++)
            res = fmax(res, fabs(r[k]));
        if (!(res <= RES_TOL))
            continue;
        sfm_r2r_transform T;
        memcpy(T.C.m, C, sizeof C);
        for (int i = 0; i < 3; i++)
            T.p.v[i] = p[i] * L;
        if (!sfmi_r2r_is_duplicate(out, n_out, &T, L, DUP_TOL))
            out[n_out++] = T;
    }
    return n_out;
}

const sfmi_r2r_system_desc sfmi_r2r_d6 = {
    SFM_R2R_SYS_D6, 6, {SFM_R2R_D, SFM_R2R_D, SFM_R2R_D, SFM_R2R_D, SFM_R2R_D, SFM_R2R_D},
    40, 16 * SFMI_R2R_D6_NSOL, solve, "d6"};
