/*
 * Internal helpers shared by the solvers (not part of the public API).
 *
 * Hartley normalization (Hartley 1997, "In defense of the eight-point
 * algorithm"): translate 2D points to their centroid and scale them so the
 * mean distance to it is sqrt(2). T maps (u, v, 1) to normalized coordinates.
 */
#ifndef SFM_SOLVERS_NORMALIZE_H
#define SFM_SOLVERS_NORMALIZE_H

#include "core/inline.h"
#include "core/linalg_util.h"

/* Normalizing similarity of n 2D points (row-major (n,2)): T = [s 0 -s cx;
 * 0 s -s cy; 0 0 1], stored as (s, -s cx, -s cy) in t[3]. Returns 0, or -1
 * when all points coincide (no scale). */
int sfmi_hartley_2d(const double *p, int n, double t[3]);

/* The finiteness check and normalizations of n pixel pairs p1, p2 ((n,2)
 * each): SFM_E_NONFINITE when a coordinate is not finite, 1 when the points
 * of either set coincide (sfmi_hartley_2d: no scale, no model), else 0 with
 * t1, t2 written. */
SFMI_INLINE int sfmi_hartley_pairs(const double *p1, const double *p2, int n, double t1[3],
                                   double t2[3])
{
    if (!sfmi_la_all_finite(p1, 2 * (size_t)n) || !sfmi_la_all_finite(p2, 2 * (size_t)n))
        return SFM_E_NONFINITE;
    if (sfmi_hartley_2d(p1, n, t1) || sfmi_hartley_2d(p2, n, t2))
        return 1;
    return 0;
}

/* The inverse of the normalization t, stored the same way:
 * ti = (1/s, -a/s, -b/s) for t = (s, a, b). */
void sfmi_hartley_inverse(const double t[3], double ti[3]);

/* Full 3x3 matrix of a normalization stored as t[3]. */
void sfmi_hartley_matrix(const double t[3], double T[9]);

/* Scale M (9 entries) to unit Frobenius norm. Returns 0, or -1 when M is
 * zero or not finite (M is then left as is). */
int sfmi_normalize9(double M[9]);

#endif
