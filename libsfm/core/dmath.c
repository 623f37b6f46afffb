/*
 * Elementary functions from IEEE 754 binary64 + - * / sqrt only; see
 * dmath.h for the contract and the accuracy of each.
 *
 * Methods (the classical ones; see J.-M. Muller, "Elementary Functions:
 * Algorithms and Implementation", 3rd ed., and Muller et al., "Handbook of
 * Floating-Point Arithmetic", ch. 4 for the error-free transformations):
 *   - error-free sum (Knuth's TwoSum, Dekker's Fast2Sum) and product
 *     (Dekker's TwoProduct with Veltkamp's split, no FMA) carry the extra
 *     bits where an intermediate result needs them;
 *   - exp: x = k ln2 + r with a 40-bit ln2 head (k ln2_hi exact), Taylor
 *     polynomial of degree 13 on |r| <= ln2/2, scaled by 2^k with one rounding;
 *   - log: x = 2^k (1 + f), sqrt(2)/2 <= 1 + f < sqrt(2), log(1+f) =
 *     2 atanh(s) with s = f / (2 + f), written as f - f^2/2 + s (f^2/2 + R(s^2))
 *     so that the leading terms come from the exact f;
 *   - atan: breakpoints c = i/8 and atan(z) = atan(c) + atan((z - c)/(1 + zc)),
 *     Taylor polynomial on |t| <= 1/16; atan2, asin and acos through it;
 *   - sin, cos: x = n pi/2 + r, Cody-Waite with pi/2 in four parts (three of
 *     33 bits, so n * part is exact for n < 2^20) below 2^20, Payne-Hanek
 *     (exact integer product with a 224-bit window of 2/pi) above; Taylor
 *     polynomials on |r| <= pi/4 taking the reduced argument as two doubles;
 *   - hypot, cbrt: the square (cube) formed exactly as two doubles and one
 *     Newton correction of the root against it;
 *   - pow: exp(y log x) with log x as two doubles (relative error ~2^-62).
 * Constants are the binary64 nearest the exact values (hex literals), split
 * into head and tail where a product with an integer must be exact; the
 * digits of pi, ln 2 and 2/pi come from exact rational series (Machin's
 * formula, 2 atanh(1/3)); tools/gen_dmath_constants.py prints them.
 */
#include "core/dmath.h"

#include <stdint.h>
#include <string.h>

static uint64_t dm_bits(double x)
{
    uint64_t u;
    memcpy(&u, &x, sizeof u);
    return u;
}

static double dm_double(uint64_t u)
{
    double x;
    memcpy(&x, &u, sizeof x);
    return x;
}

static double dm_nan(void) { return dm_double(0x7ff8000000000000ull); }
static double dm_inf(void) { return dm_double(0x7ff0000000000000ull); }

#define DM_MANT 0x000fffffffffffffull

/* 2^k for -1022 <= k <= 1023. */
static double dm_pow2i(int k) { return dm_double((uint64_t)(k + 1023) << 52); }

/* x 2^k with a single rounding (when the result is subnormal). */
static double dm_scale(double x, int k)
{
    while (k > 1023) {
        x *= 0x1p1023;
        k -= 1023;
    }
    while (k < -1022) {
        if (k >= -1022 - 53) {
            /* x is normal and >= 2^-1: x 2^-1022 is still normal (exact);
             * the last product rounds once. */
            x *= 0x1p-1022;
            k += 1022;
            break;
        }
        x *= 0x1p-1022;
        k += 1022;
    }
    return x * dm_pow2i(k);
}

/* s + e = a + b exactly. */
static void dm_two_sum(double a, double b, double *s, double *e)
{
    double t = a + b;
    double bb = t - a;
    *e = (a - (t - bb)) + (b - bb);
    *s = t;
}

/* s + e = a + b exactly, for |a| >= |b| (or a == 0). */
static void dm_fast_two_sum(double a, double b, double *s, double *e)
{
    double t = a + b;
    *e = b - (t - a);
    *s = t;
}

/* Veltkamp's split: a = hi + lo, each with at most 26 significant bits.
 * Valid for |a| < 2^995. */
static void dm_split(double a, double *hi, double *lo)
{
    double c = 134217729.0 * a; /* 2^27 + 1 */
    double h = c - (c - a);
    *hi = h;
    *lo = a - h;
}

/* p + e = a * b exactly (barring underflow), without FMA. */
static void dm_two_prod(double a, double b, double *p, double *e)
{
    double ah, al, bh, bl;
    double q = a * b;
    dm_split(a, &ah, &al);
    dm_split(b, &bh, &bl);
    *e = (((ah * bh - q) + ah * bl) + al * bh) + al * bl;
    *p = q;
}

