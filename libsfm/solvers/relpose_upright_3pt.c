/*
 * Relative pose from three bearing pairs and one direction known in both
 * frames (gravity, a vanishing direction): the "upright" 3-point problem.
 *
 * F. Fraundorfer, P. Tanskanen, M. Pollefeys, "A Minimal Case Solution to the
 * Calibrated Relative Pose Problem for the Case of Two Known Orientation
 * Angles", ECCV 2010; O. Naroditsky, X. S. Zhou, J. Gallier, S. Roumeliotis,
 * K. Daniilidis, "Two efficient solutions for visual odometry using
 * directional correspondence", PAMI 2012; M. Kalantari, A. Hashemi, F. Jung,
 * J.-P. Guedon, "A new solution to the relative orientation problem using
 * only 3 points and the vertical direction", JMIV 2011.
 *
 * Each frame is rotated so that its known direction becomes the y axis (Q1 d1
 * = Q2 d2 = e_y, any direction allowed); the remaining rotation is Ry(theta)
 * and R = Q2^T Ry(theta) Q1, t = Q2^T t'. With r_i(theta) = Ry(theta) x1'_i x
 * x2'_i, the three epipolar constraints say t' is orthogonal to all r_i, so
 * F(theta) = det[r_1; r_2; r_3] = 0. The rows are affine in (cos, sin), and
 * the cubic part vanishes at (cos, sin) = (1, +-i), so on the unit circle F
 * is a trigonometric polynomial of degree 2 (at most four roots): F = g0 +
 * g1 cos + g2 sin + g3 cos 2theta + g4 sin 2theta. Its coefficients are read
 * from F at five angles with exact cosines (0, 90, 180, 270, 45 degrees).
 *
 * The tangent half-angle form of Kalantari et al. has a pole at 180 degrees,
 * where the quartic's leading coefficient F(180) vanishes. Here the pole is
 * put at whichever of 0, 90, 180, 270 degrees has the largest |F|: the
 * leading coefficient of the quartic equals F at the pole, so it is never
 * small unless F is small everywhere; no angle is singular.
 *
 * Assumptions: d2 = R d1 exactly (a noisy direction gives the nearest
 * consistent model). Bearings need not be unit. Stack: under 1.5 KiB
 * (gcc 12 -O2 x86-64: 1216 + 80 bytes).
 */
#include <math.h>
#include <string.h>

#include "sfm/sfm_pose.h"
#include "solvers/small_math.h"

/* Newton steps on the determinant per root; relative tolerance under which
 * a negative discriminant is taken as zero. */
#define NEWTON_STEPS 2
#define QUAD_TOL 1e-10
#ifndef QUARTIC_NEWTON
#define QUARTIC_NEWTON 1
#endif
#ifndef NEWTON_SKIP
#define NEWTON_SKIP 1e-13
#endif

/* A rotation Q (rows u, d, w) with Q d = e_y, for unit d. */
static void align_to_y(const double d[3], double Q[9])
{
    double ad0 = fabs(d[0]), ad1 = fabs(d[1]), ad2 = fabs(d[2]);
    double u[3];
    /* u = e_k x d for the axis k least aligned with d, normalized */
    if (ad0 <= ad1 && ad0 <= ad2) {
        u[0] = 0.0;
        u[1] = -d[2];
        u[2] = d[1];
    } else if (ad1 <= ad2) {
        u[0] = d[2];
        u[1] = 0.0;
        u[2] = -d[0];
    } else {
        u[0] = -d[1];
        u[1] = d[0];
        u[2] = 0.0;
    }
    double inv = 1.0 / sqrt(sfmi_dot3(u, u));
    u[0] *= inv;
    u[1] *= inv;
    u[2] *= inv;
    double w[3];
    sfmi_cross3(u, d, w);
    Q[0] = u[0];
    Q[1] = u[1];
    Q[2] = u[2];
    Q[3] = d[0];
    Q[4] = d[1];
    Q[5] = d[2];
    Q[6] = w[0];
    Q[7] = w[1];
    Q[8] = w[2];
}

/* Real roots of the monic x^2 + b x + c appended to r; returns the new count. */
static int quad_roots(double b, double c, double *r, int n)
{
    /* monic x^2 + b x + c */
    double disc = b * b - 4.0 * c;
    /* A slightly negative discriminant is taken as a double root: close
     * root pairs are common (far points make the true root nearly double)
     * and the Newton steps on the determinant separate them again. */
    if (disc < 0.0) {
        if (disc < -QUAD_TOL * (b * b + fabs(c)))
            return n;
        disc = 0.0;
    }
    double s = sqrt(disc);
    double q = -0.5 * (b + copysign(s, b));
    if (q != 0.0) {
        r[n++] = q;
        r[n++] = c / q;
    } else {
        r[n++] = 0.0; /* b = c = 0 */
    }
    return n;
}

