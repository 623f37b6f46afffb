/*
 * Robot-to-robot base system B1_D_D_D_D: robot 1 sees robot 2 at the first
 * step (b1), the distance is measured at four more (Zhou & Roumeliotis,
 * IEEE T-RO 2013, the system of one bearing and four distances; 28 complex
 * solutions by a GF(p) Groebner basis of its Cayley form).
 *
 * Canonical form: steps[0] has the identity ego-motion; p = l u0 (u0 = b1_0).
 * For a given l, a = C t2_1 lies on the sphere |a| = |t2_1| and on the
 * sphere |a - e| = d_1 about e = t1_1 - l u0: a circle a(phi) in the plane
 * normal to e, whose in-plane axes can be held fixed (m = u0 x t1_1 is
 * normal to e for every l). As in B1_B1_D_D, C is the rotation taking t2_1
 * to a followed by a turn theta about a, the frame at a is linear in a, and
 * each remaining distance equation (k = 2, 3, 4) reads
 *   alpha_k cos(theta) + beta_k sin(theta) + gamma_k = 0,
 * alpha, beta, gamma trigonometric polynomials of degree 1 in phi. The three
 * share a (cos, sin) on the unit circle when det[alpha beta gamma] = 0
 * (degree 3 in phi) and the Cramer solution of two of them has unit norm
 * (degree 4): two polynomials in tan(phi/2) of degrees 6 and 8, whose
 * Sylvester resultant (14 x 14, by LU) is a continuous function of l that
 * vanishes at the solutions. It is scanned over the l the data allow
 * (l <= d_k + |t1_k| + |t2_k|, and the circle real); sign changes are
 * bisected and sign-keeping dips searched for a hidden pair. At each root
 * l, phi is a common root of the two polynomials and theta follows by
 * Cramer's rule; Newton steps on the three distance equations in
 * (l, phi, theta) polish it, and only l > 0 with all equations met is kept.
 *
 * Degenerate data: t1_1 on the bearing's line (no fixed circle axes) or
 * robot 2 not moved by step 1: SFM_E_DEGENERATE. Stack under 6 KB (the
 * polynomial root finder's); no ws. About 2000 resultants (14 x 14 LU each)
 * per solve.
 */
#include <math.h>

#include "core/dmath.h"
#include "sfm/sfm_linalg.h"
#include "sfm/sfm_poly.h"
#include "solvers/r2r_align.h"
#include "solvers/r2r_internal.h"

#define NLAM 1500
#define MAX_ROOTS 32
#define TWO_PI 6.283185307179586476925286766559

typedef struct geo {
    double u0[3], t11[3], m[3], rho, d1, lmax;
    double G[9];      /* columns: frame of {2} with first axis t2_1 */
    double v[3][3];   /* G^T t2_k, k = 2, 3, 4 */
    double t1[3][3];  /* t1_k */
    double K[3];      /* |t2_k|^2 - d_k^2 */
    double c7[7], s7[7], c9[9], s9[9]; /* cos, sin of 2 pi j / 7 and / 9 */
} geo;

typedef struct circ {
    double n[3], e2[3], h0, r;
    double abc[3][3][3]; /* [eq][alpha, beta, gamma][const, cos, sin] */
} circ;

/* a, the frame at a (columns) and the equations' coefficients at (cos, sin) */
static void at_phi(const geo *g, const circ *c, double l, double cp, double sp, double a[3],
                   double F[9], double abc[3][3])
{
    double f2[3], f3[3];
    for (int i = 0; i < 3; i++)
        a[i] = c->h0 * c->n[i] + c->r * (cp * g->m[i] + sp * c->e2[i]);
    sfmi_r2r_circle_frame(c->n, a, c->h0, c->r, g->rho, F, f2, f3);
    for (int k = 0; k < 3; k++) {
        double q[3];
        sfmi_r2r_distance_cs(l, g->u0, g->t1[k], g->v[k], f2, f3, q, abc[k]);
        abc[k][2] = sfmi_dot3(q, q) + g->K[k] + 2.0 * g->v[k][0] * sfmi_dot3(q, a) / g->rho;
    }
}

