/* Fuzz target: the replay manifest parser. Counting and parsing must agree,
 * and every accepted row must hold the invariants the replay relies on. */
#define _POSIX_C_SOURCE 200809L
#include <stdlib.h>
#include <string.h>

#include "sfm/sfm_capture.h"

int LLVMFuzzerTestOneInput(const uint8_t *data, size_t size);

/* A component of the relative name that is exactly "..". */
static int has_dotdot(const char *f)
{
    for (const char *p = f;; p++) {
        if ((p == f || p[-1] == '/') && p[0] == '.' && p[1] == '.' && (p[2] == '/' || p[2] == '\0'))
            return 1;
        if (*p == '\0')
            return 0;
    }
}

int LLVMFuzzerTestOneInput(const uint8_t *data, size_t size)
{
    const char *text = (const char *)data;
    int n = sfm_manifest_parse(text, size, NULL, 0);
    if (n < 0) {
        if (n != SFM_E_FORMAT && n != SFM_E_CAPACITY)
            abort();
        return 0;
    }
    if (n == 0)
        return 0;
    sfm_manifest_entry *e = malloc((size_t)n * sizeof *e);
    if (e == NULL)
        return 0;
    if (sfm_manifest_parse(text, size, e, n) != n)
        abort();
    for (int i = 0; i < n; i++) {
        size_t len = strnlen(e[i].file, SFM_CAPTURE_PATH_MAX);
        if (len == 0 || len >= SFM_CAPTURE_PATH_MAX || e[i].file[0] == '/' ||
            has_dotdot(e[i].file) || e[i].timestamp_ns < 0)
            abort();
        if (i > 0 && (e[i].timestamp_ns < e[i - 1].timestamp_ns || e[i].sequence <= e[i - 1].sequence))
            abort();
    }
    if (n > 1 && sfm_manifest_parse(text, size, e, n - 1) != SFM_E_CAPACITY)
        abort();
    free(e);
    return 0;
}