/* Real roots of the monic quartic x^4 + b x^3 + c x^2 + d x + e (Ferrari),
 * each polished by Newton steps. Returns the count (0..4). */
static int quartic_roots(double b, double c, double d, double e, double r[4])
{
    double b2 = b * b;
    double p = c - 0.375 * b2;
    double q = d - 0.5 * b * c + 0.125 * b2 * b;
    double rr = e - 0.25 * b * d + 0.0625 * b2 * c - 0.01171875 * b2 * b2;
    double y[4];
    int n = 0;
    /* resolvent: m^3 + p m^2 + (p^2/4 - r) m - q^2/8 = 0, largest root m >= 0 */
    double m = sfmi_cubic_largest_root(p, 0.25 * p * p - rr, -0.125 * q * q);
    double scale = fabs(p) + sqrt(fabs(rr));
    if (m > 1e-14 * scale && m > 0.0) {
        double s = sqrt(2.0 * m);
        double h = q / (2.0 * s);
        n = quad_roots(-s, 0.5 * p + m + h, y, n);
        n = quad_roots(s, 0.5 * p + m - h, y, n);
    } else {
        /* biquadratic (q = 0): z^2 + p z + r = 0, y = +-sqrt(z) */
        double z[2];
        int nz = quad_roots(p, rr, z, 0);
        for (int i = 0; i < nz; i++) {
            if (z[i] >= 0.0) {
                double sz = sqrt(z[i]);
                y[n++] = sz;
                y[n++] = -sz;
            }
        }
        if (n > 4)
            n = 4;
    }
    for (int i = 0; i < n; i++) {
        double x = y[i] - 0.25 * b;
        for (int it = 0; it < QUARTIC_NEWTON; it++) {
            double f = (((x + b) * x + c) * x + d) * x + e;
            double df = ((4.0 * x + 3.0 * b) * x + 2.0 * c) * x + d;
            if (df == 0.0)
                break;
            x -= f / df;
        }
        r[i] = x;
    }
    return n;
}

static inline double det_rows(const double a[3], const double b[3], const double c[3])
{
    double t[3];
    sfmi_cross3(b, c, t);
    return sfmi_dot3(a, t);
}

/* The rows r_i(theta) = c P_i + s S_i + W_i at (c, s) = (cos, sin) theta (see
 * below for P, S1, W0, W2). */
static inline void up_rows(const double P[3][3], const double S1[3], const double W0[3],
                           const double W2[3], double c, double s, double r[3][3])
{
#define UP_ROW(i_)                                                             \
    r[i_][0] = c * P[i_][0] + s * P[i_][2] + W0[i_];                           \
    r[i_][1] = c * P[i_][1] + s * S1[i_];                                      \
    r[i_][2] = c * P[i_][2] - s * P[i_][0] + W2[i_];
    UP_ROW(0)
    UP_ROW(1)
    UP_ROW(2)
#undef UP_ROW
}

