#!/bin/sh
# Fuzzes each target for a while: new inputs go to BUILD/fuzz/corpus/<t>
# (the committed seeds in tests/fuzz/corpus/<t> are read, not changed);
# a crash leaves its input in BUILD/fuzz/artifacts/ and fails the run.
# Usage: run_fuzz.sh BIN_DIR SECONDS target ...
set -u
bin=$1; secs=$2; shift 2
status=0
for t in "$@"; do
    mkdir -p "$bin/corpus/$t" "$bin/artifacts"
    log="$bin/fuzz-$t.log"
    echo "=== fuzz_$t for $secs s"
    "$bin/fuzz_$t" -max_total_time="$secs" -rss_limit_mb=2048 -print_final_stats=1 \
        -artifact_prefix="$bin/artifacts/$t-" "$bin/corpus/$t" "tests/fuzz/corpus/$t" > "$log" 2>&1
    rc=$?
    grep -E 'stat::number_of_executed_units|stat::peak_rss_mb|^#[0-9]+ +DONE' "$log" | tail -n 3
    if [ $rc -ne 0 ]; then
        status=1
        echo "FAIL fuzz_$t (exit $rc): see $log and $bin/artifacts/"
        grep -E 'ERROR|SUMMARY' "$log" | head -n 3
    fi
done
[ $status -eq 0 ] && echo "fuzz: every target ran clean"
exit $status
