/*
 * Robot-to-robot base system B1_B1_D_D: robot 1 sees robot 2 at the first
 * two steps (b1), the distance is measured at two more (Zhou & Roumeliotis,
 * IEEE T-RO 2013, the system of two bearings and two distances; at most 16
 * solutions here, the degree of the univariate polynomial below).
 *
 * Canonical form: steps[0] has the identity ego-motion. With u_k = R1_k b1_k
 * (in {1}) the bearings say p = l u0 and C t2_1 + p - t1_1 = m u1, so
 * a = C t2_1 lies in the plane through t1_1 spanned by u0 and u1 (normal n)
 * and on the sphere |a| = |t2_1|: a circle, a(phi). Given a, (l, m) follow
 * linearly, and C is the rotation taking t2_1 to a followed by a turn theta
 * about a. The frame (a/|a|, n x a / r, (|a|^2 n - (n.a) a) / (|a| r)) is
 * linear in a (r the circle's radius), so each distance equation
 *   |C t2_k + l u0 - t1_k|^2 = d_k^2   (k = 2, 3)
 * reads alpha_k cos(theta) + beta_k sin(theta) + gamma_k = 0 with alpha,
 * beta, gamma trigonometric polynomials of degree 2 in phi. Eliminating
 * theta (Cramer, then cos^2 + sin^2 = 1) leaves a trigonometric polynomial
 * of degree 8 in phi; it is sampled at 17 angles, its Fourier coefficients
 * taken exactly by a DFT, and it becomes a degree-16 polynomial in
 * tan(phi/2) whose real roots (Sturm, sfm_poly_real_roots) give phi; each is
 * polished by Newton steps on the trigonometric form, theta follows from
 * Cramer's rule, and only roots with l, m > 0 are kept.
 *
 * Degenerate data: u0 parallel to u1 (no plane) or robot 2 not moved by
 * step 1 (t2_1 = 0): SFM_E_DEGENERATE. Stack under 2 KB plus
 * sfm_poly_real_roots' 6 KB; no ws.
 */
#include <math.h>

#include "core/dmath.h"
#include "sfm/sfm_poly.h"
#include "solvers/r2r_align.h"
#include "solvers/r2r_internal.h"

#define NS 17   /* samples of the degree-8 trigonometric polynomial */
#define TDEG 8  /* its degree */
#define TWO_PI 6.283185307179586476925286766559

typedef struct geo {
    double n[3], e1[3], e2[3]; /* plane normal and in-plane basis (e1 = u0) */
    double u0[3], u1[3], t11[3];
    double h0, r, rho;         /* plane offset n.a, circle radius, |t2_1| */
    double u1e1, u1e2;         /* u1 in the plane basis */
    double G[9];               /* columns: frame of {2} with first axis t2_1 */
    double v[2][3];            /* G^T t2_k of the distance steps */
    double t1[2][3], K[2];     /* t1_k and |t2_k|^2 + |t1_k|^2 - d_k^2 */
} geo;

/* Everything at one circle angle: a, (l, m), the frame F (columns) and the
 * coefficients of the two distance equations in (cos theta, sin theta, 1). */
static void at_phi(const geo *g, double c, double s, double *lam, double *mu, double F[9],
                   double abc[2][3])
{
    double a[3], d[3];
    for (int i = 0; i < 3; i++) {
        a[i] = g->h0 * g->n[i] + g->r * (c * g->e1[i] + s * g->e2[i]);
        d[i] = a[i] - g->t11[i];
    }
    double m = sfmi_dot3(d, g->e2) / g->u1e2;
    double l = m * g->u1e1 - sfmi_dot3(d, g->e1);
    double f2[3], f3[3];
    sfmi_r2r_circle_frame(g->n, a, g->h0, g->r, g->rho, F, f2, f3);
    for (int k = 0; k < 2; k++) {
        double q[3];
        sfmi_r2r_distance_cs(l, g->u0, g->t1[k], g->v[k], f2, f3, q, abc[k]);
        abc[k][2] = l * l - 2.0 * l * sfmi_dot3(g->u0, g->t1[k]) + g->K[k] +
                    2.0 * g->v[k][0] * sfmi_dot3(q, a) / g->rho;
    }
    *lam = l;
    *mu = m;
}

/* The eliminant: zero where both distance equations share a (cos, sin). */
static double eliminant(double abc[2][3])
{
    double a2 = abc[0][0], b2 = abc[0][1], c2 = abc[0][2];
    double a3 = abc[1][0], b3 = abc[1][1], c3 = abc[1][2];
    double x = b2 * c3 - b3 * c2, y = a3 * c2 - a2 * c3, z = a2 * b3 - a3 * b2;
    return x * x + y * y - z * z;
}

/* Complex polynomial multiply by (1 + i t): ascending coefficients. */
static void mul_1pit(double *re, double *im, int deg)
{
    for (int j = deg + 1; j >= 1; j--) {
        double r = re[j] - im[j - 1], i_ = im[j] + re[j - 1];
        re[j] = r;
        im[j] = i_;
    }
}

