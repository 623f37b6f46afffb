/* The one external copy of each helper of small_math.h, which the files built
 * for size call (core/inline.h; C11 6.7.4: the header's inline definitions,
 * this file's extern declarations). */
#define SFMI_INLINE_EXTERN
#include "solvers/small_math.h"

extern inline int sfmi_all_finite3(const double *v);
extern inline int sfmi_all_finite9(const double *v);
extern inline void sfmi_cross3(const double *a, const double *b, double *c);
extern inline double sfmi_dot3(const double *a, const double *b);
extern inline void sfmi_matvec3(const double *M, const double *x, double *y);
extern inline void sfmi_matvec3_t(const double *M, const double *x, double *y);
extern inline void sfmi_matmul3(const double *A, const double *B, double *C);
extern inline void sfmi_matmul3_tn(const double *A, const double *B, double *C);
extern inline void sfmi_matmul3_nt(const double *A, const double *B, double *C);
extern inline double sfmi_rank2_null3(const double *r0, const double *r1, const double *r2,
                                      double rel, double n[3]);
extern inline double sfmi_cubic_largest_root(double b, double c, double d);