int sfm_relpose_upright_3pt(const double x1[9], const double x2[9], const double d1[3],
                            const double d2[3], sfm_pose poses[SFM_RELPOSE_UPRIGHT_3PT_MAX_SOLUTIONS])
{
    if (!x1 || !x2 || !d1 || !d2 || !poses)
        return SFM_E_ARGUMENT;
    if (!(sfmi_all_finite9(x1) && sfmi_all_finite9(x2) && sfmi_all_finite3(d1) && sfmi_all_finite3(d2)))
        return SFM_E_NONFINITE;
    double n1 = sfmi_dot3(d1, d1), n2 = sfmi_dot3(d2, d2);
    if (!(n1 > 0.0) || !(n2 > 0.0))
        return SFM_E_ARGUMENT;

    double Q1[9], Q2[9];
    {
        double i1 = 1.0 / sqrt(n1), i2 = 1.0 / sqrt(n2);
        double u1[3] = {d1[0] * i1, d1[1] * i1, d1[2] * i1};
        double u2[3] = {d2[0] * i2, d2[1] * i2, d2[2] * i2};
        align_to_y(u1, Q1);
        align_to_y(u2, Q2);
    }

    /* Aligned bearings a (frame 1), b (frame 2) and the affine pieces of
     * r_i = Ry(theta) a_i x b_i = c P_i + s S_i + W_i. With
     * Ry a = (c a0 + s a2, a1, c a2 - s a0):
     *   P = (a0, 0, a2) x b = (-a2 b1, a2 b0 - a0 b2, a0 b1),
     *   S = (a2, 0, -a0) x b = (P2, -(a0 b0 + a2 b2), -P0),
     *   W = (0, a1, 0) x b = (a1 b2, 0, -a1 b0). */
    double P[3][3], S1[3], W0[3], W2[3], A[3][3], B[3][3];
    double mag = 1.0;
    for (int i = 0; i < 3; i++) {
        const double *p1 = x1 + 3 * i, *p2 = x2 + 3 * i;
        double *a = A[i], *b = B[i];
        a[0] = Q1[0] * p1[0] + Q1[1] * p1[1] + Q1[2] * p1[2];
        a[1] = Q1[3] * p1[0] + Q1[4] * p1[1] + Q1[5] * p1[2];
        a[2] = Q1[6] * p1[0] + Q1[7] * p1[1] + Q1[8] * p1[2];
        b[0] = Q2[0] * p2[0] + Q2[1] * p2[1] + Q2[2] * p2[2];
        b[1] = Q2[3] * p2[0] + Q2[4] * p2[1] + Q2[5] * p2[2];
        b[2] = Q2[6] * p2[0] + Q2[7] * p2[1] + Q2[8] * p2[2];
        P[i][0] = -a[2] * b[1];
        P[i][1] = a[2] * b[0] - a[0] * b[2];
        P[i][2] = a[0] * b[1];
        S1[i] = -(a[0] * b[0] + a[2] * b[2]);
        W0[i] = a[1] * b[2];
        W2[i] = -a[1] * b[0];
        mag *= sfmi_dot3(a, a) * sfmi_dot3(b, b);
    }
#define UP_ROWS(r, c, s) up_rows((const double(*)[3])P, S1, W0, W2, c, s, r)
    /* F at 0, 90, 180, 270 and 45 degrees */
    double F[4], F45;
    {
        const double h = 0.70710678118654752440;
        double r[3][3];
        UP_ROWS(r, 1.0, 0.0);
        F[0] = det_rows(r[0], r[1], r[2]);
        UP_ROWS(r, 0.0, 1.0);
        F[1] = det_rows(r[0], r[1], r[2]);
        UP_ROWS(r, -1.0, 0.0);
        F[2] = det_rows(r[0], r[1], r[2]);
        UP_ROWS(r, 0.0, -1.0);
        F[3] = det_rows(r[0], r[1], r[2]);
        UP_ROWS(r, h, h);
        F45 = det_rows(r[0], r[1], r[2]);
    }
    double g0 = 0.25 * (F[0] + F[1] + F[2] + F[3]);
    double g1 = 0.5 * (F[0] - F[2]);
    double g2 = 0.5 * (F[1] - F[3]);
    double g3 = 0.25 * (F[0] + F[2] - F[1] - F[3]);
    double g4 = F45 - g0 - 0.70710678118654752440 * (g1 + g2);

    /* Pole of the half-angle chart at the sample with the largest |F|. */
    int kp = 0;
    for (int k = 1; k < 4; k++)
        if (fabs(F[k]) > fabs(F[kp]))
            kp = k;
    /* Degenerate sample (F identically zero, e.g. coincident points). */
    if (!(fabs(F[kp]) > 1e-13 * sqrt(mag)))
        return 0;
    /* theta = theta' + theta0 with theta0 = pole - 180 degrees */
    static const double C0t[4] = {-1.0, 0.0, 1.0, 0.0};
    static const double S0t[4] = {0.0, -1.0, 0.0, 1.0};
    static const double C2t[4] = {1.0, -1.0, 1.0, -1.0};
    double C0 = C0t[kp], S0 = S0t[kp], C2 = C2t[kp];
    double h1 = g1 * C0 + g2 * S0, h2 = -g1 * S0 + g2 * C0, h3 = g3 * C2, h4 = g4 * C2;
    double ia = 1.0 / (g0 - h1 + h3);
    double kr[4];
    int nk = quartic_roots((2.0 * h2 - 4.0 * h4) * ia, (2.0 * g0 - 6.0 * h3) * ia,
                           (2.0 * h2 + 4.0 * h4) * ia, (g0 + h1 + h3) * ia, kr);

    int nsol = 0;
    for (int j = 0; j < nk; j++) {
        double k = kr[j];
        double den = 1.0 / (1.0 + k * k);
        double cp = (1.0 - k * k) * den, sp = 2.0 * k * den;
        double c = C0 * cp - S0 * sp, s = S0 * cp + C0 * sp;
        double r[3][3];
        UP_ROWS(r, c, s);
        /* Newton steps in the angle on the determinant itself (the slope from
         * the trigonometric polynomial): near a root the rows are small, of
         * the order of the parallax, and the determinant keeps the digits
         * that the interpolated polynomial loses for far points. */
        for (int itn = 0; itn < NEWTON_STEPS; itn++) {
            double f = det_rows(r[0], r[1], r[2]);
            double df = -g1 * s + g2 * c - 4.0 * g3 * s * c + 2.0 * g4 * (c * c - s * s);
            double dl = -f / df;
            if (!(fabs(dl) < 0.1) || fabs(dl) < NEWTON_SKIP)
                break;
            double cn = c - s * dl, sn = s + c * dl;
            double nn = 1.0 / sqrt(cn * cn + sn * sn);
            c = cn * nn;
            s = sn * nn;
            UP_ROWS(r, c, s);
        }
        /* t' is orthogonal to the three rows */
        double tq[3];
        double mt = sfmi_rank2_null3(r[0], r[1], r[2], 1e-6, tq);
        if (!(mt > 0.0))
            continue;
        /* Sign of t' and cheirality. With v_i = Ry a_i and r_i = v_i x b_i,
         * the depths along a_i (frame 1) and b_i (frame 2) have the signs of
         * -(t' x b_i).r_i and -(t' x v_i).r_i. The sign of t' follows the
         * majority of the frame-1 depths; a solution that then leaves a point
         * behind either camera is not a physical one and is dropped. */
        double s1[3];
        int vote = 0;
        for (int i = 0; i < 3; i++) {
            double tb[3];
            sfmi_cross3(tq, B[i], tb);
            s1[i] = -sfmi_dot3(tb, r[i]);
            vote += (s1[i] > 0.0) - (s1[i] < 0.0);
        }
        double sg = vote < 0 ? -1.0 : 1.0;
        if (sg * s1[0] < 0.0 || sg * s1[1] < 0.0 || sg * s1[2] < 0.0)
            continue;
        int behind = 0;
        for (int i = 0; i < 3; i++) {
            const double *a = A[i];
            double v[3] = {c * a[0] + s * a[2], a[1], c * a[2] - s * a[0]}, tv[3];
            sfmi_cross3(tq, v, tv);
            behind |= sg * sfmi_dot3(tv, r[i]) > 0.0;
        }
        if (behind)
            continue;
        double it = sg / sqrt(mt);
        tq[0] *= it;
        tq[1] *= it;
        tq[2] *= it;
        /* c, s and t' are finite whenever the root is: one check */
        if ((c + s + tq[0] + tq[1] + tq[2]) * 0.0 != 0.0)
            continue;
        /* R = Q2^T Ry Q1 = Q2^T M, t = Q2^T t' (written out: loops here are
         * not unrolled at -O2) */
        double M0 = c * Q1[0] + s * Q1[6], M1 = c * Q1[1] + s * Q1[7], M2 = c * Q1[2] + s * Q1[8];
        double M6 = c * Q1[6] - s * Q1[0], M7 = c * Q1[7] - s * Q1[1], M8 = c * Q1[8] - s * Q1[2];
        double M3 = Q1[3], M4 = Q1[4], M5 = Q1[5];
        double *Ro = poses[nsol].R, *to = poses[nsol].t;
#define UP_RROW(rw)                                                            \
    Ro[3 * (rw)] = Q2[(rw)] * M0 + Q2[3 + (rw)] * M3 + Q2[6 + (rw)] * M6;       \
    Ro[3 * (rw) + 1] = Q2[(rw)] * M1 + Q2[3 + (rw)] * M4 + Q2[6 + (rw)] * M7;   \
    Ro[3 * (rw) + 2] = Q2[(rw)] * M2 + Q2[3 + (rw)] * M5 + Q2[6 + (rw)] * M8;   \
    to[(rw)] = Q2[(rw)] * tq[0] + Q2[3 + (rw)] * tq[1] + Q2[6 + (rw)] * tq[2];
        UP_RROW(0)
        UP_RROW(1)
        UP_RROW(2)
#undef UP_RROW
        nsol++;
    }
#undef UP_ROWS
    return nsol;
}
