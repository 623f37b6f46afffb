/*
 * Polynomial roots against truth: polynomials are built from known roots, and
 * every root found must lie within the first-order perturbation bound of a
 * true root, |dx| <= k (d+1) eps sum|c_i||x|^(d-i) / |p'(x)| (the coefficients
 * themselves are rounded when the polynomial is expanded). Random cases whose
 * roots are closer than that bound allows to resolve are skipped and counted.
 */
#include <float.h>
#include <string.h>

#include "sfm/sfm.h"
#include "sfm_test.h"

#define EPS DBL_EPSILON

/* c (degree n, leading coefficient lead) = lead * prod (x - r_i) */
static void poly_from_roots(const double *r, int n, double lead, double *c)
{
    c[0] = lead;
    for (int k = 0; k < n; k++) {
        c[k + 1] = 0.0;
        for (int j = k + 1; j >= 1; j--)
            c[j] -= r[k] * c[j - 1];
    }
}

static void sort(double *v, int n)
{
    for (int i = 1; i < n; i++) {
        double x = v[i];
        int j = i - 1;
        while (j >= 0 && v[j] > x) {
            v[j + 1] = v[j];
            j--;
        }
        v[j + 1] = x;
    }
}

/* first-order bound on how far rounding the coefficients moves simple root x */
static double root_tol(const double *c, int d, double x)
{
    double a = fabs(c[0]), dp = 0.0, p = c[0];
    for (int i = 1; i <= d; i++) {
        dp = dp * x + p;
        p = p * x + c[i];
        a = a * fabs(x) + fabs(c[i]);
    }
    return 16.0 * (double)(d + 1) * EPS * a / fabs(dp) + 4.0 * EPS * fabs(x);
}

/* the same for a double root x: rounding moves it by the square root of
 * (coefficient error / |p''(x)/2|) */
static double double_tol(const double *c, int d, double x)
{
    double a = fabs(c[0]), p = c[0], dp = 0.0, ddp = 0.0;
    for (int i = 1; i <= d; i++) {
        ddp = ddp * x + dp;
        dp = dp * x + p;
        p = p * x + c[i];
        a = a * fabs(x) + fabs(c[i]);
    }
    /* ddp accumulates p''/2 */
    return sqrt(16.0 * (double)(d + 1) * EPS * a / fabs(ddp)) + 4.0 * EPS * fabs(x);
}

/* 1 when adjacent true roots are far enough apart (30 bounds) to be told apart */
static int resolvable(const double *c, int d, const double *r)
{
    for (int i = 0; i + 1 < d; i++) {
        double gap = r[i + 1] - r[i];
        if (!(gap > 30.0 * root_tol(c, d, r[i]) && gap > 30.0 * root_tol(c, d, r[i + 1])))
            return 0;
    }
    return 1;
}

typedef int (*closed_fn)(const double *, double *);

static int call_roots(int d, int closed, const double *c, double *out)
{
    if (closed && d == 2)
        return sfm_poly_roots2(c, out);
    if (closed && d == 3)
        return sfm_poly_roots3(c, out);
    if (closed && d == 4)
        return sfm_poly_roots4(c, out);
    return sfm_poly_real_roots(c, d, -HUGE_VAL, HUGE_VAL, out);
}

/* Simple roots r (sorted, distinct): every one found, once, within bound. */
static void check_simple(sfm_test_ctx *t, const double *c, int d, const double *r, int closed)
{
    double out[SFM_POLY_MAX_DEGREE];
    int n = call_roots(d, closed, c, out);
    SFM_CHECK_EQ_INT(n, d);
    if (n != d) {
#ifndef SFM_TEST_REDUCED /* newlib's printf of a double needs a heap */
        for (int i = 0; i < d; i++)
            SFM_TEST_LOG("true root %.17g", r[i]);
        for (int i = 0; i < n; i++)
            SFM_TEST_LOG("found     %.17g", out[i]);
#endif
        return;
    }
    for (int i = 0; i < d; i++)
        SFM_CHECK_NEAR(out[i], r[i], root_tol(c, d, r[i]));
    for (int i = 1; i < n; i++)
        SFM_CHECK(out[i - 1] < out[i]);
}

