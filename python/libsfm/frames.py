"""Frames from a recording or a camera, as numpy images with timestamps.

    from libsfm import frames
    for f in frames.open_replay("run1"):
        f.image          # (height, width) uint8, a copy
        f.timestamp_ns   # int
        f.sequence       # int

Sources are the C capture library (libsfm_capture.so, built by
`make capture`), loaded on first use with its own cdef
(build/sfm_capture_cdef.h); `frames.Recorder` writes such a recording.
"""
import collections
import os

import numpy as np
from cffi import FFI

from . import _ffi
from ._ffi import SfmError, to_float, to_int

__all__ = ["Frame", "Source", "Recorder", "open_replay", "open_device", "open_libcamera",
           "list_libcamera"]

Frame = collections.namedtuple("Frame", "image timestamp_ns sequence")

_cap = {}

_IMAGE_FORMATS = {"pgm": 0, "png": 1, "jpg": 2, "jpeg": 2}
_PIXFMT = {None: 0, "grey": 1, "gray": 1, "yuyv": 2, "nv12": 3, "mjpeg": 4}


def _load():
    """(ffi, lib) of libsfm_capture.so, loaded once."""
    if "lib" not in _cap:
        path = _ffi.find_companion("libsfm_capture", "LIBSFM_CAPTURE_LIBRARY")
        ffi = FFI()
        try:
            handle = ffi.dlopen(path)
        except OSError:
            raise OSError("libsfm_capture.so not found beside %s: run `make capture` or set LIBSFM_CAPTURE_LIBRARY"
                          % _ffi._libpath)
        if not os.path.isabs(path):
            path = _ffi._loaded_path("libsfm_capture") or path
        ffi.dlclose(handle)
        cdef = _ffi._find_cdef(path, "sfm_capture_cdef.h", "LIBSFM_CAPTURE_CDEF")
        ffi = FFI()
        with open(cdef) as f:
            ffi.cdef(f.read())
        _cap["ffi"] = ffi
        _cap["lib"] = ffi.dlopen(path)
    return _cap["ffi"], _cap["lib"]


def _check(status, where):
    if status < 0:
        raise SfmError(status, where)
    return status


class _Closing:
    """`with` support and close() at collection for a class with close()."""

    def __enter__(self):
        return self

    def __exit__(self, *exc):
        self.close()

    def __del__(self):
        try:
            self.close()
        except Exception:
            pass


class Source(_Closing):
    """A frame source: iterate for Frame tuples; close() (or `with`) when done.

    Each frame's image is copied out of the source's buffer, so it stays
    valid after the next frame arrives.
    """

    def __init__(self, handle, timeout_ms):
        self._ffi, self._lib = _load()
        self._c = handle
        self.timeout_ms = to_int(timeout_ms, "timeout_ms")

    @property
    def info(self):
        """dict: width, height (pixels), source_format, fourcc, buffers, fps
        (frames per second or None), driver, card."""
        ffi, lib = self._ffi, self._lib
        i = ffi.new("sfm_capture_info *")
        _check(lib.sfm_capture_get_info(self._c, i), "info")
        return {
            "width": i.width, "height": i.height,
            "source_format": ffi.string(lib.sfm_pixfmt_name(i.source_format)).decode(),
            "fourcc": i.fourcc, "buffers": i.buffers,
            "fps": (i.fps_num / i.fps_den) if i.fps_den else None,
            "driver": ffi.string(i.driver).decode(errors="replace"),
            "card": ffi.string(i.card).decode(errors="replace"),
        }

    @property
    def stats(self):
        """dict: frames delivered, drops (sequence gaps), errors."""
        s = self._ffi.new("sfm_capture_stats *")
        _check(self._lib.sfm_capture_get_stats(self._c, s), "stats")
        return {"frames": s.frames, "drops": s.drops, "errors": s.errors}

    def read(self, timeout_ms=None):
        """The next Frame, or None at the end of a recording. Raises SfmError
        on timeout, a lost device or an unreadable frame."""
        if self._c is None:
            raise ValueError("source is closed")
        ffi, lib = self._ffi, self._lib
        f = ffi.new("sfm_frame *")
        t = self.timeout_ms if timeout_ms is None else to_int(timeout_ms, "timeout_ms")
        rc = _check(lib.sfm_capture_acquire(self._c, t, f), "acquire")
        if rc == 0:
            return None
        try:
            h, w, stride = f.height, f.width, f.stride
            buf = ffi.buffer(f.data, stride * (h - 1) + w)
            rows = np.frombuffer(buf, dtype=np.uint8, count=stride * (h - 1) + w)
            img = np.lib.stride_tricks.as_strided(rows, shape=(h, w), strides=(stride, 1)).copy()
            return Frame(img, int(f.timestamp_ns), int(f.sequence))
        finally:
            _check(lib.sfm_capture_release(self._c, f), "release")

    def __iter__(self):
        return self

    def __next__(self):
        fr = self.read()
        if fr is None:
            raise StopIteration
        return fr

    def close(self):
        """Release the source (idempotent)."""
        if self._c is not None:
            self._lib.sfm_capture_close(self._c)
            self._c = None


