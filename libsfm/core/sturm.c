/*
 * Real roots of a polynomial of degree up to SFM_POLY_MAX_DEGREE by Sturm
 * sequences.
 *
 * The sequence s0 = p, s1 = p', s(k+1) = -rem(s(k-1), s(k)) counts the
 * distinct real roots in (a, b] as V(a) - V(b), V the number of sign changes
 * (Sturm 1835; e.g. Basu, Pollack and Roy, Algorithms in Real Algebraic
 * Geometry, ch. 2). A remainder that is zero to within the rounding error of
 * the division ends the sequence: the last member is then the gcd of p and
 * p', which is how multiple roots are counted once.
 *
 * The variable is first scaled by a power of two so that every root lies in
 * (-1, 1) (Fujiwara's bound), which keeps the sequence's coefficients
 * balanced. Intervals are bisected until each holds one root. When p changes
 * sign over it, the root is found by Newton steps safeguarded by the Illinois
 * variant of regula falsi and by bisection, to the resolution of double
 * precision. Without a sign change (a root of even multiplicity) bisection on
 * the count goes on to the resolution of double precision, and the point is
 * kept only if p vanishes there to within its evaluation error.
 *
 * In floating point the sign counts near a multiple root or a tight cluster
 * can be off by one. A remainder close to its rounding noise flags this, and
 * the roots are then also sought between the critical points of p (see
 * segment_roots); the two answers are merged.
 *
 * Stack use: about 6 KB (two sequences of (d+1)^2 doubles are never live at
 * once; interval stack of 2 d + 2 entries).
 */
#include <float.h>
#include <math.h>
#include <string.h>

#include "core/poly_internal.h"
#include "sfm/sfm_poly.h"
#include "core/dmath.h"

#define NMAX (SFM_POLY_MAX_DEGREE + 1)
/* A remainder whose every coefficient is below this multiple of the largest
 * term that went into it is rounding noise. */
#define REM_TOL (2.0 * DBL_EPSILON)
#define MAX_BISECT 4000
/* A remainder this small relative to its division raises the suspicion of a
 * multiple root. */
#define SUSPECT_TOL 1e-3
/* Two roots whose midpoint p cannot tell from zero (eps times the absolute
 * Horner sum, a realistic rather than worst-case rounding error) are one. */
#define MERGE_TOL(d) (1.0 / (2.0 * (double)((d) + 1)))

typedef struct sturm_seq {
    double s[NMAX][NMAX]; /* s[k][0..deg[k]], descending */
    int deg[NMAX];
    int n; /* members */
} sturm_seq;

/* Builds the sequence; returns 1 when some remainder came out small (a
 * multiple root or a tight cluster may be hiding: the caller then also looks
 * at the critical points). */
