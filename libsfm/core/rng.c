/* xoshiro256** 1.0 (Blackman & Vigna, 2018), seeded by splitmix64. */
#include "sfm/sfm_rng.h"

#include <math.h>
#include "core/dmath.h"

static uint64_t splitmix64(uint64_t *x)
{
    uint64_t z = (*x += 0x9e3779b97f4a7c15ULL);
    z = (z ^ (z >> 30)) * 0xbf58476d1ce4e5b9ULL;
    z = (z ^ (z >> 27)) * 0x94d049bb133111ebULL;
    return z ^ (z >> 31);
}

static uint64_t rotl(uint64_t x, int k)
{
    return (x << k) | (x >> (64 - k));
}

int sfm_rng_seed(sfm_rng *rng, uint64_t seed)
{
    if (rng == NULL)
        return SFM_E_ARGUMENT;
    uint64_t x = seed;
    for (int i = 0; i < 4; i++)
        rng->s[i] = splitmix64(&x);
    return SFM_OK;
}

uint64_t sfm_rng_next(sfm_rng *rng)
{
    uint64_t *s = rng->s;
    uint64_t result = rotl(s[1] * 5, 7) * 9;
    uint64_t t = s[1] << 17;
    s[2] ^= s[0];
    s[3] ^= s[1];
    s[1] ^= s[2];
    s[0] ^= s[3];
    s[2] ^= t;
    s[3] = rotl(s[3], 45);
    return result;
}

uint32_t sfm_rng_bounded(sfm_rng *rng, uint32_t n)
{
    if (n == 0)
        return 0;
    /* Lemire, "Fast random integer generation in an interval", 2019. */
    uint64_t m = (uint64_t)(uint32_t)(sfm_rng_next(rng) >> 32) * n;
    uint32_t low = (uint32_t)m;
    if (low < n) {
        uint32_t threshold = (uint32_t)(-n) % n;
        while (low < threshold) {
            m = (uint64_t)(uint32_t)(sfm_rng_next(rng) >> 32) * n;
            low = (uint32_t)m;
        }
    }
    return (uint32_t)(m >> 32);
}

double sfm_rng_uniform(sfm_rng *rng)
{
    return (double)(sfm_rng_next(rng) >> 11) * 0x1.0p-53;
}

double sfm_rng_normal(sfm_rng *rng)
{
    double u, v, s;
    do {
        u = 2.0 * sfm_rng_uniform(rng) - 1.0;
        v = 2.0 * sfm_rng_uniform(rng) - 1.0;
        s = u * u + v * v;
    } while (s >= 1.0 || s == 0.0);
    return u * sqrt(-2.0 * sfmi_log(s) / s);
}