/* ---------------------------------------------------------------- constants */

static const double LN2_HI = 0x1.62e42fefa2000p-1; /* 40 significant bits */
static const double LN2_LO = 0x1.9ef35793c7673p-41;
static const double INV_LN2 = 0x1.71547652b82fep+0;
static const double INV_LN2_LO = 0x1.777d0ffda0d24p-56;
static const double SQRT2 = 0x1.6a09e667f3bcdp+0;

static const double PI_HI = 0x1.921fb54442d18p+1;
static const double PI_LO = 0x1.1a62633145c07p-53;
static const double PIO2_HI = 0x1.921fb54442d18p+0;
static const double PIO2_LO = 0x1.1a62633145c07p-54;
static const double PIO4_HI = 0x1.921fb54442d18p-1;
static const double INV_PIO2 = 0x1.45f306dc9c883p-1;
/* pi/2 = PIO2_1 + PIO2_2 + PIO2_3 + PIO2_4 to 152 bits; the first three
 * have 33 significant bits. */
static const double PIO2_1 = 0x1.921fb54400000p+0;
static const double PIO2_2 = 0x1.0b4611a600000p-34;
static const double PIO2_3 = 0x1.3198a2e000000p-69;
static const double PIO2_4 = 0x1.b839a252049c1p-104;

/* 2/pi in 32-bit words, most significant first: 2/pi = sum w[j] 2^(-32(j+1)). */
static const uint32_t TWO_OVER_PI[44] = {
    0xa2f9836eu, 0x4e441529u, 0xfc2757d1u, 0xf534ddc0u, 0xdb629599u, 0x3c439041u,
    0xfe5163abu, 0xdebbc561u, 0xb7246e3au, 0x424dd2e0u, 0x06492eeau, 0x09d1921cu,
    0xfe1deb1cu, 0xb129a73eu, 0xe88235f5u, 0x2ebb4484u, 0xe99c7026u, 0xb45f7e41u,
    0x3991d639u, 0x835339f4u, 0x9c845f8bu, 0xbdf9283bu, 0x1ff897ffu, 0xde05980fu,
    0xef2f118bu, 0x5a0a6d1fu, 0x6d367ecfu, 0x27cb09b7u, 0x4f463f66u, 0x9e5fea2du,
    0x7527bac7u, 0xebe5f17bu, 0x3d0739f7u, 0x8a5292eau, 0x6bfb5fb1u, 0x1f8d5d08u,
    0x56033046u, 0xfc7b6babu, 0xf0cfbc20u, 0x9af4361du, 0xa9e39161u, 0x5ee61b08u,
    0x6599855fu, 0x14a06840u,
};

/* atan(i/8) = ATAN_HI[i] + ATAN_LO[i], i = 0..8. */
static const double ATAN_HI[9] = {
    0.0,
    0x1.fd5ba9aac2f6ep-4, 0x1.f5b75f92c80ddp-3, 0x1.6f61941e4def1p-2, 0x1.dac670561bb4fp-2,
    0x1.1e00babdefeb4p-1, 0x1.4978fa3269ee1p-1, 0x1.700a7c5784634p-1, 0x1.921fb54442d18p-1,
};
static const double ATAN_LO[9] = {
    0.0,
    -0x1.cd37686760c17p-59, 0x1.8ab6e3cf7afbdp-57, -0x1.c63aae6f6e918p-56, 0x1.a2b7f222f65e2p-56,
    -0x1.928df287a668fp-58, 0x1.2419a87f2a458p-56, -0x1.8c34d25aadef6p-56, 0x1.1a62633145c07p-55,
};

/* 1/n!, n = 0..17. */
static const double INV_FACT[18] = {
    0x1.0000000000000p+0, 0x1.0000000000000p+0, 0x1.0000000000000p-1, 0x1.5555555555555p-3,
    0x1.5555555555555p-5, 0x1.1111111111111p-7, 0x1.6c16c16c16c17p-10, 0x1.a01a01a01a01ap-13,
    0x1.a01a01a01a01ap-16, 0x1.71de3a556c734p-19, 0x1.27e4fb7789f5cp-22, 0x1.ae64567f544e4p-26,
    0x1.1eed8eff8d898p-29, 0x1.6124613a86d09p-33, 0x1.93974a8c07c9dp-37, 0x1.ae7f3e733b81fp-41,
    0x1.ae7f3e733b81fp-45, 0x1.952c77030ad4ap-49,
};

