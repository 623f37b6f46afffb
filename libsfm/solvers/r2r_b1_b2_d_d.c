/*
 * Robot-to-robot base system B1_B2_D_D: robot 1 sees robot 2 at the first
 * step (b1), robot 2 sees robot 1 at the second (b2), the distance is
 * measured at two more (Zhou & Roumeliotis, IEEE T-RO 2013, the system of
 * one bearing from each robot and two distances; 16 complex solutions by a
 * GF(p) Groebner basis of its Cayley form; at most 24 candidates here, the
 * degree of the polynomial below).
 *
 * Canonical form: steps[0] has the identity ego-motion. With u0 = b1_0 and
 * w = R2_1 b2_1 the bearings say p = l u0 and C^T (t1_1 - p) - t2_1 = n w:
 * x = t1_1 - l u0 (in {1}) is C y with y = t2_1 + n w (in {2}), so |x| = |y|,
 * a hyperbola in (l, n), parametrised rationally by tau,
 *   l - a = (tau + K / tau) / 2,  n + b = (tau - K / tau) / 2
 * (a = u0.t1_1, b = w.t2_1, K the hyperbola's constant). C is the rotation
 * taking y to x followed by a turn theta about x. The frames
 * (x/|x|, m, x/|x| x m) and (y/|y|, k, y/|y| x k) have constant middle axes
 * (m the normal of u0 and t1_1, k that of w and t2_1: u0 x x and w x y do
 * not move), so each distance equation times |x|^2 reads
 *   alpha cos(theta) + beta (|x| sin(theta)) + gamma = 0
 * with alpha, beta, gamma polynomials of degrees 2, 1, 4 in (l, n).
 * Eliminating theta (Cramer, then |x|^2 cos^2 + (|x| sin)^2 = |x|^2) leaves a
 * Laurent polynomial of degree 12 in tau (at most 24 real roots). Its
 * coefficients are badly scaled (the roots spread over decades and come in
 * close pairs), so it is not expanded: it is evaluated directly along both
 * halves of the real tau axis, between bounds the data give, on a
 * logarithmic grid; sign changes are bisected, and sign-keeping dips are
 * searched (golden section) for a hidden pair. Each root is polished by
 * Newton steps on the two distance equations in (tau, theta), and only
 * roots with l, n > 0 that satisfy both are kept.
 *
 * Degenerate data: t1_1 on the first bearing's line, t2_1 on the second's,
 * or a degenerate hyperbola (K = 0): SFM_E_DEGENERATE. Stack under 2 KB; no
 * ws. About 1200 evaluations of the eliminant per solve.
 */
#include <math.h>

#include "core/dmath.h"
#include "solvers/r2r_align.h"
#include "solvers/r2r_internal.h"

#define LDEG 12 /* Laurent degree of the eliminant in tau: at most 24 real roots */
#define NSCAN 600
#define MAX_ROOTS (4 * LDEG)



typedef struct geo {
    double a, b, K, r0, t11sq;
    double u0[3], w[3], m[3], k[3];
    /* per distance step: constants of the pieces (see coefs) */
    double qm[2], v2[2], Y0[2], Y1[2], Z0[2], Z1[2], yt0[2], yt1[2], qx1[2], qx0[2];
    double qq1[2], qq0[2], Kd[2];
} geo;

/* alpha, beta, gamma of both distance equations and |x|^2 at (l, n) */
static void coefs(const geo *g, double l, double n, double abc[2][3], double *rho2)
{
    double r2 = l * l - 2.0 * g->a * l + g->t11sq;
    for (int k = 0; k < 2; k++) {
        double Y = g->Y0[k] + g->Y1[k] * n, Z = g->Z0[k] + g->Z1[k] * l;
        double yt = g->yt0[k] + g->yt1[k] * n;
        double qx = g->qx0[k] + g->qx1[k] * l - l * l;
        double qq = l * l + g->qq1[k] * l + g->qq0[k] + g->Kd[k];
        abc[k][0] = 2.0 * (g->v2[k] * g->qm[k] * r2 + Y * Z);
        abc[k][1] = 2.0 * (g->v2[k] * Z - g->qm[k] * Y);
        abc[k][2] = r2 * qq + 2.0 * yt * qx;
    }
    *rho2 = r2;
}

/* zero where both distance equations share one (cos, |x| sin) on the circle */
static double eliminant(double abc[2][3], double r2)
{
    double X = abc[0][1] * abc[1][2] - abc[1][1] * abc[0][2];
    double Y = abc[1][0] * abc[0][2] - abc[0][0] * abc[1][2];
    double D = abc[0][0] * abc[1][1] - abc[1][0] * abc[0][1];
    return r2 * (X * X - D * D) + Y * Y;
}

static void ln_of_tau(const geo *g, double tau, double *l, double *n)
{
    *l = g->a + 0.5 * (tau + g->K / tau);
    *n = -g->b + 0.5 * (tau - g->K / tau);
}

