/*
 * Small dense linear algebra on caller storage.
 *
 * All matrices are double, row-major: A[r*cols + c]. Sizes are int and must be
 * >= 1. Vectors stored "as columns" of a row-major matrix V mean V[i*n + k] is
 * component i of vector k. No function allocates; those that need scratch
 * memory take (ws, ws_size) and report their need through *_workspace_size().
 * On any failure the outputs are left untouched (in-place factorizations say
 * when their input is modified).
 */
#ifndef SFM_LINALG_H
#define SFM_LINALG_H

#include "sfm/sfm_common.h"

#ifdef __cplusplus
extern "C" {
#endif

/* Largest dimension any routine here accepts (rows and columns). */
#define SFM_LINALG_MAX_DIM 4096

/* ---- LU with partial pivoting (n x n) ----------------------------------
 * sfm_lu_factor overwrites A with L (unit lower, below the diagonal) and U,
 * piv[i] = row swapped with row i at step i.
 * Statuses: SFM_OK, SFM_E_ARGUMENT, SFM_E_NONFINITE, SFM_E_SINGULAR (an exactly
 * zero pivot; A is then partially overwritten). */
SFM_API int sfm_lu_factor(double *A, int n, int *piv);
/* Solve A X = B with B (n x nrhs) overwritten by X.
 * Statuses: SFM_OK, SFM_E_ARGUMENT, SFM_E_NONFINITE. */
SFM_API int sfm_lu_solve(const double *LU, const int *piv, int n, double *B, int nrhs);

/* ---- Cholesky (n x n symmetric positive definite) ----------------------
 * Overwrites the lower triangle of A with L (A = L L^T) and zeroes the strict
 * upper triangle. Only the lower triangle of the input is read.
 * Statuses: SFM_OK, SFM_E_ARGUMENT, SFM_E_NONFINITE, SFM_E_SINGULAR (not
 * positive definite; A is then partially overwritten). */
SFM_API int sfm_cholesky_factor(double *A, int n);
/* Solve L L^T X = B, B (n x nrhs) overwritten. Statuses: SFM_OK, SFM_E_ARGUMENT. */
SFM_API int sfm_cholesky_solve(const double *L, int n, double *B, int nrhs);

/* ---- Householder QR (m x n, m >= n) -------------------------------------
 * Overwrites A with R (upper triangle) and the Householder vectors (below the
 * diagonal, implicit unit leading entry); tau[n] holds their scales.
 * Statuses: SFM_OK, SFM_E_ARGUMENT, SFM_E_NONFINITE. */
SFM_API int sfm_qr_factor(double *A, int m, int n, double *tau);
/* Form the full orthogonal Q (m x m) from a factorization.
 * Statuses: SFM_OK, SFM_E_ARGUMENT. */
SFM_API int sfm_qr_form_q(const double *QR, const double *tau, int m, int n, double *Q);
/* Least-squares solve min |A x - b|: b (m) is overwritten, x is b[0..n).
 * Statuses: SFM_OK, SFM_E_ARGUMENT, SFM_E_SINGULAR (zero diagonal in R). */
SFM_API int sfm_qr_solve(const double *QR, const double *tau, int m, int n, double *b);

/* ---- Singular value decomposition (any m x n) ---------------------------
 * A = U diag(S) V^T. S has min(m,n) entries, descending, >= 0.
 * U is m x m (full; may be NULL when not wanted), V is n x n (may be NULL).
 * A is not modified. One-sided Jacobi: accurate small singular values.
 * Statuses: SFM_OK, SFM_E_ARGUMENT, SFM_E_NONFINITE, SFM_E_WORKSPACE,
 * SFM_E_NO_CONVERGENCE. */
SFM_API size_t sfm_svd_workspace_size(int m, int n);
SFM_API int sfm_svd(const double *A, int m, int n, double *U, double *S, double *V,
                    void *ws, size_t ws_size);

/* ---- Symmetric eigendecomposition (n x n) -------------------------------
 * Only the lower triangle of A is read. w[n] ascending; V (n x n, may be
 * NULL) holds orthonormal eigenvectors as columns.
 * Statuses: SFM_OK, SFM_E_ARGUMENT, SFM_E_NONFINITE, SFM_E_WORKSPACE,
 * SFM_E_NO_CONVERGENCE. */
SFM_API size_t sfm_sym_eig_workspace_size(int n);
SFM_API int sfm_sym_eig(const double *A, int n, double *w, double *V, void *ws, size_t ws_size);

/* ---- Real nonsymmetric eigenproblem (n x n) -----------------------------
 * Hessenberg reduction + shifted QR. Eigenvalue k is wr[k] + i*wi[k]; complex
 * conjugate pairs are adjacent, positive imaginary part first. V (n x n, may
 * be NULL) holds eigenvectors as columns, LAPACK style: for a real eigenvalue,
 * column k is the unit-norm eigenvector; for a pair (k, k+1), columns k and
 * k+1 are the real and imaginary parts of the eigenvector of wr[k]+i*wi[k],
 * scaled so the complex vector has unit norm. Eigenvalues are ordered by
 * descending real part, then descending imaginary part.
 * Statuses: SFM_OK, SFM_E_ARGUMENT, SFM_E_NONFINITE, SFM_E_WORKSPACE,
 * SFM_E_NO_CONVERGENCE. */
SFM_API size_t sfm_eig_workspace_size(int n);
SFM_API int sfm_eig(const double *A, int n, double *wr, double *wi, double *V,
                    void *ws, size_t ws_size);

/* ---- Null space ---------------------------------------------------------
 * The k right singular vectors of A (m x n) with the smallest singular values,
 * as the columns of N (n x k), smallest first; S (k, may be NULL) receives
 * those singular values. Works for m < n too (the true null space then has
 * dimension at least n - m). 1 <= k <= n.
 * Statuses: as sfm_svd. */
SFM_API size_t sfm_nullspace_workspace_size(int m, int n);
SFM_API int sfm_nullspace(const double *A, int m, int n, int k, double *N, double *S,
                          void *ws, size_t ws_size);

#ifdef __cplusplus
}
#endif
#endif