static int build_sequence(const double *p, int d, sturm_seq *q)
{
    int suspect = 0;
    memcpy(q->s[0], p, (size_t)(d + 1) * sizeof(double));
    q->deg[0] = d;
    /* p' scaled to largest magnitude one (a positive scale keeps signs) */
    double m = 0.0;
    for (int i = 0; i < d; i++) {
        q->s[1][i] = p[i] * (double)(d - i);
        m = fmax(m, fabs(q->s[1][i]));
    }
    for (int i = 0; i < d; i++)
        q->s[1][i] /= m;
    q->deg[1] = d - 1;
    q->n = 2;
    while (q->n < NMAX && q->deg[q->n - 1] > 0) {
        const double *u = q->s[q->n - 2];
        const double *v = q->s[q->n - 1];
        int du = q->deg[q->n - 2], dv = q->deg[q->n - 1];
        double r[NMAX], mag[NMAX];
        memcpy(r, u, (size_t)(du + 1) * sizeof(double));
        for (int i = 0; i <= du; i++)
            mag[i] = fabs(r[i]);
        /* long division; mag[j] is the largest term that went into r[j], the
         * scale of its rounding error */
        for (int k = 0; k <= du - dv; k++) {
            double f = r[k] / v[0];
            for (int j = 1; j <= dv; j++) {
                r[k + j] -= f * v[j];
                mag[k + j] = fmax(mag[k + j], fabs(f * v[j]));
            }
        }
        const double *rem = r + (du - dv + 1);
        const double *rmag = mag + (du - dv + 1);
        int dr = dv - 1, lead = 0;
        /* how far the remainder stands above its rounding noise */
        double ratio = 0.0;
        for (int i = 0; i <= dr; i++)
            if (rmag[i] > 0.0)
                ratio = fmax(ratio, fabs(rem[i]) / rmag[i]);
        if (ratio <= REM_TOL)
            lead = dr + 1;
        while (lead <= dr && rem[lead] == 0.0)
            lead++;
        if (lead > dr) {
            suspect = 1;
            break; /* zero remainder: the last member is gcd(p, p') */
        }
        if (ratio < SUSPECT_TOL)
            suspect = 1;
        double mm = 0.0;
        for (int i = lead; i <= dr; i++)
            mm = fmax(mm, fabs(rem[i]));
        double *w = q->s[q->n];
        for (int i = lead; i <= dr; i++)
            w[i - lead] = -rem[i] / mm;
        q->deg[q->n] = dr - lead;
        q->n++;
    }
    return suspect;
}

static int sign_changes(const sturm_seq *q, double x)
{
    int changes = 0, last = 0;
    for (int k = 0; k < q->n; k++) {
        double v = sfm_poly_eval(q->s[k], q->deg[k], x);
        int sg = (v > 0.0) - (v < 0.0);
        if (sg != 0) {
            if (last != 0 && sg != last)
                changes++;
            last = sg;
        }
    }
    return changes;
}

static int sgn(double v) { return (v > 0.0) - (v < 0.0); }

/* p(x) and p'(x) by Horner, without the error bound of sfmi_poly_eval_d */
static double eval_pd(const double *p, int d, double x, double *dp)
{
    double v = p[0], dv = 0.0;
    for (int i = 1; i <= d; i++) {
        dv = dv * x + v;
        v = v * x + p[i];
    }
    *dp = dv;
    return v;
}

/* Root of p in (a, b) where p(a), p(b) have opposite signs. Points are
 * classed as p < 0 or p >= 0, and the bracket always keeps one of each: an
 * exact zero met on the way (a touching root of even multiplicity, say) then
 * cannot pull the iteration away from the sign change it was given. */
static double bracketed(const double *p, int d, double a, double b, double pa, double pb)
{
    int neg_a = pa < 0.0;
    double x = a + 0.5 * (b - a);
    int side = 0; /* Illinois: which end was kept last time */
    for (int it = 0; it < 200; it++) {
        double width = b - a;
        if (width <= 2.0 * DBL_EPSILON * fmax(fabs(a), fabs(b)) || width <= DBL_MIN)
            break;
        double dpx, px = eval_pd(p, d, x, &dpx);
        if ((px < 0.0) == neg_a) {
            a = x;
            pa = px;
            if (side == -1)
                pb *= 0.5;
            side = -1;
        } else {
            b = x;
            pb = px;
            if (side == 1)
                pa *= 0.5;
            side = 1;
        }
        double xn = dpx != 0.0 ? x - px / dpx : (double)NAN;
        if (!(xn > a && xn < b) || fabs(xn - x) > 0.5 * width) {
            /* Newton left the bracket or is slow: Illinois step, else bisect */
            xn = pb != pa ? (a * pb - b * pa) / (pb - pa) : (double)NAN;
            if (!(xn > a && xn < b) || (b - a) > 0.5 * width)
                xn = a + 0.5 * (b - a);
        }
        if (fabs(xn - x) <= 2.0 * DBL_EPSILON * fabs(x))
            return xn; /* converged */
        x = xn;
    }
    return x;
}

typedef struct ival {
    double a, b;
    int va, vb;
} ival;

