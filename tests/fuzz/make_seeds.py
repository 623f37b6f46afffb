"""Writes the small seed corpus of each fuzz target under corpus/<target>/.
Run from the project root: .venv/bin/python tests/fuzz/make_seeds.py
(the seeds are committed; this records how they were made)."""
import base64
import os
import struct

import cv2
import numpy as np

ROOT = os.path.join(os.path.dirname(os.path.abspath(__file__)), "corpus")
rng = np.random.default_rng(7)


def put(target, name, data):
    d = os.path.join(ROOT, target)
    os.makedirs(d, exist_ok=True)
    with open(os.path.join(d, name), "wb") as f:
        f.write(data)


# PGM / PPM
img = rng.integers(0, 256, size=(6, 5), dtype=np.uint8)
put("pnm", "p5.pgm", b"P5\n5 6\n255\n" + img.tobytes())
put("pnm", "p5_comment.pgm", b"P5 # c\n# more\n5 6\n# x\n255\n" + img.tobytes())
put("pnm", "p6.ppm", b"P6\n3 2\n255\n" + rng.integers(0, 256, 18, dtype=np.uint8).tobytes())
put("pnm", "p2.pgm", b"P2\n3 2\n15\n0 1 2\n13 14 15\n")
put("pnm", "p3.ppm", b"P3\n2 1\n255\n255 0 0  0 0 255\n")
put("pnm", "p5_16bit.pgm", b"P5\n2 2\n65535\n" + struct.pack(">4H", 0, 1000, 40000, 65535))
put("pnm", "truncated.pgm", b"P5\n4 4\n255\n\x01\x02")

# Manifests
put("manifest", "three_columns.csv", b"sequence,timestamp_ns,file\n0,1000,00000000.pgm\n2,2000,00000001.pgm\n")
put("manifest", "euroc.csv", b"#timestamp [ns],filename\n1403636579763555584,1403636579763555584.png\n"
    b"1403636579813555456,1403636579813555456.png\n")
put("manifest", "crlf_spaces.csv", b"0, 5 ,a.pgm\r\n# note\r\n\r\n1,6, sub/b.png\r\n")
put("manifest", "bad_order.csv", b"0,10,a.pgm\n1,9,b.pgm\n")

# Raw frames for the converters: w-1, h-1, extra stride, bytes.
def raw(target, w, h, extra, bpp, rows):
    n = (w * bpp + extra) * (rows - 1) + w * bpp
    put(target, "%dx%d_pad%d" % (w, h, extra), bytes([w - 1, h - 1, extra]) + rng.integers(0, 256, n, dtype=np.uint8).tobytes())

raw("convert_gray8", 8, 4, 0, 1, 4)
raw("convert_gray8", 5, 3, 7, 1, 3)
raw("convert_yuyv", 8, 4, 0, 2, 4)
raw("convert_yuyv", 6, 2, 4, 2, 2)
raw("convert_rgb24", 4, 4, 0, 3, 4)
raw("convert_rgb24", 3, 2, 5, 3, 2)
raw("convert_nv12", 8, 4, 0, 1, 6)
raw("convert_nv12", 6, 4, 2, 1, 6)
put("convert_yuyv", "short", bytes([7, 3, 0]) + b"\x10" * 20)

