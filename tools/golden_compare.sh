#!/bin/sh
# Runs the golden-output program once per target and compares each run's
# lines with the committed golden file; one test per target.
# Usage: golden_compare.sh GOLDEN_FILE NAME=COMMAND ...
# With GOLDEN_UPDATE=1 the first target's output is written to GOLDEN_FILE
# first (then every target, that one included, is compared with it).
set -u
golden=$1; shift
tmp=${TMPDIR:-/tmp}/golden.$$
mkdir -p "$tmp"
trap 'rm -rf "$tmp"' EXIT
pass=0; fail=0; first=1
for spec in "$@"; do
    name=${spec%%=*}; cmd=${spec#*=}
    # keep only the result lines: name, status, 16 hex digits
    sh -c "$cmd" > "$tmp/$name.raw" 2>&1
    rc=$?
    grep -E '^[A-Za-z0-9_.+]+ +-?[0-9]+ [0-9a-f]{16}$' "$tmp/$name.raw" > "$tmp/$name.out" || true
    if [ "$first" = 1 ] && [ "${GOLDEN_UPDATE:-0}" = 1 ]; then
        if [ "$rc" -ne 0 ] || [ ! -s "$tmp/$name.out" ]; then
            echo "FAIL $name: exit $rc, not updating $golden"; cat "$tmp/$name.raw"; exit 1
        fi
        cp "$tmp/$name.out" "$golden"
        echo "updated $golden from $name ($(wc -l < "$golden") outputs)"
    fi
    first=0
    if [ "$rc" -eq 0 ] && diff -u "$golden" "$tmp/$name.out" > "$tmp/$name.diff"; then
        echo "ok   $name: $(wc -l < "$tmp/$name.out") outputs identical to $golden"
        pass=$((pass + 1))
    else
        echo "FAIL $name (exit $rc): outputs differ from $golden"
        cat "$tmp/$name.diff"
        grep -vE '^[A-Za-z0-9_.+]+ +-?[0-9]+ [0-9a-f]{16}$' "$tmp/$name.raw" | head -20
        fail=$((fail + 1))
    fi
done
echo "golden: $pass passed, $fail failed"
[ "$fail" -eq 0 ]
