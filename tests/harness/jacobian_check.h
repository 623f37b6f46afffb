/*
 * verify_jacobian for the refiners (after PoseLib's test helper of that
 * name): an analytic Jacobian against central differences taken in the
 * tangent space the refiner updates in.
 */
#ifndef SFM_TEST_JACOBIAN_CHECK_H
#define SFM_TEST_JACOBIAN_CHECK_H

#include "core/lm.h"

/* f(user, delta, r): the m residuals at the base point moved by the
 * tangent step delta (n entries); returns non-zero when defined there. */
typedef int (*sfm_test_residual_fn)(const void *user, const double *delta, double *r);

/* Worst column error max_j max_i |J_ij - D_ij| / (1 + max_i |D_ij|), D the
 * central differences of f with step h (J is m x n row-major, n <= 64,
 * m <= 16); INFINITY when f fails at a probe. */
double sfm_test_verify_jacobian(sfm_test_residual_fn f, const void *user, int n, int m,
                                const double *J, double h);

/* The same for residual block i of an LM driver problem: its analytic
 * Jacobian at the blocks' values against central differences through the
 * blocks' manifolds (sfmi_lm_block_plus). */
double sfm_test_verify_lm_residual(const sfmi_lm_problem *prob, int i, double h);

#endif
