/* The one external copy of each helper of linalg_util.h, which the files built
 * for size call (core/inline.h; C11 6.7.4: the header's inline definitions,
 * this file's extern declarations). */
#define SFMI_INLINE_EXTERN
#include "core/linalg_util.h"

extern inline int sfmi_la_dim_ok(int n);
extern inline int sfmi_la_all_finite(const double *a, size_t n);
extern inline int sfmi_la_is_rotation(const double *R, double tol);
extern inline double sfmi_la_max_abs(const double *a, size_t n);
extern inline double sfmi_la_pow2_scale(double maxabs);
extern inline double sfmi_la_jacobi_angle(double zeta, double *c, double *s);
extern inline void sfmi_la_rotate(double *x, double *y, int n, size_t inc, double c, double s);
extern inline int sfmi_mat3_inverse(const double *A, double *Ai, double min_abs_det);
extern inline int sfmi_chol3(const double *A, double *L);