/* the two distance equations (times |x|^2) at real (tau, theta) */
static void residuals(const geo *g, double tau, double th, double e[2], double de_dth[2])
{
    double l, n, s, c;
    ln_of_tau(g, tau, &l, &n);
    double abc[2][3], r2;
    coefs(g, l, n, abc, &r2);
    double rho = sqrt(r2);
    sfmi_sincos(th, &s, &c);
    for (int k = 0; k < 2; k++) {
        e[k] = abc[k][0] * c + abc[k][1] * rho * s + abc[k][2];
        if (de_dth)
            de_dth[k] = -abc[k][0] * s + abc[k][1] * rho * c;
    }
}

static double elim_at(const geo *g, double tau)
{
    double l, n;
    ln_of_tau(g, tau, &l, &n);
    double abc[2][3], r2;
    coefs(g, l, n, abc, &r2);
    return eliminant(abc, r2);
}

static double elim_cb(const void *g, double x)
{
    return elim_at((const geo *)g, x);
}

/* Real roots of the eliminant on both halves of the real tau axis within
 * [|K| / M, M]: sign changes on a logarithmic grid of NSCAN points per half,
 * each refined by bisection, and sign-keeping dips searched for a hidden
 * pair (sfmi_r2r_scan_step). The eliminant is evaluated directly (not from
 * coefficients), so a root is as accurate as the equations allow; two roots
 * closer than the grid spacing without a sign change between them are
 * missed (the tests count how often). */
static int scan_roots(const geo *g, double M, double *taus)
{
    double lo = sfmi_log(fabs(g->K) / M), hi = sfmi_log(M);
    if (!(hi > lo))
        return 0;
    int m = 0;
    for (int half = 0; half < 2; half++) {
        double sg = half ? -1.0 : 1.0, t[3] = {0.0, 0.0, 0.0};
        double f[3] = {(double)NAN, (double)NAN, (double)NAN};
        for (int j = 0; j <= NSCAN && m + 2 <= MAX_ROOTS; j++) {
            double tc = sg * sfmi_exp(lo + (hi - lo) * j / NSCAN), fc = elim_at(g, tc);
            if (!isfinite(fc))
                return SFM_E_SINGULAR;
            m = sfmi_r2r_scan_step(elim_cb, g, t, f, tc, fc, 60, 0, taus, m);
        }
    }
    return m;
}

