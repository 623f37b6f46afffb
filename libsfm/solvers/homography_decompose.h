/* Internal: the two poses of a plane-induced homography. */
#ifndef SFM_SOLVERS_HOMOGRAPHY_DECOMPOSE_H
#define SFM_SOLVERS_HOMOGRAPHY_DECOMPOSE_H

/*
 * H (row-major) maps normalised points of image 1 to image 2, x2 ~ H x1, for
 * points X1 on a plane n^T X1 = d (d > 0) seen by cameras X2 = R X1 + t.
 * p1, p2 (m >= 1 pairs, z = 1 coordinates) are points on the plane: they fix
 * the sign of H (positive depths in both views) and the side of the plane
 * (n^T x1 > 0). Writes the physically valid decompositions (R, unit t) to
 * R[0..k), t[0..k) and returns k: 2 in general, 0 when H is a rotation
 * (no translation to recover) or not finite. Stack only, about 0.5 KB.
 */
int sfmi_homography_decompose(const double H[9], const double *p1, const double *p2, int m,
                              double R[2][9], double t[2][3]);

#endif
