/*
 * Minimal and linear solvers for two-view epipolar geometry and homographies.
 *
 * Conventions
 *  - Matrices are 3x3 row-major (sfm_mat3). Point arrays are row-major:
 *    bearings are (n,3) unit-norm vectors (x[3*i+k]); pixels and plane points
 *    are (n,2) (p[2*i+k]) and are lifted to (u, v, 1).
 *  - Poses map world to camera, x_cam = R X + t. Between two cameras,
 *    x_cam2 = R x_cam1 + t; the essential matrix is E = [t]x R and satisfies
 *    x2^T E x1 = 0 for corresponding bearings. A fundamental matrix satisfies
 *    p2h^T F p1h = 0, a homography p2h ~ H p1h (h: homogeneous (u, v, 1)).
 *  - Essential and fundamental matrices are returned with unit Frobenius norm
 *    (their sign is arbitrary). Homographies have unit Frobenius norm and
 *    det(H) > 0.
 *  - Each solver returns the number of solutions written (0..its MAX),
 *    always from index 0, or a negative sfm_status. A degenerate sample
 *    (coincident or collinear points, a rank-deficient system) gives 0
 *    solutions. For the 5-point, pure rotation (zero baseline) gives 0
 *    solutions in about 999 samples of 1000 and otherwise finite but
 *    meaningless matrices. Outputs beyond the count are not touched, nothing
 *    is written on an error, and outputs never hold NaN/Inf.
 *  - No solver allocates; stack use is bounded (stated per function, measured
 *    on x86-64 with -O2). Inputs and outputs must not overlap.
 *  - Statuses common to all: SFM_E_ARGUMENT (NULL pointer, n below the
 *    minimum), SFM_E_NONFINITE (NaN/Inf in an input).
 */
#ifndef SFM_SOLVERS_H
#define SFM_SOLVERS_H

#include "sfm/sfm_common.h"

#ifdef __cplusplus
extern "C" {
#endif

#define SFM_RELPOSE_5PT_MAX_SOLUTIONS 10
#define SFM_FUNDAMENTAL_7PT_MAX_SOLUTIONS 3
#define SFM_RELPOSE_8PT_MAX_SOLUTIONS 1
#define SFM_FUNDAMENTAL_8PT_MAX_SOLUTIONS 1
#define SFM_HOMOGRAPHY_4PT_MAX_SOLUTIONS 1
#define SFM_HOMOGRAPHY_DLT_MAX_SOLUTIONS 1

/* Essential matrices from 5 bearing pairs (Nister 2004). x1, x2: (5,3)
 * bearings (any nonzero length; only directions matter). E: room for
 * SFM_RELPOSE_5PT_MAX_SOLUTIONS. Returns 0..10. The real roots of the
 * tenth-degree polynomial are isolated by a Sturm sequence; each solution is
 * polished by Gauss-Newton on the ten original cubic constraints; when the
 * elimination is ill-conditioned a second ordering of the null basis is
 * solved too and the solution sets merged. Ground truth found (within 1e-6)
 * on > 99.9% of noise-free problems up to 100 baselines deep; beyond that
 * the problem nears the pure-rotation degeneracy (about 95% at 100 to 1000
 * baselines). Stack: under 12 KB.
 * Statuses: count, SFM_E_ARGUMENT, SFM_E_NONFINITE. */
SFM_API int sfm_relpose_5pt(const double *x1, const double *x2, sfm_mat3 *E);

/* Fundamental matrices from 7 pixel pairs (rank-2 constraint, a cubic).
 * p1, p2: (7,2). F: room for SFM_FUNDAMENTAL_7PT_MAX_SOLUTIONS. Returns 0..3.
 * Stack: under 2 KB. Statuses: count, SFM_E_ARGUMENT, SFM_E_NONFINITE. */
SFM_API int sfm_fundamental_7pt(const double *p1, const double *p2, sfm_mat3 *F);

/* Essential matrix from n >= 8 bearing pairs: least-squares solution of the
 * epipolar constraints, projected to the nearest essential matrix (singular
 * values equal, third zero). x1, x2: (n,3). Returns 0 or 1. Stack: under 2 KB
 * for n = 8, under 7 KB for n > 8 (any n: rows are streamed into a QR).
 * Statuses: count, SFM_E_ARGUMENT, SFM_E_NONFINITE, SFM_E_CAPACITY and
 * SFM_E_NO_CONVERGENCE (from the core SVD; not expected in practice). */
SFM_API int sfm_relpose_8pt(const double *x1, const double *x2, int n, sfm_mat3 *E);

/* Fundamental matrix from n >= 8 pixel pairs, Hartley-normalized least
 * squares with rank 2 enforced (smallest singular value zeroed). p1, p2:
 * (n,2). Returns 0 or 1. Stack: under 7 KB for any n.
 * Statuses: count, SFM_E_ARGUMENT, SFM_E_NONFINITE, SFM_E_CAPACITY and
 * SFM_E_NO_CONVERGENCE (from the core SVD; not expected in practice). */
SFM_API int sfm_fundamental_8pt(const double *p1, const double *p2, int n, sfm_mat3 *F);

/* Homography from exactly 4 point pairs (plane points or pixels), p2h ~ H
 * p1h, by a direct projective-basis construction. p1, p2: (4,2). Returns 0
 * (three points collinear in either image, or coincident points) or 1.
 * Stack: under 1 KB. Statuses: count, SFM_E_ARGUMENT, SFM_E_NONFINITE. */
SFM_API int sfm_homography_4pt(const double *p1, const double *p2, sfm_mat3 *H);

/* Homography from n >= 4 point pairs: Hartley-normalized DLT, least squares
 * on the algebraic error. p1, p2: (n,2). Returns 0 (rank-deficient: e.g. all
 * points collinear) or 1. Stack: under 2 KB for n = 4, under 7 KB for n > 4.
 * Statuses: count, SFM_E_ARGUMENT, SFM_E_NONFINITE, SFM_E_CAPACITY and
 * SFM_E_NO_CONVERGENCE (from the core SVD; not expected in practice). */
SFM_API int sfm_homography_dlt(const double *p1, const double *p2, int n, sfm_mat3 *H);

#ifdef __cplusplus
}
#endif
#endif