/* 1/(2n+1), n = 0..10, and 2/(2n+1), n = 0..13. */
static const double INV_ODD[11] = {
    0x1.0000000000000p+0, 0x1.5555555555555p-2, 0x1.999999999999ap-3, 0x1.2492492492492p-3,
    0x1.c71c71c71c71cp-4, 0x1.745d1745d1746p-4, 0x1.3b13b13b13b14p-4, 0x1.1111111111111p-4,
    0x1.e1e1e1e1e1e1ep-5, 0x1.af286bca1af28p-5, 0x1.8618618618618p-5,
};
static const double TWO_OVER_ODD[14] = {
    0x1.0000000000000p+1, 0x1.5555555555555p-1, 0x1.999999999999ap-2, 0x1.2492492492492p-2,
    0x1.c71c71c71c71cp-3, 0x1.745d1745d1746p-3, 0x1.3b13b13b13b14p-3, 0x1.1111111111111p-3,
    0x1.e1e1e1e1e1e1ep-4, 0x1.af286bca1af28p-4, 0x1.8618618618618p-4, 0x1.642c8590b2164p-4,
    0x1.47ae147ae147bp-4, 0x1.2f684bda12f68p-4,
};

/* -------------------------------------------------------------- hypot, cbrt */

double sfmi_hypot(double x, double y)
{
    if (isinf(x) || isinf(y))
        return dm_inf(); /* even when the other is NaN (Annex F) */
    if (isnan(x) || isnan(y))
        return x + y;
    x = fabs(x);
    y = fabs(y);
    if (x < y) {
        double t = x;
        x = y;
        y = t;
    }
    if (y == 0.0)
        return x;
    if (x > 0x1p60 * y)
        return x + y; /* y^2 / (2x) is below half an ulp of x */
    /* Bring both into a range where the squares neither overflow nor
     * underflow; powers of two scale exactly. */
    double scale = 1.0, unscale = 1.0;
    if (x > 0x1p500) {
        scale = 0x1p-600;
        unscale = 0x1p600;
    } else if (y < 0x1p-500) {
        scale = 0x1p600;
        unscale = 0x1p-600;
    }
    x *= scale;
    y *= scale;
    double xx, xe, yy, ye, h, he;
    dm_two_prod(x, x, &xx, &xe);
    dm_two_prod(y, y, &yy, &ye);
    dm_two_sum(xx, yy, &h, &he);
    double l = he + (xe + ye);
    double r = sqrt(h);
    /* One Newton step against h + l: r + (h + l - r^2) / (2r). */
    double rr, re;
    dm_two_prod(r, r, &rr, &re);
    r += (((h - rr) - re) + l) / (2.0 * r);
    return r * unscale;
}

double sfmi_cbrt(double x)
{
    if (!isfinite(x) || x == 0.0)
        return x + x;
    double ax = fabs(x);
    int sc = 0;
    if (ax < 0x1p-1000) {
        ax *= 0x1p300; /* exact; cbrt(2^300) = 2^100 */
        sc = -100;
    }
    uint64_t u = dm_bits(ax);
    int e = (int)(u >> 52) - 1023;
    int q = (e >= 0) ? e / 3 : -((-e + 2) / 3); /* floor(e / 3) */
    int r = e - 3 * q;                           /* 0, 1, 2 */
    double m = dm_double((u & DM_MANT) | ((uint64_t)(1023 + r) << 52)); /* [1, 8) */
    /* Linear fit of cbrt on [2^r, 2^(r+1)] (relative error 1.1 %), then two
     * Halley steps (cubic convergence: 1e-2 -> 1e-6 -> 1e-18). */
    static const double A[3] = {0.753396, 0.949219, 1.195941};
    static const double B[3] = {0.257654, 0.162312, 0.10225};
    double yv = A[r] + B[r] * m;
    for (int i = 0; i < 2; i++) {
        double y3 = yv * yv * yv;
        yv = yv * (y3 + 2.0 * m) / (2.0 * y3 + m);
    }
    /* Newton step against the exact cube: y + (m - y^3) / (3 y^2). */
    double a, ae, b, be;
    dm_two_prod(yv, yv, &a, &ae);
    dm_two_prod(a, yv, &b, &be);
    double d = (m - b) - (be + ae * yv);
    yv += d / (3.0 * a);
    return copysign(yv * dm_pow2i(q + sc), x);
}

/* ---------------------------------------------------------------- exp, log */

/* exp(x + xlo) for |x| <= 709.79 and |xlo| <= ulp(x); overflow gives inf,
 * underflow 0 or a subnormal. */
