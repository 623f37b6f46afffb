#!/bin/sh
# Instructions per sfm_trifocal_7pt call: callgrind's total instruction count
# of two runs that differ only in the number of calls, for 7 and 50 triplets.
# Usage: trifocal_callgrind.sh path/to/trifocal_callgrind
set -eu
bin=$1
n1=${CALLS1:-100}
n2=${CALLS2:-300}
count() {
    valgrind --tool=callgrind --callgrind-out-file=/dev/null "$bin" "$1" "$2" 2>&1 \
        | sed -n 's/.*Collected : \([0-9]*\).*/\1/p'
}
for n in 7 50; do
    a=$(count "$n1" "$n")
    b=$(count "$n2" "$n")
    awk -v a="$a" -v b="$b" -v d=$((n2 - n1)) -v n="$n" -v c1="$n1" -v c2="$n2" \
        'BEGIN { printf "trifocal_7pt n=%d: Ir(%d calls) %.0f, Ir(%d calls) %.0f, %.0f instr/call\n", n, c1, a, c2, b, (b - a) / d }'
done
