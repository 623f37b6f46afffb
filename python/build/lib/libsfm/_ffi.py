"""Loads libsfm.so in cffi ABI mode and converts arrays and statuses.

The cdef is the public headers after the preprocessor (tools/gen_cdef.sh),
kept beside the library it describes, so the two cannot disagree.
"""
import os

import numpy as np
from cffi import FFI

_HERE = os.path.dirname(os.path.abspath(__file__))
_ROOT = os.path.dirname(os.path.dirname(_HERE))


def _find_library():
    env = os.environ.get("LIBSFM_LIBRARY")
    candidates = [env] if env else []
    candidates += [
        os.path.join(_ROOT, "build", "libsfm.so"),
        os.path.join(_HERE, "libsfm.so"),
        "/usr/local/lib/libsfm.so",
        "/usr/lib/libsfm.so",
    ]
    for path in candidates:
        if path and os.path.exists(path):
            return path
    raise OSError("libsfm.so not found: run `make` or set LIBSFM_LIBRARY")


def _find_cdef(libpath):
    env = os.environ.get("LIBSFM_CDEF")
    candidates = [env] if env else []
    libdir = os.path.dirname(libpath)
    candidates += [
        os.path.join(libdir, "sfm_cdef.h"),
        os.path.join(libdir, "..", "share", "sfm", "sfm_cdef.h"),
    ]
    for path in candidates:
        if path and os.path.exists(path):
            return path
    raise OSError("sfm_cdef.h not found beside %s: run `make`" % libpath)


ffi = FFI()
_libpath = _find_library()
with open(_find_cdef(_libpath)) as f:
    ffi.cdef(f.read())
lib = ffi.dlopen(_libpath)


class SfmError(RuntimeError):
    """A libsfm call returned a negative status."""

    def __init__(self, status, where=""):
        self.status = int(status)
        self.message = ffi.string(lib.sfm_status_str(self.status)).decode()
        super().__init__("%s%s (status %d)" % (where + ": " if where else "", self.message, self.status))


def check(status, where=""):
    """Return a non-negative status unchanged; raise SfmError otherwise."""
    if status < 0:
        raise SfmError(status, where)
    return status


def as_array(a, shape, name="array"):
    """A C-contiguous float64 copy-or-view of `a`, checked against `shape`.

    `shape` entries may be None (any size) or an int. Raises ValueError before
    any C call when the shape does not fit.
    """
    arr = np.ascontiguousarray(np.asarray(a, dtype=np.float64))
    if arr.ndim != len(shape) or any(s is not None and s != d for s, d in zip(shape, arr.shape)):
        raise ValueError("%s must have shape %s, got %s" % (name, tuple("n" if s is None else s for s in shape), arr.shape))
    return arr


def dptr(arr):
    """double* into a C-contiguous float64 numpy array."""
    return ffi.cast("double *", ffi.from_buffer(arr))


def iptr(arr):
    """int* into a C-contiguous int32 numpy array."""
    return ffi.cast("int *", ffi.from_buffer(arr))


def workspace(nbytes):
    """A caller-owned workspace buffer of nbytes (numpy keeps it alive)."""
    buf = np.empty(max(int(nbytes), 1), dtype=np.uint8)
    return buf, ffi.from_buffer(buf), buf.nbytes
