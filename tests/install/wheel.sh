#!/bin/sh
# The Python package as a user gets it: a wheel built from python/ (its
# setup.py compiles the C library with the project's Makefile in a private
# build directory), installed into a fresh venv outside the repository, then
# imported from another directory with no variable set and used: the loaded
# library must be the copy inside the installed package, an estimator must
# recover a known pose, and replay must work through the packaged capture
# library. The venv reaches numpy and cffi through a .pth line to the
# project venv's site-packages, so no network is needed.
#   sh tests/install/wheel.sh
set -u
top=$(pwd)
build=${BUILD:-build}
out=$top/$build/wheel-test
py=$top/${PYTHON_VENV:-.venv}/bin/python
rm -rf "$out"
mkdir -p "$out"
pass=0; fail=0
ok() { echo "ok   $1"; pass=$((pass + 1)); }
ko() { echo "FAIL $1"; fail=$((fail + 1)); }

# `python -m build` on python/: an sdist (which carries the C tree in csrc/)
# and the wheel built from that sdist, unpacked elsewhere, so the wheel's
# library comes from the sdist's own sources. Built from a copy of python/
# beside the checkout's C tree so the checkout gets no build/ or egg-info.
mkdir -p "$out/src" && cp -r python "$out/src/python" && rm -rf "$out/src/python/build" "$out"/src/python/*.egg-info
for f in Makefile mk include libsfm tools firmware_examples; do ln -s "$top/$f" "$out/src/$f"; done
if env -u LIBSFM_SOURCE_DIR "$py" -m build -n -o "$out/dist" "$out/src/python" >"$out/build.log" 2>&1 &&
   tar tzf "$out"/dist/libsfm-*.tar.gz | grep -q "/csrc/libsfm/core/svd.c$"; then
    whl=$(ls "$out"/dist/libsfm-*.whl)
    ok "sdist (with csrc/) and wheel built: $(basename "$whl")"
else
    tail -30 "$out/build.log"; ko "wheel build"; echo "$pass passed, $fail failed"; exit 1
fi
case $(basename "$whl") in
    *-py3-none-linux_*.whl) ok "tagged py3-none-<platform> (cffi ABI mode: any Python 3)" ;;
    *) ko "wheel tag: $(basename "$whl")" ;;
esac
contents=$("$py" -m zipfile -l "$whl")
for f in libsfm/libsfm.so.0 libsfm/sfm_cdef.h libsfm/libsfm_capture.so.0 libsfm/sfm_capture_cdef.h; do
    echo "$contents" | grep -q " *$f " || echo "$contents" | grep -q "^$f" || ko "wheel lacks $f"
done

# The venv and the working directory are outside the repository.
away=$(mktemp -d "${TMPDIR:-/tmp}/sfm-wheel-test.XXXXXX")
trap 'rm -rf "$away"' EXIT
"$py" -m venv "$away/venv"
deps=$("$py" -c 'import numpy, cffi, os; print(os.path.dirname(os.path.dirname(numpy.__file__)))')
vsite=$("$away/venv/bin/python" -c 'import site; print(site.getsitepackages()[0])')
echo "$deps" > "$vsite/project-deps.pth"
if "$away/venv/bin/python" -m pip install -q --no-deps --no-index "$whl" >"$out/install.log" 2>&1; then
    ok "pip install into a fresh venv"
else cat "$out/install.log"; ko "pip install"; fi

mkdir -p "$away/elsewhere/rec"
printf 'P5\n4 3\n255\n' > "$away/elsewhere/rec/f0.pgm"
printf '\001\002\003\004\005\006\007\010\011\012\013\014' >> "$away/elsewhere/rec/f0.pgm"
printf 'sequence,timestamp_ns,file\n0,42,f0.pgm\n' > "$away/elsewhere/rec/manifest.csv"
if (cd "$away/elsewhere" && env -u PYTHONPATH -u LIBSFM_LIBRARY -u LIBSFM_CDEF -u LD_LIBRARY_PATH \
      "$away/venv/bin/python" -c '
import os, numpy as np, libsfm
from libsfm import _ffi, frames
assert _ffi._found_by == "package", _ffi._found_by
assert _ffi._libpath.startswith(os.path.dirname(libsfm.__file__)), _ffi._libpath
assert libsfm.__file__.startswith("'"$away"'/venv/"), libsfm.__file__
assert libsfm.lib.sfm_version() // 10000 == _ffi.SO_MAJOR
# Relative pose of a known motion (5 deg yaw, unit step) from 60 exact matches.
rng = np.random.default_rng(3)
X = np.c_[rng.uniform(-2, 2, 60), rng.uniform(-1.5, 1.5, 60), rng.uniform(4, 10, 60)]
a = np.radians(5.0)
R = np.array([[np.cos(a), 0, np.sin(a)], [0, 1, 0], [-np.sin(a), 0, np.cos(a)]])
t = np.array([0.8, 0.0, 0.6])
K = np.array([[500.0, 0, 320], [0, 500, 240], [0, 0, 1]])
def proj(P):
    p = P @ K.T
    return p[:, :2] / p[:, 2:]
res = libsfm.estimate_relative_pose(proj(X), proj(X @ R.T + t), K, K, threshold_px=1.0)
field = lambda r, k: r[k] if isinstance(r, dict) else getattr(r, k)
Re, te = np.asarray(field(res, "R")), np.asarray(field(res, "t")).ravel()
rot = np.degrees(np.arccos(np.clip((np.trace(Re.T @ R) - 1) / 2, -1, 1)))
tdir = np.degrees(np.arccos(np.clip(te @ t / np.linalg.norm(te) / np.linalg.norm(t), -1, 1)))
assert rot < 0.01 and tdir < 0.1, (rot, tdir)
got = [f for f in frames.open_replay("rec")]
assert len(got) == 1 and got[0].timestamp_ns == 42 and got[0].image.tolist() == [[1, 2, 3, 4], [5, 6, 7, 8], [9, 10, 11, 12]]
print("from %s: libsfm %s loaded from %s; relative pose error %.2g deg / %.2g deg; replay ok"
      % (os.getcwd(), libsfm.version(), _ffi._libpath, rot, tdir))
'); then ok "import from another directory, no variable: estimator and replay"; else ko "import and use"; fi

# The README's Python quick start, extracted from README.md, run in that
# venv on matches of a known motion and on a one-frame recording placed
# where it looks.
awk '/^### Python/{f=1} f&&/^```python$/{g=1;next} g&&/^```$/{exit} g' README.md > "$away/elsewhere/quickstart.py"
mkdir -p "$away/elsewhere/build/demo" && cp -r "$away/elsewhere/rec" "$away/elsewhere/build/demo/synthetic"
(cd "$away/elsewhere" && "$away/venv/bin/python" -c '
import numpy as np
rng = np.random.default_rng(5)
X = np.c_[rng.uniform(-2, 2, 50), rng.uniform(-1.5, 1.5, 50), rng.uniform(4, 10, 50)]
K = np.array([[500.0, 0, 320], [0, 500, 240], [0, 0, 1]])
p = lambda P: (P @ K.T)[:, :2] / (P @ K.T)[:, 2:]
np.savetxt("matches.txt", np.c_[p(X), p(X + np.array([1.0, 0, 0]))])
')
if qs=$(cd "$away/elsewhere" && env -u PYTHONPATH "$away/venv/bin/python" quickstart.py 2>&1) &&
   echo "$qs" | grep -q "^50 inliers" && echo "$qs" | grep -q "^0 42 (3, 4)$"; then
    ok "README Python quick start ran: $(echo "$qs" | head -n 1)"
else echo "$qs"; ko "README Python quick start"; fi

rm -rf "$out/src"
echo "$pass passed, $fail failed"
[ "$fail" -eq 0 ]
