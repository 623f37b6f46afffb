/*
 * Internal: how the small helpers of the internal headers (core/linalg_util.h,
 * solvers/small_math.h, solvers/normalize.h, robust/estimator.h) are defined.
 *
 * Where a file is built for speed they are static inline: every object has
 * its own copy, inlined into its loops. Where it is built for size (-Os,
 * which defines __OPTIMIZE_SIZE__: the cold code of the Cortex-M7 build) the
 * compiler keeps most of them out of line, and one static copy per calling
 * object came to 3.5 KB of flash. There they are C11 inline definitions
 * (6.7.4) instead, and every caller shares one external copy, emitted by
 * the file that defines SFMI_INLINE_EXTERN before its includes
 * (core/linalg_util.c, solvers/small_math.c, solvers/normalize.c,
 * robust/estimator.c). The operations are the same either way, so are the
 * results.
 */
#ifndef SFM_CORE_INLINE_H
#define SFM_CORE_INLINE_H

#if defined(__OPTIMIZE_SIZE__) || defined(SFMI_INLINE_EXTERN)
#define SFMI_INLINE inline
#else
#define SFMI_INLINE static inline
#endif

#endif