/* The circle at l; 0 when it is not real. */
static int circle(const geo *g, double l, circ *c)
{
    double e[3];
    for (int i = 0; i < 3; i++)
        e[i] = g->t11[i] - l * g->u0[i];
    double E = sqrt(sfmi_dot3(e, e));
    if (!(E > 0.0))
        return 0;
    for (int i = 0; i < 3; i++)
        c->n[i] = e[i] / E;
    c->h0 = (g->rho * g->rho + E * E - g->d1 * g->d1) / (2.0 * E);
    double r2 = g->rho * g->rho - c->h0 * c->h0;
    if (!(r2 > 1e-12 * g->rho * g->rho))
        return 0;
    c->r = sqrt(r2);
    sfmi_cross3(c->n, g->m, c->e2);
    return 1;
}

/* Fourier coefficients (const, cos, sin) of alpha, beta, gamma: exact from
 * phi = 0, pi/2, pi for degree 1. */
static void coef_fourier(const geo *g, circ *c, double l)
{
    double a[3], F[9], v0[3][3], v1[3][3], v2[3][3];
    at_phi(g, c, l, 1.0, 0.0, a, F, v0);
    at_phi(g, c, l, 0.0, 1.0, a, F, v1);
    at_phi(g, c, l, -1.0, 0.0, a, F, v2);
    for (int k = 0; k < 3; k++)
        for (int j = 0; j < 3; j++) {
            double c0 = 0.5 * (v0[k][j] + v2[k][j]);
            c->abc[k][j][0] = c0;
            c->abc[k][j][1] = 0.5 * (v0[k][j] - v2[k][j]);
            c->abc[k][j][2] = v1[k][j] - c0;
        }
}

static void eval_abc(const circ *c, double cp, double sp, double abc[3][3])
{
    for (int k = 0; k < 3; k++)
        for (int j = 0; j < 3; j++)
            abc[k][j] = c->abc[k][j][0] + c->abc[k][j][1] * cp + c->abc[k][j][2] * sp;
}

static double det3_of(double abc[3][3])
{
    double M[9];
    for (int k = 0; k < 3; k++)
        for (int j = 0; j < 3; j++)
            M[3 * k + j] = abc[k][j];
    return sfmi_r2r_det3(M);
}

static double norm_of(double abc[3][3])
{
    double X = abc[0][1] * abc[1][2] - abc[1][1] * abc[0][2];
    double Y = abc[1][0] * abc[0][2] - abc[0][0] * abc[1][2];
    double D = abc[0][0] * abc[1][1] - abc[1][0] * abc[0][1];
    return X * X + Y * Y - D * D;
}

/* (1 + t^2)^D f(phi(t)), t = tan(phi/2), ascending, from 2D + 1 samples of
 * a trigonometric polynomial f of degree D (exact DFT). */
static void half_angle_poly(const double *fs, int D, const double *cs, const double *sn,
                            double *P)
{
    int N = 2 * D + 1;
    double A[5], B[5], re[9], im[9], w[9];
    for (int k = 0; k <= D; k++) {
        double sa = 0.0, sb = 0.0;
        for (int j = 0; j < N; j++) {
            sa += fs[j] * cs[(k * j) % N];
            sb += fs[j] * sn[(k * j) % N];
        }
        A[k] = (k == 0 ? 1.0 : 2.0) * sa / N;
        B[k] = 2.0 * sb / N;
    }
    for (int i = 0; i <= 2 * D; i++) {
        P[i] = 0.0;
        re[i] = im[i] = 0.0;
    }
    re[0] = 1.0;
    for (int k = 0; k <= D; k++) {
        if (k > 0)
            for (int rep = 0; rep < 2; rep++) /* times (1 + i t) */
                for (int j = 2 * k; j >= 1; j--) {
                    double r = re[j] - im[j - 1], ii = im[j] + re[j - 1];
                    re[j] = r;
                    im[j] = ii;
                }
        for (int j = 0; j <= 2 * D; j++)
            w[j] = j == 0 ? 1.0 : 0.0;
        for (int e = 0; e < D - k; e++) /* (1 + t^2)^(D - k) */
            for (int j = 2 * e + 2; j >= 2; j--)
                w[j] += w[j - 2];
        for (int i = 0; i <= 2 * k; i++) {
            double z = A[k] * re[i] + B[k] * im[i];
            for (int j = 0; j <= 2 * (D - k); j++)
                P[i + j] += z * w[j];
        }
    }
}

