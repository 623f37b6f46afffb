#!/bin/sh
# Instructions per call of each pose solver under callgrind: two runs with
# different call counts, so the set-up (problem generation, start-up) cancels:
# (I(N2) - I(N1)) / (N2 - N1).
# Usage: pose_callgrind.sh path/to/pose_bench
set -eu
bin=$1
N1=${N1:-2000}
N2=${N2:-4000}
count() {
    valgrind --tool=callgrind --callgrind-out-file=/dev/null "$bin" --calls "$1" "$2" 2>&1 \
        | sed -n 's/.*Collected : \([0-9]*\).*/\1/p'
}
printf '%-14s %14s\n' solver instr/call
for s in p3p upright3pt essential tri_dlt tri_midpoint tri_optimal; do
    a=$(count "$N1" "$s")
    b=$(count "$N2" "$s")
    awk -v a="$a" -v b="$b" -v n1="$N1" -v n2="$N2" -v s="$s" \
        'BEGIN { printf "%-14s %14.0f\n", s, (b - a) / (n2 - n1) }'
done
