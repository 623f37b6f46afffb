/*
 * Polynomial evaluation and closed-form real roots of degree 2, 3 and 4.
 *
 * Every closed form only proposes candidates; each candidate is then polished
 * by Newton steps on the original polynomial and duplicates are merged, so the
 * accuracy of a simple root is set by its condition number, not by the
 * cancellation inside the formula.
 *
 *  - quadratic: the form without cancellation, q = -(b + sign(b) sqrt(D)) / 2,
 *    x1 = q / a, x2 = c / q (Numerical Recipes, 3rd ed., section 5.6);
 *  - cubic: Viete's trigonometric form for three real roots, Cardano's with the
 *    sign chosen against cancellation for one (Numerical Recipes 5.6);
 *  - quartic: Ferrari's factorisation into two quadratics through the largest
 *    real root of the resolvent cubic.
 *
 * A discriminant that is negative only by rounding (a double root) still
 * proposes its real part; such "maybe" candidates are kept only if the
 * polynomial vanishes there to within its evaluation error.
 * Stack use: under 200 bytes per call.
 */
#include <float.h>
#include <math.h>
#include <string.h>

#include "core/poly_internal.h"
#include "sfm/sfm_poly.h"
#include "core/dmath.h"

/* Relative size of a negative discriminant still treated as rounding noise. */
#define MAYBE_TOL 1e-4
#define POLISH_STEPS 24

double sfm_poly_eval(const double *c, int degree, double x)
{
    double v = c[0];
    for (int i = 1; i <= degree; i++)
        v = v * x + c[i];
    return v;
}

void sfmi_poly_eval_d(const double *c, int d, double x, double *p, double *dp, double *err)
{
    double v = c[0], dv = 0.0, a = fabs(c[0]), ax = fabs(x);
    for (int i = 1; i <= d; i++) {
        dv = dv * x + v;
        v = v * x + c[i];
        a = a * ax + fabs(c[i]);
    }
    *p = v;
    *dp = dv;
    *err = 2.0 * (double)(d + 1) * DBL_EPSILON * a;
}

int sfmi_poly_normalize(const double *c, int d, double *out)
{
    int s = 0;
    while (s <= d && c[s] == 0.0)
        s++;
    if (s > d)
        return -1;
    double m = 0.0;
    for (int i = s; i <= d; i++)
        m = fmax(m, fabs(c[i]));
    int e;
    (void)frexp(m, &e);
    for (int i = s; i <= d; i++)
        out[i - s] = ldexp(c[i], -e);
    return d - s;
}

double sfmi_poly_polish(const double *c, int d, double x, int max_steps)
{
    double p, dp, err;
    sfmi_poly_eval_d(c, d, x, &p, &dp, &err);
    for (int k = 0; k < max_steps && p != 0.0 && dp != 0.0; k++) {
        double xn = x - p / dp;
        if (!isfinite(xn) || xn == x)
            break;
        double pn, dpn, errn;
        sfmi_poly_eval_d(c, d, xn, &pn, &dpn, &errn);
        if (!(fabs(pn) < fabs(p)))
            break;
        x = xn;
        p = pn;
        dp = dpn;
    }
    return x;
}

int sfmi_poly_finish(const double *c, int d, double *r, int n, double value_tol)
{
    int m = 0;
    for (int i = 0; i < n; i++)
        if (isfinite(r[i]))
            r[m++] = r[i];
    for (int i = 1; i < m; i++) { /* insertion sort: n <= 20 */
        double v = r[i];
        int j = i - 1;
        while (j >= 0 && r[j] > v) {
            r[j + 1] = r[j];
            j--;
        }
        r[j + 1] = v;
    }
    int k = 0;
    for (int i = 0; i < m; i++) {
        if (k > 0) {
            double a = r[k - 1], b = r[i];
            double mid = a + 0.5 * (b - a), p, dp, err;
            sfmi_poly_eval_d(c, d, mid, &p, &dp, &err);
            int same = b - a <= 8.0 * DBL_EPSILON * fmax(fabs(a), fabs(b));
            if (same || fabs(p) <= value_tol * err) {
                /* one root seen twice: keep the end where |p| is smaller */
                double pa, pb, ea, eb;
                sfmi_poly_eval_d(c, d, a, &pa, &dp, &ea);
                sfmi_poly_eval_d(c, d, b, &pb, &dp, &eb);
                double best = fabs(pa) <= fabs(pb) ? a : b;
                double pbest = fmin(fabs(pa), fabs(pb));
                r[k - 1] = fabs(p) < pbest ? mid : best;
                continue;
            }
        }
        r[k++] = r[i];
    }
    return k;
}

/* Candidate list with "maybe" flags. */
typedef struct cand {
    double x[4];
    int maybe[4];
    int n;
} cand;

static void cand_add(cand *cs, double x, int maybe)
{
    if (cs->n < 4 && isfinite(x)) {
        cs->x[cs->n] = x;
        cs->maybe[cs->n] = maybe;
        cs->n++;
    }
}

/* Candidates of a x^2 + b x + c, a != 0. */
static void quad_cands(double a, double b, double c, cand *cs)
{
    double bb = b * b, ac4 = 4.0 * a * c;
    double D = bb - ac4;
    double scale = bb + fabs(ac4);
    if (D < 0.0) {
        if (D >= -MAYBE_TOL * scale)
            cand_add(cs, -b / (2.0 * a), 1);
        return;
    }
    if (D == 0.0) {
        cand_add(cs, -b / (2.0 * a), 0);
        return;
    }
    double q = -0.5 * (b + copysign(sqrt(D), b));
    cand_add(cs, q / a, 0);
    cand_add(cs, c / q, 0);
}