static double dm_exp_core(double x, double xlo)
{
    double kd = floor(x * INV_LN2 + 0.5);
    int k = (int)kd;
    double hi = x - kd * LN2_HI; /* exact */
    double lo = kd * LN2_LO - xlo;
    double r = hi - lo;
    double p = INV_FACT[13];
    for (int i = 12; i >= 2; i--)
        p = p * r + INV_FACT[i];
    p *= r * r; /* exp(r) - 1 - r */
    double yv = 1.0 + (hi - (lo - p));
    return dm_scale(yv, k);
}

double sfmi_exp(double x)
{
    if (isnan(x))
        return x + x;
    if (x > 0x1.62e42fefa39efp+9) /* log(DBL_MAX) */
        return dm_inf();
    if (x < -0x1.74910d52d3052p+9) /* below log of half the smallest subnormal */
        return 0.0;
    if (fabs(x) < 0x1p-54)
        return 1.0 + x;
    return dm_exp_core(x, 0.0);
}

/* x > 0 finite: x = 2^k (1 + f) with sqrt(2)/2 <= 1 + f < sqrt(2), f exact. */
static void dm_log_parts(double x, int *k, double *f)
{
    int e = 0;
    if (x < 0x1p-1022) {
        x *= 0x1p54;
        e = -54;
    }
    uint64_t u = dm_bits(x);
    e += (int)(u >> 52) - 1023;
    double m = dm_double((u & DM_MANT) | 0x3ff0000000000000ull);
    if (m >= SQRT2) {
        m *= 0.5;
        e++;
    }
    *k = e;
    *f = m - 1.0;
}

/* R(z) = sum_{n>=1} 2 z^n / (2n+1) to n = 10 (|z| <= 0.0295: the first
 * omitted term is below 2^-59 relative to the result). */
static double dm_log_r(double z)
{
    double p = TWO_OVER_ODD[10];
    for (int i = 9; i >= 1; i--)
        p = p * z + TWO_OVER_ODD[i];
    return p * z;
}

/* log(2^k (1 + f)) + c, c a small correction. */
static double dm_log_kernel(int k, double f, double c)
{
    double s = f / (2.0 + f);
    double z = s * s;
    double hfsq = 0.5 * f * f;
    double kd = (double)k;
    return kd * LN2_HI - ((hfsq - (s * (hfsq + dm_log_r(z)) + (kd * LN2_LO + c))) - f);
}

/* The special values of log and log2: NaN, x < 0, +-0 and +inf. Returns 1
 * with *r set for those, 0 for a positive finite x. */
static int dm_log_special(double x, double *r)
{
    if (isnan(x))
        *r = x + x;
    else if (x < 0.0)
        *r = dm_nan();
    else if (x == 0.0)
        *r = -dm_inf();
    else if (isinf(x))
        *r = x;
    else
        return 0;
    return 1;
}

double sfmi_log(double x)
{
    double r;
    if (dm_log_special(x, &r))
        return r;
    int k;
    double f;
    dm_log_parts(x, &k, &f);
    return dm_log_kernel(k, f, 0.0);
}

double sfmi_log1p(double x)
{
    if (isnan(x))
        return x + x;
    if (x < -1.0)
        return dm_nan();
    if (x == -1.0)
        return -dm_inf();
    if (isinf(x))
        return x;
    if (fabs(x) < 0x1p-54)
        return x; /* also keeps the sign of zero */
    double u = 1.0 + x;
    /* The part of x lost in 1 + x, relative to u: log(u + c) = log u + c/u. */
    double c = 0.0;
    if (x < 0x1p53)
        c = (x <= 1.0) ? x - (u - 1.0) : 1.0 - (u - x);
    int k;
    double f;
    dm_log_parts(u, &k, &f);
    return dm_log_kernel(k, f, c / u);
}

double sfmi_log2(double x)
{
    double r0;
    if (dm_log_special(x, &r0))
        return r0;
    int k;
    double f;
    dm_log_parts(x, &k, &f);
    double s = f / (2.0 + f);
    double hfsq = 0.5 * f * f;
    /* log(1+f) = hi + lo with hi = f - f^2/2 rounded and lo the rest. */
    double hi, lo;
    dm_fast_two_sum(f, -hfsq, &hi, &lo);
    lo += s * (hfsq + dm_log_r(s * s));
    double a, ae, r, re;
    dm_two_prod(hi, INV_LN2, &a, &ae);
    ae += lo * INV_LN2 + hi * INV_LN2_LO;
    dm_two_sum((double)k, a, &r, &re);
    return r + (re + ae);
}

