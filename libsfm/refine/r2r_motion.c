/*
 * Leader-follower formations: the EKF of the leader's relative pose seen by
 * the follower, and the follower's next-step motion minimising the trace of
 * the posterior covariance (Zhou, Zhou, Roumeliotis, IROS 2011). Conventions
 * and the reduction to one univariate polynomial: include/sfm/sfm_r2r_motion.h.
 *
 * The boundary polynomial. On the circle q = m + r (cos th, sin th), put
 * t = tan(th / 2) and W = 1 + t^2: then W q = Q(t) with
 *   Q_x = (m_x + r) + (m_x - r) t^2,   Q_y = m_y + 2 r t + m_y t^2,
 * and W |q|^2 = s1(t), a quadratic (|q|^2 is affine in (cos th, sin th)).
 * Range: g = Q^T B Q / Q^T (A + s^2 I) Q; bearing, with V = J Q:
 * g = V^T B V / (V^T A V + s^2 s1^2). Either way g = N(t) / D(t) with N, D
 * quartics in t (the common factor W^2 cancels). dg/dth = (W/2) dg/dt and
 * W > 0, so the boundary critical points are the real roots of N' D - N D'
 * (degree 7 whose leading terms, 4 N4 D4 on both sides, cancel exactly:
 * degree 6), and th = pi (t = infinity) is the one point of the circle left
 * to check.
 */
#include <string.h>

#include "core/dmath.h"
#include "core/linalg_util.h"
#include "sfm/sfm_poly.h"
#include "sfm/sfm_r2r_motion.h"
#include "solvers/small_math.h"

#define PI_ 3.14159265358979323846

static int finite_n(const double *v, int n)
{
    for (int i = 0; i < n; i++)
        if (!isfinite(v[i]))
            return 0;
    return 1;
}

static double wrap_angle(double a)
{
    /* to (-pi, pi] in a bounded number of steps whatever the (finite)
     * angle: a subtraction loop never ends once 2 pi is below half an ulp
     * of a (|a| > 2^55), and takes |a| / 2 pi turns before. Beyond a few
     * turns one floor reduction (exact to a few ulp of a), then at most one
     * turn either way; the clamp covers the last ulp of a huge angle. */
    if (a > 3.0 * PI_ || a < -3.0 * PI_)
        a -= 2.0 * PI_ * floor((a + PI_) / (2.0 * PI_));
    if (a > PI_)
        a -= 2.0 * PI_;
    if (a <= -PI_)
        a += 2.0 * PI_;
    if (a > PI_)
        a = PI_;
    if (a <= -PI_)
        a = PI_;
    return a;
}

/* P += s v v^T, then P exactly symmetric (each off-diagonal pair replaced by
 * its mean): the last step of a covariance propagation or update. */
static void add_outer_symmetric(double P[9], double s, const double v[3])
{
    for (int i = 0; i < 3; i++)
        for (int j = 0; j < 3; j++)
            P[3 * i + j] += s * v[i] * v[j];
    for (int i = 0; i < 3; i++)
        for (int j = i + 1; j < 3; j++) {
            const double m = 0.5 * (P[3 * i + j] + P[3 * j + i]);
            P[3 * i + j] = m;
            P[3 * j + i] = m;
        }
}

/* symmetric (to 1e-9 of its largest entry) and positive definite (3x3
 * Cholesky with strictly positive pivots) */
static int spd3(const double P[9])
{
    double mx = 0.0;
    for (int i = 0; i < 9; i++)
        mx = fabs(P[i]) > mx ? fabs(P[i]) : mx;
    if (!(mx > 0.0))
        return 0;
    for (int i = 0; i < 3; i++)
        for (int j = i + 1; j < 3; j++)
            if (fabs(P[3 * i + j] - P[3 * j + i]) > 1e-9 * mx)
                return 0;
    double L[9];
    return sfmi_chol3(P, L);
}

static int noise_ok(const sfm_r2r_motion_noise *n)
{
    const double s[5] = {n->sigma_leader_d, n->sigma_leader_w, n->sigma_follower_d,
                         n->sigma_follower_w, n->sigma_meas};
    for (int i = 0; i < 5; i++)
        if (!(s[i] >= 0.0))
            return 0;
    return n->sigma_meas > 0.0;
}

