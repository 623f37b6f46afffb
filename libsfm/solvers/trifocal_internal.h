/* Internal helpers shared by the trifocal files. */
#ifndef SFM_SOLVERS_TRIFOCAL_INTERNAL_H
#define SFM_SOLVERS_TRIFOCAL_INTERNAL_H

/* Scales v (n entries) to unit norm; SFM_E_SINGULAR when it is zero. */
int sfmi_trifocal_normalize(double *v, int n);

/* Negates v (n entries) when its largest-magnitude entry (the first of
 * them) is negative: the sign the tensors and epipoles are returned with. */
void sfmi_trifocal_fix_sign(double *v, int n);

/* Reprojection residual of x under camera P for the homogeneous point X
 * (x_proj - x, pixels), with d r / d X (2x4, may be NULL) and the factors
 * cam = (iw, u, v) (may be NULL) of d r / d P (2x12, row-major P entries)
 * = iw [X^T 0 -u X^T; 0 X^T -v X^T]: iw = 1 / (P X)_3 and (u, v) the
 * projection. 0 when X projects to infinity. */
int sfmi_trifocal_residual(const double P[12], const double X[4], const double x[2], double r[2],
                          double JX[8], double cam[3]);

/* sfm_trifocal_7pt, also giving the unit epipoles e2, e3 of T (signed as
 * sfm_trifocal_epipoles signs them): those the algebraic step held fixed, so
 * no second extraction is needed. e2, e3 are written on success only. */
int sfmi_trifocal_7pt_epipoles(const double *x1, const double *x2, const double *x3, int n,
                               double T[27], double e2[3], double e3[3], void *ws, size_t ws_size);

/* The Gram matrix A^T A (27 x 27, upper triangle; the strict lower part
 * zero) of the point equations of sfm_trifocal_7pt for the n triplets
 * x[0..2] (n x 2 each), each view's points mapped by its normalising
 * similarity first (3 x 3 at H + 9 v, sfmi_hartley_matrix). */
void sfmi_trifocal_gram(const double *const x[3], int n, const double *H, double *G);

/* The cameras P2, P3 compatible with T (P1 = [I | 0]) from its unit
 * epipoles (H&Z sec. 15.1.4), as sfm_trifocal_cameras builds them. */
void sfmi_trifocal_cameras_from(const double T[27], const double e2[3], const double e3[3],
                                double P2[12], double P3[12]);

#endif