/* log x = *h + *l for x > 0 finite, relative error about 2^-62 (pow needs
 * it: an error e in y log x is a relative error e in the result). */
static void dm_log_dd(double x, double *h, double *l)
{
    static const double TWO3_HI = 0x1.5555555555555p-1, TWO3_LO = 0x1.5555555555555p-55;
    int k;
    double f;
    dm_log_parts(x, &k, &f);
    /* s = f / (2 + f) to about 2^-105. */
    double dh, dl, p, pe;
    dm_two_sum(2.0, f, &dh, &dl);
    double sh = f / dh;
    dm_two_prod(sh, dh, &p, &pe);
    double sl = (((f - p) - pe) - sh * dl) / dh;
    /* log(1+f) = 2s + (2/3) s^3 + s^5 R2(s^2), R2 = 2/5 + 2/7 s^2 + ...:
     * 2s exact from (sh, sl), (2/3) sh^3 as two doubles, the rest (below
     * 2^-12 of the result) and the sl terms of s^3 in plain double. */
    double z, ze, c, ce, t, te;
    dm_two_prod(sh, sh, &z, &ze);
    dm_two_prod(sh, z, &c, &ce);
    ce += sh * ze;
    dm_two_prod(c, TWO3_HI, &t, &te);
    te += ce * TWO3_HI + c * TWO3_LO;
    /* to s^27: |s| <= 0.1716, the first omitted term is below 2^-66 */
    double r2 = TWO_OVER_ODD[13];
    for (int i = 12; i >= 2; i--)
        r2 = r2 * z + TWO_OVER_ODD[i];
    double rest = (c * z) * r2 + 2.0 * z * sl;
    double a, ae;
    dm_two_sum(2.0 * sh, t, &a, &ae);
    double b = ae + ((2.0 * sl + te) + rest);
    double kd = (double)k;
    double H, e;
    dm_two_sum(kd * LN2_HI, a, &H, &e);
    double L = e + (b + kd * LN2_LO);
    dm_fast_two_sum(H, L, h, l);
}

/* 0: not an integer, 1: odd integer, 2: even integer. */
static int dm_int_kind(double y)
{
    double ay = fabs(y);
    if (ay >= 0x1p53)
        return 2;
    if (floor(ay) != ay)
        return 0;
    return (floor(ay * 0.5) * 2.0 == ay) ? 2 : 1;
}

double sfmi_pow(double x, double y)
{
    if (y == 0.0 || x == 1.0)
        return 1.0; /* even for NaN (Annex F) */
    if (isnan(x) || isnan(y))
        return x + y;
    int yk = dm_int_kind(y);
    if (isinf(y)) {
        double ax = fabs(x);
        if (ax == 1.0)
            return 1.0;
        return ((ax < 1.0) == (y < 0.0)) ? dm_inf() : 0.0;
    }
    if (x == 0.0) {
        if (y < 0.0)
            return (yk == 1) ? copysign(dm_inf(), x) : dm_inf();
        return (yk == 1) ? x : 0.0;
    }
    if (isinf(x)) {
        if (x > 0.0)
            return (y < 0.0) ? 0.0 : dm_inf();
        if (y < 0.0)
            return (yk == 1) ? -0.0 : 0.0;
        return (yk == 1) ? -dm_inf() : dm_inf();
    }
    if (x < 0.0 && yk == 0)
        return dm_nan();
    double sign = (x < 0.0 && yk == 1) ? -1.0 : 1.0;
    double lh, ll;
    dm_log_dd(fabs(x), &lh, &ll);
    if (fabs(y) > 0x1p64) {
        /* |log x| >= 2^-53 for x != 1, so |y log x| > 2^11: the result
         * overflows or underflows. */
        return ((lh > 0.0) == (y > 0.0)) ? sign * dm_inf() : sign * 0.0;
    }
    double ph, pe, h, l;
    dm_two_prod(y, lh, &ph, &pe);
    pe += y * ll;
    dm_fast_two_sum(ph, pe, &h, &l);
    if (h > 709.79)
        return sign * dm_inf();
    if (h < -745.2)
        return sign * 0.0;
    return sign * dm_exp_core(h, l);
}

/* ----------------------------------------------------------- atan and kin */

