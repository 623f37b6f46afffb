/*
 * The library's elementary functions (libsfm/core/dmath.c) beside the
 * platform's libm: nanoseconds per call over a fixed set of arguments in the
 * range where the library calls each one, and the ratio. Timing only; the
 * accuracy is tested in tests/unit/test_dmath.c.
 */
#define _POSIX_C_SOURCE 199309L
#include <math.h>
#include <stdint.h>
#include <stdio.h>
#include <time.h>

#include "core/dmath.h"

#define N 4096
#define REPS 400

static double now_ns(void)
{
    struct timespec ts;
    clock_gettime(CLOCK_MONOTONIC, &ts);
    return (double)ts.tv_sec * 1e9 + (double)ts.tv_nsec;
}

static uint64_t state = 0x9e3779b97f4a7c15ull;
static double uniform(double lo, double hi)
{
    state ^= state << 13;
    state ^= state >> 7;
    state ^= state << 17;
    return lo + (hi - lo) * (double)(state >> 11) * 0x1p-53;
}

static double xs[N], ys[N];
static volatile double sink;

typedef double (*fn1)(double);
typedef double (*fn2)(double, double);

static double time1(fn1 f)
{
    double best = 1e30;
    for (int rep = 0; rep < 5; rep++) {
        double acc = 0.0, t0 = now_ns();
        for (int r = 0; r < REPS; r++)
            for (int i = 0; i < N; i++)
                acc += f(xs[i]);
        double t = (now_ns() - t0) / ((double)REPS * N);
        sink = acc;
        if (t < best)
            best = t;
    }
    return best;
}

static double time2(fn2 f)
{
    double best = 1e30;
    for (int rep = 0; rep < 5; rep++) {
        double acc = 0.0, t0 = now_ns();
        for (int r = 0; r < REPS; r++)
            for (int i = 0; i < N; i++)
                acc += f(ys[i], xs[i]);
        double t = (now_ns() - t0) / ((double)REPS * N);
        sink = acc;
        if (t < best)
            best = t;
    }
    return best;
}

static void row1(const char *name, fn1 ours, fn1 libm, double lo, double hi)
{
    for (int i = 0; i < N; i++)
        xs[i] = uniform(lo, hi);
    double a = time1(ours), b = time1(libm);
    printf("%-7s [%8.3g, %8.3g]  %7.1f ns  %7.1f ns  %5.2f\n", name, lo, hi, a, b, a / b);
}

static void row2(const char *name, fn2 ours, fn2 libm, double lo, double hi)
{
    for (int i = 0; i < N; i++) {
        xs[i] = uniform(lo, hi);
        ys[i] = uniform(lo, hi);
    }
    double a = time2(ours), b = time2(libm);
    printf("%-7s [%8.3g, %8.3g]  %7.1f ns  %7.1f ns  %5.2f\n", name, lo, hi, a, b, a / b);
}

static double pow_xy(double y, double x) { return pow(fabs(x), y); }
static double sfmi_pow_xy(double y, double x) { return sfmi_pow(fabs(x), y); }

int main(void)
{
    printf("function range                 libsfm     libm    ratio\n");
    row2("hypot", sfmi_hypot, hypot, -10.0, 10.0);
    row1("cbrt", sfmi_cbrt, cbrt, -100.0, 100.0);
    row2("atan2", sfmi_atan2, atan2, -10.0, 10.0);
    row1("atan", sfmi_atan, atan, -10.0, 10.0);
    row1("sin", sfmi_sin, sin, -3.2, 3.2);
    row1("cos", sfmi_cos, cos, -3.2, 3.2);
    row1("sin", sfmi_sin, sin, 1e3, 1e6);
    row1("sin", sfmi_sin, sin, 1e10, 1e15);
    row1("acos", sfmi_acos, acos, -1.0, 1.0);
    row1("asin", sfmi_asin, asin, -1.0, 1.0);
    row1("exp", sfmi_exp, exp, -30.0, 30.0);
    row1("log", sfmi_log, log, 1e-6, 1e6);
    row1("log1p", sfmi_log1p, log1p, -0.5, 10.0);
    row1("log2", sfmi_log2, log2, 1e-6, 1e6);
    row2("pow", sfmi_pow_xy, pow_xy, -8.0, 8.0);
    return 0;
}
