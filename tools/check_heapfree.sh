#!/bin/sh
# Fails when any object of the given archives references an allocator.
# Usage: check_heapfree.sh [NM=tool] lib.a ...
set -eu
NM=${NM:-nm}
status=0
for lib in "$@"; do
    bad=$($NM -u "$lib" 2>/dev/null | grep -E '^\s*U (malloc|calloc|realloc|free|aligned_alloc|posix_memalign|strdup|_Znwm|_Znam)$' || true)
    if [ -n "$bad" ]; then
        echo "heap-free check FAILED for $lib: references"
        echo "$bad"
        status=1
    else
        echo "heap-free check ok: $lib references no allocator"
    fi
done
if [ $status -eq 0 ]; then echo "1 passed, 0 failed"; else echo "0 passed, 1 failed"; fi
exit $status
