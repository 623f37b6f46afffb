/* Internal helpers shared by the trifocal files. */
#ifndef SFM_SOLVERS_TRIFOCAL_INTERNAL_H
#define SFM_SOLVERS_TRIFOCAL_INTERNAL_H

/* Scales v (n entries) to unit norm; SFM_E_SINGULAR when it is zero. */
int sfm_trifocal_normalize(double *v, int n);

#endif
