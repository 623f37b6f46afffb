#include "core/arena.h"

#include <stdint.h>

#include "sfm/sfm_common.h"

static size_t round_up(size_t n)
{
    return (n + (SFM_WS_ALIGN - 1)) & ~(size_t)(SFM_WS_ALIGN - 1);
}

void sfmi_arena_measure(sfmi_arena *a)
{
    a->base = NULL;
    a->cap = SIZE_MAX;
    a->used = 0;
    a->failed = 0;
}

void sfmi_arena_init(sfmi_arena *a, void *buf, size_t size)
{
    uintptr_t p = (uintptr_t)buf;
    size_t pad = (size_t)((SFM_WS_ALIGN - (p & (SFM_WS_ALIGN - 1))) & (SFM_WS_ALIGN - 1));
    a->used = 0;
    a->failed = 0;
    /* The full alignment slack is reserved whatever the pointer's actual
     * alignment, so the size a measuring arena reports is exactly the
     * smallest that works: one byte less fails on every buffer. */
    if (buf == NULL || size < SFM_WS_ALIGN - 1) {
        a->base = NULL;
        a->cap = 0;
        a->failed = 1;
        return;
    }
    a->base = (unsigned char *)buf + pad;
    a->cap = size - (SFM_WS_ALIGN - 1);
}

void *sfmi_arena_alloc(sfmi_arena *a, size_t bytes)
{
    size_t n = round_up(bytes);
    if (n < bytes || a->failed) {
        a->failed = 1;
        return NULL;
    }
    if (a->base == NULL) { /* measuring */
        if (a->used > SIZE_MAX - n) {
            a->failed = 1;
            return NULL;
        }
        a->used += n;
        return NULL;
    }
    if (n > a->cap - a->used) {
        a->failed = 1;
        return NULL;
    }
    void *p = a->base + a->used;
    a->used += n;
    return p;
}

size_t sfmi_arena_required(const sfmi_arena *a)
{
    if (a->failed)
        return 0;
    return a->used + (SFM_WS_ALIGN - 1);
}

int sfmi_arena_ok(const sfmi_arena *a)
{
    return a->base != NULL && !a->failed;
}
