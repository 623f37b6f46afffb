#!/bin/sh
# The static library exports only the API and internal sfmi_ names: every
# global symbol it defines is either sfmi_* or an sfm_* name declared in a
# public header (include/sfm/*.h). The shared library already hides the
# internal ones; a static link sees them all, so a stray prefix there is a
# name clash waiting for a user's program.
# Usage: check_symbols.sh LIBSFM.a   (NM selects the nm, default nm)
set -eu
lib=$1
nm=${NM:-nm}
tmp=${TMPDIR:-/tmp}/check_symbols.$$
trap 'rm -f "$tmp".*' EXIT
"$nm" -g --defined-only "$lib" | awk 'NF >= 3 { print $NF }' | sort -u > "$tmp.syms"
grep -ohE '\bsfm_[A-Za-z0-9_]+[[:space:]]*\(' include/sfm/*.h | sed -E 's/[[:space:]]*\($//' |
    sort -u > "$tmp.public"
# extern data declared in the public headers counts as public too
grep -ohE '^(SFM_API +)?extern [^;]*\bsfm_[A-Za-z0-9_]+' include/sfm/*.h |
    grep -oE 'sfm_[A-Za-z0-9_]+$' >> "$tmp.public" || true
sort -u -o "$tmp.public" "$tmp.public"
bad=0; n=0
while read -r s; do
    n=$((n + 1))
    case $s in
    sfmi_*) ;;
    sfm_*)
        if ! grep -qx "$s" "$tmp.public"; then
            echo "FAIL: $s is exported but not declared in include/sfm/*.h (internal names take sfmi_)"
            bad=$((bad + 1))
        fi ;;
    *)
        echo "FAIL: $s is exported without the sfm_ or sfmi_ prefix"
        bad=$((bad + 1)) ;;
    esac
done < "$tmp.syms"
echo "$n global symbols in $lib, $bad misnamed"
if [ "$bad" -eq 0 ]; then echo "symbols: 1 passed, 0 failed"; else echo "symbols: 0 passed, 1 failed"; exit 1; fi
