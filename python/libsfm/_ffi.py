"""Loads libsfm.so in cffi ABI mode and converts arrays and statuses.

The library is looked for in this order (see _find_library): LIBSFM_LIBRARY,
the copy inside the package, the build tree of a source checkout, then the
system loader (libsfm.so.<major> from an installed prefix, LD_LIBRARY_PATH).
`_ffi._libpath` is the file loaded, `_ffi._found_by` which rule found it.

The cdef is the public headers after the preprocessor (tools/gen_cdef.sh),
kept beside the library it describes, so the two cannot disagree.
"""
import numbers
import operator
import os

import numpy as np
from cffi import FFI

_HERE = os.path.dirname(os.path.abspath(__file__))
_ROOT = os.path.dirname(os.path.dirname(_HERE))
# The shared object's major version this binding is written for
# (SFM_VERSION_MAJOR; the file is libsfm.so.<major>).
SO_MAJOR = 0
# Before 1.0 each minor version changes the API: the MINOR this binding's
# calls are written for (SFM_VERSION_MINOR); another one is refused at import.
API_MINOR = 3


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
if SO_MAJOR == 0 and lib.sfm_version() // 100 != API_MINOR:
    raise ImportError("%s is libsfm %d.%d; this binding drives %d.%d (rebuild or reinstall the library)"
                      % (_libpath, lib.sfm_version() // 10000, lib.sfm_version() // 100 % 100, SO_MAJOR,
                         API_MINOR))


class SfmError(RuntimeError):
    """A libsfm call returned a negative status.

    Attributes: status (the negative sfm_status value), name (its C name,
    e.g. "SFM_E_SINGULAR"), message (sfm_status_str), where (the C function
    or the Python call) and argument (the argument at fault when the binding
    can tell, else None)."""

    def __init__(self, status, where="", argument=None):
        self.status = int(status)
        self.message = ffi.string(lib.sfm_status_str(self.status)).decode()
        self.name = status_name(self.status)
        self.where = where
        self.argument = argument
        text = "%s%s%s (%s, status %d)" % (where + ": " if where else "",
                                            "argument %r: " % argument if argument else "",
                                            self.message, self.name, self.status)
        super().__init__(text)


def status_name(status):
    """The C name of a status value ("SFM_OK", "SFM_E_SINGULAR", ...)."""
    for name in dir(lib):
        if (name == "SFM_OK" or name.startswith("SFM_E_")) and getattr(lib, name) == status:
            return name
    return "status %d" % status


def check(status, where="", inputs=None, argument=None):
    """Return a non-negative status unchanged; raise SfmError otherwise.

    inputs: optional {name: array} of the call's float inputs; on
    SFM_E_NONFINITE the first one holding a NaN or an infinity is named in
    the error. argument: the argument to name for any failure."""
    if status < 0:
        if argument is None and inputs and status == lib.SFM_E_NONFINITE:
            for name, arr in inputs.items():
                if arr is not None and not np.all(np.isfinite(arr)):
                    argument = name
                    break
        raise SfmError(status, where, argument)
    return status


def _refuse_complex(arr, a, name):
    if np.iscomplexobj(arr) or isinstance(a, complex):
        raise TypeError("%s must be real, got complex values" % name)


def as_array(a, shape, name="array"):
    """A C-contiguous float64 copy-or-view of `a`, checked against `shape`.

    `shape` entries may be None (any size) or an int. Raises ValueError before
    any C call when the shape does not fit, TypeError for complex or
    non-numeric input (numpy would drop an imaginary part silently)."""
    raw = np.asarray(a)
    _refuse_complex(raw, a, name)
    if raw.dtype.kind not in "biuf":
        raise TypeError("%s must hold real numbers, got dtype %s" % (name, raw.dtype))
    arr = np.ascontiguousarray(raw, dtype=np.float64)
    if arr.ndim != len(shape) or any(s is not None and s != d for s, d in zip(shape, arr.shape)):
        raise ValueError("%s must have shape %s, got %s" % (name, tuple("n" if s is None else s for s in shape), arr.shape))
    return arr


