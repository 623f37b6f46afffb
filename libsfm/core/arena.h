/*
 * Internal: a bump allocator that carves one caller buffer.
 *
 * The same layout code runs twice: once on a measuring arena (buffer NULL) to
 * compute a workspace size, once on the caller's buffer. Because both runs use
 * identical offsets from a 16-byte aligned base, the size reported and the
 * carving done cannot drift apart. Failure is sticky: carve everything, then
 * check sfmi_arena_ok() once.
 */
#ifndef SFM_CORE_ARENA_H
#define SFM_CORE_ARENA_H

#include <stddef.h>

typedef struct sfmi_arena {
    unsigned char *base; /* aligned start, NULL when measuring */
    size_t cap;          /* usable bytes after alignment */
    size_t used;
    int failed;
} sfmi_arena;

/* Measuring mode: sfmi_arena_alloc returns NULL and only counts. */
void sfmi_arena_measure(sfmi_arena *a);
/* Carving mode over buf[0..size); buf may be unaligned. */
void sfmi_arena_init(sfmi_arena *a, void *buf, size_t size);
/* bytes rounded up to SFM_WS_ALIGN; NULL when measuring or out of room. */
void *sfmi_arena_alloc(sfmi_arena *a, size_t bytes);
/* Total workspace bytes a measured layout needs, alignment slack included. */
size_t sfmi_arena_required(const sfmi_arena *a);
/* 1 when carving succeeded (always 0 for a measuring arena). */
int sfmi_arena_ok(const sfmi_arena *a);

#define SFM_ARENA_ARRAY(a, type, n) ((type *)sfmi_arena_alloc((a), sizeof(type) * (size_t)(n)))

#endif