/* The two polynomials in t at l (ascending; degrees 6 and 8). 0 when the
 * circle is not real. */
static int polys_at(const geo *g, double l, circ *c, double p1[7], double p2[9])
{
    if (!circle(g, l, c))
        return 0;
    coef_fourier(g, c, l);
    double f1[7], f2[9], abc[3][3];
    for (int j = 0; j < 7; j++) {
        eval_abc(c, g->c7[j], g->s7[j], abc);
        f1[j] = det3_of(abc);
    }
    for (int j = 0; j < 9; j++) {
        eval_abc(c, g->c9[j], g->s9[j], abc);
        f2[j] = norm_of(abc);
    }
    half_angle_poly(f1, 3, g->c7, g->s7, p1);
    half_angle_poly(f2, 4, g->c9, g->s9, p2);
    return 1;
}

/* Sign-carrying resultant of the two polynomials at l (NAN off the circle). */
static double resultant(const geo *g, double l)
{
    circ c;
    double p1[7], p2[9], S[14 * 14];
    int piv[14];
    if (!polys_at(g, l, &c, p1, p2))
        return (double)NAN;
    double n1 = 0.0, n2 = 0.0;
    for (int i = 0; i < 7; i++)
        n1 = sfmi_r2r_max(n1, fabs(p1[i]));
    for (int i = 0; i < 9; i++)
        n2 = sfmi_r2r_max(n2, fabs(p2[i]));
    if (!(n1 > 0.0) || !(n2 > 0.0))
        return 0.0;
    for (int i = 0; i < 14 * 14; i++)
        S[i] = 0.0;
    for (int r = 0; r < 8; r++) /* 8 shifts of p1 (descending) */
        for (int j = 0; j <= 6; j++)
            S[r * 14 + r + j] = p1[6 - j] / n1;
    for (int r = 0; r < 6; r++) /* 6 shifts of p2 */
        for (int j = 0; j <= 8; j++)
            S[(8 + r) * 14 + r + j] = p2[8 - j] / n2;
    if (sfm_lu_factor(S, 14, piv) < 0)
        return 0.0;
    double det = 1.0;
    for (int i = 0; i < 14; i++) {
        det *= S[i * 14 + i];
        if (piv[i] != i)
            det = -det;
        if (fabs(det) < 1e-200 || fabs(det) > 1e200) /* keep the sign, tame the size */
            det = det < 0.0 ? -1e-100 : 1e-100;
    }
    return det;
}

static double resultant_cb(const void *g, double x)
{
    return resultant((const geo *)g, x);
}

/* Roots of the resultant on [lo, hi] (an interval where the circle is
 * real): Chebyshev nodes, dense near the ends where the circle shrinks to a
 * point and the resultant with it; sign changes are bisected, sign-keeping
 * dips searched for a hidden pair. */
static int scan_interval(const geo *g, double lo, double hi, int nodes, double *ls, int m)
{
    double t[3] = {0.0, 0.0, 0.0}, f[3] = {(double)NAN, (double)NAN, (double)NAN};
    for (int j = 0; j < nodes && m + 2 <= MAX_ROOTS; j++) {
        double lc = 0.5 * (lo + hi) - 0.5 * (hi - lo) * sfmi_cos(0.5 * TWO_PI * (j + 0.5) / nodes);
        double fc = resultant(g, lc);
        m = sfmi_r2r_scan_step(resultant_cb, g, t, f, lc, fc, 50, 1, ls, m);
    }
    return m;
}

