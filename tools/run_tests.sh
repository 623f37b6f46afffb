#!/usr/bin/env bash
# Runs each make target given, keeps going when one fails, and ends with one
# summary line adding up every step's "N passed, N failed" (or pytest's
# "N passed" line).
set -u
logdir=${BUILD:-build}/test-logs
mkdir -p "$logdir"
total_pass=0; total_fail=0; bad_steps=()
start=$(date +%s)
for step in "$@"; do
    echo "=== $step"
    t0=$(date +%s)
    make --no-print-directory "$step" 2>&1 | tee "$logdir/$step.log"
    rc=${PIPESTATUS[0]}
    line=$(grep -E '^([A-Za-z-]+: )?[0-9]+ passed, [0-9]+ failed' "$logdir/$step.log" | tail -n 1 || true)
    p=0; f=0
    if [ -n "$line" ]; then
        p=$(sed -E 's/^([A-Za-z-]+: )?([0-9]+) passed.*/\2/' <<<"$line")
        f=$(sed -E 's/.* ([0-9]+) failed.*/\1/' <<<"$line")
    else
        py=$(grep -E '^(=+ )?[0-9]+ (passed|failed|error).* in [0-9.]+s' "$logdir/$step.log" | tail -n 1 || true)
        if [ -n "$py" ]; then
            p=$(grep -oE '[0-9]+ passed' <<<"$py" | grep -oE '[0-9]+' || echo 0)
            f=0; for n in $(grep -oE '[0-9]+ (failed|errors?)' <<<"$py" | grep -oE '^[0-9]+'); do f=$((f + n)); done
            [ -n "$p" ] || p=0; [ -n "$f" ] || f=0
        fi
    fi
    if [ "$rc" -ne 0 ] && [ "$f" -eq 0 ]; then f=1; fi
    if [ "$rc" -ne 0 ]; then bad_steps+=("$step"); fi
    total_pass=$((total_pass + p)); total_fail=$((total_fail + f))
    printf -- '--- %s: %d passed, %d failed, exit %d, %ds\n' "$step" "$p" "$f" "$rc" $(( $(date +%s) - t0 ))
done
echo
echo "steps: $#, failed steps: ${#bad_steps[@]} ${bad_steps[*]:-}, $(( $(date +%s) - start ))s"
echo "test: $total_pass passed, $total_fail failed"
[ ${#bad_steps[@]} -eq 0 ]