/* Descending coefficients of (1 + t^2)^8 f(phi(t)), t = tan(phi/2), for
 * f = sum_k A_k cos(k phi) + B_k sin(k phi): e^{i k phi} (1 + t^2)^k =
 * (1 + i t)^{2k}. */
static void to_half_angle(const double *A, const double *B, double *desc)
{
    double P[2 * TDEG + 1] = {0.0}, re[2 * TDEG + 1] = {1.0}, im[2 * TDEG + 1] = {0.0};
    for (int k = 0; k <= TDEG; k++) {
        if (k > 0) {
            mul_1pit(re, im, 2 * k - 2);
            mul_1pit(re, im, 2 * k - 1);
        }
        double w[2 * TDEG + 1] = {1.0}; /* (1 + t^2)^(8 - k) */
        for (int e = 0; e < TDEG - k; e++)
            for (int j = 2 * e + 2; j >= 2; j--)
                w[j] += w[j - 2];
        for (int i = 0; i <= 2 * k; i++) {
            double z = A[k] * re[i] + B[k] * im[i];
            for (int j = 0; j <= 2 * (TDEG - k); j++)
                P[i + j] += z * w[j];
        }
    }
    for (int i = 0; i <= 2 * TDEG; i++)
        desc[i] = P[2 * TDEG - i];
}