static int noise_finite(const sfm_r2r_motion_noise *n)
{
    const double s[5] = {n->sigma_leader_d, n->sigma_leader_w, n->sigma_follower_d,
                         n->sigma_follower_w, n->sigma_meas};
    return finite_n(s, 5);
}

static int step_finite(const sfm_r2r_motion_step *u)
{
    const double v[6] = {u->leader_d.v[0], u->leader_d.v[1], u->leader_w,
                         u->follower_w, u->follower_d.v[0], u->follower_d.v[1]};
    return finite_n(v, 6);
}

/* The prediction without the follower's translation: c (where the leader is
 * seen if the follower only turns), the predicted heading and the propagated
 * covariance, which the follower's translation does not change. */
static void predict_core(const double x[3], const double P[9], const sfm_r2r_motion_step *u,
                         const sfm_r2r_motion_noise *n, double c[2], double *phi_out,
                         double Pp[9])
{
    double sp, cp, sw, cw;
    sfmi_sincos(x[2], &sp, &cp);
    sfmi_sincos(u->follower_w, &sw, &cw);
    /* e = R(phi) leader_d; a = p + e; c = R(-w) a */
    const double ex = cp * u->leader_d.v[0] - sp * u->leader_d.v[1];
    const double ey = sp * u->leader_d.v[0] + cp * u->leader_d.v[1];
    const double ax = x[0] + ex, ay = x[1] + ey;
    c[0] = cw * ax + sw * ay;
    c[1] = -sw * ax + cw * ay;
    *phi_out = wrap_angle(x[2] + u->leader_w - u->follower_w);

    /* Phi = [R(-w), R(-w) J e; 0 0 1], J = [0 -1; 1 0] */
    const double jex = -ey, jey = ex;
    double F[9] = {cw, sw, cw * jex + sw * jey, -sw, cw, -sw * jex + cw * jey, 0.0, 0.0, 1.0};
    double FP[9];
    sfmi_matmul3(F, P, FP);
    sfmi_matmul3_nt(FP, F, Pp);
    /* leader translation: R(-w) R(phi) is a rotation, so sigma^2 I on p;
     * leader rotation: phi only; follower translation: -I on p; follower
     * rotation: column (-J c, -1) */
    const double qd = n->sigma_leader_d * n->sigma_leader_d +
                      n->sigma_follower_d * n->sigma_follower_d;
    Pp[0] += qd;
    Pp[4] += qd;
    Pp[8] += n->sigma_leader_w * n->sigma_leader_w;
    const double s2 = n->sigma_follower_w * n->sigma_follower_w;
    const double g[3] = {c[1], -c[0], -1.0}; /* -J c = (c_y, -c_x) */
    add_outer_symmetric(Pp, s2, g);
}

/* measurement Jacobian row h (3) at position q; 0 when |q| is too small */
static int meas_jacobian(int sensor, const double q[2], double h[3], double *pred)
{
    const double s = q[0] * q[0] + q[1] * q[1];
    const double rho = sqrt(s);
    if (!(rho >= 1e-9))
        return 0;
    if (sensor == SFM_R2R_MOTION_RANGE) {
        h[0] = q[0] / rho;
        h[1] = q[1] / rho;
        *pred = rho;
    } else {
        h[0] = -q[1] / s;
        h[1] = q[0] / s;
        *pred = sfmi_atan2(q[1], q[0]);
    }
    h[2] = 0.0;
    return 1;
}

/* trace after the update at Jacobian row h: tr(P) - |P h|^2 / (h P h + s^2) */
static double posterior_trace(const double Pp[9], const double h[3], double sm)
{
    double ph[3];
    for (int i = 0; i < 3; i++)
        ph[i] = Pp[3 * i] * h[0] + Pp[3 * i + 1] * h[1] + Pp[3 * i + 2] * h[2];
    const double S = h[0] * ph[0] + h[1] * ph[1] + h[2] * ph[2] + sm * sm;
    return Pp[0] + Pp[4] + Pp[8] - (ph[0] * ph[0] + ph[1] * ph[1] + ph[2] * ph[2]) / S;
}

static int common_checks(const double x[3], const double P[9], const sfm_r2r_motion_noise *n)
{
    if (!finite_n(x, 3) || !finite_n(P, 9) || !noise_finite(n))
        return SFM_E_NONFINITE;
    if (!noise_ok(n) || !spd3(P))
        return SFM_E_ARGUMENT;
    return SFM_OK;
}