/* atan(z + zl) = *h + *l for 0 <= z <= 1, |zl| <= ulp(z). */
static void dm_atan01(double z, double zl, double *h, double *l)
{
    int i = (int)(z * 8.0 + 0.5);
    double th, tl;
    if (i == 0) {
        th = z;
        tl = zl;
    } else {
        /* t = (z - c) / (1 + zc) as two doubles: z - c is exact, the
         * denominator and the quotient carry their rounding errors. */
        double c = 0.125 * (double)i;
        double num = z - c;
        double zc, zce, dh, dl, p, pe;
        dm_two_prod(z, c, &zc, &zce);
        dm_two_sum(1.0, zc, &dh, &dl);
        dl += zce + zl * c;
        th = num / dh;
        dm_two_prod(th, dh, &p, &pe);
        tl = ((((num - p) - pe) + zl) - th * dl) / dh;
    }
    double t2 = th * th;
    /* atan(t) = t - t^3 P(t^2), P = 1/3 - t^2/5 + ... to t^12; |t| <= 1/16,
     * so the first omitted term is below 2^-59 |t|. */
    double p = INV_ODD[6];
    for (int j = 5; j >= 1; j--)
        p = INV_ODD[j] - t2 * p;
    double s, se;
    dm_two_sum(ATAN_HI[i], th, &s, &se);
    *h = s;
    *l = se + (ATAN_LO[i] + (tl - (th * t2) * p));
}

/* atan((y + yl) / (x + xl)) = *h + *l in [0, pi/2] for y, x > 0 within
 * 2^60 of each other and in [2^-560, 2^560], so the products are exact. */
static void dm_atan2_pos(double y, double yl, double x, double xl, double *h, double *l)
{
    int swap = y > x;
    if (swap) {
        double t = y, tl = yl;
        y = x;
        yl = xl;
        x = t;
        xl = tl;
    }
    double q = y / x, p, pe;
    dm_two_prod(q, x, &p, &pe);
    double ql = ((((y - p) - pe) + yl) - q * xl) / x;
    double a, al;
    dm_atan01(q, ql, &a, &al);
    if (swap) {
        double s, e;
        dm_two_sum(PIO2_HI, -a, &s, &e);
        *h = s;
        *l = e + (PIO2_LO - al);
    } else {
        *h = a;
        *l = al;
    }
}

/* pi - (h + l), rounded. */
static double dm_pi_minus(double h, double l)
{
    double s, e;
    dm_two_sum(PI_HI, -h, &s, &e);
    return s + (e + (PI_LO - l));
}

double sfmi_atan(double x)
{
    if (isnan(x))
        return x + x;
    double ax = fabs(x);
    if (ax < 0x1p-27)
        return x; /* atan x = x (1 - x^2/3 ...): x is within half an ulp */
    if (ax > 0x1p60)
        return copysign(PIO2_HI, x);
    double h, l;
    dm_atan2_pos(ax, 0.0, 1.0, 0.0, &h, &l);
    return copysign(h + l, x);
}

double sfmi_atan2(double y, double x)
{
    if (isnan(x) || isnan(y))
        return x + y;
    if (y == 0.0) {
        if (signbit(x))
            return copysign(PI_HI, y);
        return y; /* x > 0 or +0: +-0 */
    }
    if (x == 0.0)
        return copysign(PIO2_HI, y);
    if (isinf(y)) {
        if (isinf(x))
            return copysign(x > 0.0 ? PIO4_HI : 3.0 * PIO4_HI, y);
        return copysign(PIO2_HI, y);
    }
    if (isinf(x))
        return copysign(x > 0.0 ? 0.0 : PI_HI, y);
    double ax = fabs(x), ay = fabs(y), a;
    if (ay < 0x1p-60 * ax) {
        a = ay / ax; /* atan(q) = q to half an ulp */
        if (x < 0.0)
            a = PI_HI - (a - PI_LO);
    } else if (ax < 0x1p-60 * ay) {
        double b = ax / ay;
        a = (x < 0.0) ? PIO2_HI + (b + PIO2_LO) : PIO2_HI - (b - PIO2_LO);
    } else {
        /* A common power of two keeps the ratio and the exact products. */
        double big = ax > ay ? ax : ay;
        if (big > 0x1p500) {
            ax *= 0x1p-600;
            ay *= 0x1p-600;
        } else if (big < 0x1p-500) {
            ax *= 0x1p600;
            ay *= 0x1p600;
        }
        double h, l;
        dm_atan2_pos(ay, 0.0, ax, 0.0, &h, &l);
        a = (x < 0.0) ? dm_pi_minus(h, l) : h + l;
    }
    return copysign(a, y);
}