/* The l in (0, lmax] where the circle is real: |rho - d1| < |t1_1 - l u0| <
 * rho + d1, between the roots of two quadratics in l. */
static int scan(const geo *g, double *ls)
{
    double a = sfmi_dot3(g->u0, g->t11), T = sfmi_dot3(g->t11, g->t11);
    double br[6] = {0.0, g->lmax};
    int nb = 2;
    double V[2] = {g->rho + g->d1, g->rho - g->d1};
    for (int i = 0; i < 2; i++) {
        double disc = a * a - T + V[i] * V[i];
        if (disc > 0.0) {
            double sq = sqrt(disc);
            for (int sgn = -1; sgn <= 1; sgn += 2) {
                double x = a + sgn * sq;
                if (x > 0.0 && x < g->lmax)
                    br[nb++] = x;
            }
        }
    }
    for (int i = 1; i < nb; i++) /* sort the breakpoints */
        for (int j = i; j > 0 && br[j] < br[j - 1]; j--) {
            double tmp = br[j];
            br[j] = br[j - 1];
            br[j - 1] = tmp;
        }
    int m = 0;
    for (int i = 0; i + 1 < nb; i++) {
        double lo = br[i], hi = br[i + 1];
        circ c;
        if (!(hi > lo) || !circle(g, 0.5 * (lo + hi), &c))
            continue;
        int nodes = (int)(NLAM * (hi - lo) / g->lmax) + 40;
        m = scan_interval(g, lo, hi, nodes, ls, m);
    }
    return m;
}

/* residuals of the three distance equations at (l, phi, theta) */
static int resid(const geo *g, double l, double phi, double th, double e[3], double *C)
{
    circ c;
    if (!circle(g, l, &c))
        return 0;
    double a[3], F[9], abc[3][3], sp, cp, st, ct;
    sfmi_sincos(phi, &sp, &cp);
    sfmi_sincos(th, &st, &ct);
    at_phi(g, &c, l, cp, sp, a, F, abc);
    for (int k = 0; k < 3; k++)
        e[k] = abc[k][0] * ct + abc[k][1] * st + abc[k][2];
    if (C)
        sfmi_r2r_turn_compose(F, ct, st, g->G, C);
    return 1;
}