/* The checks of propagate and cost (a status) and, when they pass, the
 * prediction: the leader's position q in the follower's new frame, the
 * heading phi and the propagated covariance Pp. */
static int predict_step(const double x[3], const double P[9], const sfm_r2r_motion_step *u,
                        const sfm_r2r_motion_noise *noise, double q[2], double *phi, double Pp[9])
{
    if (!step_finite(u))
        return SFM_E_NONFINITE;
    int st = common_checks(x, P, noise);
    if (st != SFM_OK)
        return st;
    double c[2];
    predict_core(x, P, u, noise, c, phi, Pp);
    q[0] = c[0] - u->follower_d.v[0];
    q[1] = c[1] - u->follower_d.v[1];
    return SFM_OK;
}

int sfm_r2r_motion_propagate(const double x[3], const double P[9], const sfm_r2r_motion_step *u,
                             const sfm_r2r_motion_noise *noise, double x_out[3], double P_out[9])
{
    if (!x || !P || !u || !noise || !x_out || !P_out)
        return SFM_E_ARGUMENT;
    double q[2], phi, Pp[9];
    int st = predict_step(x, P, u, noise, q, &phi, Pp);
    if (st != SFM_OK)
        return st;
    const double xo[3] = {q[0], q[1], phi};
    /* finite inputs can still overflow (a sigma of 1e200 squared) */
    if (!finite_n(xo, 3) || !finite_n(Pp, 9))
        return SFM_E_NONFINITE;
    memcpy(x_out, xo, sizeof xo);
    memcpy(P_out, Pp, sizeof Pp);
    return SFM_OK;
}

int sfm_r2r_motion_update(const double x[3], const double P[9], int sensor, double z,
                          const sfm_r2r_motion_noise *noise, double x_out[3], double P_out[9])
{
    if (!x || !P || !noise || !x_out || !P_out)
        return SFM_E_ARGUMENT;
    if (sensor != SFM_R2R_MOTION_RANGE && sensor != SFM_R2R_MOTION_BEARING)
        return SFM_E_ARGUMENT;
    if (!finite_n(x, 3) || !finite_n(P, 9) || !isfinite(noise->sigma_meas) || !isfinite(z))
        return SFM_E_NONFINITE;
    if (!(noise->sigma_meas > 0.0) || !spd3(P) || (sensor == SFM_R2R_MOTION_RANGE && z < 0.0))
        return SFM_E_ARGUMENT;
    double h[3], pred;
    if (!meas_jacobian(sensor, x, h, &pred))
        return SFM_E_SINGULAR;
    double innov = z - pred;
    if (sensor == SFM_R2R_MOTION_BEARING)
        innov = wrap_angle(innov);
    double ph[3];
    for (int i = 0; i < 3; i++)
        ph[i] = P[3 * i] * h[0] + P[3 * i + 1] * h[1] + P[3 * i + 2] * h[2];
    const double r2 = noise->sigma_meas * noise->sigma_meas;
    const double S = h[0] * ph[0] + h[1] * ph[1] + h[2] * ph[2] + r2;
    double k[3] = {ph[0] / S, ph[1] / S, ph[2] / S};
    double xo[3] = {x[0] + k[0] * innov, x[1] + k[1] * innov, wrap_angle(x[2] + k[2] * innov)};
    /* Joseph form: (I - k h) P (I - k h)^T + k r2 k^T */
    double M[9], MP[9], Po[9];
    for (int i = 0; i < 3; i++)
        for (int j = 0; j < 3; j++)
            M[3 * i + j] = (i == j ? 1.0 : 0.0) - k[i] * h[j];
    sfmi_matmul3(M, P, MP);
    sfmi_matmul3_nt(MP, M, Po);
    add_outer_symmetric(Po, r2, k);
    if (!finite_n(xo, 3) || !finite_n(Po, 9))
        return SFM_E_NONFINITE; /* overflow of finite inputs */
    memcpy(x_out, xo, sizeof xo);
    memcpy(P_out, Po, sizeof Po);
    return SFM_OK;
}

