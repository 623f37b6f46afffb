#!/bin/sh
# Instruction counts (valgrind callgrind, repeatable on a loaded machine) of
# one libsfm solve and one Ceres Solve() per benchmark size.
# Usage: sh bench/ba_callgrind.sh [build/bench/ba_bench]
set -eu
BIN=${1:-build/bench/ba_bench}
tmp=$(mktemp -d)
printf '%-8s %14s %14s %7s\n' size libsfm_Ir ceres_Ir ratio
i=0
for size in 3x200 5x500 10x2000; do
    valgrind --tool=callgrind --callgrind-out-file="$tmp/s" --toggle-collect=sfm_ba_solve "$BIN" once $i >/dev/null 2>"$tmp/s.err"
    valgrind --tool=callgrind --callgrind-out-file="$tmp/c" '--toggle-collect=ceres::Solve(*' "$BIN" once $i >/dev/null 2>"$tmp/c.err"
    s=$(sed -n 's/.*Collected : \([0-9]*\).*/\1/p' "$tmp/s.err")
    c=$(sed -n 's/.*Collected : \([0-9]*\).*/\1/p' "$tmp/c.err")
    printf "%-8s %14s %14s %6.2fx\n" "$size" "$s" "$c" "$(awk "BEGIN { print $c / $s }")"
    i=$((i + 1))
done
rm -rf "$tmp"
