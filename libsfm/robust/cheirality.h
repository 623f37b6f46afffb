/* Internal: choose the decomposition of an essential matrix that puts the
 * most of the listed bearing pairs in front of both cameras. */
#ifndef SFM_ROBUST_CHEIRALITY_H
#define SFM_ROBUST_CHEIRALITY_H

/* 1 when the pair (b1, b2) triangulates in front of both cameras of the
 * relative pose x2 = R x1 + t (depths from the two-ray least squares). */
int sfmi_robust_in_front(const double R[9], const double t[3], const double *b1,
                        const double *b2);

/* Over idx[0..n) (all points 0..n-1 when idx is NULL). Writes R, t (|t| = 1)
 * and returns the count in front, or -1 when E has rank below 2. */
int sfmi_robust_pose_from_essential(const double E[9], const double *b1, const double *b2,
                                   const int *idx, int n, double R[9], double t[3]);

#endif