def open_replay(directory, rate="max", speed=1.0, loop=False, timeout_ms=-1):
    """A recording (manifest.csv or data.csv plus images) as a Source.

    rate: "max" (as fast as read), "recorded" (at the recorded pace, `speed`
    times faster) or a number of frames per second; loop: start again after
    the last frame; timeout_ms: how long read() waits for a frame that is
    not due yet (milliseconds, -1 forever). Frames are (h, w) uint8 gray.
    A frame file whose resolved path (symbolic links followed) leaves the
    directory is refused (SfmError SFM_E_FORMAT).
    """
    ffi, lib = _load()
    o = ffi.new("sfm_replay_options *")
    if rate == "max":
        o.rate = 0
    elif rate == "recorded":
        o.rate = 1
    elif isinstance(rate, (int, float)) and not isinstance(rate, bool) and rate > 0:
        o.rate, o.fixed_fps = 2, to_float(rate, "rate")
    else:
        raise ValueError("rate must be 'max', 'recorded' or a positive number, got %r" % (rate,))
    speed = to_float(speed, "speed")
    if not speed > 0:
        raise ValueError("speed must be positive, got %r" % speed)
    o.speed = speed
    o.loop = 1 if loop else 0
    out = ffi.new("sfm_capture **")
    _check(lib.sfm_capture_open_replay(os.fsencode(directory), o, out), "open_replay(%s)" % directory)
    return Source(out[0], timeout_ms)


def open_device(device="/dev/video0", width=0, height=0, pixel_format=None, fps=0,
                buffers=0, timeout_ms=2000):
    """A V4L2 camera as a Source (frames delivered as (h, w) uint8 gray).

    width, height: requested size in pixels (0: the driver's); pixel_format:
    None (first offered of grey, nv12, yuyv, mjpeg) or one of those names;
    fps: requested frames per second (0: as is); buffers: driver buffers (0:
    4); timeout_ms: read()'s wait in milliseconds (-1 forever).
    """
    if pixel_format not in _PIXFMT:
        raise ValueError("pixel_format must be one of grey, yuyv, nv12, mjpeg or None")
    ffi, lib = _load()
    o = ffi.new("sfm_v4l2_options *")
    o.width, o.height = to_int(width, "width", 0), to_int(height, "height", 0)
    o.format, o.fps, o.buffers = _PIXFMT[pixel_format], to_int(fps, "fps", 0), to_int(buffers, "buffers", 0)
    out = ffi.new("sfm_capture **")
    _check(lib.sfm_capture_open_v4l2(os.fsencode(device), o, out), "open_device(%s)" % device)
    return Source(out[0], timeout_ms)