SFM_TEST(poly_eval_horner)
{
    const double c[4] = {2.0, -3.0, 0.5, 7.0};
    SFM_CHECK_NEAR(sfm_poly_eval(c, 3, 0.0), 7.0, 0.0);
    SFM_CHECK_NEAR(sfm_poly_eval(c, 3, 2.0), 16.0 - 12.0 + 1.0 + 7.0, 0.0);
    SFM_CHECK_NEAR(sfm_poly_eval(c, 0, 5.0), 2.0, 0.0);
}

SFM_TEST(poly_quadratic_known_cases)
{
    double r[2];
    /* cancellation-prone: roots 1e-8 and 1e8, the small one to full precision */
    const double c1[3] = {1.0, -(1e8 + 1e-8), 1.0};
    SFM_CHECK_EQ_INT(sfm_poly_roots2(c1, r), 2);
    SFM_CHECK_NEAR(r[0], 1e-8, 4.0 * EPS * 1e-8);
    SFM_CHECK_NEAR(r[1], 1e8, 4.0 * EPS * 1e8);
    /* double root, reported once */
    const double c2[3] = {1.0, -6.0, 9.0};
    SFM_CHECK_EQ_INT(sfm_poly_roots2(c2, r), 1);
    SFM_CHECK_NEAR(r[0], 3.0, 1e-15);
    /* (x - 0.1)^2 with rounded coefficients: still one root near 0.1 */
    const double c3[3] = {1.0, -0.2, 0.01};
    SFM_CHECK_EQ_INT(sfm_poly_roots2(c3, r), 1);
    SFM_CHECK_NEAR(r[0], 0.1, 1e-8);
    /* no real roots */
    const double c4[3] = {1.0, 0.0, 1.0};
    SFM_CHECK_EQ_INT(sfm_poly_roots2(c4, r), 0);
    /* leading zero: linear 2x - 4 */
    const double c5[3] = {0.0, 2.0, -4.0};
    SFM_CHECK_EQ_INT(sfm_poly_roots2(c5, r), 1);
    SFM_CHECK_NEAR(r[0], 2.0, 0.0);
    /* constant and zero polynomials: no isolated roots */
    const double c6[3] = {0.0, 0.0, 5.0}, c7[3] = {0.0, 0.0, 0.0};
    SFM_CHECK_EQ_INT(sfm_poly_roots2(c6, r), 0);
    SFM_CHECK_EQ_INT(sfm_poly_roots2(c7, r), 0);
    /* a root at zero, and widely scaled coefficients */
    const double c8[3] = {1e-300, 3e-300, 0.0};
    SFM_CHECK_EQ_INT(sfm_poly_roots2(c8, r), 2);
    SFM_CHECK_NEAR(r[0], -3.0, 4.0 * EPS * 3.0);
    SFM_CHECK_NEAR(r[1], 0.0, 0.0);
    const double c9[3] = {1e200, -3e200, 2e200};
    SFM_CHECK_EQ_INT(sfm_poly_roots2(c9, r), 2);
    SFM_CHECK_NEAR(r[0], 1.0, 4.0 * EPS);
    SFM_CHECK_NEAR(r[1], 2.0, 8.0 * EPS);
}

