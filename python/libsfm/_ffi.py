"""Loads libsfm.so in cffi ABI mode and converts arrays and statuses.

The library is looked for in this order (see _find_library): LIBSFM_LIBRARY,
the copy inside the package, the build tree of a source checkout, then the
system loader (libsfm.so.<major> from an installed prefix, LD_LIBRARY_PATH).
`_ffi._libpath` is the file loaded, `_ffi._found_by` which rule found it.

The cdef is the public headers after the preprocessor (tools/gen_cdef.sh),
kept beside the library it describes, so the two cannot disagree.
"""
import os

import numpy as np
from cffi import FFI

_HERE = os.path.dirname(os.path.abspath(__file__))
_ROOT = os.path.dirname(os.path.dirname(_HERE))
# The shared object's major version this binding is written for
# (SFM_VERSION_MAJOR; the file is libsfm.so.<major>).
SO_MAJOR = 0


def _first(paths):
    return next((p for p in paths if p and os.path.exists(p)), None)


def _lib_in(directory, stem):
    """stem.so.<major> or stem.so in directory, or None."""
    return _first([os.path.join(directory, "%s.so.%d" % (stem, SO_MAJOR)),
                   os.path.join(directory, stem + ".so")])


def _loaded_path(stem):
    """The file the system loader mapped for stem (Linux), or None."""
    try:
        with open("/proc/self/maps") as f:
            for line in f:
                path = line.split(None, 5)[-1].strip()
                if os.path.basename(path).startswith(stem + ".so"):
                    return path
    except OSError:
        pass
    return None


def _find_library():
    """(path or soname, how it was found) of libsfm, in the documented order:

    1. LIBSFM_LIBRARY, a path to the shared object;
    2. the copy inside this package (a wheel or `pip install` carries it);
    3. the build tree of the source checkout this package sits in
       (python/libsfm beside build/, after `make`);
    4. the system loader: libsfm.so.<major> through LD_LIBRARY_PATH, the
       ldconfig cache and the default directories (an installed prefix).
    """
    env = os.environ.get("LIBSFM_LIBRARY")
    if env:
        if not os.path.exists(env):
            raise OSError("LIBSFM_LIBRARY=%s: no such file" % env)
        return env, "LIBSFM_LIBRARY"
    inside = _lib_in(_HERE, "libsfm")
    if inside:
        return inside, "package"
    tree = _lib_in(os.path.join(_ROOT, "build"), "libsfm")
    if tree and os.path.exists(os.path.join(_ROOT, "Makefile")):
        return tree, "build tree"
    return "libsfm.so.%d" % SO_MAJOR, "system loader"


def _find_cdef(libpath, name="sfm_cdef.h", env="LIBSFM_CDEF"):
    """The cdef that describes libpath: env, beside it, in the package, or in
    <prefix>/share/sfm for a library in <prefix>/lib."""
    libdir = os.path.dirname(libpath)
    found = _first([os.environ.get(env),
                    os.path.join(libdir, name),
                    os.path.join(libdir, "..", "share", "sfm", name),
                    os.path.join(libdir, "..", "..", "share", "sfm", name),
                    os.path.join(_HERE, name)])
    if found is None:
        raise OSError("%s not found beside %s (nor in ../share/sfm): run `make`, or set %s" % (name, libpath, env))
    return found


def _open():
    path, how = _find_library()
    lib_ffi = FFI()
    if how == "system loader":
        try:
            handle = lib_ffi.dlopen(path)
        except OSError:
            raise OSError("libsfm not found: not in the package, no build tree, and the system loader has no %s "
                          "(pip install the package, run `make`, `make install`, or set LIBSFM_LIBRARY)" % path)
        path = _loaded_path("libsfm") or path
        lib_ffi.dlclose(handle)
    with open(_find_cdef(path)) as f:
        lib_ffi.cdef(f.read())
    return lib_ffi, lib_ffi.dlopen(path), path, how


def find_companion(stem, env):
    """A library built beside libsfm (libsfm_capture): env, then beside the
    loaded libsfm, then the build tree, then the system loader's soname."""
    path = _first([os.environ.get(env), _lib_in(os.path.dirname(_libpath), stem),
                   _lib_in(os.path.join(_ROOT, "build"), stem)])
    return path or "%s.so.%d" % (stem, SO_MAJOR)


ffi, lib, _libpath, _found_by = _open()


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