/* Candidates of the monic cubic x^3 + a x^2 + b x + c. */
static void cubic_cands(double a, double b, double c, cand *cs)
{
    double Q = (a * a - 3.0 * b) / 9.0;
    double R = (2.0 * a * a * a - 9.0 * a * b + 27.0 * c) / 54.0;
    double a3 = a / 3.0;
    double Q3 = Q * Q * Q, R2 = R * R;
    if (R2 < Q3) {
        double sq = sqrt(Q);
        double th = sfmi_acos(fmax(-1.0, fmin(1.0, R / (sq * Q))));
        const double tau = 6.283185307179586476925286766559;
        cand_add(cs, -2.0 * sq * sfmi_cos(th / 3.0) - a3, 0);
        cand_add(cs, -2.0 * sq * sfmi_cos((th + tau) / 3.0) - a3, 0);
        cand_add(cs, -2.0 * sq * sfmi_cos((th - tau) / 3.0) - a3, 0);
        return;
    }
    double A = -copysign(sfmi_cbrt(fabs(R) + sqrt(R2 - Q3)), R);
    double B = A != 0.0 ? Q / A : 0.0;
    cand_add(cs, A + B - a3, 0);
    /* the complex pair -(A+B)/2 - a/3 +- i sqrt(3)/2 (A - B) */
    if (fabs(A - B) <= MAYBE_TOL * (fabs(A) + fabs(B)))
        cand_add(cs, -0.5 * (A + B) - a3, 1);
}

/* Polish, validate "maybe" candidates, sort and merge; copies to out. */
static int settle(const double *c, int d, cand *cs, double *out)
{
    double r[4];
    int n = 0;
    for (int i = 0; i < cs->n; i++) {
        double x = sfmi_poly_polish(c, d, cs->x[i], POLISH_STEPS);
        if (cs->maybe[i]) {
            double p, dp, err;
            sfmi_poly_eval_d(c, d, x, &p, &dp, &err);
            if (!(fabs(p) <= 4.0 * err))
                continue;
        }
        r[n++] = x;
    }
    n = sfmi_poly_finish(c, d, r, n, 1.0);
    for (int i = 0; i < n; i++)
        out[i] = r[i];
    return n;
}

static int check_coeffs(const double *c, int n)
{
    for (int i = 0; i < n; i++)
        if (!isfinite(c[i]))
            return SFM_E_NONFINITE;
    return SFM_OK;
}

/* Roots of a normalized polynomial of degree d <= 4 (leading coefficient
 * non-zero). r needs room for d entries. */
static int roots_upto4(const double *s, int d, double *r)
{
    cand cs;
    cs.n = 0;
    switch (d) {
    case 0:
        return 0;
    case 1:
        r[0] = -s[1] / s[0];
        return isfinite(r[0]) ? 1 : 0;
    case 2:
        quad_cands(s[0], s[1], s[2], &cs);
        break;
    case 3: {
        double a = s[1] / s[0], b = s[2] / s[0], cc = s[3] / s[0];
        if (!(isfinite(a) && isfinite(b) && isfinite(cc)))
            return sfm_poly_real_roots(s, d, -HUGE_VAL, HUGE_VAL, r);
        cubic_cands(a, b, cc, &cs);
        if (cs.n == 0)
            return sfm_poly_real_roots(s, d, -HUGE_VAL, HUGE_VAL, r);
        break;
    }
    default: {
        double a = s[1] / s[0], b = s[2] / s[0], cc = s[3] / s[0], dd = s[4] / s[0];
        if (!(isfinite(a) && isfinite(b) && isfinite(cc) && isfinite(dd)))
            return sfm_poly_real_roots(s, d, -HUGE_VAL, HUGE_VAL, r);
        /* resolvent cubic y^3 - b y^2 + (a c - 4 d) y + (4 b d - a^2 d - c^2) */
        double rc[4] = {1.0, -b, a * cc - 4.0 * dd, 4.0 * b * dd - a * a * dd - cc * cc};
        double yr[3];
        int ny = sfm_poly_roots3(rc, yr);
        if (ny <= 0)
            return sfm_poly_real_roots(s, d, -HUGE_VAL, HUGE_VAL, r);
        double y = yr[ny - 1];
        double e = fmax(0.25 * a * a + y - b, 0.0);
        double g = fmax(0.25 * y * y - dd, 0.0);
        double f = 0.5 * a * y - cc;
        double sq, h;
        if (e * e >= g) {
            sq = sqrt(e);
            h = sq > 0.0 ? f / (2.0 * sq) : 0.0;
        } else {
            h = sqrt(g);
            sq = f / (2.0 * h);
        }
        quad_cands(1.0, 0.5 * a - sq, 0.5 * y - h, &cs);
        quad_cands(1.0, 0.5 * a + sq, 0.5 * y + h, &cs);
        break;
    }
    }
    return settle(s, d, &cs, r);
}

static int roots_closed(const double *c, int d, double *roots)
{
    if (!c || !roots)
        return SFM_E_ARGUMENT;
    int st = check_coeffs(c, d + 1);
    if (st < 0)
        return st;
    double s[5], r[4];
    int ds = sfmi_poly_normalize(c, d, s);
    if (ds <= 0)
        return 0; /* a constant (or zero) polynomial has no isolated roots */
    int n = roots_upto4(s, ds, r);
    if (n < 0)
        return n;
    memcpy(roots, r, (size_t)n * sizeof(double));
    return n;
}

int sfm_poly_roots2(const double c[3], double roots[2]) { return roots_closed(c, 2, roots); }
int sfm_poly_roots3(const double c[4], double roots[3]) { return roots_closed(c, 3, roots); }
int sfm_poly_roots4(const double c[5], double roots[4]) { return roots_closed(c, 4, roots); }
