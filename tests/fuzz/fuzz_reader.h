/*
 * The fuzz targets' byte reader: fixed-size values taken from the front of
 * the input; once it runs out every value is zero (so a short input is a
 * valid, mostly-zero case rather than a rejected one).
 */
#ifndef SFM_FUZZ_READER_H
#define SFM_FUZZ_READER_H

#include <stddef.h>
#include <stdint.h>
#include <string.h>

typedef struct reader {
    const uint8_t *p;
    size_t n;
} reader;

static inline unsigned take_u8(reader *r)
{
    if (r->n == 0)
        return 0;
    r->n--;
    return *r->p++;
}

#define FUZZ_TAKE(name, type)                 \
    static inline type name(reader *r)        \
    {                                         \
        type v = 0;                           \
        if (r->n >= sizeof v) {               \
            memcpy(&v, r->p, sizeof v);       \
            r->p += sizeof v;                 \
            r->n -= sizeof v;                 \
        }                                     \
        return v;                             \
    }
FUZZ_TAKE(take_f64, double)
FUZZ_TAKE(take_i32, int32_t)
#undef FUZZ_TAKE

#endif
