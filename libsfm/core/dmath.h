/*
 * The library's elementary functions. Every transcendental function the
 * library calls goes through these names, never through <math.h> directly:
 * the platform's libm rounds differently on x86-64 (glibc, which also picks
 * FMA or non-FMA code paths by CPU), aarch64 and Cortex-M (newlib), and a
 * last-bit difference in hypot under an SVD or in atan2 in a rotation is
 * amplified by refinement until results differ between targets.
 *
 * dmath.c builds each of them from IEEE 754 binary64 + - * / and sqrt only
 * (plus exact bit manipulation of the representation), which every target
 * rounds identically when the build has -ffp-contract=off, so the same
 * argument gives the same bits on every target and compiler.
 *
 * sqrt, fabs, floor, ceil, fmin, fmax and copysign are exact or correctly
 * rounded by IEEE 754 on every target and stay as they are.
 *
 * Accuracy, in units in the last place of the exact result, as bounded by
 * tests/unit/test_dmath.c against the platform's libm (long double where it
 * is wider) over the ranges stated there; subnormal results in subnormal ulps:
 *   hypot, cbrt, atan, atan2, asin, acos   < 0.6 ulp (measured <= 0.51)
 *   exp, log, log1p, log2, sin, cos        < 1 ulp   (measured <= 0.83)
 *   pow                                    < 2 ulp   (measured <= 0.96,
 *                                          |y log x| up to 745)
 * sin and cos reduce their argument exactly at every magnitude (Cody-Waite
 * with a 152-bit pi/2 below 2^20, Payne-Hanek with 1,408 bits of 2/pi above).
 * Special values follow C11 Annex F (signed zeros, infinities, NaN); errno
 * and the floating-point exception flags are not part of the contract.
 *
 * Internal names carry the sfmi_ prefix: they are not API.
 */
#ifndef SFM_CORE_DMATH_H
#define SFM_CORE_DMATH_H

#include <math.h>

double sfmi_hypot(double x, double y);
double sfmi_cbrt(double x);
double sfmi_atan2(double y, double x);
double sfmi_atan(double x);
double sfmi_sin(double x);
double sfmi_cos(double x);
/* Both at once, sharing the argument reduction. */
void sfmi_sincos(double x, double *s, double *c);
double sfmi_acos(double x);
double sfmi_asin(double x);
double sfmi_exp(double x);
double sfmi_log(double x);
double sfmi_log1p(double x);
double sfmi_log2(double x);
double sfmi_pow(double x, double y);

#endif