SFM_TEST(poly_cubic_quartic_known_cases)
{
    double r[4], c[5];
    /* (x-1)(x-2)(x-3) and x^3 - 1 (one real root) */
    const double a[4] = {1.0, -6.0, 11.0, -6.0};
    SFM_CHECK_EQ_INT(sfm_poly_roots3(a, r), 3);
    SFM_CHECK_NEAR(r[0], 1.0, 4 * EPS);
    SFM_CHECK_NEAR(r[1], 2.0, 8 * EPS);
    SFM_CHECK_NEAR(r[2], 3.0, 8 * EPS);
    const double b[4] = {1.0, 0.0, 0.0, -1.0};
    SFM_CHECK_EQ_INT(sfm_poly_roots3(b, r), 1);
    SFM_CHECK_NEAR(r[0], 1.0, 4 * EPS);
    /* triple root x^3: at least found once near 0 */
    const double tr[4] = {1.0, 0.0, 0.0, 0.0};
    SFM_CHECK_EQ_INT(sfm_poly_roots3(tr, r), 1);
    SFM_CHECK_NEAR(r[0], 0.0, 0.0);
    /* biquadratic (x^2-1)(x^2-4), and one with no real roots (x^2+1)(x^2+4) */
    const double q1[5] = {1.0, 0.0, -5.0, 0.0, 4.0};
    SFM_CHECK_EQ_INT(sfm_poly_roots4(q1, r), 4);
    SFM_CHECK_NEAR(r[0], -2.0, 8 * EPS);
    SFM_CHECK_NEAR(r[1], -1.0, 4 * EPS);
    SFM_CHECK_NEAR(r[2], 1.0, 4 * EPS);
    SFM_CHECK_NEAR(r[3], 2.0, 8 * EPS);
    const double q2[5] = {1.0, 0.0, 5.0, 0.0, 4.0};
    SFM_CHECK_EQ_INT(sfm_poly_roots4(q2, r), 0);
    /* two double roots: (x-2)^2 (x+1)^2 */
    const double dr[4] = {2.0, 2.0, -1.0, -1.0};
    poly_from_roots(dr, 4, 1.0, c);
    SFM_CHECK_EQ_INT(sfm_poly_roots4(c, r), 2);
    SFM_CHECK_NEAR(r[0], -1.0, 1e-7);
    SFM_CHECK_NEAR(r[1], 2.0, 1e-7);
    SFM_CHECK_EQ_INT(sfm_poly_real_roots(c, 4, -HUGE_VAL, HUGE_VAL, r), 2);
    SFM_CHECK_NEAR(r[0], -1.0, 1e-7);
    SFM_CHECK_NEAR(r[1], 2.0, 1e-7);
    /* leading zeros fall back to the lower degree */
    const double l3[5] = {0.0, 1.0, -6.0, 11.0, -6.0};
    SFM_CHECK_EQ_INT(sfm_poly_roots4(l3, r), 3);
    SFM_CHECK_NEAR(r[2], 3.0, 8 * EPS);
    const double l2[4] = {0.0, 1.0, 0.0, -4.0};
    SFM_CHECK_EQ_INT(sfm_poly_roots3(l2, r), 2);
    SFM_CHECK_NEAR(r[0], -2.0, 4 * EPS);
}

/* Random simple roots: uniform, widely scaled, clustered pairs. */
static void random_roots(sfm_test_ctx *t, int kind, int d, double *r)
{
    for (int i = 0; i < d; i++) {
        switch (kind) {
        case 0:
            r[i] = sfm_test_uniform(t, -10.0, 10.0);
            break;
        case 1: /* magnitudes 1e-3 .. 1e3, either sign */
            r[i] = pow(10.0, sfm_test_uniform(t, -3.0, 3.0)) *
                   (sfm_test_uniform(t, -1.0, 1.0) < 0.0 ? -1.0 : 1.0);
            break;
        default: /* a pair 1e-7 .. 1e-3 apart (relative) */
            r[i] = sfm_test_uniform(t, -2.0, 2.0);
            if (i == 1)
                r[1] = r[0] * (1.0 + pow(10.0, sfm_test_uniform(t, -7.0, -3.0)));
            break;
        }
    }
    sort(r, d);
}

