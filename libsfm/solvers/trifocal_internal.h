/* Internal helpers shared by the trifocal files. */
#ifndef SFM_SOLVERS_TRIFOCAL_INTERNAL_H
#define SFM_SOLVERS_TRIFOCAL_INTERNAL_H

#include <math.h>
#include <stddef.h>

#include "core/lm.h"

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

/* Its body, for the callers in the trifocal files: where the build is for
 * speed they inline it (sfmi_tf_residual; RANSAC asks for it for every
 * point of every view of every step), where it is for size they call the
 * one external copy. */
static inline int sfmi_tf_residual_impl(const double P[12], const double X[4], const double x[2],
                                        double r[2], double JX[8], double cam[3])
{
    double p[3];
    for (int k = 0; k < 3; k++)
        p[k] = P[k * 4] * X[0] + P[k * 4 + 1] * X[1] + P[k * 4 + 2] * X[2] + P[k * 4 + 3] * X[3];
    if (!(fabs(p[2]) > 1e-300))
        return 0;
    double iw = 1.0 / p[2], u = p[0] * iw, v = p[1] * iw;
    r[0] = u - x[0];
    r[1] = v - x[1];
    if (JX != NULL)
        for (int c = 0; c < 4; c++) {
            JX[c] = (P[c] - u * P[8 + c]) * iw;
            JX[4 + c] = (P[4 + c] - v * P[8 + c]) * iw;
        }
    if (cam != NULL) {
        cam[0] = iw;
        cam[1] = u;
        cam[2] = v;
    }
    return 1;
}
#if defined(__OPTIMIZE_SIZE__)
#define sfmi_tf_residual sfmi_trifocal_residual
#else
#define sfmi_tf_residual sfmi_tf_residual_impl
#endif

/* The projective cameras of the minimal problem, six point triplets
 * (trifocal_6pt.c): x1, x2, x3 pixels (n x 2 each), the triplets idx[0..6)
 * of them (idx NULL: the first six). P2[k], P3[k] with
 * P1 = [I | 0], each of unit Frobenius norm, for the k < 3 solutions
 * returned (0 for a degenerate sample: three of the first four points
 * collinear in a view, or a step without a unique answer). Every solution
 * reproduces the six triplets exactly. */
int sfmi_trifocal_6pt(const double *x1, const double *x2, const double *x3, const int *idx,
                      double P2[][12], double P3[][12]);

/* The Gram matrix A^T A (27 x 27, upper triangle; the strict lower part
 * zero) of the point equations of sfm_trifocal_7pt for the n triplets
 * x[0..2] (n x 2 each), each view's points mapped by its normalising
 * similarity first (3 x 3 at H + 9 v, sfmi_hartley_matrix). */
void sfmi_trifocal_gram(const double *const x[3], int n, const double *H, double *G);

/* The cameras P2, P3 compatible with T (P1 = [I | 0]) from its unit
 * epipoles (H&Z sec. 15.1.4), as sfm_trifocal_cameras builds them. */
void sfmi_trifocal_cameras_from(const double T[27], const double e2[3], const double e3[3],
                                double P2[12], double P3[12]);

/* sfmi_lm_sphere_basis(X, 4, B) (core/lm.h), written out for unit
 * 4-vectors where the build is for speed: the same operations in the same
 * order, so the same bits, without the generic loop's index tests (the
 * point error and the refits call it for every point of every step). */
#if defined(__OPTIMIZE_SIZE__)
#define sfmi_tf_sphere_basis4(X, B) sfmi_lm_sphere_basis((X), 4, (B))
#else
static inline void sfmi_tf_sphere_basis4(const double x[4], double B[12])
{
    int k = 0;
    double nn = 0.0;
    for (int i = 0; i < 4; i++) {
        nn += x[i] * x[i];
        if (fabs(x[i]) > fabs(x[k]))
            k = i;
    }
    double v[4] = {x[0], x[1], x[2], x[3]};
    v[k] += (x[k] >= 0.0 ? 1.0 : -1.0) * sqrt(nn);
    const double vv = v[0] * v[0] + v[1] * v[1] + v[2] * v[2] + v[3] * v[3];
    const double s = vv > 0.0 ? 2.0 / vv : 0.0;
    for (int c = 0; c < 3; c++) {
        const int j = c + (c >= k); /* the columns skip k */
        for (int r = 0; r < 4; r++)
            B[r * 3 + c] = (r == j ? 1.0 : 0.0) - s * v[r] * v[j];
    }
}
#endif

#endif
