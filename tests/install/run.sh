#!/bin/sh
# `make install` as a robot project uses it: staged with DESTDIR under one
# PREFIX, then moved to another directory (a relocated prefix: the pkg-config
# and CMake files must find it from where they sit). From there consumers of
# both libraries are built with pkg-config and with CMake's find_package(sfm),
# shared and static, and run; the shared objects carry their SONAME and the
# programs record that name, not a path; the tools run; the Python package
# finds the installed library through the system loader; `make uninstall`
# removes every file it installed.
#   sh tests/install/run.sh      (from the project root, after make all capture)
set -u
top=$(pwd)
build=${BUILD:-build}
out=$top/$build/install-test
rm -rf "$out"
mkdir -p "$out"
stage=$out/stage
prefix=$out/moved/sfm-0.1
pass=0; fail=0
ok() { echo "ok   $1"; pass=$((pass + 1)); }
ko() { echo "FAIL $1"; fail=$((fail + 1)); }
py=$top/${PYTHON_VENV:-.venv}/bin/python
major=$(sed -n 's/^#define SFM_VERSION_MAJOR \([0-9]*\).*/\1/p' include/sfm/sfm_common.h)

if make --no-print-directory install DESTDIR="$stage" PREFIX=/opt/sfm >"$out/install.log" 2>&1; then
    ok "make install DESTDIR=... PREFIX=/opt/sfm"
else
    cat "$out/install.log"; ko "make install"; echo "$pass passed, $fail failed"; exit 1
fi
mkdir -p "$(dirname "$prefix")" && mv "$stage/opt/sfm" "$prefix"
export PKG_CONFIG_PATH=$prefix/lib/pkgconfig
LIB=$prefix/lib

# Files and links.
for l in libsfm libsfm_capture; do
    real=$(readlink -f "$LIB/$l.so")
    soname=$(readelf -d "$real" | sed -n 's/.*(SONAME).*\[\(.*\)\]/\1/p')
    if [ "$(readlink "$LIB/$l.so")" = "$l.so.$major" ] && [ -f "$LIB/$l.so.$major" ] &&
       [ "$soname" = "$l.so.$major" ] && [ -f "$LIB/$l.a" ]; then
        ok "$l: $l.so -> $l.so.$major -> $(basename "$real"), SONAME $soname, $l.a"
    else
        ko "$l: links or SONAME wrong (SONAME '$soname', $(ls -l "$LIB" | grep "$l" | tr '\n' ' '))"
    fi
done
for f in bin/sfm-record bin/sfm-replay include/sfm/sfm.h include/sfm/sfm_capture.h include/sfm/sfm_eigen.hpp \
         lib/pkgconfig/sfm.pc lib/pkgconfig/sfm-capture.pc lib/cmake/sfm/sfmConfig.cmake \
         share/sfm/sfm_cdef.h share/sfm/sfm_capture_cdef.h; do
    [ -e "$prefix/$f" ] || ko "missing $f"
done

# pkg-config, shared.
cc_pc() { # name source libs...
    n=$1; src=$2; shift 2
    ${CC:-cc} $(pkg-config --cflags "$@") "$src" -o "$out/$n" $(pkg-config --libs "$@")
}
needed() { readelf -d "$1" | sed -n 's/.*(NEEDED).*\[\(.*\)\]/\1/p' | tr '\n' ' '; }
if cc_pc consumer_pc tests/install/consumer.c sfm && LD_LIBRARY_PATH=$LIB "$out/consumer_pc" &&
   needed "$out/consumer_pc" | grep -q "libsfm.so.$major "; then
    ok "pkg-config sfm: built, ran, NEEDED $(needed "$out/consumer_pc")"
else ko "pkg-config sfm"; fi
if cc_pc capture_pc tests/install/capture_consumer.c sfm-capture &&
   LD_LIBRARY_PATH=$LIB "$out/capture_pc" "$out/rec_pc" &&
   needed "$out/capture_pc" | grep -q "libsfm_capture.so.$major "; then
    ok "pkg-config sfm-capture: built, ran, NEEDED $(needed "$out/capture_pc")"
else ko "pkg-config sfm-capture"; fi
if [ "$(pkg-config --modversion sfm-capture)" = "$(pkg-config --modversion sfm)" ]; then
    ok "pkg-config versions: $(pkg-config --modversion sfm)"
else ko "pkg-config versions differ"; fi

