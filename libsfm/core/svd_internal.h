/* Internal: the SVD after argument checks, shared with the null-space code. */
#ifndef SFM_CORE_SVD_INTERNAL_H
#define SFM_CORE_SVD_INTERNAL_H

#include <stddef.h>

/* As sfm_svd, arguments already checked (A finite, sizes valid). S is written
 * only on success, as are U and V. */
int sfmi_svd_core(const double *A, int m, int n, double *U, double *S, double *V, void *ws,
                 size_t ws_size);

#endif
