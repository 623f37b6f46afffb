#!/bin/sh
# Installs what `make test` needs on a fresh Debian 12 machine: Debian
# packages when run as root, and a local Python venv. A missing tool that
# cannot be installed is a loud failure, never a silent skip.
set -eu
cd "$(dirname "$0")/.."

DEB_PACKAGES="gcc g++ make cmake pkg-config
 gcc-aarch64-linux-gnu libc6-dev-arm64-cross qemu-user
 gcc-arm-none-eabi libnewlib-arm-none-eabi qemu-system-arm
 libeigen3-dev libceres-dev clang libclang-rt-14-dev
 libjpeg-dev libpng-dev libcamera-dev
 python3 python3-venv valgrind"

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
REQ=python/requirements-test.txt
if [ ! -x "$VENV/bin/python" ]; then
    echo "setup: creating Python venv in $VENV"
    python3 -m venv "$VENV"
fi
if [ ! -f "$VENV/.req-stamp" ] || ! cmp -s "$REQ" "$VENV/.req-stamp"; then
    echo "setup: installing Python packages from $REQ"
    "$VENV/bin/python" -m pip install -q --disable-pip-version-check -r "$REQ"
    cp "$REQ" "$VENV/.req-stamp"
fi
echo "setup: ok"
