"""Recorded-frame replay through cffi: record a synthetic sequence, replay
it, and get back the same frames, timestamps and sequence numbers."""
import os

import numpy as np
import pytest

import libsfm
from libsfm import SfmError, frames


def synthetic(k, h=48, w=64):
    y, x = np.mgrid[0:h, 0:w]
    return ((x * 3 + y * 2 + k * 7 + ((x // 4) ^ (y // 4)) % 2 * 40) % 256).astype(np.uint8)


STAMPS = [1_700_000_000_000_000_000 + k * 33_333_333 + k * k for k in range(8)]


@pytest.mark.parametrize("fmt", ["pgm", "png"])
def test_record_then_replay_gives_back_frames_and_timestamps(tmp_path, fmt):
    d = tmp_path / "rec"
    with frames.Recorder(str(d), image_format=fmt) as r:
        for k, ts in enumerate(STAMPS):
            r.write(synthetic(k), ts, sequence=100 + 2 * k)
        assert r.count == len(STAMPS)
    with frames.open_replay(str(d)) as src:
        info = src.info
        assert (info["width"], info["height"], info["driver"]) == (64, 48, "replay")
        got = list(src)
        stats = src.stats
    assert [f.timestamp_ns for f in got] == STAMPS
    assert [f.sequence for f in got] == [100 + 2 * k for k in range(len(STAMPS))]
    for k, f in enumerate(got):
        assert f.image.dtype == np.uint8 and f.image.shape == (48, 64)
        np.testing.assert_array_equal(f.image, synthetic(k))
    assert stats == {"frames": len(STAMPS), "drops": len(STAMPS) - 1, "errors": 0}


def test_rgb_frames_replay_as_bt601_gray(tmp_path):
    rgb = np.random.default_rng(1).integers(0, 256, size=(10, 12, 3), dtype=np.uint8)
    with frames.Recorder(str(tmp_path / "c")) as r:
        r.write(rgb, 5)
    (f,) = list(frames.open_replay(str(tmp_path / "c")))
    ref = rgb.astype(np.float64) @ np.array([0.299, 0.587, 0.114])
    assert np.max(np.abs(f.image - ref)) <= 1.0


def test_bad_arguments_raise_before_c(tmp_path):
    with frames.Recorder(str(tmp_path / "x")) as r:
        with pytest.raises(ValueError):
            r.write(np.zeros((4, 4), dtype=np.float64), 0)
        with pytest.raises(ValueError):
            r.write(np.zeros((4, 4, 2), dtype=np.uint8), 0)
        r.write(np.zeros((4, 4), dtype=np.uint8), 10)
        with pytest.raises(libsfm.SfmError):
            r.write(np.zeros((4, 4), dtype=np.uint8), 5)  # time going back
    with pytest.raises(ValueError):
        frames.open_replay(str(tmp_path / "x"), rate="sometimes")
    with pytest.raises(ValueError):
        frames.Recorder(str(tmp_path / "y"), image_format="bmp")


def test_missing_recording_is_a_clear_error(tmp_path):
    with pytest.raises(libsfm.SfmError) as e:
        frames.open_replay(str(tmp_path / "nothing"))
    assert e.value.status == -11  # SFM_E_NO_DEVICE


def test_device_where_one_exists():
    if not os.path.exists("/dev/video0"):
        pytest.skip("no /dev/video0 on this machine")
    with frames.open_device("/dev/video0") as src:
        f = src.read()
        assert f.image.ndim == 2


def test_libcamera_without_a_camera():
    ids = frames.list_libcamera()
    if ids:
        pytest.skip("a camera is attached: %s" % ids)
    with pytest.raises(libsfm.SfmError) as e:
        frames.open_libcamera()
    assert e.value.status == -11  # SFM_E_NO_DEVICE


def test_missing_v4l2_device_is_no_device():
    with pytest.raises(libsfm.SfmError) as e:
        frames.open_device("/dev/sfm-no-such-video")
    assert e.value.status == -11
    with pytest.raises(ValueError):
        frames.open_device("/dev/video0", pixel_format="rgb")


def test_recorder_refuses_a_frame_of_another_size_or_kind(tmp_path):
    """The recorder wrote such frames; its own replay then refused the
    recording."""
    d = tmp_path / "rec"
    with frames.Recorder(str(d)) as r:
        r.write(np.zeros((4, 6), np.uint8), 10)
        with pytest.raises(SfmError) as e:
            r.write(np.zeros((4, 7), np.uint8), 20)
        assert e.value.argument == "image" and e.value.name == "SFM_E_ARGUMENT"
        with pytest.raises(SfmError):
            r.write(np.zeros((4, 6, 3), np.uint8), 20)
        with pytest.raises(ValueError, match="timestamp_ns"):
            r.write(np.zeros((4, 6), np.uint8), -1)
        with pytest.raises(ValueError, match="sequence"):
            r.write(np.zeros((4, 6), np.uint8), 30, sequence=2 ** 64)
        r.write(np.ones((4, 6), np.uint8), 30)
        assert r.count == 2
    got = list(frames.open_replay(str(d)))
    assert [f.timestamp_ns for f in got] == [10, 30]


def test_replay_refuses_a_frame_linked_outside_the_recording(tmp_path):
    d = tmp_path / "rec"
    with frames.Recorder(str(d)) as r:
        r.write(np.zeros((4, 6), np.uint8), 10)
        r.write(np.zeros((4, 6), np.uint8), 20)
    outside = tmp_path / "elsewhere.pgm"
    os.rename(str(d / "00000001.pgm"), str(outside))
    os.symlink(str(outside), str(d / "00000001.pgm"))
    with pytest.raises(SfmError) as e:
        frames.open_replay(str(d))
    assert e.value.name == "SFM_E_FORMAT"


def test_source_integers_are_checked(tmp_path):
    d = tmp_path / "rec"
    with frames.Recorder(str(d)) as r:
        r.write(np.zeros((4, 6), np.uint8), 10)
    with pytest.raises(ValueError, match="timeout_ms"):
        frames.open_replay(str(d), timeout_ms=2 ** 31)
    with pytest.raises(TypeError, match="timeout_ms"):
        frames.open_replay(str(d), timeout_ms=1.5)
