"""Instructions per relative-pose RANSAC call (callgrind) on the scenes of
bench/ransac_bench.py, for one or two builds of libsfm.a side by side.

Writes the first --scenes scenes of each row (same generator and seeds as
ransac_bench.py) to a file, builds bench/ransac_callgrind.c against each
libsfm.a given, and prints callgrind's instruction count per call (whole
program over the row's scenes, divided by their number; start-up is the
same for every build) and the ratio of the second build to the first.

Usage: python bench/ransac_callgrind.py [--scenes 5] [--rows "unit,200,0.25,2;..."]
       build/libsfm.a [other/libsfm.a]
"""
import argparse
import os
import re
import struct
import subprocess
import sys
import tempfile

import numpy as np

HERE = os.path.dirname(os.path.abspath(__file__))
sys.path.insert(0, HERE)
import ransac_bench as rb  # noqa: E402

ROWS = [("unit", 200, 0.25, 1.0), ("unit", 200, 0.5, 2.0), ("unit", 1000, 0.5, 2.0),
        ("unit", 1000, 0.75, 1.0), ("small", 1000, 0.25, 2.0), ("small", 1000, 0.5, 2.0),
        ("small", 1000, 0.75, 1.0), ("tiny", 1000, 0.5, 1.0)]


def scenes(row, count):
    cls, n, ratio, thr = row
    rng = rb.row_rng(cls, n, ratio, thr)
    return [rb.relpose_scene(rng, n, ratio, cls=cls)[:2] for _ in range(count)]


def instructions(drv, path):
    out = subprocess.run(["valgrind", "--tool=callgrind", "--callgrind-out-file=/dev/null", drv, path],
                         capture_output=True, text=True, check=True)
    return int(re.search(r"Collected : (\d+)", out.stderr).group(1))


def main():
    ap = argparse.ArgumentParser()
    ap.add_argument("--scenes", type=int, default=5)
    ap.add_argument("--rows", default=None,
                    help='rows instead of the default ones: "unit,200,0.25,2;small,1000,0.5,1"')
    ap.add_argument("libs", nargs="+")
    a = ap.parse_args()
    tmp = tempfile.mkdtemp()
    drivers = []
    for j, lib in enumerate(a.libs):
        drv = os.path.join(tmp, "drv%d" % j)
        subprocess.run(["cc", "-O2", "-I", os.path.join(HERE, "..", "include"),
                        os.path.join(HERE, "ransac_callgrind.c"), "-o", drv, lib, "-lm"], check=True)
        drivers.append(drv)
    print("row | " + " | ".join("M instr/call (%s)" % lib for lib in a.libs) +
          (" | ratio" if len(a.libs) == 2 else ""))
    rows = ROWS if a.rows is None else [
        (c, int(n), float(r), float(t)) for c, n, r, t in (x.split(",") for x in a.rows.split(";"))]
    for i, row in enumerate(rows):
        path = os.path.join(tmp, "row%d.bin" % i)
        sc = scenes(row, a.scenes)
        with open(path, "wb") as f:
            f.write(struct.pack("<iid", len(sc), row[1], row[3]))
            for p1, p2 in sc:
                f.write(np.ascontiguousarray(p1, dtype="<f8").tobytes())
                f.write(np.ascontiguousarray(p2, dtype="<f8").tobytes())
        counts = [instructions(d, path) / len(sc) for d in drivers]
        line = "%s N=%d %d%% %.0f px | " % (row[0], row[1], round(100 * row[2]), row[3])
        line += " | ".join("%.1f" % (c / 1e6) for c in counts)
        if len(counts) == 2:
            line += " | %.3f" % (counts[1] / counts[0])
        print(line, flush=True)


if __name__ == "__main__":
    main()