def open_libcamera(camera_id=None, width=0, height=0, buffers=0, timeout_ms=2000):
    """A libcamera camera (e.g. a Raspberry Pi camera) as a Source.

    camera_id: an id from list_libcamera() or None for the first; width,
    height in pixels (0: the camera's default); buffers (0: 4); timeout_ms:
    read()'s wait in milliseconds."""
    ffi, lib = _load()
    o = ffi.new("sfm_libcamera_options *")
    o.width, o.height = to_int(width, "width", 0), to_int(height, "height", 0)
    o.buffers = to_int(buffers, "buffers", 0)
    out = ffi.new("sfm_capture **")
    cid = ffi.NULL if camera_id is None else os.fsencode(camera_id)
    _check(lib.sfm_capture_open_libcamera(cid, o, out), "open_libcamera")
    return Source(out[0], timeout_ms)


def list_libcamera():
    """Camera ids libcamera reports (raises SfmError when unavailable)."""
    ffi, lib = _load()
    n = _check(lib.sfm_libcamera_list(ffi.NULL, 0, 0), "list_libcamera")
    if n == 0:
        return []
    ids = ffi.new("char[]", n * 256)
    n = _check(lib.sfm_libcamera_list(ids, n, 256), "list_libcamera")
    return [ffi.string(ids + 256 * k).decode() for k in range(n)]


class Recorder(_Closing):
    """Writes frames to a replay directory (created; must not hold a manifest).

    image_format: "pgm" (default, lossless), "png" (lossless) or "jpg".
    """

    def __init__(self, directory, image_format="pgm"):
        if image_format not in _IMAGE_FORMATS:
            raise ValueError("image_format must be pgm, png or jpg")
        self._ffi, self._lib = _load()
        out = self._ffi.new("sfm_recorder **")
        _check(self._lib.sfm_recorder_open(os.fsencode(directory), _IMAGE_FORMATS[image_format], out),
               "Recorder(%s)" % directory)
        self._r = out[0]
        self._next_seq = 0
        self._shape = None  # of the first frame: every frame must match it

    def write(self, image, timestamp_ns, sequence=None):
        """Append one frame. image: (h, w) gray or (h, w, 3) RGB uint8, of the
        size and kind of the first frame written (SfmError SFM_E_ARGUMENT
        otherwise, nothing written); timestamp_ns: int nanoseconds, never
        decreasing; sequence: int, increasing, default one more than the
        last."""
        if self._r is None:
            raise ValueError("recorder is closed")
        img = np.asarray(image)
        if img.dtype != np.uint8 or not (img.ndim == 2 or (img.ndim == 3 and img.shape[2] == 3)):
            raise ValueError("image must be uint8 of shape (h, w) or (h, w, 3), got %s %s" % (img.dtype, img.shape))
        if img.shape[0] < 1 or img.shape[1] < 1:
            raise ValueError("image must not be empty")
        img = np.ascontiguousarray(img)
        seq = self._next_seq if sequence is None else to_int(sequence, "sequence", 0, 2 ** 64 - 1)
        ts = to_int(timestamp_ns, "timestamp_ns", 0, 2 ** 63 - 1)
        ffi = self._ffi
        f = ffi.new("sfm_frame *")
        f.data = ffi.cast("const uint8_t *", ffi.from_buffer(img))
        f.height, f.width = img.shape[0], img.shape[1]
        f.stride = img.strides[0]
        f.format = 1 if img.ndim == 2 else 5
        f.timestamp_ns = ts
        f.sequence = seq
        st = self._lib.sfm_recorder_write(self._r, f)
        if st < 0:
            other = self._shape is not None and img.shape != self._shape
            raise SfmError(st, "Recorder.write", "image" if other else None)
        self._shape = self._shape or img.shape
        self._next_seq = seq + 1

    @property
    def count(self):
        """Frames written so far."""
        return _check(self._lib.sfm_recorder_count(self._r), "count") if self._r is not None else 0

    def close(self):
        """Close the manifest; raises SfmError when a write had failed."""
        if self._r is not None:
            r, self._r = self._r, None
            _check(self._lib.sfm_recorder_close(r), "Recorder.close")
