/* Internal helpers of the stereo module. */
#ifndef SFM_STEREO_INTERNAL_H
#define SFM_STEREO_INTERNAL_H

#include <math.h>
#include <stdint.h>
#include <string.h>

#include "core/linalg_util.h"
#include "sfm/sfm_common.h"
#include "sfm/sfm_stereo.h"

#if defined(__SSE2__)
#include <emmintrin.h>
#elif defined(__ARM_NEON)
#include <arm_neon.h>
#endif

/* Eight 16-bit lanes through the GCC/Clang vector extension: SSE2 on
 * x86-64, NEON on aarch64, scalar code elsewhere (the compiler lowers the
 * vector type). The matchers' costs are integers, so every target computes
 * the same values. Only min needs an intrinsic: the extension has none. */
typedef int16_t sfmi_v16 __attribute__((vector_size(16)));
typedef uint16_t sfmi_u16 __attribute__((vector_size(16)));

static inline sfmi_v16 sfmi_v16_min(sfmi_v16 a, sfmi_v16 b)
{
#if defined(__SSE2__)
    return (sfmi_v16)_mm_min_epi16((__m128i)a, (__m128i)b);
#elif defined(__ARM_NEON)
    return (sfmi_v16)vminq_s16((int16x8_t)a, (int16x8_t)b);
#else
    sfmi_v16 m = a < b;
    return (a & m) | (b & ~m);
#endif
}

static inline sfmi_v16 sfmi_v16_max(sfmi_v16 a, sfmi_v16 b)
{
#if defined(__SSE2__)
    return (sfmi_v16)_mm_max_epi16((__m128i)a, (__m128i)b);
#elif defined(__ARM_NEON)
    return (sfmi_v16)vmaxq_s16((int16x8_t)a, (int16x8_t)b);
#else
    sfmi_v16 m = a > b;
    return (a & m) | (b & ~m);
#endif
}

static inline sfmi_v16 sfmi_v16_load(const int16_t *p)
{
    sfmi_v16 v;
    memcpy(&v, p, sizeof v);
    return v;
}

static inline void sfmi_v16_store(int16_t *p, sfmi_v16 v)
{
    memcpy(p, &v, sizeof v);
}

static inline sfmi_v16 sfmi_v16_splat(int x)
{
    int16_t s = (int16_t)x;
    sfmi_v16 v = {s, s, s, s, s, s, s, s};
    return v;
}

/* Smallest lane. */
static inline int sfmi_v16_hmin(sfmi_v16 v)
{
#if defined(__SSE2__)
    __m128i m = (__m128i)v;
    m = _mm_min_epi16(m, _mm_srli_si128(m, 8));
    m = _mm_min_epi16(m, _mm_srli_si128(m, 4));
    m = _mm_min_epi16(m, _mm_srli_si128(m, 2));
    return (int16_t)_mm_cvtsi128_si32(m);
#elif defined(__ARM_NEON) && defined(__aarch64__)
    return vminvq_s16((int16x8_t)v);
#else
    int16_t a[8];
    memcpy(a, &v, sizeof a);
    int m = a[0];
    for (int i = 1; i < 8; i++)
        if (a[i] < m)
            m = a[i];
    return m;
#endif
}

/* Smallest lane, in every lane. */
static inline sfmi_v16 sfmi_v16_hmin_all(sfmi_v16 v)
{
#if defined(__SSE2__)
    __m128i m = (__m128i)v;
    m = _mm_min_epi16(m, _mm_shuffle_epi32(m, 0x4e));
    m = _mm_min_epi16(m, _mm_shuffle_epi32(m, 0xb1));
    m = _mm_min_epi16(m, _mm_shufflehi_epi16(_mm_shufflelo_epi16(m, 0xb1), 0xb1));
    return (sfmi_v16)m;
#elif defined(__ARM_NEON) && defined(__aarch64__)
    return (sfmi_v16)vdupq_n_s16(vminvq_s16((int16x8_t)v));
#else
    return sfmi_v16_splat(sfmi_v16_hmin(v));
#endif
}

/* Bit counts of eight 16-bit lanes (SWAR). */
static inline sfmi_v16 sfmi_v16_popcount(sfmi_v16 v)
{
    sfmi_u16 x = (sfmi_u16)v;
    x = x - ((x >> 1) & 0x5555);
    x = (x & 0x3333) + ((x >> 2) & 0x3333);
    x = (x + (x >> 4)) & 0x0f0f;
    x = (x + (x >> 8)) & 0x1f;
    return (sfmi_v16)x;
}

/* Bit counts of a + b for two 16-bit lanes' worth of bits per lane (one
 * 32-bit census split in halves): the halves are merged after the 2-bit
 * step, when every nibble holds at most 8. */
static inline sfmi_v16 sfmi_v16_popcount2(sfmi_v16 a, sfmi_v16 b)
{
    sfmi_u16 x = (sfmi_u16)a, y = (sfmi_u16)b;
    x = x - ((x >> 1) & 0x5555);
    y = y - ((y >> 1) & 0x5555);
    x = (x & 0x3333) + ((x >> 2) & 0x3333) + (y & 0x3333) + ((y >> 2) & 0x3333);
    x = (x & 0x0f0f) + ((x >> 4) & 0x0f0f); /* bytes up to 16: no carry */
    x = (x + (x >> 8)) & 0x3f;
    return (sfmi_v16)x;
}

/* Inverse of a 3x3; SFM_E_SINGULAR when the determinant is not above
 * 1e-14 of the product of the row norms. */
static inline int sfmi_stereo_inv3(const double *A, double *Ai)
{
    double n0 = sqrt(A[0] * A[0] + A[1] * A[1] + A[2] * A[2]);
    double n1 = sqrt(A[3] * A[3] + A[4] * A[4] + A[5] * A[5]);
    double n2 = sqrt(A[6] * A[6] + A[7] * A[7] + A[8] * A[8]);
    return sfmi_mat3_inverse(A, Ai, 1e-14 * n0 * n1 * n2) ? SFM_OK : SFM_E_SINGULAR;
}

/* Image size and disparity range the matchers accept: the range (of either
 * sign) fits in the image. */
static inline int sfmi_stereo_range_ok(int width, int height, int dmin, int D)
{
    if (width < 16 || height < 16 || width > SFM_STEREO_MAX_WIDTH || height > 32767)
        return 0;
    if (D < 8 || D > SFM_STEREO_MAX_DISPARITIES || D % 8 != 0)
        return 0;
    return dmin > -width && dmin < width && D + (dmin > 0 ? dmin : -dmin) <= width;
}

#endif
