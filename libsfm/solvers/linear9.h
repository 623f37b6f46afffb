/*
 * Internal: null spaces of linear systems in 9 unknowns (the entries of a 3x3
 * matrix), shared by the epipolar and homography solvers.
 */
#ifndef SFM_SOLVERS_LINEAR9_H
#define SFM_SOLVERS_LINEAR9_H

/* Orthonormal basis of the null space of A (m x 9, row-major, 1 <= m <= 8):
 * 9 - m vectors written as the rows of N ((9-m) x 9). Householder QR of A^T;
 * exact for an exactly rank-m A. A is overwritten. Returns 0, or -1 when A
 * is rank-deficient to 1e-12 relative (the null space is then larger).
 * Stack: a few hundred bytes. */
int sfmi_null9_exact(double *A, int m, double *N);

/* Streaming least squares min |A h|, |h| = 1 for A with rows fed one at a
 * time: R is the 9x9 upper triangle of a Givens QR of the rows so far. */
typedef struct sfmi_ls9 {
    double R[81];
    int rows;
} sfmi_ls9;

void sfmi_ls9_init(sfmi_ls9 *ls);
void sfmi_ls9_add_row(sfmi_ls9 *ls, const double row[9]);
/* Unit h minimizing |A h| (the right singular vector of the smallest
 * singular value). Returns 0, -1 when the minimizer is not unique (the
 * second smallest singular value below 1e-10 of the largest) or the rows
 * are fewer than 8, or a negative sfm_status from the core SVD.
 * Stack: under 4 KB. */
int sfmi_ls9_solve(sfmi_ls9 *ls, double h[9]);



/* SVD of a 3x3 matrix through the core: M = U diag(S) V^T, S descending.
 * Returns 0 or a negative sfm_status. Stack: under 1 KB. */
int sfmi_svd3(const double M[9], double U[9], double S[3], double V[9]);
#endif
