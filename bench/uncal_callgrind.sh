#!/bin/sh
# Instructions of sfm_recon_three_view_uncalibrated per triplet (default
# options, seed 1), from callgrind: one dump after each call, collection only
# inside it. Usage: uncal_callgrind.sh path/to/uncal_bench DIR LINES
# (LINES: the index's data lines, comma-separated, e.g. 1,10,20,30,40,50).
set -eu
bin=$1
dir=$2
lines=$3
out=$(mktemp -d)
valgrind --tool=callgrind --toggle-collect=sfm_recon_three_view_uncalibrated \
    --dump-after=sfm_recon_three_view_uncalibrated --callgrind-out-file="$out/cg.%p" \
    "$bin" "$dir" "$lines" > "$out/stdout" 2> "$out/stderr"
i=0
for f in $(ls "$out"/cg.* | awk -F. '{print $NF, $0}' | sort -n | cut -d" " -f2); do
    ir=$(sed -n 's/^summary: \([0-9]*\).*/\1/p' "$f")
    [ -n "$ir" ] && [ "$ir" -gt 0 ] || continue
    i=$((i + 1))
    echo "$(sed -n "${i}p" "$out/stdout")  Ir $ir"
done
awk '/^summary:/ { s += $2 } END { printf "total Ir %.0f\n", s }' "$out"/cg.*
rm -rf "$out"
