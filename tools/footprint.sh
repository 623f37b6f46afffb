#!/bin/sh
# The Cortex-M7 footprint as `make firmware` prints it: flash (text) and RAM
# (data + bss) of the core's objects per module, from arm-none-eabi-size on
# DIR/obj/libsfm/<module>/*.o, then the relative-pose example's image.
#   sh tools/footprint.sh BUILD/cortex-m7 "core solvers ..."
set -eu
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
elf=$dir/examples/relpose_demo.elf
if [ -f "$elf" ]; then
    $SIZE "$elf" | tail -n 1 | awk "$C"' {printf "relpose_demo.elf: flash %s B (text %s + data %s), static RAM %s B (data %s + bss %s)\n", c($1 + $2), c($1), c($2), c($2 + $3), c($2), c($3)}'
fi
