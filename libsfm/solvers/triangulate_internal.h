/* Shared pieces of the triangulation methods (libsfm/refine). */
#ifndef SFM_SOLVERS_TRIANGULATE_INTERNAL_H
#define SFM_SOLVERS_TRIANGULATE_INTERNAL_H

#include "sfm/sfm_common.h"

/* Streaming least squares for the homogeneous 4-vector of one point: rows
 * are folded by Givens rotations into a 4x4 upper-triangular factor. */
typedef struct sfmi_tri_acc {
    double R[16];
} sfmi_tri_acc;

void sfmi_tri_acc_init(sfmi_tri_acc *acc);
/* Adds the row a (4 entries; scaled to unit norm here, a zero row is ignored). */
void sfmi_tri_acc_add(sfmi_tri_acc *acc, const double a[4]);
/* Adds the two DLT rows of observation (u, v) of camera P. */
void sfmi_tri_acc_add_obs(sfmi_tri_acc *acc, const double P[12], double u, double v);
/* Homogeneous solution (unit norm) from the smallest right singular vector.
 * Returns SFM_OK or SFM_E_NO_CONVERGENCE. */
int sfmi_tri_acc_solve(const sfmi_tri_acc *acc, double Xh[4]);

/* Writes X and returns the flags for a homogeneous point Xh seen by nviews
 * cameras P (nviews x 12), from its signed depths. */
int sfmi_tri_finish_h(const double Xh[4], int nviews, const double *P, double X[3]);

#endif