static void random_simple_roots(sfm_test_ctx *t, int d, int closed, int iters)
{
    double r[SFM_POLY_MAX_DEGREE], c[SFM_POLY_MAX_DEGREE + 1];
    int skipped = 0, run = 0;
    for (int kind = 0; kind < 3; kind++) {
        for (int it = 0; it < iters; it++) {
            random_roots(t, kind, d, r);
            double lead = sfm_test_uniform(t, 0.1, 10.0) * (it % 2 ? -1.0 : 1.0);
            poly_from_roots(r, d, lead, c);
            if (!resolvable(c, d, r)) {
                skipped++;
                continue;
            }
            run++;
            int before = t->failures;
            check_simple(t, c, d, r, closed);
            if (t->failures != before)
                return;
        }
    }
    SFM_CHECK(run > 2 * skipped);
    SFM_TEST_LOG("degree %d %s: %d cases, %d skipped as unresolvable", d,
                 closed ? "closed form" : "Sturm", run, skipped);
}

SFM_TEST(poly_closed_forms_random_known_roots)
{
    for (int d = 2; d <= 4; d++)
        random_simple_roots(t, d, 1, SFM_TEST_ITERS(2000));
}

SFM_TEST(poly_sturm_random_known_roots)
{
    const int degs[] = {1, 2, 3, 4, 5, 7, 10, 15, 20};
    for (int k = 0; k < (int)(sizeof degs / sizeof degs[0]); k++)
        random_simple_roots(t, degs[k], 0, SFM_TEST_ITERS(degs[k] <= 10 ? 1000 : 300));
}

/* A double root among simple ones is found once, within the square-root
 * perturbation bound, and no simple root is lost. */
static void double_root_case(sfm_test_ctx *t, const double *r, int d, int closed)
{
    double c[SFM_POLY_MAX_DEGREE + 1], out[SFM_POLY_MAX_DEGREE];
    poly_from_roots(r, d, 1.0, c);
    int n = call_roots(d, closed, c, out);
    SFM_CHECK(n >= d - 1 && n <= d);
    for (int i = 0; i < d; i++) {
        double best = HUGE_VAL;
        for (int j = 0; j < n; j++)
            best = fmin(best, fabs(out[j] - r[i]));
        int dbl = (i > 0 && r[i] == r[i - 1]) || (i + 1 < d && r[i] == r[i + 1]);
        double tol = dbl ? double_tol(c, d, r[i]) : root_tol(c, d, r[i]);
        SFM_CHECK_MSG(best <= tol, "root %.17g: nearest found %.3g away (%s, degree %d)", r[i],
                      best, closed ? "closed" : "Sturm", d);
    }
}

SFM_TEST(poly_double_roots)
{
    const double a[3] = {1.0, 1.0, 2.0};
    const double b[3] = {-3.0, 5.0, 5.0};
    const double q[4] = {-1.5, 0.25, 0.25, 4.0};
    const double s10[10] = {-4.0, -3.0, -2.0, -1.0, 0.5, 0.5, 2.0, 3.0, 5.0, 7.0};
    for (int closed = 0; closed <= 1; closed++) {
        double out[4], c[5];
        double_root_case(t, a, 3, closed);
        double_root_case(t, b, 3, closed);
        double_root_case(t, q, 4, closed);
        poly_from_roots(a, 3, 1.0, c);
        SFM_CHECK_EQ_INT(call_roots(3, closed, c, out), 2); /* exact coefficients */
    }
    double_root_case(t, s10, 10, 0);
    /* random double roots among simple ones */
    double r[10];
    for (int it = 0; it < SFM_TEST_ITERS(500); it++) {
        int d = 3 + it % 8;
        for (int i = 0; i < d; i++)
            r[i] = sfm_test_uniform(t, -3.0, 3.0);
        r[1] = r[0];
        sort(r, d);
        double c[11];
        poly_from_roots(r, d, 1.0, c);
        /* the double root's neighbours must be far enough for a clean case */
        int ok = 1;
        for (int i = 0; i + 1 < d; i++)
            if (r[i + 1] != r[i] && r[i + 1] - r[i] < 0.05)
                ok = 0;
        if (!ok)
            continue;
        double_root_case(t, r, d, d <= 4);
    }
}