# MJPEG: width-1 and height-1 as 16-bit little-endian, then a JPEG.
for name, im in [("gray16x8", (np.arange(128).reshape(8, 16) * 2).astype(np.uint8)),
                 ("color16x16", rng.integers(0, 256, size=(16, 16, 3), dtype=np.uint8))]:
    ok, jpg = cv2.imencode(".jpg", im, [cv2.IMWRITE_JPEG_QUALITY, 90])
    h, w = im.shape[:2]
    put("convert_mjpeg", name, struct.pack("<HH", w - 1, h - 1) + jpg.tobytes())
    put("convert_mjpeg", name + "_cut", struct.pack("<HH", w - 1, h - 1) + jpg.tobytes()[: len(jpg) // 2])

# sfm_features_align_points (tests/fuzz/fuzz_align.c): a parameter-selector
# byte (and the parameters it selects), two images (w-1, h-1, row padding,
# raw-pixel flag[, pixels]), n, then per coordinate pair a mode byte and
# either a raw double or a position byte and hundredths.
def image(w, h, pad, raw=b""):
    return bytes([w - 1, h - 1, pad, 1 if raw else 0]) + raw


def point(px, frac, dx):
    return bytes([0, px, frac, 128 + dx])


put("align", "empty", b"")
put("align", "four_points", b"\x00" + image(40, 30, 3) + image(40, 30, 0) + b"\x04" +
    b"".join(point(p, 37, d) for p, d in ((12, 10), (11, 5), (20, -20), (15, 0), (25, 3), (14, -4), (18, 9), (10, 1))))
put("align", "raw_doubles", b"\x00" + image(48, 40, 1) + image(48, 40, 1) + b"\x02" +
    b"\x03" + struct.pack("<dd", 1e300, 20.0) + b"\x03" + struct.pack("<dd", 2.0 ** 31, -2.0 ** 31) +
    b"\x01" + struct.pack("<d", 20.0) + b"\x80" + b"\x02\x10\x90" + struct.pack("<d", float("nan")))
put("align", "bad_radius", b"\x01\x0b" + image(30, 30, 0) + image(30, 30, 0) + b"\x01" + point(15, 0, 0) * 2)
put("align", "params", b"\x1c" + struct.pack("<ddd", 0.5, -1.0, 0.0) + image(24, 20, 2) + image(24, 20, 2) + b"\x02" +
    point(10, 50, 30) + point(9, 0, 0) + point(12, 0, -30) + point(11, 0, 0))
put("align", "tiny_raw", b"\x00" + image(2, 1, 0, b"\x00\xff") + image(1, 1, 0, b"\x80") + b"\x01" + point(0, 0, 0) * 2)

# sfm_selfcal_solve (tests/fuzz/fuzz_selfcal.c): 10-byte records (op, index,
# 8 value bytes: a special value when the first is below 64, else a double).
def rec(op, idx, value=b"\x00"):
    return bytes([op, idx]) + (value + b"\x00" * 8)[:8]


def dbl(v):
    b = struct.pack("<d", v)
    return b if b[0] >= 64 else bytes([64]) + b[1:]  # keep it a raw double


put("selfcal", "empty", b"")
put("selfcal", "p_nan", rec(0, 7, b"\x07"))
put("selfcal", "x_zero_rows", b"".join(rec(1, k, b"\x00") for k in range(16)))
put("selfcal", "wh_one", b"".join(rec(2, k, b"\x02") for k in range(10)))
put("selfcal", "obs_view_out_of_range", rec(4, 3, b"\x07"))
put("selfcal", "obs_point_negative", rec(5, 69, b"\x00"))
put("selfcal", "ws_one_short", rec(9, 0, b"\x00"))
put("selfcal", "two_views", rec(7, 2))
put("selfcal", "largest_model", rec(10, 4, b"\x01") + rec(10, 5, b"\x02"))
put("selfcal", "shared_pp_sizes_differ", rec(10, 5, b"\x01") + rec(2, 4, dbl(700.0)))
put("selfcal", "pixels_moved", rec(3, 11, dbl(1e6)) + rec(3, 40, dbl(-3.5)) + rec(6, 60))
put("selfcal", "cameras_rescaled", rec(12, 0, dbl(1e-318)) + rec(12, 1, dbl(1e180)) + rec(12, 2, dbl(-3e-20)))
put("selfcal", "focal_range", rec(10, 2, dbl(1e-300)) + rec(10, 3, dbl(1e300)) + rec(11, 2, b"\xff"))
# found by fuzz_align: the last step of a point converging onto the border
# of a 37 x 29 image crossed it unsampled (fixed in align.c)
put("align", "border_last_step", base64.b64decode(
    "AC8nJ+Tk5HlCBgBQYQAADOTkDOQMDAwMDAwMDAwMDAwMDAwMDgzkRwAAAAAAAAAM5OQM5AwMDAwMDgwMDAwMDAwMDOTk5Bg="))

# the stereo entry points (tests/fuzz/fuzz_stereo.c): byte 0 picks the call
def cam(model, f, cx, cy):
    return bytes([model]) + struct.pack("<dddd", f, f, cx, cy) + b"\x00" * 5


def rect_seed(t, alpha=0.0, w=40, h=30, R=(1, 0, 0, 0, 1, 0, 0, 0, 1)):
    return (b"\x00" + cam(0, 40.0, 19.5, 14.5) * 2 + struct.pack("<9d", *R) +
            struct.pack("<3d", *t) + struct.pack("<d", alpha) + bytes([w, h, 0, 0]))


put("stereo", "rectify_horizontal", rect_seed((-0.1, 0.0, 0.0)))
put("stereo", "rectify_vertical", rect_seed((0.0, -0.1, 0.0), alpha=1.0))
put("stereo", "rectify_coincident", rect_seed((0.0, 0.0, 0.0)))
put("stereo", "rectify_nan", rect_seed((float("nan"), 0.0, 0.0)))
put("stereo", "rectify_1x1", rect_seed((-0.1, 0.0, 0.0), w=1, h=1))
put("stereo", "remap_small", b"\x01" + bytes([7, 5, 1, 4, 3, 1, 0]) + bytes(range(64)) * 4)
put("stereo", "remap_1x1_far", b"\x01" + bytes([0, 0, 0, 1, 1, 0, 0, 0x50]) + b"\x01" +
    struct.pack("<i", 2 ** 31 - 1) + b"\x01" + struct.pack("<i", -2 ** 31))
put("stereo", "sgm_noise", b"\x02" + bytes([8, 4, 1, 0, 2, 1, 5, 60, 2]) + rng.bytes(2 * 24 * 20))
put("stereo", "sgm_wide_range", b"\x02" + bytes([0, 0, 1, 0xf0, 4, 0, 5, 60, 2]) + rng.bytes(2 * 16 * 16))
put("stereo", "block_flat", b"\x03" + bytes([4, 4, 1, 0, 2]) + b"\x80" * (2 * 20 * 20) + bytes([2, 8, 2]))
put("stereo", "block_negative", b"\x03" + bytes([0, 0, 1, 0xf8, 1]) + rng.bytes(2 * 16 * 16) + bytes([1, 0, 0]))
put("stereo", "empty", b"")

# the sequence pipeline (tests/fuzz/fuzz_vo.c): dims, workspace mode, camera
# (model / calibrated byte, flags, raw doubles), parameter records, clock,
# texture seed, frames (mode, flags, stride pad, timestamp step, content,
# gravity, read-out selector)
VO_FIELDS = {"track_radius": 0, "init_radius": 1, "ratio": 3, "threshold": 4, "max_iterations": 6,
             "min_inliers": 7, "min_parallax_deg": 9, "ba_iterations": 14, "use_trifocal": 15,
             "seed": 16, "frame_budget": 17, "max_features": 18, "window": 19, "n_levels": 20,
             "scale_factor": 21, "calibrated": 24}


def vo_rec(field, value):
    f = VO_FIELDS[field]
    if isinstance(value, float):
        return bytes([f]) + struct.pack("<d", value)
    return bytes([f]) + struct.pack("<q", value)


def vo_frame(mode, content=b"", flags=0, pad=0, dts=33, gravity=None, read=0):
    """mode 0 tile (content: pw-1, ph-1, pixels), 1 scene (content: offset,
    dy as int8), 2 the previous frame, 3 flat (content: gray); flags: 1 NULL
    image, 2 NULL data, 4 NULL result, 8 another size, 16 short stride, 32
    covariance, 64 reset first, 128 gravity (then gravity: an even byte, down
    the y axis tilted by its bits 1-3 and 4-6 in hundredths, or b"\\x01" + 3
    doubles)."""
    g = b""
    if gravity is not None:
        flags |= 128
        g = gravity
    return bytes([mode, flags, pad, dts & 0xff]) + content + g + bytes([read])


def vo_seed(frames, w=96, h=72, nf=200, win=5, ws=0, model=0, calibrated=0, cam_flags=0,
            cam=b"", recs=(), clock=0, tex_seed=11):
    return (bytes([w - 33, h - 33, nf - 8 if nf >= 8 else nf, win - 3 if win >= 3 else win, ws,
                   model | (calibrated << 2), cam_flags]) + cam + bytes([len(recs)]) + b"".join(recs) +
            bytes([clock]) + struct.pack("<I", tex_seed) + bytes([len(frames)]) + b"".join(frames))


# the scene's shifts are whole pixels: a 0.5 px threshold lets the 5-point
# support test (rotation sd) pass on a 96 x 72 frame
SHARP = vo_rec("threshold", 0.5)


def slide(step, n=6, **kw):
    return [vo_frame(1, struct.pack("<bb", step * k - 20, 0), **kw) for k in range(n)]


put("vo", "empty", b"")
put("vo", "scene_slide", vo_seed(slide(4), recs=[SHARP]))
put("vo", "scene_gravity_covariance", vo_seed(slide(4, flags=32, gravity=b"\x00"), recs=[SHARP]))
put("vo", "scene_clock_budget", vo_seed(slide(4), clock=5, recs=[SHARP, vo_rec("frame_budget", 0.01)]))
put("vo", "scene_self_calibration", vo_seed(slide(5, n=4), calibrated=1, recs=[SHARP]))
put("vo", "scene_fisheye", vo_seed(slide(4), model=2, cam_flags=32 | 64, recs=[SHARP]))
put("vo", "identical_frames", vo_seed([vo_frame(1, b"\x00\x00")] + [vo_frame(2)] * 5))
put("vo", "tiles_flat_small", vo_seed([vo_frame(0, bytes([7, 7]) + rng.bytes(64), pad=3),
                                       vo_frame(3, b"\x80"), vo_frame(0, b"\x00\x00\x00")],
                                      w=33, h=33, nf=8, win=3))
put("vo", "bad_frames", vo_seed([vo_frame(1, b"\x00\x00"), vo_frame(1, b"\x04\x00", flags=1),
                                 vo_frame(1, b"\x04\x00", flags=2), vo_frame(1, b"\x04\x00", flags=4),
                                 vo_frame(1, b"\x04\x00", flags=8), vo_frame(1, b"\x04\x00", flags=16)]))
put("vo", "bad_time_gravity", vo_seed([vo_frame(1, b"\x00\x00"), vo_frame(1, b"\x04\x00", dts=-1),
                                       vo_frame(1, b"\x04\x00", gravity=b"\x01" + struct.pack("<3d", 0, float("nan"), 0)),
                                       vo_frame(1, b"\x04\x00", gravity=b"\x01" + struct.pack("<3d", 0, 0, -0.0)),
                                       vo_frame(1, b"\x08\x00", flags=64, dts=-5, read=2),
                                       vo_frame(1, b"\x0c\x00", read=3 | 128)]))
put("vo", "camera_nan", vo_seed(slide(4, n=2), cam_flags=1, cam=struct.pack("<d", float("nan"))))
put("vo", "camera_zero_focal", vo_seed(slide(4, n=2), cam_flags=1, cam=struct.pack("<d", 0.0)))
# a mirrored camera (negative fx) is valid: reported focal -96 (fuzz_vo's
# first run took focal >= 0 for an invariant)
put("vo", "camera_negative_focal", vo_seed(slide(4), cam_flags=1, cam=struct.pack("<d", -96.0), recs=[SHARP]))
put("vo", "camera_huge_focal", vo_seed(slide(4), model=1, cam_flags=1 | 32 | 64, cam=struct.pack("<d", 1e300)))
put("vo", "camera_unknown_model", vo_seed(slide(4, n=2), model=3))
put("vo", "brown_not_self_calibrated", vo_seed(slide(4, n=2), model=1, calibrated=1))
put("vo", "ws_one_short", vo_seed(slide(4, n=1), ws=1))
put("vo", "dims_out_of_range", vo_seed(slide(4, n=1), nf=248 + 8, win=250 + 3))
put("vo", "hostile_params", vo_seed(slide(4), recs=[vo_rec("track_radius", 1e300), vo_rec("init_radius", 1e300),
                                                    vo_rec("threshold", 1e300), vo_rec("min_inliers", 6),
                                                    vo_rec("seed", -1), vo_rec("ba_iterations", 0)]))
put("vo", "params_nan", vo_seed(slide(4, n=2), recs=[vo_rec("ratio", float("nan"))]))

# the leader-follower filter (tests/fuzz/fuzz_r2r_motion.c): a sensor byte
# (1 range, 2 bearing, 0 and 3 unknown), then the 28 doubles the target reads
# in order, here its own defaults with one field replaced per seed
R2R_DEFAULTS = {
    "x": (2.0, 0.5, 0.1),
    "P": (0.1, 0, 0, 0, 0.1, 0, 0, 0, 0.01),
    "leader_d": (0.1, 0.0), "leader_w": 0.05, "follower_w": 0.02, "follower_d": (0.1, 0.0),
    "sigma": (0.01, 0.01, 0.01, 0.01, 0.05),  # leader d, leader w, follower d, follower w, meas
    "d0": (0.0, 0.0), "radius": 0.5, "min_distance": 0.0, "z": 1.0,
}
R2R_ORDER = ("x", "P", "leader_d", "leader_w", "follower_w", "follower_d", "sigma", "d0", "radius",
             "min_distance", "z")


def r2r_seed(sensor, **changes):
    fields = dict(R2R_DEFAULTS, **changes)
    vals = []
    for name in R2R_ORDER:
        v = fields[name]
        vals.extend(v if isinstance(v, tuple) else (v,))
    return bytes([sensor]) + struct.pack("<%dd" % len(vals), *vals)


put("r2r_motion", "empty", b"\x01")
put("r2r_motion", "nominal_range", r2r_seed(1))
put("r2r_motion", "nominal_bearing", r2r_seed(2))
put("r2r_motion", "unknown_sensor", r2r_seed(3))
put("r2r_motion", "at_leader", r2r_seed(1, x=(0.0, 0.0, 0.1)))
put("r2r_motion", "nan_state", r2r_seed(2, x=(float("nan"), 0.5, 0.1)))
put("r2r_motion", "huge_heading", r2r_seed(2, x=(2.0, 0.5, 1e154)))
put("r2r_motion", "huge_bearing", r2r_seed(2, z=1e154))
put("r2r_motion", "covariance_overflow", r2r_seed(2, P=(0.1, 0, 0, 0, 0.1, 0, 0, 0, 1e308)))
put("r2r_motion", "sigma_overflow", r2r_seed(1, sigma=(0.01, 0.01, 1e308, 0.01, 0.05)))
