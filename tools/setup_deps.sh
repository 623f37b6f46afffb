#!/bin/sh
# Installs what a make target needs on a fresh Debian 12 machine: Debian
# packages when run as root, and a local Python venv. A missing tool that
# cannot be installed is a loud failure, never a silent skip.
#   setup_deps.sh        everything `make test` needs (python/requirements-test.txt)
#   setup_deps.sh demo   what `make demo` needs: a compiler and numpy + OpenCV
#                        (python/requirements-demo.txt)
set -eu
cd "$(dirname "$0")/.."
mode=${1:-test}

case $mode in
demo)
    DEB_PACKAGES="gcc g++ make pkg-config python3 python3-venv"
    REQ=python/requirements-demo.txt ;;
test)
    DEB_PACKAGES="gcc g++ make cmake pkg-config
 gcc-aarch64-linux-gnu libc6-dev-arm64-cross qemu-user
 gcc-arm-none-eabi libnewlib-arm-none-eabi qemu-system-arm
 libeigen3-dev libceres-dev clang libclang-rt-14-dev
 libjpeg-dev libpng-dev libcamera-dev
 python3 python3-venv valgrind"
    REQ=python/requirements-test.txt ;;
*)
    echo "setup: unknown mode '$mode' (demo or test)" >&2; exit 2 ;;
esac

missing=""
for p in $DEB_PACKAGES; do
    dpkg-query -W -f='${Status}' "$p" 2>/dev/null | grep -q "install ok installed" || missing="$missing $p"
done
if [ -n "$missing" ]; then
    if [ "$(id -u)" = 0 ] && command -v apt-get >/dev/null; then
        echo "setup: installing Debian packages:$missing"
        export DEBIAN_FRONTEND=noninteractive
        apt-get update -q >/dev/null
        apt-get install -y -q --no-install-recommends $missing >/dev/null
    else
        echo "setup: FAILED: missing Debian packages:$missing" >&2
        echo "setup: run as root, or: sudo apt-get install$missing" >&2
        exit 1
    fi
fi

VENV=${PYTHON_VENV:-.venv}
STAMP=$VENV/.req-stamp-$mode
if [ ! -x "$VENV/bin/python" ]; then
    echo "setup: creating Python venv in $VENV"
    python3 -m venv "$VENV"
fi
if [ ! -f "$STAMP" ] || ! cmp -s "$REQ" "$STAMP"; then
    echo "setup: installing Python packages from $REQ"
    "$VENV/bin/python" -m pip install -q --disable-pip-version-check -r "$REQ"
    cp "$REQ" "$STAMP"
fi
echo "setup: ok ($mode)"