/* sqrt(1 - x^2) = *h + *l for 0 <= x <= 1, the square formed exactly. */
static void dm_sqrt1mx2(double x, double *h, double *l)
{
    double s, sl;
    if (x < 0.5) {
        double xx, xe;
        dm_two_prod(x, x, &xx, &xe);
        dm_two_sum(1.0, -xx, &s, &sl);
        sl -= xe;
    } else {
        double d = 1.0 - x; /* exact */
        double u, ue, e;
        dm_two_sum(1.0, x, &u, &ue);
        dm_two_prod(d, u, &s, &e);
        sl = e + d * ue;
    }
    double r = sqrt(s);
    if (r == 0.0) {
        *h = 0.0;
        *l = 0.0;
        return;
    }
    double rr, re;
    dm_two_prod(r, r, &rr, &re);
    *h = r;
    *l = (((s - rr) - re) + sl) / (2.0 * r);
}

double sfmi_asin(double x)
{
    if (isnan(x))
        return x + x;
    double ax = fabs(x);
    if (ax > 1.0)
        return dm_nan();
    if (ax < 0x1p-26)
        return x;
    if (ax == 1.0)
        return copysign(PIO2_HI, x);
    double ch, cl, h, l;
    dm_sqrt1mx2(ax, &ch, &cl);
    dm_atan2_pos(ax, 0.0, ch, cl, &h, &l);
    return copysign(h + l, x);
}

double sfmi_acos(double x)
{
    if (isnan(x))
        return x + x;
    double ax = fabs(x);
    if (ax > 1.0)
        return dm_nan();
    if (x == 1.0)
        return 0.0;
    if (x == -1.0)
        return PI_HI;
    if (ax < 0x1p-60)
        return PIO2_HI;
    double ch, cl, h, l;
    dm_sqrt1mx2(ax, &ch, &cl);
    dm_atan2_pos(ch, cl, ax, 0.0, &h, &l);
    return (x < 0.0) ? dm_pi_minus(h, l) : h + l;
}

/* ------------------------------------------------------------- sin, cos */

/* Bits [pos, pos + 32) of the little-endian limbs L[0..n); zero outside. */
static uint32_t dm_bits32(const uint32_t *L, int n, int pos)
{
    int w = (pos >= 0) ? pos / 32 : -((-pos + 31) / 32);
    int off = pos - 32 * w;
    uint64_t lo = (w >= 0 && w < n) ? L[w] : 0u;
    uint64_t hi = (w + 1 >= 0 && w + 1 < n) ? L[w + 1] : 0u;
    return (uint32_t)(((hi << 32) | lo) >> off);
}

/* Payne-Hanek for x >= 2^20 finite: x = q pi/2 + (*rh + *rl), returns q mod 4. */
static int dm_reduce_large(double x, double *rh, double *rl)
{
    uint64_t u = dm_bits(x);
    uint64_t M = (u & DM_MANT) | (1ull << 52);
    int E = (int)(u >> 52) - 1023 - 52; /* x = M 2^E, E >= -32 */
    /* Words of 2/pi above index j0 (1-based) contribute multiples of 4 to
     * x 2/pi; seven words from j0 on leave >= 191 fraction bits, enough for
     * the closest a double comes to a multiple of pi/2 (about 2^-62). */
    int j0 = (E < 2) ? 1 : (E - 2) / 32 + 1;
    uint32_t A[7], L[9];
    for (int i = 0; i < 7; i++)
        A[i] = TWO_OVER_PI[j0 + 5 - i]; /* little-endian window */
    uint64_t m0 = M & 0xffffffffu, m1 = M >> 32, carry = 0;
    for (int i = 0; i < 7; i++) {
        uint64_t p = (uint64_t)A[i] * m0 + carry;
        L[i] = (uint32_t)p;
        carry = p >> 32;
    }
    L[7] = (uint32_t)carry;
    carry = 0;
    for (int i = 0; i < 7; i++) {
        uint64_t p = (uint64_t)A[i] * m1 + L[i + 1] + carry;
        L[i + 1] = (uint32_t)p;
        carry = p >> 32;
    }
    L[8] = (uint32_t)carry;
    /* x 2/pi = L 2^-s with s fraction bits. */
    int s = 32 * (j0 + 6) - E;
    int q = (int)(dm_bits32(L, 9, s) & 3u);
    uint32_t F[4];
    for (int i = 0; i < 4; i++)
        F[i] = dm_bits32(L, 9, s - 32 * (i + 1)); /* F[0] most significant */
    double sign = 1.0;
    if (F[0] & 0x80000000u) {
        /* fraction >= 1/2: round q up and take 1 - fraction, negated */
        q = (q + 1) & 3;
        uint64_t c = 1;
        for (int i = 3; i >= 0; i--) {
            uint64_t v = (uint64_t)(uint32_t)~F[i] + c;
            F[i] = (uint32_t)v;
            c = v >> 32;
        }
        sign = -1.0;
    }
    double t1 = (double)F[0] * 0x1p-32, t2 = (double)F[1] * 0x1p-64;
    double t3 = (double)F[2] * 0x1p-96, t4 = (double)F[3] * 0x1p-128;
    double h, l;
    dm_two_sum(t1, t2, &h, &l);
    l += t3 + t4;
    double p, pe;
    dm_two_prod(h, PIO2_HI, &p, &pe);
    pe += h * PIO2_LO + l * PIO2_HI;
    dm_fast_two_sum(p, pe, rh, rl);
    *rh *= sign;
    *rl *= sign;
    return q;
}

