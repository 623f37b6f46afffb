/*
 * The library's elementary functions. Every transcendental function the
 * library calls goes through these names, never through <math.h> directly:
 * the platform's libm rounds differently on x86-64 (glibc, which also picks
 * FMA or non-FMA code paths by CPU), aarch64 and Cortex-M (newlib), and a
 * last-bit difference in hypot under an SVD or in atan2 in a rotation is
 * amplified by refinement until results differ between targets.
 *
 * sqrt, fabs, floor, ceil, fmin and fmax are exact or correctly rounded by
 * IEEE 754 on every target and stay as they are.
 *
 * Internal names carry the sfmi_ prefix: they are not API.
 */
#ifndef SFM_CORE_DMATH_H
#define SFM_CORE_DMATH_H

#include <math.h>

/* Until the portable implementations land these forward to libm, so that
 * call sites can be converted independently of them. */
static inline double sfmi_hypot(double x, double y) { return hypot(x, y); }
static inline double sfmi_cbrt(double x) { return cbrt(x); }
static inline double sfmi_atan2(double y, double x) { return atan2(y, x); }
static inline double sfmi_atan(double x) { return atan(x); }
static inline double sfmi_sin(double x) { return sin(x); }
static inline double sfmi_cos(double x) { return cos(x); }
static inline double sfmi_acos(double x) { return acos(x); }
static inline double sfmi_asin(double x) { return asin(x); }
static inline double sfmi_exp(double x) { return exp(x); }
static inline double sfmi_log(double x) { return log(x); }
static inline double sfmi_log1p(double x) { return log1p(x); }
static inline double sfmi_log2(double x) { return log2(x); }
static inline double sfmi_pow(double x, double y) { return pow(x, y); }

#endif
