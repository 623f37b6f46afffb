/* Internal: 256-bit Hamming distance with a portable popcount. */
#ifndef SFM_FEATURES_HAMMING_H
#define SFM_FEATURES_HAMMING_H

#include <stdint.h>
#include <string.h>

/* Sum of the set bits of four 64-bit words (SWAR, "Hacker's Delight" 5-1:
 * 2-bit then 4-bit partial sums per word; two words' nibble sums still fit
 * a nibble, so the fold to bytes runs once per pair of words and the byte
 * sum once per descriptor). With a hardware popcount the builtin is used. */
static inline int sfmi_feat_popcount256(uint64_t a, uint64_t b, uint64_t c, uint64_t d)
{
#if defined(__POPCNT__) && defined(__GNUC__)
    return __builtin_popcountll(a) + __builtin_popcountll(b) + __builtin_popcountll(c) +
           __builtin_popcountll(d);
#else
    const uint64_t m1 = 0x5555555555555555ULL, m2 = 0x3333333333333333ULL, m4 = 0x0F0F0F0F0F0F0F0FULL;
    a -= (a >> 1) & m1;
    b -= (b >> 1) & m1;
    c -= (c >> 1) & m1;
    d -= (d >> 1) & m1;
    a = (a & m2) + ((a >> 2) & m2);
    b = (b & m2) + ((b >> 2) & m2);
    c = (c & m2) + ((c >> 2) & m2);
    d = (d & m2) + ((d >> 2) & m2);
    uint64_t s = a + b, t = c + d; /* nibbles <= 8 */
    s = (s & m4) + ((s >> 4) & m4);
    t = (t & m4) + ((t >> 4) & m4);
    s += t; /* bytes <= 32 */
    return (int)((s * 0x0101010101010101ULL) >> 56);
#endif
}

static inline uint64_t sfmi_feat_load64(const uint8_t *p)
{
    uint64_t v;
    memcpy(&v, p, 8);
    return v;
}

static inline int sfmi_feat_hamming256(const uint8_t *x, const uint8_t *y)
{
    return sfmi_feat_popcount256(sfmi_feat_load64(x) ^ sfmi_feat_load64(y),
                                sfmi_feat_load64(x + 8) ^ sfmi_feat_load64(y + 8),
                                sfmi_feat_load64(x + 16) ^ sfmi_feat_load64(y + 16),
                                sfmi_feat_load64(x + 24) ^ sfmi_feat_load64(y + 24));
}

#endif