SFM_TEST(poly_sturm_wilkinson10_and_interval)
{
    /* roots 1..10: the coefficients are integers below 2^53, exact */
    double r[10], c[11], out[10];
    for (int i = 0; i < 10; i++)
        r[i] = (double)(i + 1);
    poly_from_roots(r, 10, 1.0, c);
    SFM_CHECK_EQ_INT(sfm_poly_real_roots(c, 10, -HUGE_VAL, HUGE_VAL, out), 10);
    for (int i = 0; i < 10; i++)
        SFM_CHECK_NEAR(out[i], r[i], 1e-9 * r[i]);
    /* open interval: (3, 7.5) holds 4, 5, 6, 7; the ends are excluded */
    SFM_CHECK_EQ_INT(sfm_poly_real_roots(c, 10, 3.0, 7.5, out), 4);
    SFM_CHECK_NEAR(out[0], 4.0, 1e-10);
    SFM_CHECK_NEAR(out[3], 7.0, 1e-10);
    SFM_CHECK_EQ_INT(sfm_poly_real_roots(c, 10, 3.0, 4.0, out), 0);
    SFM_CHECK_EQ_INT(sfm_poly_real_roots(c, 10, 10.5, HUGE_VAL, out), 0);
    /* roots at zero are divided out and reported once */
    const double z[6] = {1.0, -1.0, -2.0, 0.0, 0.0, 0.0}; /* x^3 (x-2)(x+1) */
    SFM_CHECK_EQ_INT(sfm_poly_real_roots(z, 5, -HUGE_VAL, HUGE_VAL, out), 3);
    SFM_CHECK_NEAR(out[0], -1.0, 4 * EPS);
    SFM_CHECK_NEAR(out[1], 0.0, 0.0);
    SFM_CHECK_NEAR(out[2], 2.0, 8 * EPS);
    SFM_CHECK_EQ_INT(sfm_poly_real_roots(z, 5, 0.0, HUGE_VAL, out), 1);
    /* leading zeros: degree drops */
    const double l[4] = {0.0, 0.0, 2.0, -1.0};
    SFM_CHECK_EQ_INT(sfm_poly_real_roots(l, 3, -HUGE_VAL, HUGE_VAL, out), 1);
    SFM_CHECK_NEAR(out[0], 0.5, 0.0);
    /* no real roots at all: x^10 + 1 */
    double e[11] = {1.0, 0, 0, 0, 0, 0, 0, 0, 0, 0, 1.0};
    SFM_CHECK_EQ_INT(sfm_poly_real_roots(e, 10, -HUGE_VAL, HUGE_VAL, out), 0);
}

SFM_TEST(poly_sturm_tight_cluster_degree10)
{
    /* the shape a 5-point solver meets: ten roots, two of them 1e-6 apart */
    double r[10] = {-2.5, -1.2, -0.4, 0.3, 0.7, 0.7000007, 1.1, 1.9, 3.2, 6.0};
    double c[11];
    poly_from_roots(r, 10, 0.37, c);
    check_simple(t, c, 10, r, 0);
    /* three roots within 1e-4 and a root 1e6 times smaller than the largest */
    double s[8] = {-3.0e2, -1e-4, 0.999, 1.0, 1.001, 2.0, 40.0, 250.0};
    poly_from_roots(s, 8, -2.0, c);
    check_simple(t, c, 8, s, 0);
}