static int solve(const sfm_r2r_step *s, sfm_r2r_transform *out, double *ws)
{
    (void)ws;
    geo g;
    sfmi_r2r_u(&s[0], g.u0);
    sfmi_r2r_u(&s[1], g.u1);
    for (int i = 0; i < 3; i++)
        g.t11[i] = s[1].t1.v[i];
    const double *t21 = s[1].t2.v;
    sfmi_cross3(g.u0, g.u1, g.n);
    double nn = sqrt(sfmi_dot3(g.n, g.n));
    g.rho = sqrt(sfmi_dot3(t21, t21));
    double scale = 1.0 + sqrt(sfmi_dot3(g.t11, g.t11));
    if (!(nn > 1e-9) || !(g.rho > 1e-9 * scale))
        return SFM_E_DEGENERATE;
    double nu0 = sqrt(sfmi_dot3(g.u0, g.u0));
    for (int i = 0; i < 3; i++) {
        g.n[i] /= nn;
        g.e1[i] = g.u0[i] / nu0;
    }
    sfmi_cross3(g.n, g.e1, g.e2);
    g.h0 = sfmi_dot3(g.n, g.t11);
    double r2 = g.rho * g.rho - g.h0 * g.h0;
    if (!(r2 > 1e-12 * g.rho * g.rho))
        return 0; /* the plane misses the sphere: no real a */
    g.r = sqrt(r2);
    g.u1e1 = sfmi_dot3(g.u1, g.e1);
    g.u1e2 = sfmi_dot3(g.u1, g.e2);
    /* frame of {2}: t2_1, then any two perpendicular axes */
    double ax[3][3];
    sfmi_r2r_axis_frame(t21, g.rho, ax, g.G);
    for (int k = 0; k < 2; k++) {
        const sfm_r2r_step *sk = &s[2 + k];
        for (int j = 0; j < 3; j++)
            g.v[k][j] = sfmi_dot3(ax[j], sk->t2.v);
        for (int i = 0; i < 3; i++)
            g.t1[k][i] = sk->t1.v[i];
        g.K[k] = sfmi_dot3(sk->t2.v, sk->t2.v) + sfmi_dot3(sk->t1.v, sk->t1.v) -
                 sk->d * sk->d;
    }

    /* Fourier coefficients of the eliminant from NS samples (exact for
     * degree TDEG < NS / 2) */
    double A[TDEG + 1], B[TDEG + 1], fs[NS], cs[NS], sn[NS], fbig = 0.0;
    for (int j = 0; j < NS; j++) {
        double lam, mu, F[9], abc[2][3];
        sfmi_sincos(TWO_PI * j / NS, &sn[j], &cs[j]);
        at_phi(&g, cs[j], sn[j], &lam, &mu, F, abc);
        fs[j] = eliminant(abc);
        fbig = fbig > fabs(fs[j]) ? fbig : fabs(fs[j]);
    }
    if (!(fbig > 0.0) || !isfinite(fbig))
        return SFM_E_SINGULAR;
    for (int k = 0; k <= TDEG; k++) {
        double sa = 0.0, sb = 0.0;
        for (int j = 0; j < NS; j++) {
            int idx = (k * j) % NS; /* cos(k phi_j) = cs[k j mod NS] */
            sa += fs[j] / fbig * cs[idx];
            sb += fs[j] / fbig * sn[idx];
        }
        A[k] = (k == 0 ? 1.0 : 2.0) * sa / NS;
        B[k] = 2.0 * sb / NS;
    }
    /* Two half-angle maps, t = tan(phi/2) and t = tan((phi - pi)/2), each
     * used on |t| <= 1 only: no root sits where its polynomial is stretched. */
    double phis[4 * TDEG];
    int nr = 0;
    for (int half = 0; half < 2; half++) {
        double sg = half ? -1.0 : 1.0, Ah[TDEG + 1], Bh[TDEG + 1], roots[2 * TDEG];
        for (int k = 0; k <= TDEG; k++) { /* f(phi + pi): the odd harmonics flip */
            double sk = (k % 2) ? sg : 1.0;
            Ah[k] = sk * A[k];
            Bh[k] = sk * B[k];
        }
        double desc[2 * TDEG + 1];
        to_half_angle(Ah, Bh, desc);
        double lim = half ? 1.0 : 1.0 + 1e-9;
        int m = sfm_poly_real_roots(desc, 2 * TDEG, -lim, lim, roots);
        if (m < 0)
            return m;
        for (int i = 0; i < m; i++)
            phis[nr++] = 2.0 * sfmi_atan(roots[i]) + (half ? 0.5 * TWO_PI : 0.0);
    }

    int n_out = 0;
    for (int ri = 0; ri < nr; ri++) {
        double phi = phis[ri];
        for (int it = 0; it < 3; it++) { /* Newton on the trigonometric form */
            double f = A[0], df = 0.0;
            for (int k = 1; k <= TDEG; k++) {
                double sk, ck;
                sfmi_sincos(k * phi, &sk, &ck);
                f += A[k] * ck + B[k] * sk;
                df += k * (B[k] * ck - A[k] * sk);
            }
            if (!(fabs(df) > 0.0))
                break;
            double step = f / df;
            if (!(fabs(step) < 0.1))
                break;
            phi -= step;
        }
        double c, sph, lam, mu, F[9], abc[2][3];
        sfmi_sincos(phi, &sph, &c);
        at_phi(&g, c, sph, &lam, &mu, F, abc);
        if (!(lam > 0.0 && mu > 0.0))
            continue;
        double det = abc[0][0] * abc[1][1] - abc[1][0] * abc[0][1];
        double ct = (abc[0][1] * abc[1][2] - abc[1][1] * abc[0][2]) / det;
        double st = (abc[1][0] * abc[0][2] - abc[0][0] * abc[1][2]) / det;
        double nt = sqrt(ct * ct + st * st);
        if (!(nt > 0.5 && nt < 2.0) || !isfinite(nt))
            continue; /* not a common root of the two distance equations */
        ct /= nt;
        st /= nt;
        /* Newton on the two distance equations in (phi, theta): the
         * eliminant's roots can be ill-conditioned where two are close */
        double th = sfmi_atan2(st, ct);
        for (int it = 0; it < 3; it++) {
            double e[2], J[4], ab2[2][3], l2, m2, F2[9], h = 1e-7;
            sfmi_sincos(phi + h, &sph, &c);
            at_phi(&g, c, sph, &l2, &m2, F2, ab2);
            sfmi_sincos(th, &st, &ct);
            for (int k = 0; k < 2; k++) {
                e[k] = abc[k][0] * ct + abc[k][1] * st + abc[k][2];
                J[2 * k] = (ab2[k][0] * ct + ab2[k][1] * st + ab2[k][2] - e[k]) / h;
                J[2 * k + 1] = -abc[k][0] * st + abc[k][1] * ct;
            }
            double dj = J[0] * J[3] - J[1] * J[2];
            double dp = (e[0] * J[3] - e[1] * J[1]) / dj, dt = (J[0] * e[1] - J[2] * e[0]) / dj;
            if (!isfinite(dp) || !isfinite(dt) || fabs(dp) > 0.05 || fabs(dt) > 0.05)
                break;
            phi -= dp;
            th -= dt;
            sfmi_sincos(phi, &sph, &c);
            at_phi(&g, c, sph, &lam, &mu, F, abc);
        }
        sfmi_sincos(th, &st, &ct);
        if (!(lam > 0.0 && mu > 0.0))
            continue;
        double big = 0.0, res = 0.0; /* both distance equations must hold */
        for (int k = 0; k < 2; k++) {
            res = sfmi_r2r_max(res, fabs(abc[k][0] * ct + abc[k][1] * st + abc[k][2]));
            big = sfmi_r2r_max(big, fabs(abc[k][0]) + fabs(abc[k][1]) + fabs(abc[k][2]));
        }
        if (!(res <= 1e-8 * big))
            continue;
        sfm_r2r_transform T;
        sfmi_r2r_turn_compose(F, ct, st, g.G, T.C.m);
        for (int i = 0; i < 3; i++)
            T.p.v[i] = lam * g.u0[i] / nu0;
        if (!sfmi_r2r_is_duplicate(out, n_out, &T, 1.0 + lam, 1e-9))
            out[n_out++] = T;
    }
    return n_out;
}

const sfmi_r2r_system_desc sfmi_r2r_b1_b1_d_d = {
    SFM_R2R_SYS_B1_B1_D_D, 4, {SFM_R2R_B1, SFM_R2R_B1, SFM_R2R_D, SFM_R2R_D, 0, 0},
    2 * TDEG, 0, solve, "b1_b1_d_d"};
