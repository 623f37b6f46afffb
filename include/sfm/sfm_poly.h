/*
 * Real roots of real polynomials.
 *
 * Coefficients are in descending order of power, as numpy.roots: c[0] x^d +
 * c[1] x^(d-1) + ... + c[d]. Roots are returned ascending, each real root once
 * (a double root once). Functions return the number of roots written (>= 0)
 * or a negative status; on failure nothing is written, on success only the
 * first `count` entries. Stack use is bounded and documented per function.
 *
 * Accuracy: a simple root is found to within a small multiple of its
 * condition, (d+1) eps sum|c_i||x|^(d-i) / |p'(x)|. A double root is found to
 * within the square root of that perturbation; when the rounded coefficients
 * split it into two real roots closer than that, both may be returned. Roots
 * closer together than their condition allows cannot be told apart in double
 * precision and come back as one. A polynomial that is constant (or zero)
 * after leading zeros are dropped has no isolated roots: count 0.
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

/* Closed forms, numerically stable (no cancellation in the quadratic formula;
 * cubic by Viete/Cardano, quartic by Ferrari's resolvent cubic; every root
 * polished by Newton steps on the original polynomial). A leading coefficient
 * of zero falls back to the lower degree. Stack use under 1 KB (a cubic or
 * quartic whose normalised coefficients overflow falls back to
 * sfm_poly_real_roots). Statuses: count >= 0, SFM_E_ARGUMENT (NULL),
 * SFM_E_NONFINITE (NaN/Inf coefficient). */
SFM_API int sfm_poly_roots2(const double c[3], double roots[2]);
SFM_API int sfm_poly_roots3(const double c[4], double roots[3]);
SFM_API int sfm_poly_roots4(const double c[5], double roots[4]);

/* All real roots in the open interval (lo, hi) of a polynomial of degree
 * 1..SFM_POLY_MAX_DEGREE, by a Sturm sequence with bisection, polished by
 * safeguarded Newton / Illinois steps. Pass lo = -INFINITY / hi = INFINITY for
 * all real roots (Fujiwara's bound is used). roots needs room for `degree`
 * entries. Leading zero coefficients lower the degree. Stack use about 6 KB.
 * Statuses: count >= 0, SFM_E_ARGUMENT (NULL, degree < 1, !(lo < hi)),
 * SFM_E_NONFINITE (NaN/Inf coefficient, NaN bound), SFM_E_CAPACITY (degree
 * above SFM_POLY_MAX_DEGREE). */
SFM_API int sfm_poly_real_roots(const double *c, int degree, double lo, double hi, double *roots);

#ifdef __cplusplus
}
#endif
#endif
