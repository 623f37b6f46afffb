/*
 * Real roots of real polynomials.
 *
 * Coefficients are in descending order of power, as numpy.roots: c[0] x^d +
 * c[1] x^(d-1) + ... + c[d]. Roots are returned ascending, each real root once
 * (a double root once). Functions return the number of roots written (>= 0)
 * or a negative status. Stack use is bounded and documented per function.
 */
#ifndef SFM_POLY_H
#define SFM_POLY_H

#include "sfm/sfm_common.h"

#ifdef __cplusplus
extern "C" {
#endif

#define SFM_POLY_MAX_DEGREE 20

/* Horner evaluation; c non-NULL, degree 0..SFM_POLY_MAX_DEGREE (not checked). */
SFM_API double sfm_poly_eval(const double *c, int degree, double x);

/* Closed forms, numerically stable (no cancellation in the quadratic formula,
 * polished by Newton). A leading coefficient of zero falls back to the lower
 * degree. Statuses: count >= 0, SFM_E_ARGUMENT, SFM_E_NONFINITE. */
SFM_API int sfm_poly_roots2(const double c[3], double roots[2]);
SFM_API int sfm_poly_roots3(const double c[4], double roots[3]);
SFM_API int sfm_poly_roots4(const double c[5], double roots[4]);

/* All real roots in the open interval (lo, hi) of a polynomial of degree
 * 1..SFM_POLY_MAX_DEGREE, by a Sturm sequence with bisection, polished by
 * Newton. Pass lo = -INFINITY / hi = INFINITY for all real roots (a Cauchy
 * bound is used). roots needs room for `degree` entries.
 * Statuses: count >= 0, SFM_E_ARGUMENT, SFM_E_NONFINITE, SFM_E_CAPACITY
 * (degree above SFM_POLY_MAX_DEGREE). */
SFM_API int sfm_poly_real_roots(const double *c, int degree, double lo, double hi, double *roots);

#ifdef __cplusplus
}
#endif
#endif