/* Roots of p (degree d >= 1, normalized) in (a0, b0], appended to r (room
 * for d). Returns the count; *suspect as build_sequence. */
static int isolate(const double *p, int d, double a0, double b0, double *r, int *suspect)
{
    sturm_seq q;
    int n = 0;
    *suspect = build_sequence(p, d, &q);
    ival st[2 * SFM_POLY_MAX_DEGREE + 2];
    int top = 0;
    st[top].a = a0;
    st[top].b = b0;
    st[top].va = sign_changes(&q, a0);
    st[top].vb = sign_changes(&q, b0);
    top++;
    for (int steps = 0; top > 0 && steps < MAX_BISECT && n < d; steps++) {
        ival I = st[--top];
        int cnt = I.va - I.vb;
        if (cnt <= 0)
            continue;
        double pa = sfm_poly_eval(p, d, I.a), pb = sfm_poly_eval(p, d, I.b);
        double width = I.b - I.a;
        int tiny = width <= 4.0 * DBL_EPSILON * fmax(fabs(I.a), fabs(I.b)) ||
                   width <= 4.0 * DBL_MIN;
        if (cnt == 1 && pb == 0.0) {
            r[n++] = I.b;
            continue;
        }
        if (cnt == 1 && sgn(pa) * sgn(pb) < 0) {
            r[n++] = bracketed(p, d, I.a, I.b, pa, pb);
            continue;
        }
        double m = I.a + 0.5 * width;
        if (tiny || !(m > I.a && m < I.b)) {
            /* a multiple root (or a cluster double precision cannot split):
             * keep it once, if p vanishes there */
            double x = sfmi_poly_polish(p, d, m, 64), px, dpx, err;
            sfmi_poly_eval_d(p, d, x, &px, &dpx, &err);
            if (fabs(px) <= 4.0 * err)
                r[n++] = x;
            continue;
        }
        if (top + 2 > (int)(sizeof st / sizeof st[0]))
            break;
        int vm = sign_changes(&q, m);
        st[top].a = m; /* right half first: the left is popped next */
        st[top].b = I.b;
        st[top].va = vm;
        st[top].vb = I.vb;
        top++;
        st[top].a = I.a;
        st[top].b = m;
        st[top].va = I.va;
        st[top].vb = vm;
        top++;
    }
    return n;
}

/* Second opinion when the Sturm sequence came out suspect (a remainder near
 * its rounding noise: a multiple root or a tight cluster, where the sign
 * counts of a sequence built in floating point can be off). Between adjacent
 * critical points (roots of p', found by their own Sturm sequence) p is
 * monotonic: it has a root there exactly when it changes sign. A critical
 * point where p vanishes to within its evaluation error, and p does not
 * cross zero, is a root of even multiplicity. Appends to r (room for d more)
 * and returns the new count. */
static int segment_roots(const double *p, int d, double a0, double b0, double *r, int n)
{
    double dp[NMAX], t[SFM_POLY_MAX_DEGREE + 2], v[SFM_POLY_MAX_DEGREE + 2];
    int touch[SFM_POLY_MAX_DEGREE + 2], dummy;
    for (int i = 0; i < d; i++)
        dp[i] = p[i] * (double)(d - i);
    int dd = sfmi_poly_normalize(dp, d - 1, dp);
    int m = dd >= 1 ? isolate(dp, dd, a0, b0, t + 1, &dummy) : 0;
    m = sfmi_poly_finish(dp, dd, t + 1, m, 0.0);
    t[0] = a0;
    t[m + 1] = b0;
    for (int j = 0; j <= m + 1; j++) {
        double dpx, err;
        sfmi_poly_eval_d(p, d, t[j], &v[j], &dpx, &err);
        touch[j] = 0;
        if (j > 0 && j <= m && fabs(v[j]) <= 4.0 * err)
            touch[j] = 1;
    }
    for (int j = 1; j <= m; j++) {
        /* a small value of strictly the other sign than both neighbours is
         * the resolved extremum between two close roots, not a root */
        if (touch[j] && v[j] != 0.0 && sgn(v[j]) != sgn(v[j - 1]) && sgn(v[j]) != sgn(v[j + 1]))
            touch[j] = 0;
        if (touch[j] && n < 2 * SFM_POLY_MAX_DEGREE)
            r[n++] = t[j];
    }
    for (int j = 0; j <= m; j++) {
        if (touch[j] || touch[j + 1] || sgn(v[j]) * sgn(v[j + 1]) >= 0)
            continue;
        if (n < 2 * SFM_POLY_MAX_DEGREE)
            r[n++] = bracketed(p, d, t[j], t[j + 1], v[j], v[j + 1]);
    }
    return n;
}