/* x finite: x = q pi/2 + (*rh + *rl) with |rh| <= pi/4 (plus rounding);
 * returns q mod 4. */
static int dm_reduce(double x, double *rh, double *rl)
{
    double ax = fabs(x);
    if (ax <= PIO4_HI) {
        *rh = x;
        *rl = 0.0;
        return 0;
    }
    if (ax < 0x1p20) {
        double n = floor(x * INV_PIO2 + 0.5); /* |n| < 2^20 */
        double t = x - n * PIO2_1;             /* exact */
        double h, e, h2, e2;
        dm_two_sum(t, -(n * PIO2_2), &h, &e);
        dm_two_sum(h, -(n * PIO2_3), &h2, &e2);
        double lo = (e + e2) - n * PIO2_4;
        dm_fast_two_sum(h2, lo, rh, rl);
        return (int)((int64_t)n & 3);
    }
    int q = dm_reduce_large(ax, rh, rl);
    if (x < 0.0) {
        *rh = -*rh;
        *rl = -*rl;
        q = (4 - q) & 3;
    }
    return q;
}

/* sin(x + y), |x| <= pi/4, |y| <= ulp(x). Taylor to x^17 (first omitted
 * term below 2^-60 |x|). */
static double dm_sin_k(double x, double y)
{
    double z = x * x;
    double p = INV_FACT[17];
    for (int i = 15; i >= 3; i -= 2)
        p = INV_FACT[i] - z * p;
    /* p = 1/3! - z/5! + ...; sin = x - x^3 p */
    return x + (y * (1.0 - 0.5 * z) - (z * x) * p);
}

/* cos(x + y), |x| <= pi/4, |y| <= ulp(x). Taylor to x^16. */
static double dm_cos_k(double x, double y)
{
    double z, zl;
    dm_two_prod(x, x, &z, &zl);
    double hz = 0.5 * z;
    double w = 1.0 - hz;
    double p = INV_FACT[16];
    for (int i = 14; i >= 4; i -= 2)
        p = INV_FACT[i] - z * p;
    /* p = 1/4! - z/6! + ...; cos = 1 - x^2/2 + x^4 p */
    return w + ((((1.0 - w) - hz) - 0.5 * zl) + ((z * z) * p - x * y));
}

double sfmi_sin(double x)
{
    if (!isfinite(x))
        return x - x;
    if (fabs(x) < 0x1p-26)
        return x;
    double h, l;
    switch (dm_reduce(x, &h, &l)) {
    case 0: return dm_sin_k(h, l);
    case 1: return dm_cos_k(h, l);
    case 2: return -dm_sin_k(h, l);
    default: return -dm_cos_k(h, l);
    }
}

double sfmi_cos(double x)
{
    if (!isfinite(x))
        return x - x;
    if (fabs(x) < 0x1p-27)
        return 1.0;
    double h, l;
    switch (dm_reduce(x, &h, &l)) {
    case 0: return dm_cos_k(h, l);
    case 1: return -dm_sin_k(h, l);
    case 2: return -dm_cos_k(h, l);
    default: return dm_sin_k(h, l);
    }
}

void sfmi_sincos(double x, double *s, double *c)
{
    if (!isfinite(x)) {
        *s = *c = x - x;
        return;
    }
    if (fabs(x) < 0x1p-27) {
        *s = x;
        *c = 1.0;
        return;
    }
    double h, l;
    int q = dm_reduce(x, &h, &l);
    double sv = dm_sin_k(h, l), cv = dm_cos_k(h, l);
    switch (q) {
    case 0: *s = sv; *c = cv; break;
    case 1: *s = cv; *c = -sv; break;
    case 2: *s = -sv; *c = -cv; break;
    default: *s = -cv; *c = sv; break;
    }
}
