/*
 * Deterministic random numbers: xoshiro256** seeded through splitmix64.
 * The state lives in the caller's memory; there is no global generator. The
 * same seed gives the same sequence on every platform.
 */
#ifndef SFM_RNG_H
#define SFM_RNG_H

#include "sfm/sfm_common.h"

#ifdef __cplusplus
extern "C" {
#endif

typedef struct sfm_rng { uint64_t s[4]; } sfm_rng;

/* Default seed used when a caller does not choose one. */
#define SFM_RNG_DEFAULT_SEED 0x5f3759df2024ULL

/* Statuses: SFM_OK, SFM_E_ARGUMENT (rng NULL). */
SFM_API int sfm_rng_seed(sfm_rng *rng, uint64_t seed);
/* Next raw 64-bit output. rng must be non-NULL (hot path; not checked). */
SFM_API uint64_t sfm_rng_next(sfm_rng *rng);
/* Uniform integer in [0, n) by rejection (Lemire), no modulo bias; 0 when n == 0. */
SFM_API uint32_t sfm_rng_bounded(sfm_rng *rng, uint32_t n);
/* Uniform double in [0, 1) with 53 random bits. */
SFM_API double sfm_rng_uniform(sfm_rng *rng);
/* Standard normal deviate (Marsaglia polar method). */
SFM_API double sfm_rng_normal(sfm_rng *rng);

#ifdef __cplusplus
}
#endif
#endif