static int solve(const sfm_r2r_step *s, sfm_r2r_transform *out, double *ws)
{
    (void)ws;
    geo g;
    sfmi_r2r_u(&s[0], g.u0);
    double nu = sqrt(sfmi_dot3(g.u0, g.u0));
    const double *t21 = s[1].t2.v;
    for (int i = 0; i < 3; i++) {
        g.u0[i] /= nu;
        g.t11[i] = s[1].t1.v[i];
    }
    sfmi_cross3(g.u0, g.t11, g.m);
    double nm = sqrt(sfmi_dot3(g.m, g.m));
    g.rho = sqrt(sfmi_dot3(t21, t21));
    double scale = 1.0 + sqrt(sfmi_dot3(g.t11, g.t11));
    if (!(nm > 1e-9 * scale) || !(g.rho > 1e-9 * scale))
        return SFM_E_DEGENERATE;
    for (int i = 0; i < 3; i++)
        g.m[i] /= nm;
    g.d1 = s[1].d;
    for (int j = 0; j < 9; j++) {
        if (j < 7)
            sfmi_sincos(TWO_PI * j / 7, &g.s7[j], &g.c7[j]);
        sfmi_sincos(TWO_PI * j / 9, &g.s9[j], &g.c9[j]);
    }
    double ax[3][3];
    sfmi_r2r_axis_frame(t21, g.rho, ax, g.G);
    g.lmax = HUGE_VAL;
    for (int k = 0; k < 3; k++) {
        const sfm_r2r_step *sk = &s[2 + k];
        for (int j = 0; j < 3; j++)
            g.v[k][j] = sfmi_dot3(ax[j], sk->t2.v);
        for (int i = 0; i < 3; i++)
            g.t1[k][i] = sk->t1.v[i];
        g.K[k] = sfmi_dot3(sk->t2.v, sk->t2.v) - sk->d * sk->d;
        double bk = sk->d + sqrt(sfmi_dot3(sk->t1.v, sk->t1.v)) +
                    sqrt(sfmi_dot3(sk->t2.v, sk->t2.v));
        g.lmax = g.lmax < bk ? g.lmax : bk;
    }
    {
        double bk = g.d1 + sqrt(sfmi_dot3(g.t11, g.t11)) + g.rho;
        g.lmax = g.lmax < bk ? g.lmax : bk;
    }

    double ls[MAX_ROOTS];
    int nl = scan(&g, ls), n_out = 0;
    for (int il = 0; il < nl; il++) {
        circ c;
        double p1[7], p2[9], desc[7], roots[6];
        if (!polys_at(&g, ls[il], &c, p1, p2))
            continue;
        for (int i = 0; i <= 6; i++)
            desc[i] = p1[6 - i];
        int nr = sfm_poly_real_roots(desc, 6, -HUGE_VAL, HUGE_VAL, roots);
        for (int ir = 0; ir < nr; ir++) {
            double l = ls[il], phi = 2.0 * sfmi_atan(roots[ir]), abc[3][3], sp, cp;
            sfmi_sincos(phi, &sp, &cp);
            eval_abc(&c, cp, sp, abc);
            double D = abc[0][0] * abc[1][1] - abc[1][0] * abc[0][1];
            double ct = (abc[0][1] * abc[1][2] - abc[1][1] * abc[0][2]) / D;
            double st = (abc[1][0] * abc[0][2] - abc[0][0] * abc[1][2]) / D;
            double nt = sqrt(ct * ct + st * st);
            if (!(nt > 0.7 && nt < 1.4))
                continue; /* phi is no common root */
            double th = sfmi_atan2(st, ct), e[3];
            for (int it = 0; it < 6; it++) { /* Newton in (l, phi, theta) */
                double J[9], e1[3], dx[3], h = 1e-7 * (1.0 + l);
                if (!resid(&g, l, phi, th, e, NULL))
                    break;
                if (!resid(&g, l + h, phi, th, e1, NULL))
                    break;
                for (int k = 0; k < 3; k++)
                    J[3 * k] = (e1[k] - e[k]) / h;
                if (!resid(&g, l, phi + 1e-7, th, e1, NULL))
                    break;
                for (int k = 0; k < 3; k++)
                    J[3 * k + 1] = (e1[k] - e[k]) / 1e-7;
                if (!resid(&g, l, phi, th + 1e-7, e1, NULL))
                    break;
                for (int k = 0; k < 3; k++)
                    J[3 * k + 2] = (e1[k] - e[k]) / 1e-7;
                if (!sfmi_r2r_solve3(J, e, dx) || fabs(dx[0]) > 0.1 * (1.0 + l) ||
                    fabs(dx[1]) > 0.2 || fabs(dx[2]) > 0.2)
                    break;
                l -= dx[0];
                phi -= dx[1];
                th -= dx[2];
            }
            sfm_r2r_transform T;
            if (!(l > 0.0) || !resid(&g, l, phi, th, e, T.C.m))
                continue;
            double res = sfmi_r2r_max(fabs(e[0]), sfmi_r2r_max(fabs(e[1]), fabs(e[2])));
            if (!(res <= 1e-9 * (1.0 + l * l + scale * scale)))
                continue;
            for (int i = 0; i < 3; i++)
                T.p.v[i] = l * g.u0[i];
            if (n_out < 28 && !sfmi_r2r_is_duplicate(out, n_out, &T, 1.0 + l, 1e-8))
                out[n_out++] = T;
        }
    }
    return n_out;
}

const sfmi_r2r_system_desc sfmi_r2r_b1_d_d_d_d = {
    SFM_R2R_SYS_B1_D_D_D_D, 5, {SFM_R2R_B1, SFM_R2R_D, SFM_R2R_D, SFM_R2R_D, SFM_R2R_D, 0},
    28, 0, solve, "b1_d_d_d_d"};