int sfm_poly_real_roots(const double *c, int degree, double lo, double hi, double *roots)
{
    if (!c || !roots)
        return SFM_E_ARGUMENT;
    if (degree > SFM_POLY_MAX_DEGREE)
        return SFM_E_CAPACITY;
    if (degree < 1)
        return SFM_E_ARGUMENT;
    if (isnan(lo) || isnan(hi))
        return SFM_E_NONFINITE;
    if (!(lo < hi))
        return SFM_E_ARGUMENT;
    for (int i = 0; i <= degree; i++)
        if (!isfinite(c[i]))
            return SFM_E_NONFINITE;

    double p[NMAX], r[2 * SFM_POLY_MAX_DEGREE + 1];
    int n = 0, zero_root = 0;
    int d = sfmi_poly_normalize(c, degree, p);
    if (d <= 0)
        return 0; /* a constant (or zero) polynomial has no isolated roots */
    if (p[d] == 0.0) { /* roots at zero: divide them out */
        zero_root = 1;
        while (d > 0 && p[d] == 0.0)
            d--;
    }
    double sigma = 1.0;
    if (d >= 1) {
        /* Fujiwara's bound: every root has |x| < 2 max |p_i/p_0|^(1/i) (the
         * last term halved). Substituting x = sigma y with sigma the next
         * power of two puts every root in |y| < 1 and balances the
         * coefficients the Sturm sequence is built from. */
        double lb = -1e9; /* log2 of the bound, in logs against overflow */
        for (int i = 1; i <= d; i++) {
            if (p[i] == 0.0)
                continue;
            double t = sfmi_log2(fabs(p[i])) - sfmi_log2(fabs(p[0])) - (i == d ? 1.0 : 0.0);
            lb = fmax(lb, t / (double)i);
        }
        int e = (int)ceil(lb) + 1;
        if (e > 900)
            e = 900;
        if (e < -900)
            e = -900;
        sigma = ldexp(1.0, e);
        double q[NMAX];
        for (int i = 0; i <= d; i++)
            q[i] = ldexp(p[i], -e * i);
        d = sfmi_poly_normalize(q, d, p);
    }
    if (d == 1) {
        r[n++] = -p[1] / p[0];
    } else if (d >= 2) {
        double a0 = fmax(lo / sigma, -1.0625), b0 = fmin(hi / sigma, 1.0625);
        if (a0 < b0) {
            int suspect = 0;
            n = isolate(p, d, a0, b0, r, &suspect);
            if (suspect && d >= 2)
                n = segment_roots(p, d, a0, b0, r, n);
            n = sfmi_poly_finish(p, d, r, n, MERGE_TOL(d));
        }
    }
    int k = 0;
    for (int i = 0; i < n; i++) {
        double x = r[i] * sigma;
        if (x > lo && x < hi)
            r[k++] = x;
    }
    if (zero_root && lo < 0.0 && 0.0 < hi) {
        int j = k;
        while (j > 0 && r[j - 1] > 0.0) {
            r[j] = r[j - 1];
            j--;
        }
        r[j] = 0.0;
        k++;
    }
    if (k > degree) /* cannot happen for distinct roots; guards the caller */
        k = degree;
    memcpy(roots, r, (size_t)k * sizeof(double));
    return k;
}
