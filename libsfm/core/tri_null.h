/* Internal: the smallest right singular vector of a triangular factor. */
#ifndef SFM_CORE_TRI_NULL_H
#define SFM_CORE_TRI_NULL_H

/* Right singular vector of the smallest singular value of the n x n upper
 * triangular R (row-major, stride n; entries below the diagonal are not
 * read), by inverse iteration on R^T R with two triangular solves a step
 * (never forming R^T R, so the accuracy is that of R, as for an SVD of R),
 * going on with two vectors and their Ritz vector when one converges
 * slowly. Pivots below eps |R|_max are raised to it, as LAPACK's inverse
 * iteration does, so an exactly singular R is fine. scratch holds 5n
 * doubles. Returns 1 and writes v (unit norm) when the iteration settled to
 * tol (the remaining change of v, extrapolated from the contraction seen;
 * 1e-13 is rounding level for n <= 27) within 20 + 40 steps; returns 0
 * with v untouched when it did not
 * (the smallest singular values too close together, or |R|_max zero, not
 * finite or outside 1e-100..1e100): the caller then takes the SVD. On return 1, scratch[4n..5n)
 * holds the reciprocals of R's floored pivots, for sfmi_la_tri_gram_solve. When
 * the smallest singular value
 * is multiple, v may be any unit vector of its space (so may an SVD's).
 * n >= 1. */
int sfmi_la_tri_smallest_right(const double *R, int n, double tol, double *v, double *scratch);

/* x <- (R^T R)^-1 x by the two substitutions of one inverse-iteration step
 * (dinv: the reciprocal pivots a successful sfmi_la_tri_smallest_right left
 * in its scratch), unnormalised. */
void sfmi_la_tri_gram_solve(const double *R, int n, const double *dinv, double *x);

#endif
