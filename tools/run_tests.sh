#!/usr/bin/env bash
# Runs each make target given, keeps going when one fails, and ends with one
# summary line adding up every step's "N passed, N failed" (or pytest's
# "N passed" line), and the skips: pytest's "N skipped" and the C tests'
# "SKIP:" lines (a data set, a tool or a device that is not there), so that
# a run without ../shared/data does not read like a full one.
#
# Steps run TEST_JOBS at a time (default: the number of cores): most of them
# are one process (a test binary, an emulator, pytest), so on a 2-core machine
# two at once halve the wall time. Before any step runs, one make builds
# every step's prerequisites (read from make's own database), so that the
# steps running side by side find their files up to date and only run: no
# two makes ever write the same file. If that build fails, the steps run one
# at a time and each reports its own failure. TEST_FIRST names steps to
# start first (the longest, so that none starts last and finishes alone).
# Each step's output is printed whole when it ends, and kept in
# BUILD/test-logs/STEP.log.
set -u
logdir=${BUILD:-build}/test-logs
mkdir -p "$logdir"
jobs=${TEST_JOBS:-$(nproc 2>/dev/null || echo 1)}
[ "$jobs" -ge 1 ] 2>/dev/null || jobs=1
start=$(date +%s)

# Order: TEST_FIRST (those of them that were asked for), then the others as given.
steps=()
for s in ${TEST_FIRST:-}; do
    for a in "$@"; do [ "$a" = "$s" ] && steps+=("$s") && break; done
done
for a in "$@"; do
    case " ${TEST_FIRST:-} " in *" $a "*) ;; *) steps+=("$a") ;; esac
done

if [ "$jobs" -gt 1 ]; then
    echo "=== building every step's prerequisites (make -j$jobs)"
    t0=$(date +%s)
    prereqs=$(make -pq "${steps[@]}" 2>/dev/null | awk -v want=" ${steps[*]} " '
        $1 ~ /:$/ && index(want, " " substr($1, 1, length($1) - 1) " ") {
            for (i = 2; i <= NF; i++) if ($i ~ /=/) next
            for (i = 2; i <= NF; i++) if ($i != "|") print $i
        }' | sort -u)
    if make --no-print-directory -j"$jobs" $prereqs >"$logdir/prereqs.log" 2>&1; then
        echo "--- prerequisites built, $(( $(date +%s) - t0 ))s"
    else
        tail -n 30 "$logdir/prereqs.log"
        echo "--- building the prerequisites failed ($logdir/prereqs.log): the steps run one at a time"
        jobs=1
    fi
fi

total_pass=0; total_fail=0; total_skip=0; bad_steps=()

# report STEP: prints the step's log and its line, adds up its counts.
report() {
    local step=$1 rc dt line p=0 f=0 py k=0 ks
    read -r rc dt <"$logdir/$step.rc"
    echo "=== $step"
    cat "$logdir/$step.log"
    line=$(grep -E '^([A-Za-z0-9-]+: )?[0-9]+ passed, [0-9]+ failed' "$logdir/$step.log" | tail -n 1 || true)
    if [ -n "$line" ]; then
        p=$(sed -E 's/^([A-Za-z0-9-]+: )?([0-9]+) passed.*/\2/' <<<"$line")
        f=$(sed -E 's/.* ([0-9]+) failed.*/\1/' <<<"$line")
    else
        py=$(grep -E '^(=+ )?[0-9]+ (passed|failed|error).* in [0-9.]+s' "$logdir/$step.log" | tail -n 1 || true)
        if [ -n "$py" ]; then
            p=$(grep -oE '[0-9]+ passed' <<<"$py" | grep -oE '[0-9]+' || echo 0)
            f=0; for n in $(grep -oE '[0-9]+ (failed|errors?)' <<<"$py" | grep -oE '^[0-9]+'); do f=$((f + n)); done
            [ -n "$p" ] || p=0; [ -n "$f" ] || f=0
        fi
    fi
    ks=$(grep -E '^(=+ )?[0-9]+ (passed|failed|skipped|error).* in [0-9.]+s' "$logdir/$step.log" | tail -n 1 |
         grep -oE '[0-9]+ skipped' | grep -oE '[0-9]+' || true)
    k=$(( ${ks:-0} + $(grep -c '^SKIP:' "$logdir/$step.log" || true) ))
    if [ "$rc" -ne 0 ] && [ "$f" -eq 0 ]; then f=1; fi
    if [ "$rc" -ne 0 ]; then bad_steps+=("$step"); fi
    total_pass=$((total_pass + p)); total_fail=$((total_fail + f)); total_skip=$((total_skip + k))
    printf -- '--- %s: %d passed, %d failed, exit %d, %ds%s\n' "$step" "$p" "$f" "$rc" "$dt" \
        "$([ "$k" -gt 0 ] && echo ", $k skipped")"
}

launch() {
    local step=$1
    rm -f "$logdir/$step.rc"
    (
        t0=$(date +%s)
        make --no-print-directory "$step" >"$logdir/$step.log" 2>&1
        rc=$?
        echo "$rc $(( $(date +%s) - t0 ))" >"$logdir/$step.rc.part"
        mv "$logdir/$step.rc.part" "$logdir/$step.rc"
    ) &
}

running=()
next=0
while [ "$next" -lt "${#steps[@]}" ] || [ "${#running[@]}" -gt 0 ]; do
    while [ "${#running[@]}" -lt "$jobs" ] && [ "$next" -lt "${#steps[@]}" ]; do
        launch "${steps[$next]}"
        running+=("${steps[$next]}")
        next=$((next + 1))
    done
    done_one=0
    while [ "$done_one" -eq 0 ]; do
        still=()
        for s in "${running[@]}"; do
            if [ -e "$logdir/$s.rc" ]; then report "$s"; done_one=1; else still+=("$s"); fi
        done
        running=("${still[@]+"${still[@]}"}")
        [ "$done_one" -eq 1 ] || wait -n 2>/dev/null || sleep 1
    done
done
wait

echo
echo "steps: ${#steps[@]}, failed steps: ${#bad_steps[@]} ${bad_steps[*]:-}, $(( $(date +%s) - start ))s"
echo "test: $total_pass passed, $total_fail failed, $total_skip skipped"
[ ${#bad_steps[@]} -eq 0 ]