# CMake, shared and static, both libraries.
if cmake -S tests/install -B "$out/cmake" -DCMAKE_PREFIX_PATH="$prefix" >"$out/cmake.log" 2>&1 &&
   cmake --build "$out/cmake" >>"$out/cmake.log" 2>&1; then
    ok "cmake find_package(sfm): sfm::sfm sfm::sfm_static sfm::capture sfm::capture_static built"
    if LD_LIBRARY_PATH=$LIB "$out/cmake/consumer_shared" && "$out/cmake/consumer_static" &&
       LD_LIBRARY_PATH=$LIB "$out/cmake/capture_shared" "$out/rec_cm1" && "$out/cmake/capture_static" "$out/rec_cm2"; then
        ok "cmake consumers ran"
    else ko "cmake consumers ran"; fi
    if needed "$out/cmake/consumer_shared" | grep -q "libsfm.so.$major " &&
       ! needed "$out/cmake/consumer_shared" | grep -q /; then
        ok "cmake consumer records the SONAME: $(needed "$out/cmake/consumer_shared")"
    else ko "cmake consumer NEEDED: $(needed "$out/cmake/consumer_shared")"; fi
    if ! needed "$out/cmake/consumer_static" | grep -q libsfm; then ok "static consumer needs no libsfm.so"
    else ko "static consumer still needs libsfm.so"; fi
else
    cat "$out/cmake.log"; ko "cmake find_package(sfm)"
fi

# The README's C quick start, extracted from README.md, built with the
# pkg-config line it shows and run on matches of a known motion (60 exact
# matches, 15 wrong ones): it must keep the 60 and find the translation
# direction.
mkdir -p "$out/quickstart"
awk '/^### C, with a workspace/{f=1} f&&/^```c$/{g=1;next} g&&/^```$/{exit} g' README.md > "$out/quickstart/relpose.c"
"$py" -c '
import numpy as np
rng = np.random.default_rng(7)
X = np.c_[rng.uniform(-2, 2, 75), rng.uniform(-1.5, 1.5, 75), rng.uniform(4, 10, 75)]
a = np.radians(4.0)
R = np.array([[np.cos(a), 0, np.sin(a)], [0, 1, 0], [-np.sin(a), 0, np.cos(a)]])
K = np.array([[500.0, 0, 320], [0, 500, 240], [0, 0, 1]])
def proj(P):
    p = P @ K.T
    return p[:, :2] / p[:, 2:]
x1, x2 = proj(X), proj(X @ R.T + np.array([0.6, 0.0, 0.8]))
x2[60:] = rng.uniform(0, 480, (15, 2))
np.savetxt("'"$out/quickstart/matches.txt"'", np.c_[x1, x2], fmt="%.6f")
'
if [ -s "$out/quickstart/relpose.c" ] &&
   ${CC:-cc} -std=c11 -Wall -Wextra -Werror "$out/quickstart/relpose.c" $(pkg-config --cflags --libs sfm) -o "$out/quickstart/relpose" &&
   qs=$(LD_LIBRARY_PATH=$LIB "$out/quickstart/relpose" < "$out/quickstart/matches.txt") &&
   echo "$qs" | grep -qE '^60 of 75 inliers, t = 0\.6[0-9]* 0?-?0\.0[0-9]* 0\.8[0-9]*$'; then
    ok "README C quick start: $qs"
else ko "README C quick start (output: ${qs:-none})"; fi

# The tools.
if "$prefix/bin/sfm-replay" --help >/dev/null && "$prefix/bin/sfm-record" --help >/dev/null; then
    ok "bin/sfm-replay, bin/sfm-record run"
else ko "installed tools"; fi

# Python: a package without its own copy of the library (the pure-Python
# files alone, outside any checkout) finds the installed one through the
# system loader, from another directory.
mkdir -p "$out/pyonly" && cp -r python/libsfm "$out/pyonly/" && rm -f "$out"/pyonly/libsfm/*.so* "$out"/pyonly/libsfm/*cdef.h
if (cd "$out" && env -u LIBSFM_LIBRARY -u LIBSFM_CDEF PYTHONPATH="$out/pyonly" LD_LIBRARY_PATH="$LIB" "$py" -c '
import numpy as np, libsfm
from libsfm import _ffi
assert _ffi._found_by == "system loader", _ffi._found_by
assert _ffi._libpath.startswith("'"$LIB"'"), _ffi._libpath
print("python via the system loader:", _ffi._libpath, libsfm.version())
'); then ok "python finds the installed library (LD_LIBRARY_PATH)"; else ko "python with the installed library"; fi

# Uninstall from the staged tree: nothing of ours may be left.
mkdir -p "$stage/opt" && mv "$prefix" "$stage/opt/sfm"
make --no-print-directory uninstall DESTDIR="$stage" PREFIX=/opt/sfm >/dev/null 2>&1
left=$(find "$stage" -type f -o -type l)
if [ -z "$left" ]; then ok "make uninstall removed every file"
else ko "make uninstall left: $left"; fi

echo "$pass passed, $fail failed"
[ "$fail" -eq 0 ]
