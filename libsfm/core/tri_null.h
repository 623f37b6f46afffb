/* Internal: the smallest right singular vector of a triangular factor. */
#ifndef SFM_CORE_TRI_NULL_H
#define SFM_CORE_TRI_NULL_H

/* Right singular vector of the smallest singular value of the n x n upper
 * triangular R (row-major, stride n; entries below the diagonal are not
 * read), by inverse iteration on R^T R with two triangular solves a step
 * (never forming R^T R, so the accuracy is that of R, as for an SVD of R).
 * Pivots below eps |R|_max are raised to it, as LAPACK's inverse iteration
 * does, so an exactly singular R is fine. scratch holds 2n doubles.
 * Returns 1 and writes v (unit norm) when the iteration settled to 1e-13 in
 * at most 64 steps; returns 0 with v untouched when it did not (the two
 * smallest singular values too close for inverse iteration, or R zero or
 * not finite): the caller then takes the SVD. n >= 1. */
int sfm_la_tri_smallest_right(const double *R, int n, double *v, double *scratch);

#endif