int sfm_r2r_motion_cost(const double x[3], const double P[9], const sfm_r2r_motion_step *u,
                        const sfm_r2r_motion_noise *noise, int sensor, double *trace)
{
    if (!x || !P || !u || !noise || !trace)
        return SFM_E_ARGUMENT;
    if (sensor != SFM_R2R_MOTION_RANGE && sensor != SFM_R2R_MOTION_BEARING)
        return SFM_E_ARGUMENT;
    double q[2], phi, Pp[9], h[3], pred;
    int st = predict_step(x, P, u, noise, q, &phi, Pp);
    if (st != SFM_OK)
        return st;
    if (!meas_jacobian(sensor, q, h, &pred))
        return SFM_E_SINGULAR;
    const double tr = posterior_trace(Pp, h, noise->sigma_meas);
    if (!isfinite(tr))
        return SFM_E_NONFINITE; /* overflow of finite inputs */
    *trace = tr;
    return SFM_OK;
}

/* ---- the KKT critical points ------------------------------------------- */

/* ascending-order polynomial helpers; degrees small and fixed */
static void pmul(const double *a, int na, const double *b, int nb, double *out)
{
    for (int i = 0; i <= na + nb; i++)
        out[i] = 0.0;
    for (int i = 0; i <= na; i++)
        for (int j = 0; j <= nb; j++)
            out[i + j] += a[i] * b[j];
}

/* the quadratic form [X Y] S [X Y]^T of quadratics X, Y: a quartic */
static void qform(const double S[4], const double X[3], const double Y[3], double out[5])
{
    double xx[5], xy[5], yy[5];
    pmul(X, 2, X, 2, xx);
    pmul(X, 2, Y, 2, xy);
    pmul(Y, 2, Y, 2, yy);
    for (int i = 0; i < 5; i++)
        out[i] = S[0] * xx[i] + (S[1] + S[2]) * xy[i] + S[3] * yy[i];
}

typedef struct lf_problem {
    int sensor;
    double A[4], B[4]; /* position blocks of P' and P'^2 */
    double s2;         /* sigma_meas^2 */
} lf_problem;

/* g(q), the trace reduction; the same expressions as posterior_trace */
static double lf_gain(const lf_problem *pb, const double q[2])
{
    double vx = q[0], vy = q[1];
    const double s = q[0] * q[0] + q[1] * q[1];
    if (pb->sensor == SFM_R2R_MOTION_BEARING) {
        vx = -q[1];
        vy = q[0];
    }
    const double nb = pb->B[0] * vx * vx + 2.0 * pb->B[1] * vx * vy + pb->B[3] * vy * vy;
    const double na = pb->A[0] * vx * vx + 2.0 * pb->A[1] * vx * vy + pb->A[3] * vy * vy;
    const double den = pb->sensor == SFM_R2R_MOTION_BEARING ? na + pb->s2 * s * s : na + pb->s2 * s;
    return nb / den;
}

/* Roots of the boundary polynomial on the circle (m, r): the tangent half
 * angles t, written to t_out (up to 6); returns their count or a status. */
static int boundary_roots(const lf_problem *pb, const double m[2], double r, double *t_out)
{
    const double X[3] = {m[0] + r, 0.0, m[0] - r};
    const double Y[3] = {m[1], 2.0 * r, m[1]};
    double N[5], D[5];
    const double mm = m[0] * m[0] + m[1] * m[1] + r * r;
    const double s1[3] = {mm + 2.0 * r * m[0], 4.0 * r * m[1], mm - 2.0 * r * m[0]};
    if (pb->sensor == SFM_R2R_MOTION_RANGE) {
        const double Ap[4] = {pb->A[0] + pb->s2, pb->A[1], pb->A[2], pb->A[3] + pb->s2};
        qform(pb->B, X, Y, N);
        qform(Ap, X, Y, D);
    } else {
        /* v = J q: (V_x, V_y) = (-Y, X) */
        const double mY[3] = {-Y[0], -Y[1], -Y[2]};
        double ss[5];
        qform(pb->B, mY, X, N);
        qform(pb->A, mY, X, D);
        pmul(s1, 2, s1, 2, ss);
        for (int i = 0; i < 5; i++)
            D[i] += pb->s2 * ss[i];
    }
    double dN[4], dD[4];
    for (int i = 0; i < 4; i++) {
        dN[i] = (i + 1) * N[i + 1];
        dD[i] = (i + 1) * D[i + 1];
    }
    double a[8], b[8], e[7];
    pmul(dN, 3, D, 4, a);
    pmul(N, 4, dD, 3, b);
    /* the t^7 terms are equal (4 N4 D4 both): degree 6 */
    for (int i = 0; i <= 6; i++)
        e[i] = a[i] - b[i];
    double mx = 0.0;
    for (int i = 0; i <= 6; i++)
        mx = fabs(e[i]) > mx ? fabs(e[i]) : mx;
    if (!(mx > 0.0))
        return 0; /* g constant on the circle: every point is critical; the
                     caller's fixed candidates cover it */
    int deg = 6;
    while (deg > 0 && fabs(e[deg]) <= 1e-14 * mx)
        deg--;
    if (deg < 1)
        return 0;
    double desc[7];
    for (int i = 0; i <= deg; i++)
        desc[i] = e[deg - i] / mx;
    return sfm_poly_real_roots(desc, deg, -HUGE_VAL, HUGE_VAL, t_out);
}

