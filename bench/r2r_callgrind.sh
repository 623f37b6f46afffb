#!/bin/sh
# Instructions per sfm_r2r_solve call of each base system (and of 12-step
# sequences with every measurement), from callgrind's total instruction
# count of two runs that differ only in the number of calls (scene
# generation and start-up cancel in the difference). Systems not built
# (SFM_E_UNSUPPORTED) still count the dispatcher's checks and reduction.
# Usage: r2r_callgrind.sh path/to/r2r_bench
set -eu
bin=$1
n1=${CALLS1:-200}
n2=${CALLS2:-600}
count() {
    valgrind --tool=callgrind --callgrind-out-file=/dev/null "$bin" "$1" "$2" 2>&1 \
        | sed -n 's/.*Collected : \([0-9]*\).*/\1/p'
}
# the two slowest solvers (milliseconds per call: the B1_D_D_D_D scan, the D6
# homotopy) take a tenth of the calls
printf '%-11s %14s   (callgrind, (Ir(%d calls) - Ir(%d calls)) / %d; b1_d_d_d_d and d6 a tenth)\n' \
    system "instr/call" "$n2" "$n1" $((n2 - n1))
for s in db1b2_d b1b2_b1 b1b2_d_d db1_db1 db1_db2 db1_b1_d db1_b2_d db1_d_d_d \
         b1_b1_b1 b1_b1_b2 b1_b1_d_d b1_b2_d_d b1_d_d_d_d d6 over12; do
    case $s in
    b1_d_d_d_d | d6) c1=$((n1 / 10)); c2=$((n2 / 10)) ;;
    *) c1=$n1; c2=$n2 ;;
    esac
    a=$(count "$s" "$c1")
    b=$(count "$s" "$c2")
    awk -v a="$a" -v b="$b" -v d=$((c2 - c1)) -v s="$s" 'BEGIN { printf "%-11s %14.0f\n", s, (b - a) / d }'
done
