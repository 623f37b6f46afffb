/*
 * Internal helpers shared by the closed-form and the Sturm root finders.
 * Every function here takes coefficients in descending order of power and
 * assumes them finite; none of them checks arguments.
 */
#ifndef SFM_CORE_POLY_INTERNAL_H
#define SFM_CORE_POLY_INTERNAL_H

/* p(x), p'(x) and a bound on the rounding error of the computed p(x):
 * 2 (d + 1) eps sum |c_i| |x|^(d-i) (Higham, Accuracy and Stability of
 * Numerical Algorithms, 2nd ed., section 5.1, rounded up). */
void sfmi_poly_eval_d(const double *c, int d, double x, double *p, double *dp, double *err);

/* Copy c (degree d) to out without its leading zeros and scaled by a power of
 * two so that the largest magnitude lies in [0.5, 1) (exact: the roots do not
 * change). Returns the remaining degree, or -1 for the zero polynomial. */
int sfmi_poly_normalize(const double *c, int d, double *out);

/* Newton steps on c from x, each accepted only while |p| decreases strictly. */
double sfmi_poly_polish(const double *c, int d, double x, int max_steps);

/* Candidate roots r[0..n) of c: drop non-finite ones, sort ascending and merge
 * neighbours within a few ulps of each other and those the polynomial cannot
 * tell apart: |p| at their midpoint within value_tol times the error bound of
 * sfmi_poly_eval_d there (0: only the ulps test). Returns the new count. */
int sfmi_poly_finish(const double *c, int d, double *r, int n, double value_tol);

#endif
