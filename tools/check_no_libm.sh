#!/bin/sh
# Fails when a source of the core library calls a transcendental function of
# libm directly instead of its core/dmath.h name (sfmi_sin, ...): libm rounds
# differently on each target. Comments and strings are stripped first, so
# prose may still name the functions.
# Usage: check_no_libm.sh DIR...
set -eu
files=$(find "$@" -name '*.[ch]' ! -name 'dmath.[ch]' | sort)
if perl -0777 -ne '
    s{/\*.*?\*/}{ }gs; s{//[^\n]*}{}g; s{"(?:\\.|[^"\\])*"}{""}g;
    while (/(?<![\w.>])((?:hypot|cbrt|atan2?|a?sin|a?cos|a?tan|sincos|sinh|cosh|tanh|exp(?:2|m1)?|log(?:1p|2|10|b)?|pow|erfc?|[lt]gamma)[fl]?)\s*\(/g) {
        print "$ARGV: calls $1() of libm; use core/dmath.h\n"; $bad = 1;
    }
    END { exit($bad ? 1 : 0) }' $files; then
    echo "no-libm: 1 passed, 0 failed"
else
    echo "no-libm: 0 passed, 1 failed"
    exit 1
fi
