#!/bin/sh
# Instructions per call of each solver, from callgrind's total instruction
# count of two runs that differ only in the number of calls (problem
# generation and start-up cancel in the difference).
# Usage: callgrind_solvers.sh path/to/solvers_bench
set -eu
bin=$1
n1=${CALLS1:-1000}
n2=${CALLS2:-3000}
count() {
    valgrind --tool=callgrind --callgrind-out-file=/dev/null "$bin" "$1" "$2" 2>&1 \
        | sed -n 's/.*Collected : \([0-9]*\).*/\1/p'
}
printf '%-8s %14s   (callgrind, (Ir(%d calls) - Ir(%d calls)) / %d)\n' solver "instr/call" "$n2" "$n1" $((n2 - n1))
for s in 5pt 7pt 8pt f8pt h4pt hdlt; do
    a=$(count "$s" "$n1")
    b=$(count "$s" "$n2")
    awk -v a="$a" -v b="$b" -v d=$((n2 - n1)) -v s="$s" 'BEGIN { printf "%-8s %14.0f\n", s, (b - a) / d }'
done
