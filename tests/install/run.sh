#!/bin/sh
# Installs into a temporary prefix and builds a consumer against it both
# ways a robot project would: pkg-config and CMake's find_package(sfm).
set -eu
top=$(pwd)
build=${BUILD:-build}
prefix=$top/$build/install-test/prefix
rm -rf "$top/$build/install-test"
make --no-print-directory install PREFIX="$prefix" >/dev/null
pass=0; fail=0
ok() { echo "ok   $1"; pass=$((pass + 1)); }
ko() { echo "FAIL $1"; fail=$((fail + 1)); }

out=$top/$build/install-test
if cc $(PKG_CONFIG_PATH=$prefix/lib/pkgconfig pkg-config --cflags sfm) tests/install/consumer.c \
      -o "$out/consumer_pc" $(PKG_CONFIG_PATH=$prefix/lib/pkgconfig pkg-config --libs sfm) &&
   LD_LIBRARY_PATH=$prefix/lib "$out/consumer_pc"; then ok pkg-config; else ko pkg-config; fi

if cmake -S tests/install -B "$out/cmake" -DCMAKE_PREFIX_PATH="$prefix" >/dev/null &&
   cmake --build "$out/cmake" >/dev/null &&
   LD_LIBRARY_PATH=$prefix/lib "$out/cmake/consumer_shared" && "$out/cmake/consumer_static"; then
    ok cmake-find-package; else ko cmake-find-package; fi

if PYTHONPATH=$top/python LIBSFM_LIBRARY=$prefix/lib/libsfm.so LIBSFM_CDEF=$prefix/share/sfm/sfm_cdef.h \
      "$top/${PYTHON_VENV:-.venv}/bin/python" -c 'import libsfm; print("python binding", libsfm.version())'; then
    ok python-installed-lib; else ko python-installed-lib; fi

# The Python package installs with pip from python/ and finds the library.
py=$top/${PYTHON_VENV:-.venv}/bin/python
# Built from a copy so the source tree gets no build/ or egg-info.
rm -rf "$out/pysrc" && cp -r "$top/python" "$out/pysrc" && rm -rf "$out/pysrc/build" "$out"/pysrc/*.egg-info
if "$py" -m pip wheel -q --no-deps --no-build-isolation "$out/pysrc" -w "$out/wheel" >/dev/null 2>&1 &&
   "$py" -m pip install -q --no-deps --target "$out/site" "$out"/wheel/libsfm-*.whl >/dev/null 2>&1 &&
   (cd "$out" && PYTHONPATH=$out/site LIBSFM_LIBRARY=$prefix/lib/libsfm.so "$py" -c 'import libsfm; print("pip-installed", libsfm.version())'); then
    ok pip-install; else ko pip-install; fi

echo "$pass passed, $fail failed"
[ "$fail" -eq 0 ]