static int solve(const sfm_r2r_step *s, sfm_r2r_transform *out, double *ws)
{
    (void)ws;
    geo g;
    sfmi_r2r_u(&s[0], g.u0);
    sfmi_r2r_w(&s[1], g.w);
    const double *t11 = s[1].t1.v, *t21 = s[1].t2.v;
    double nu = sqrt(sfmi_dot3(g.u0, g.u0)), nw = sqrt(sfmi_dot3(g.w, g.w));
    for (int i = 0; i < 3; i++) {
        g.u0[i] /= nu;
        g.w[i] /= nw;
    }
    sfmi_cross3(g.u0, t11, g.m);
    sfmi_cross3(g.w, t21, g.k);
    double nm = sqrt(sfmi_dot3(g.m, g.m)), nk = sqrt(sfmi_dot3(g.k, g.k));
    g.t11sq = sfmi_dot3(t11, t11);
    double t21sq = sfmi_dot3(t21, t21);
    double scale = 1.0 + g.t11sq + t21sq;
    if (!(nm > 1e-9 * sqrt(scale)) || !(nk > 1e-9 * sqrt(scale)))
        return SFM_E_DEGENERATE;
    for (int i = 0; i < 3; i++) {
        g.m[i] /= nm;
        g.k[i] /= nk;
    }
    g.a = sfmi_dot3(g.u0, t11);
    g.b = sfmi_dot3(g.w, t21);
    g.K = (t21sq - g.b * g.b) - (g.t11sq - g.a * g.a);
    if (!(fabs(g.K) > 1e-12 * scale))
        return SFM_E_DEGENERATE;
    g.r0 = sqrt(fabs(g.K));
    double t1xm[3], u0xm[3], t2xk[3], wxk[3];
    sfmi_cross3(t11, g.m, t1xm);
    sfmi_cross3(g.u0, g.m, u0xm);
    sfmi_cross3(t21, g.k, t2xk);
    sfmi_cross3(g.w, g.k, wxk);
    for (int k = 0; k < 2; k++) {
        const sfm_r2r_step *sk = &s[2 + k];
        const double *t1 = sk->t1.v, *t2 = sk->t2.v;
        g.qm[k] = -sfmi_dot3(t1, g.m);
        g.v2[k] = sfmi_dot3(g.k, t2);
        g.Y0[k] = sfmi_dot3(t2xk, t2);
        g.Y1[k] = sfmi_dot3(wxk, t2);
        g.Z1[k] = sfmi_dot3(g.u0, t1xm) + sfmi_dot3(t1, u0xm);
        g.Z0[k] = -sfmi_dot3(t1, t1xm);
        g.yt0[k] = sfmi_dot3(t21, t2);
        g.yt1[k] = sfmi_dot3(g.w, t2);
        g.qx1[k] = g.a + sfmi_dot3(t1, g.u0);
        g.qx0[k] = -sfmi_dot3(t1, t11);
        g.qq1[k] = -2.0 * sfmi_dot3(g.u0, t1);
        g.qq0[k] = sfmi_dot3(t1, t1);
        g.Kd[k] = sfmi_dot3(t2, t2) - sk->d * sk->d;
    }

    /* Every physical solution has l, n below a bound M the data give
     * (l <= d_k + |t1_k| + |t2_k|, n <= l + |t1_1| + |t2_1|), hence
     * |K| / (2 M') <= |tau| <= 2 M' with M' = M + |a| + |b|. */
    double M = HUGE_VAL;
    for (int k = 2; k < 4; k++) {
        double bk = s[k].d + sqrt(sfmi_dot3(s[k].t1.v, s[k].t1.v)) +
                    sqrt(sfmi_dot3(s[k].t2.v, s[k].t2.v));
        M = M < bk ? M : bk;
    }
    M += sqrt(g.t11sq) + sqrt(t21sq);
    M = 2.0 * (M + fabs(g.a) + fabs(g.b));
    double taus[MAX_ROOTS];
    int nt = scan_roots(&g, M, taus);

    int n_out = 0;
    for (int r = 0; r < nt; r++) {
        double tau = taus[r];
        double l, n, e[2], dth[2];
        ln_of_tau(&g, tau, &l, &n);
        double abc[2][3], r2;
        coefs(&g, l, n, abc, &r2);
        double D = abc[0][0] * abc[1][1] - abc[1][0] * abc[0][1];
        double c = (abc[0][1] * abc[1][2] - abc[1][1] * abc[0][2]) / D;
        double sg = (abc[1][0] * abc[0][2] - abc[0][0] * abc[1][2]) / D;
        double th = sfmi_atan2(sg / sqrt(r2), c);
        if (!isfinite(th))
            continue;
        for (int it = 0; it < 5; it++) { /* Newton in (tau, theta) */
            double h = 1e-7 * (fabs(tau) + g.r0), e2[2], J[4];
            residuals(&g, tau, th, e, dth);
            residuals(&g, tau + h, th, e2, NULL);
            for (int k = 0; k < 2; k++) {
                J[2 * k] = (e2[k] - e[k]) / h;
                J[2 * k + 1] = dth[k];
            }
            double dj = J[0] * J[3] - J[1] * J[2];
            double dt = (e[0] * J[3] - e[1] * J[1]) / dj, dq = (J[0] * e[1] - J[2] * e[0]) / dj;
            if (!isfinite(dt) || !isfinite(dq) || fabs(dt) > 0.1 * (fabs(tau) + g.r0) ||
                fabs(dq) > 0.1)
                break;
            tau -= dt;
            th -= dq;
        }
        residuals(&g, tau, th, e, NULL);
        ln_of_tau(&g, tau, &l, &n);
        if (!(l > 0.0 && n > 0.0))
            continue;
        coefs(&g, l, n, abc, &r2);
        double big = 0.0, res = 0.0;
        for (int k = 0; k < 2; k++) {
            res = sfmi_r2r_max(res, fabs(e[k]));
            big = sfmi_r2r_max(big, fabs(abc[k][0]) + fabs(abc[k][1]) * sqrt(r2) + fabs(abc[k][2]));
        }
        if (!(res <= 1e-8 * big))
            continue;
        /* C = Fx Rx(theta) Gy^T */
        double x[3], y[3], Fx[9], Gy[9], sn, cs;
        for (int i = 0; i < 3; i++) {
            x[i] = t11[i] - l * g.u0[i];
            y[i] = t21[i] + n * g.w[i];
        }
        double nx = sqrt(sfmi_dot3(x, x)), ny = sqrt(sfmi_dot3(y, y)), x3[3], y3[3];
        sfmi_cross3(x, g.m, x3);
        sfmi_cross3(y, g.k, y3);
        for (int i = 0; i < 3; i++) {
            Fx[3 * i] = x[i] / nx;
            Fx[3 * i + 1] = g.m[i];
            Fx[3 * i + 2] = x3[i] / nx;
            Gy[3 * i] = y[i] / ny;
            Gy[3 * i + 1] = g.k[i];
            Gy[3 * i + 2] = y3[i] / ny;
        }
        sfmi_sincos(th, &sn, &cs);
        sfm_r2r_transform T;
        sfmi_r2r_turn_compose(Fx, cs, sn, Gy, T.C.m);
        for (int i = 0; i < 3; i++)
            T.p.v[i] = l * g.u0[i];
        if (!sfmi_r2r_is_duplicate(out, n_out, &T, 1.0 + l, 1e-9))
            out[n_out++] = T;
    }
    return n_out;
}

const sfmi_r2r_system_desc sfmi_r2r_b1_b2_d_d = {
    SFM_R2R_SYS_B1_B2_D_D, 4, {SFM_R2R_B1, SFM_R2R_B2, SFM_R2R_D, SFM_R2R_D, 0, 0},
    16, 0, solve, "b1_b2_d_d"};
