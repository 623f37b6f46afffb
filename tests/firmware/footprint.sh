#!/bin/sh
# Holds the Cortex-M7 build to its budget:
#   the whole core (text of the budgeted objects of BUILD/cortex-m7, as
#   tools/footprint.sh --budget lists them)                    <= 128 KB of flash
#   the relative-pose example image (text + data)              <= 64 KB of flash
#   the example's RAM at run time (data + bss + heap + deepest stack, as the
#   program measures and prints it under qemu-system-arm)      <= 32 KB
# The example's linker script already refuses to link past 64 KB / 32 KB;
# this checks the figures themselves and that the program ran to the end.
#   sh tests/firmware/footprint.sh BUILD/cortex-m7
set -u
dir=${1:-build/cortex-m7}
CORE_MAX=131072
FLASH_MAX=65536
RAM_MAX=32768
pass=0; fail=0
ok() { echo "ok   $1"; pass=$((pass + 1)); }
ko() { echo "FAIL $1"; fail=$((fail + 1)); }

# The whole core as the 128 KB budget was set (issue 13): core, solvers,
# robust, refine, features and recon's calibrated three-view pose, with what
# has been split out of them since (tools/footprint.sh says which objects).
# The code added since (robot-to-robot r2r_*, recon's uncalibrated pipelines,
# dense stereo, the sequence pipeline) is built for the M7 too, so that it is
# proven portable, and its size is printed, not bounded; a program links only
# what it calls.
here=$(dirname "$0")
objs=$(sh "$here/../../tools/footprint.sh" --budget "$dir")
missing=$(for o in $objs; do [ -f "$o" ] || echo "$o"; done)
core=$(echo "$objs" | xargs arm-none-eabi-size -t | tail -n 1 | awk '{print $1}')
if [ -z "$missing" ] && [ -n "$core" ] && [ "$core" -le $CORE_MAX ]; then
    ok "core flash $core B <= $CORE_MAX ($(echo "$objs" | wc -l) objects)"
else
    ko "core flash ${core:-?} B > $CORE_MAX${missing:+, missing: $missing}"
fi
rest=$(find "$dir/obj/libsfm" -name '*.o' | sort | grep -v -x -F "$objs")
for m in $(echo "$rest" | sed 's|.*/obj/libsfm/\([^/]*\)/.*|\1|' | sort -u); do
    mo=$(echo "$rest" | grep "/obj/libsfm/$m/")
    echo "     $m: $(echo "$mo" | xargs arm-none-eabi-size -t | tail -n 1 | awk '{print $1}') B in $(echo "$mo" | wc -l) objects (not budgeted)"
done

elf=$dir/examples/relpose_demo.elf
flash=$(arm-none-eabi-size "$elf" | tail -n 1 | awk '{print $1 + $2}')
if [ -n "$flash" ] && [ "$flash" -le $FLASH_MAX ]; then ok "example flash $flash B <= $FLASH_MAX"
else ko "example flash ${flash:-?} B > $FLASH_MAX"; fi

out=$(timeout 300 qemu-system-arm -M mps2-an500 -cpu cortex-m7 -nographic -monitor none -serial none \
      -semihosting-config enable=on,target=native -kernel "$elf" 2>&1)
rc=$?
echo "$out"
ram=$(echo "$out" | sed -n 's/^ram: \([0-9]*\) bytes.*/\1/p')
if [ $rc -eq 0 ] && [ -n "$ram" ] && [ "$ram" -le $RAM_MAX ]; then ok "example RAM $ram B <= $RAM_MAX (exit $rc)"
else ko "example RAM ${ram:-not reported} B, exit $rc (bound $RAM_MAX)"; fi

echo "$pass passed, $fail failed"
[ "$fail" -eq 0 ]