/* Directions u stationary for u^T B u / u^T (A + shift I) u (range: shift
 * s^2; bearing on a circle |q| = const: v's direction, shift s^2 |q|^2): the homogeneous
 * quadratic (B u) x (A' u) = 0. Writes up to 3 unit vectors (the lines, an
 * axis added when a vanishing coefficient may have hidden it;
 * both signs are tried by the caller); returns their count, or -1 when every
 * direction is stationary (B proportional to A'). */
static int stationary_directions(const lf_problem *pb, double shift, double u[3][2])
{
    const double a00 = pb->A[0] + shift, a01 = pb->A[1], a11 = pb->A[3] + shift;
    const double b00 = pb->B[0], b01 = pb->B[1], b11 = pb->B[3];
    const double k2 = b00 * a01 - b01 * a00;         /* x^2 */
    const double k1 = b00 * a11 - b11 * a00;         /* x y */
    const double k0 = b01 * a11 - b11 * a01;         /* y^2 */
    const double mx = fabs(k0) > fabs(k1) ? (fabs(k0) > fabs(k2) ? fabs(k0) : fabs(k2))
                                          : (fabs(k1) > fabs(k2) ? fabs(k1) : fabs(k2));
    const double scale = (fabs(b00) + fabs(b11)) * (fabs(a00) + fabs(a11));
    if (!(mx > 1e-14 * scale))
        return -1;
    double roots[2];
    int n, k = 0;
    /* w = u[j] / u[o]: j = 1 (w = y/x, k0 w^2 + k1 w + k2 = 0) when
     * |k0| >= |k2|, else j = 0 (w = x/y, the coefficients reversed); u[o] = 0
     * is a root only when the leading coefficient vanishes (then so does the
     * other, and the form is k1 x y) */
    const int j = fabs(k0) >= fabs(k2), o = 1 - j;
    const double c[3] = {j ? k0 : k2, k1, j ? k2 : k0};
    if (fabs(c[0]) <= 1e-12 * mx) {
        u[k][o] = 0.0;
        u[k][j] = 1.0;
        k++;
    }
    n = sfm_poly_roots2(c, roots);
    for (int i = 0; i < n; i++) {
        const double l = sqrt(1.0 + roots[i] * roots[i]);
        u[k][o] = 1.0 / l;
        u[k][j] = roots[i] / l;
        k++;
    }
    return k;
}

typedef struct lf_best {
    double q[2];
    double g;
    double dev; /* |q - m| */
    int boundary;
} lf_best;

static void consider(lf_best *b, const lf_problem *pb, const double q[2], const double m[2],
                     int boundary)
{
    const double g = lf_gain(pb, q);
    if (!isfinite(g))
        return;
    const double dev = sqrt((q[0] - m[0]) * (q[0] - m[0]) + (q[1] - m[1]) * (q[1] - m[1]));
    /* larger gain wins; a tie (within rounding) goes to the smaller deviation */
    const double tol = 1e-12 * (fabs(g) + fabs(b->g));
    if (g > b->g + tol || (g >= b->g - tol && dev < b->dev)) {
        b->q[0] = q[0];
        b->q[1] = q[1];
        b->g = g;
        b->dev = dev;
        b->boundary = boundary;
    }
}