INT_MIN, INT_MAX = -2 ** 31, 2 ** 31 - 1


def _index(value, name):
    """A Python int from an integer argument (numpy integers included);
    TypeError naming it for a bool, a float or anything else."""
    if isinstance(value, (bool, np.bool_)):
        raise TypeError("%s must be an integer, got a bool" % name)
    try:
        return operator.index(value)
    except TypeError:
        raise TypeError("%s must be an integer, got %s" % (name, type(value).__name__)) from None


def to_int(value, name, lo=INT_MIN, hi=INT_MAX):
    """An integer argument for a C int, checked to lie in [lo, hi] (within
    int32 by default). TypeError for a non-integer (floats included: 2.5
    would be truncated), ValueError naming the argument when out of range."""
    v = _index(value, name)
    if not lo <= v <= hi:
        raise ValueError("%s must be in [%d, %d], got %d" % (name, lo, hi, v))
    return v


def to_float(value, name, finite=True):
    """A real scalar argument; TypeError for complex or non-numbers,
    ValueError for NaN or infinity when finite."""
    if isinstance(value, (complex, np.complexfloating)):
        raise TypeError("%s must be real, got complex %r" % (name, value))
    if not isinstance(value, (numbers.Real, np.floating, np.integer)) or isinstance(value, bool):
        raise TypeError("%s must be a real number, got %s" % (name, type(value).__name__))
    v = float(value)
    if finite and not np.isfinite(v):
        raise ValueError("%s must be finite, got %r" % (name, v))
    return v


def to_seed(seed, name="seed"):
    """The seed rule used by every function: any Python (or numpy) integer,
    taken modulo 2**64 (so -1 is 2**64 - 1); the C generator takes uint64."""
    return _index(seed, name) % (1 << 64)


def int_array(a, shape, name, lo=INT_MIN, hi=INT_MAX):
    """A C-contiguous int32 copy of an integer array `a`, shape checked as in
    as_array, every entry checked to lie in [lo, hi] before the narrowing
    (an int64 index of 2**32 + 3 would otherwise wrap to 3)."""
    arr = np.asarray(a)
    _refuse_complex(arr, a, name)
    if arr.size == 0 and arr.dtype.kind == "f":
        arr = arr.astype(np.int64)
    if arr.dtype.kind not in "iu":
        raise TypeError("%s must hold integers, got dtype %s" % (name, arr.dtype))
    if arr.ndim != len(shape) or any(s is not None and s != d for s, d in zip(shape, arr.shape)):
        raise ValueError("%s must have shape %s, got %s" % (name, tuple("n" if s is None else s for s in shape), arr.shape))
    if arr.size:
        amin, amax = int(arr.min()), int(arr.max())
        if amin < lo or amax > hi:
            bad = amin if amin < lo else amax
            raise ValueError("%s entries must be in [%d, %d], got %d" % (name, lo, hi, bad))
    return np.ascontiguousarray(arr, dtype=np.int32)


def dptr(arr):
    """double* into a C-contiguous float64 numpy array."""
    return ffi.cast("double *", ffi.from_buffer(arr))


def mptr(arr):
    """sfm_mat3* into a C-contiguous float64 numpy array of 9 values (3 x 3, row-major)."""
    if arr.size != 9:
        raise ValueError("a 3x3 matrix has 9 values, got %d" % arr.size)
    return ffi.cast("sfm_mat3 *", ffi.from_buffer(arr))


def iptr(arr):
    """int* into a C-contiguous int32 numpy array."""
    return ffi.cast("int *", ffi.from_buffer(arr))


def u8ptr(arr):
    """uint8_t* into a C-contiguous uint8 numpy array."""
    return ffi.cast("uint8_t *", ffi.from_buffer(arr))


def workspace(nbytes):
    """A caller-owned workspace buffer of nbytes (numpy keeps it alive)."""
    buf = np.empty(max(int(nbytes), 1), dtype=np.uint8)
    return buf, ffi.from_buffer(buf), buf.nbytes
