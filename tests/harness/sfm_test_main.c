/* Test runner: runs every registered test (or those whose name contains the
 * first argument) and ends with the line "N passed, N failed". */
#include <stdint.h>
#include <string.h>

#include "sfm_test.h"

typedef struct sfm_test_entry {
    const char *name;
    sfm_test_fn fn;
} sfm_test_entry;

extern const sfm_test_entry sfm_test_registry[];
extern const int sfm_test_registry_count;

static uint64_t fnv1a(const char *s)
{
    uint64_t h = 0xcbf29ce484222325ULL;
    for (; *s; s++) {
        h ^= (unsigned char)*s;
        h *= 0x100000001b3ULL;
    }
    return h;
}

int main(int argc, char **argv)
{
    const char *filter = argc > 1 ? argv[1] : NULL;
    int passed = 0, failed = 0;
    for (int i = 0; i < sfm_test_registry_count; i++) {
        const sfm_test_entry *e = &sfm_test_registry[i];
        if (filter && strstr(e->name, filter) == NULL)
            continue;
        sfm_test_ctx t;
        t.name = e->name;
        t.failures = 0;
        sfm_rng_seed(&t.rng, fnv1a(e->name));
        e->fn(&t);
        if (t.failures == 0) {
            passed++;
            printf("ok   %s\n", e->name);
        } else {
            failed++;
            printf("FAIL %s (%d checks)\n", e->name, t.failures);
        }
        fflush(stdout);
    }
    printf("%d passed, %d failed\n", passed, failed);
    fflush(stdout);
    return failed == 0 ? 0 : 1;
}
