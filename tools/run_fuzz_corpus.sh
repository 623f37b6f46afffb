#!/bin/sh
# Replays a saved fuzz corpus: runs each target once on each of its inputs
# (no fuzzing) and ends with "N passed, N failed" counting inputs.
# Usage: run_fuzz_corpus.sh BIN_DIR CORPUS_DIR target ...
set -u
bin=$1; corpus=$2; shift 2
pass=0; fail=0
for t in "$@"; do
    n=0; bad=0
    for f in "$corpus/$t"/*; do
        [ -f "$f" ] || continue
        n=$((n + 1))
        if ! "$bin/fuzz_$t" "$f" > /dev/null 2> "$bin/last-$t.log"; then
            bad=$((bad + 1))
            echo "FAIL fuzz_$t $f"
            tail -n 20 "$bin/last-$t.log"
        fi
    done
    if [ "$n" -eq 0 ]; then
        echo "FAIL fuzz_$t: no corpus in $corpus/$t"
        fail=$((fail + 1))
        continue
    fi
    echo "fuzz_$t: $((n - bad)) of $n inputs ok"
    pass=$((pass + n - bad)); fail=$((fail + bad))
done
echo "$pass passed, $fail failed"
[ "$fail" -eq 0 ]