int sfm_r2r_motion_next(const double x[3], const double P[9], const sfm_r2r_motion_step *u,
                        const double d0[2], double radius, double min_distance,
                        const sfm_r2r_motion_noise *noise, int sensor,
                        sfm_r2r_motion_plan *out)
{
    if (!x || !P || !u || !noise || !out)
        return SFM_E_ARGUMENT;
    if (sensor != SFM_R2R_MOTION_RANGE && sensor != SFM_R2R_MOTION_BEARING)
        return SFM_E_ARGUMENT;
    const double v[4] = {u->leader_d.v[0], u->leader_d.v[1], u->leader_w, u->follower_w};
    const double dd[2] = {d0 ? d0[0] : 0.0, d0 ? d0[1] : 0.0};
    if (!finite_n(v, 4) || !finite_n(dd, 2) || !isfinite(radius) || !isfinite(min_distance))
        return SFM_E_NONFINITE;
    int st = common_checks(x, P, noise);
    if (st != SFM_OK)
        return st;
    if (!(radius > 0.0) || !(min_distance >= 0.0))
        return SFM_E_ARGUMENT;

    double c[2], phi, Pp[9];
    predict_core(x, P, u, noise, c, &phi, Pp);
    const double m[2] = {c[0] - dd[0], c[1] - dd[1]};
    const double r = radius, dm = min_distance;
    const double mn = sqrt(m[0] * m[0] + m[1] * m[1]);
    if (dm == 0.0 ? !(mn - r > 1e-6) : !(mn + r > dm))
        return SFM_E_SINGULAR;
    /* the distance constraint can bind only when the disk reaches inside it */
    const int inner = dm > 0.0 && mn - r < dm;
    const double dm2 = dm * dm * (1.0 - 1e-12); /* feasibility, with rounding */

    lf_problem pb;
    pb.sensor = sensor;
    pb.s2 = noise->sigma_meas * noise->sigma_meas;
    pb.A[0] = Pp[0];
    pb.A[1] = Pp[1];
    pb.A[2] = Pp[3];
    pb.A[3] = Pp[4];
    /* B = position block of P'^2 = A^2 + a a^T, a = P'[0:2, 2] */
    for (int i = 0; i < 2; i++)
        for (int j = 0; j < 2; j++)
            pb.B[2 * i + j] = Pp[3 * i] * Pp[j] + Pp[3 * i + 1] * Pp[3 + j] +
                              Pp[3 * i + 2] * Pp[6 + j];
    pb.B[1] = pb.B[2] = 0.5 * (pb.B[1] + pb.B[2]);

    lf_best best = {{m[0], m[1]}, -HUGE_VAL, HUGE_VAL, 0};
    int ncrit = 0;

    /* boundary: the polynomial's roots, and th = pi */
    double ts[SFM_POLY_MAX_DEGREE];
    int nt = boundary_roots(&pb, m, r, ts);
    if (nt < 0)
        return nt;
    ncrit += nt;
    for (int i = 0; i < nt; i++) {
        const double w = 1.0 + ts[i] * ts[i];
        const double q[2] = {m[0] + r * (1.0 - ts[i] * ts[i]) / w, m[1] + r * 2.0 * ts[i] / w};
        if (q[0] * q[0] + q[1] * q[1] >= dm2)
            consider(&best, &pb, q, m, 1);
    }
    {
        const double q[2] = {m[0] - r, m[1]};
        if (q[0] * q[0] + q[1] * q[1] >= dm2)
            consider(&best, &pb, q, m, 1);
    }
    if (inner) {
        /* the distance circle |q| = dm inside the disk: g restricted to it
         * is a Rayleigh quotient of the direction (range: of q, shift s^2;
         * bearing: of v = J q, shift s^2 dm^2) */
        double dirs[3][2];
        const double shift = sensor == SFM_R2R_MOTION_RANGE ? pb.s2 : pb.s2 * dm * dm;
        int nd = stationary_directions(&pb, shift, dirs);
        for (int i = 0; i < nd; i++)
            for (int sgn = -1; sgn <= 1; sgn += 2) {
                double ux = sgn * dirs[i][0], uy = sgn * dirs[i][1];
                if (sensor == SFM_R2R_MOTION_BEARING) {
                    const double t0 = ux; /* q along -J v */
                    ux = uy;
                    uy = -t0;
                }
                const double q[2] = {dm * ux, dm * uy};
                if ((q[0] - m[0]) * (q[0] - m[0]) + (q[1] - m[1]) * (q[1] - m[1]) <= r * r) {
                    ncrit++;
                    consider(&best, &pb, q, m, 2);
                }
            }
        /* the two circles' intersections */
        const double a = (dm * dm - r * r + mn * mn) / (2.0 * mn), h2 = dm * dm - a * a;
        if (h2 >= 0.0) {
            const double h = sqrt(h2), ex = m[0] / mn, ey = m[1] / mn;
            for (int sgn = -1; sgn <= 1; sgn += 2) {
                const double q[2] = {a * ex - sgn * h * ey, a * ey + sgn * h * ex};
                ncrit++;
                consider(&best, &pb, q, m, 3);
            }
        }
    }
    /* interior (range only): the critical rays' points nearest m */
    if (sensor == SFM_R2R_MOTION_RANGE) {
        double dirs[3][2];
        int nd = stationary_directions(&pb, pb.s2, dirs);
        if (nd < 0 && m[0] * m[0] + m[1] * m[1] >= dm2) {
            consider(&best, &pb, m, m, 0); /* g constant: do not move */
        }
        for (int i = 0; i < nd; i++)
            for (int sgn = -1; sgn <= 1; sgn += 2) {
                const double ux = sgn * dirs[i][0], uy = sgn * dirs[i][1];
                double lam = ux * m[0] + uy * m[1];
                if (!(lam > 0.0))
                    continue;
                if (lam < dm)
                    lam = dm; /* the ray's nearest point to m at the allowed distance */
                const double q[2] = {lam * ux, lam * uy};
                const double e2 = (q[0] - m[0]) * (q[0] - m[0]) + (q[1] - m[1]) * (q[1] - m[1]);
                if (e2 <= r * r) {
                    ncrit++;
                    consider(&best, &pb, q, m, 0);
                }
            }
    }
    if (!(best.g > -HUGE_VAL))
        return SFM_E_SINGULAR;

    /* the multiplier: grad f = -grad g = -2 mu (q - m) on the circle */
    double mu = 0.0;
    if (best.boundary == 2) {
        /* the distance constraint dm^2 - |q|^2 <= 0: grad g = -2 mu q */
        const double hq = 1e-6 * (fabs(best.q[0]) + fabs(best.q[1]));
        const double qa[2] = {best.q[0] + hq, best.q[1]}, qb[2] = {best.q[0] - hq, best.q[1]};
        const double qc[2] = {best.q[0], best.q[1] + hq}, qd[2] = {best.q[0], best.q[1] - hq};
        const double gx = (lf_gain(&pb, qa) - lf_gain(&pb, qb)) / (2.0 * hq);
        const double gy = (lf_gain(&pb, qc) - lf_gain(&pb, qd)) / (2.0 * hq);
        mu = -(gx * best.q[0] + gy * best.q[1]) / (2.0 * dm * dm);
        if (mu < 0.0)
            mu = 0.0;
    } else if (best.boundary) {
        const double hq = 1e-6 * (fabs(best.q[0]) + fabs(best.q[1]));
        const double qa[2] = {best.q[0] + hq, best.q[1]}, qb[2] = {best.q[0] - hq, best.q[1]};
        const double qc[2] = {best.q[0], best.q[1] + hq}, qd[2] = {best.q[0], best.q[1] - hq};
        const double gx = (lf_gain(&pb, qa) - lf_gain(&pb, qb)) / (2.0 * hq);
        const double gy = (lf_gain(&pb, qc) - lf_gain(&pb, qd)) / (2.0 * hq);
        mu = (gx * (best.q[0] - m[0]) + gy * (best.q[1] - m[1])) / (2.0 * r * r);
        if (mu < 0.0)
            mu = 0.0; /* rounding at a point where the constraint is not active */
    }
    double h[3], pred;
    if (!meas_jacobian(sensor, best.q, h, &pred))
        return SFM_E_SINGULAR;
    const double tr = posterior_trace(Pp, h, noise->sigma_meas);
    const double fin[5] = {best.q[0], best.q[1], c[0] - best.q[0], c[1] - best.q[1], tr};
    if (!finite_n(fin, 5) || !isfinite(Pp[0] + Pp[4] + Pp[8]) || !isfinite(mu))
        return SFM_E_NONFINITE; /* overflow of finite inputs */
    out->q.v[0] = best.q[0];
    out->q.v[1] = best.q[1];
    out->follower_d.v[0] = c[0] - best.q[0];
    out->follower_d.v[1] = c[1] - best.q[1];
    out->trace = tr;
    out->trace_prior = Pp[0] + Pp[4] + Pp[8];
    out->multiplier = mu;
    out->on_boundary = best.boundary;
    out->n_critical = ncrit;
    return SFM_OK;
}