SFM_TEST(poly_contracts)
{
    double c[SFM_POLY_MAX_DEGREE + 2], out[SFM_POLY_MAX_DEGREE + 1];
    for (int i = 0; i < SFM_POLY_MAX_DEGREE + 2; i++)
        c[i] = 1.0 + i;
    c[1] = -50.0;
    sfm_test_fill_canary(out, sizeof out);
    SFM_CHECK_EQ_INT(sfm_poly_roots2(NULL, out), SFM_E_ARGUMENT);
    SFM_CHECK_EQ_INT(sfm_poly_roots2(c, NULL), SFM_E_ARGUMENT);
    SFM_CHECK_EQ_INT(sfm_poly_roots3(NULL, out), SFM_E_ARGUMENT);
    SFM_CHECK_EQ_INT(sfm_poly_roots4(NULL, out), SFM_E_ARGUMENT);
    SFM_CHECK_EQ_INT(sfm_poly_real_roots(NULL, 3, -1.0, 1.0, out), SFM_E_ARGUMENT);
    SFM_CHECK_EQ_INT(sfm_poly_real_roots(c, 3, -1.0, 1.0, NULL), SFM_E_ARGUMENT);
    SFM_CHECK_EQ_INT(sfm_poly_real_roots(c, 0, -1.0, 1.0, out), SFM_E_ARGUMENT);
    SFM_CHECK_EQ_INT(sfm_poly_real_roots(c, -2, -1.0, 1.0, out), SFM_E_ARGUMENT);
    SFM_CHECK_EQ_INT(sfm_poly_real_roots(c, SFM_POLY_MAX_DEGREE + 1, -HUGE_VAL, HUGE_VAL, out),
                     SFM_E_CAPACITY);
    SFM_CHECK_EQ_INT(sfm_poly_real_roots(c, 3, 1.0, 1.0, out), SFM_E_ARGUMENT);
    SFM_CHECK_EQ_INT(sfm_poly_real_roots(c, 3, 2.0, 1.0, out), SFM_E_ARGUMENT);
    SFM_CHECK_EQ_INT(sfm_poly_real_roots(c, 3, (double)NAN, 1.0, out), SFM_E_NONFINITE);
    SFM_CHECK_EQ_INT(sfm_poly_real_roots(c, 3, -1.0, (double)NAN, out), SFM_E_NONFINITE);
    const double bad[3] = {(double)NAN, (double)HUGE_VAL, -(double)HUGE_VAL};
    for (int k = 0; k < 3; k++) {
        for (int pos = 0; pos < 5; pos++) {
            double cc[5] = {1.0, -2.0, -3.0, 4.0, 1.0};
            cc[pos] = bad[k];
            if (pos < 3)
                SFM_CHECK_EQ_INT(sfm_poly_roots2(cc, out), SFM_E_NONFINITE);
            if (pos < 4)
                SFM_CHECK_EQ_INT(sfm_poly_roots3(cc, out), SFM_E_NONFINITE);
            SFM_CHECK_EQ_INT(sfm_poly_roots4(cc, out), SFM_E_NONFINITE);
            SFM_CHECK_EQ_INT(sfm_poly_real_roots(cc, 4, -HUGE_VAL, HUGE_VAL, out),
                             SFM_E_NONFINITE);
        }
    }
    SFM_CHECK(sfm_test_canary_intact(out, sizeof out));
    /* exactly `degree` entries are written at most: the one after stays */
    double r[3] = {-1.0, 0.5, 2.0}, cc[4], o[4];
    poly_from_roots(r, 3, 1.0, cc);
    sfm_test_fill_canary(o, sizeof o);
    SFM_CHECK_EQ_INT(sfm_poly_real_roots(cc, 3, -HUGE_VAL, HUGE_VAL, o), 3);
    SFM_CHECK(sfm_test_canary_intact(&o[3], sizeof o[3]));
    sfm_test_fill_canary(o, sizeof o);
    SFM_CHECK_EQ_INT(sfm_poly_roots3(cc, o), 3);
    SFM_CHECK(sfm_test_canary_intact(&o[3], sizeof o[3]));
    /* a count below capacity leaves the rest untouched too */
    sfm_test_fill_canary(o, sizeof o);
    SFM_CHECK_EQ_INT(sfm_poly_real_roots(cc, 3, 0.0, HUGE_VAL, o), 2);
    SFM_CHECK(sfm_test_canary_intact(&o[2], 2 * sizeof o[0]));
}
