/*
 * Projective structure from motion by iterative factorization.
 *
 * P. Sturm and B. Triggs, "A factorization based algorithm for multi-image
 * projective structure and motion", ECCV 1996, with the iterative depth
 * update of the measurement matrix (Triggs, "Factorization methods for
 * projective structure and motion", CVPR 1996; Heyden et al.'s iteration).
 *
 * Input: m views, n tracks, pixels x[(i * n + j) * 2 + {0, 1}] for view i and
 * track j (numpy's (m, n, 2) array), NaN in either coordinate marks a missing
 * observation. Output: cameras P_i (3x4 row-major, x ~ P_i X_j, pixels) and
 * homogeneous points X_j (unit norm), defined up to one projective transform
 * of space.
 *
 * Method.
 * 1. Each view's observations are normalized (Hartley: centroid to the
 *    origin, mean distance sqrt 2).
 * 2. The complete block: a set of views and the tracks seen in all of them,
 *    chosen greedily (views are dropped one at a time while the number of
 *    observations in the block grows); at least 2 views and 8 tracks.
 * 3. On that block the measurement matrix D (3k x p, column j the stacked
 *    z_ij q_ij) is iterated from z = 1: balance (columns to unit norm and
 *    each view's row triplet to norm sqrt(p / k), three alternations), the
 *    dominant rank-4 subspace U (3k x 4) of D, then for each track the
 *    depths maximizing |U^T Q_j z|^2 subject to |Q_j z|^2 = 1, the
 *    generalized symmetric eigenproblem Q^T U U^T Q z = lambda Q^T Q z. Since
 *    Q_j^T Q_j = diag(|q_ij|^2) it becomes a standard k x k eigenproblem in
 *    w = diag(|q_ij|) z. The iteration stops when the depths or the residual
 *    settle (options.tolerance) or after options.max_iterations.
 * 4. Views outside the block are resectioned (projective DLT on the tracks
 *    already reconstructed, at least 6), tracks outside the block are
 *    triangulated (homogeneous DLT, at least 2 views), alternately until
 *    nothing changes.
 * 5. Projective bundle adjustment over every observation (Hartley &
 *    Zisserman 18.1): cameras as unit 12-vectors (11 degrees of freedom),
 *    points as unit homogeneous 4-vectors, both updated on their spheres,
 *    the points eliminated by the Schur complement, on the library's
 *    Levenberg-Marquardt driver; reprojection error in pixels.
 *
 * Convergence measured: on the synthetic scenes of tests/unit/test_factorize.c
 * (noise 0-1 px) and on Oxford Model House the relative residual
 * 1 - (sum of the 4 largest eigenvalues of D D^T) / trace(D D^T) decreased
 * at every iteration, a monotone descent; result.monotone reports whether it
 * did on the caller's data (with the balancing the descent is not
 * guaranteed in theory).
 *
 * Memory: sfm_factorize_workspace_size(m, n) bytes, any alignment.
 */
#ifndef SFM_FACTORIZE_H
#define SFM_FACTORIZE_H

#include "sfm/sfm_common.h"

#ifdef __cplusplus
extern "C" {
#endif

#define SFM_FACTORIZE_MAX_VIEWS 32
#define SFM_FACTORIZE_MAX_POINTS 100000
#define SFM_FACTORIZE_MIN_BLOCK_POINTS 8

typedef struct sfm_factorize_options {
    int max_iterations; /* >= 1, default 200 */
    double tolerance;   /* > 0, default 1e-7: stop when no entry of a unit-norm depth
                           column moves by more, or the relative rank-4 residual
                           falls by less than tolerance times itself */
    int ba_iterations;  /* >= 0, default 100: steps of the projective bundle
                           adjustment that ends the method (0: none) */
} sfm_factorize_options;

typedef struct sfm_factorize_result {
    int iterations;       /* depth updates run on the complete block */
    int converged;        /* 1 when the depths settled within tolerance */
    int monotone;         /* 1 when the relative rank-4 residual never rose */
    double first_residual; /* relative rank-4 residual of the first and last iteration */
    double last_residual;
    int block_views;      /* size of the complete block */
    int block_points;
    int points_recovered; /* tracks with a point (the others: X_j = 0, seen in < 2 views) */
    int n_observations;   /* observations of recovered tracks */
    double reproj_rms;    /* pixels, over those observations, per coordinate pair
                             sqrt(mean |x - proj|^2), after the adjustment */
    double factorization_rms; /* the same before the adjustment */
    int ba_iterations;    /* projective bundle adjustment steps tried */
    int ba_stop;          /* its stopping reason (the LM driver's: 1 gradient,
                             2 function, 3 step, 4 iterations, 5 trust region) */
} sfm_factorize_result;

/* Defaults listed above. Statuses: SFM_OK, SFM_E_ARGUMENT (NULL). */
SFM_API int sfm_factorize_default_options(sfm_factorize_options *opt);

/* Workspace bytes; 0 when m is outside 2..SFM_FACTORIZE_MAX_VIEWS or n
 * outside 8..SFM_FACTORIZE_MAX_POINTS. */
SFM_API size_t sfm_factorize_workspace_size(int m, int n);

/* Writes P (m x 12), X (n x 4) and result (may be NULL). opt may be NULL.
 * Statuses: SFM_OK; SFM_E_ARGUMENT (NULL x, P or X, counts out of range,
 * bad option); SFM_E_NONFINITE (Inf in x; NaN marks missing);
 * SFM_E_WORKSPACE; SFM_E_SINGULAR (no complete block of 2 views and 8
 * tracks, a view that cannot be resectioned, a view whose observations all
 * coincide, or a rank-deficient block); SFM_E_NO_CONVERGENCE (an
 * eigensolver failed). Nothing is written on failure. */
SFM_API int sfm_factorize_projective(int m, int n, const double *x, const sfm_factorize_options *opt,
                                     double *P, double *X, sfm_factorize_result *result, void *ws,
                                     size_t ws_size);

#ifdef __cplusplus
}
#endif
#endif
