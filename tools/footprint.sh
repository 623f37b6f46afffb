#!/bin/sh
# The Cortex-M7 footprint as `make firmware` prints it: flash (text) and RAM
# (data + bss) of the core's objects per module, from arm-none-eabi-size on
# DIR/obj/libsfm/<module>/*.o, the budgeted core, then the relative-pose
# example's image.
#   sh tools/footprint.sh BUILD/cortex-m7 "core solvers ..."
#   sh tools/footprint.sh --budget BUILD/cortex-m7    the budgeted objects, one a line
#
# The budget of 128 KB of flash (issue 13) holds the whole core as it was when
# the budget was set: every module the library had then (core, solvers,
# robust, refine, features, and recon, which held only the calibrated
# three-view pose), with whatever has been split out of them since. What came
# later is built for the M7 too, so that it is proven portable, and printed,
# not bounded (a program links only what it calls): the robot-to-robot code
# (r2r_*, in solvers/ and refine/), recon's uncalibrated pipelines, stereo
# and vo, and the files of UNBUDGETED (later additions to a budgeted module:
# features/align, the photometric alignment of correspondences for the
# uncalibrated images path; solvers/trifocal_6pt, the minimal six-point
# solver the trifocal RANSAC samples with since it replaced the 7-point
# linear solution there, about 3 KB built for size, which a program that
# calls the trifocal RANSAC links on top of the budget). An entry is a module (every object in it but
# r2r_* and UNBUDGETED) or one file.
set -eu
BUDGET="core solvers robust refine features recon/three_view_pose"
UNBUDGETED="features/align solvers/trifocal_6pt"
budget_objs() {
    for e in $BUDGET; do
        if [ -d "$1/obj/libsfm/$e" ]; then
            find "$1/obj/libsfm/$e" -name '*.o' ! -name 'r2r_*'
        else
            echo "$1/obj/libsfm/$e.o"
        fi
    done | sort | grep -v -x -F $(for u in $UNBUDGETED; do printf -- '-e %s ' "$1/obj/libsfm/$u.o"; done)
}
if [ "${1:-}" = --budget ]; then
    budget_objs "$2"
    exit 0
fi
dir=$1
modules=$2
SIZE=${SIZE:-arm-none-eabi-size}
# 137396 -> 137,396
C='function c(n,  s) { s = sprintf("%d", n); while (s ~ /[0-9][0-9][0-9][0-9]/) sub(/[0-9][0-9][0-9]($|,)/, ",&", s); return s }'
echo "| module | flash (text) | RAM (data + bss) |"
echo "|---|---|---|"
for m in $modules; do
    objs=$(find "$dir/obj/libsfm/$m" -name '*.o' 2>/dev/null | sort)
    [ -n "$objs" ] || continue
    $SIZE -t $objs | tail -n 1 | awk -v m="$m" "$C"' {printf "| %s | %s B | %s B |\n", m, c($1), c($2 + $3)}'
done
find "$dir/obj/libsfm" -name '*.o' | sort | xargs $SIZE -t | tail -n 1 | \
    awk "$C"' {printf "| all | %s B | %s B |\n", c($1), c($2 + $3)}'
budget_objs "$dir" | xargs $SIZE -t | tail -n 1 | \
    awk -v b="$BUDGET" "$C"' {printf "| budgeted core (%s, no r2r_*) | %s B | %s B |\n", b, c($1), c($2 + $3)}'
elf=$dir/examples/relpose_demo.elf
if [ -f "$elf" ]; then
    $SIZE "$elf" | tail -n 1 | awk "$C"' {printf "relpose_demo.elf: flash %s B (text %s + data %s), static RAM %s B (data %s + bss %s)\n", c($1 + $2), c($1), c($2), c($2 + $3), c($2), c($3)}'
fi
