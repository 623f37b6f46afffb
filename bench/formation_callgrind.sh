#!/bin/sh
# Instructions per call of sfm_r2r_motion_next and of the grid search beside
# it, under callgrind: two runs with different call counts over the same
# fixed states, so the set-up cancels: (I(K2) - I(K1)) / (K2 - K1).
# Usage: formation_callgrind.sh path/to/formation_bench
set -eu
bin=$1
count() {
    valgrind --tool=callgrind --callgrind-out-file=/dev/null "$bin" --calls "$@" 2>&1 \
        | sed -n 's/.*Collected : \([0-9]*\).*/\1/p'
}
printf '%-8s %-16s %14s %8s\n' sensor method instr/call ratio
for s in range bearing; do
    a=$(count 1000 "$s"); b=$(count 3000 "$s")
    kkt=$(awk -v a="$a" -v b="$b" 'BEGIN { printf "%.0f", (b - a) / 2000 }')
    printf '%-8s %-16s %14s %8s\n' "$s" KKT "$kkt" 1
    for g in "21 72" "51 360"; do
        set -- $g
        a=$(count 20 "$s" "$1" "$2"); b=$(count 60 "$s" "$1" "$2")
        awk -v a="$a" -v b="$b" -v k="$kkt" -v s="$s" -v m="grid $1x$2" \
            'BEGIN { i = (b - a) / 40; printf "%-8s %-16s %14.0f %8.0f\n", s, m, i, i / k }'
    done
done
