#!/bin/sh
# The fresh-machine order: `make demo` builds the capture library before
# `make test` has installed its optional packages, then `make test` must
# rebuild it with them. Reproduced in a scratch build directory by hiding one
# optional dependency on the first build (HAVE_<DEP>= on the command line,
# as a missing pkg-config module would) and letting the second find it:
# the second archive must reference the dependency's symbols and a program
# linked to it must not report the backend unsupported.
#   sh tests/install/capture_config.sh BUILD
set -u
build=${1:-build}
scratch=$build/capture-config-test
rm -rf "$scratch"
pass=0; fail=0
ok() { echo "ok   $1"; pass=$((pass + 1)); }
ko() { echo "FAIL $1"; fail=$((fail + 1)); }

# The dependency to hide: libcamera where present (the case of the report),
# otherwise libjpeg.
if pkg-config --exists libcamera; then
    var=HAVE_LIBCAMERA; sym='N9libcamera'; probe=libcamera
elif pkg-config --exists libjpeg; then
    var=HAVE_LIBJPEG; sym='jpeg_'; probe=jpeg
else
    echo "FAIL neither libcamera nor libjpeg is installed: nothing optional to find"
    echo "0 passed, 1 failed"; exit 1
fi
echo "hidden then found: $var"

count_refs() { nm -u "$1" 2>/dev/null | grep -c "$sym" || true; }

# build N STAMP_VALUE [make variables]: the archive built, the stamp must
# record STAMP_VALUE, the dependency referenced exactly when it is 1.
build() {
    n=$1; want=$2; shift 2
    make --no-print-directory BUILD="$scratch" "$@" "$scratch/libsfm_capture.a" >"$scratch.log$n" 2>&1 \
        || { cat "$scratch.log$n"; ko "build $n ($var=$want)"; }
    refs=$(count_refs "$scratch/libsfm_capture.a")
    if [ "$want" = 1 ]; then has=$([ "$refs" -gt 0 ] && echo y); else has=$([ "$refs" -eq 0 ] && echo y); fi
    if grep -q "$var=$want " "$scratch/capture/config.stamp" && [ -n "$has" ]; then
        ok "build $n: config.stamp says $var=$want, $refs references to $probe"
    else
        ko "build $n: expected $var=$want, found $refs references to $probe"
    fi
}
build 1 "" "$var="   # as on a machine without the package
build 2 1            # the package found: the objects are rebuilt with it

# A third make with nothing changed compiles nothing.
if make --no-print-directory BUILD="$scratch" "$scratch/libsfm_capture.a" 2>&1 | grep -q -- ' -c '; then
    ko "third make recompiled with nothing changed"
else
    ok "third make: nothing recompiled"
fi

# At run time: the backend reports itself, not SFM_E_UNSUPPORTED.
if [ "$var" = HAVE_LIBCAMERA ]; then
    cat > "$scratch/probe.c" <<'PROBE'
#include <stdio.h>
#include "sfm/sfm_capture.h"
int main(void)
{
    char ids[4][64];
    int n = sfm_libcamera_list(&ids[0][0], 4, 64);
    printf("sfm_libcamera_list: %d (%s)\n", n, n < 0 ? sfm_status_str(n) : "cameras");
    return n == SFM_E_UNSUPPORTED;
}
PROBE
    libs=$(make --no-print-directory -s BUILD="$scratch" print-capture-ldlibs)
    if ${CC:-cc} -Iinclude -o "$scratch/probe" "$scratch/probe.c" "$scratch/libsfm_capture.a" "$build/libsfm.a" $libs &&
       "$scratch/probe"; then
        ok "libcamera backend present at run time"
    else
        ko "libcamera backend unsupported after the second build"
    fi
fi
rm -rf "$scratch" "$scratch".log*
echo "$pass passed, $fail failed"
[ "$fail" -eq 0 ]
