"""Writes the small seed corpus of each fuzz target under corpus/<target>/.
Run from the project root: .venv/bin/python tests/fuzz/make_seeds.py
(the seeds are committed; this records how they were made)."""
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
