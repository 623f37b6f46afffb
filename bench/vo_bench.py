"""VO speed, single thread, in one run: the libsfm pipeline on the rendered
640x480 demo sequence (500 features, 5-keyframe window) beside the OpenCV
frame-to-frame baseline (ORB, brute-force cross-check, findEssentialMat +
recoverPose) on the same frames; ms per frame (median, 95th percentile),
share per stage, windowed BA time per call. Frames are decoded before the
clock starts for both.

    PYTHONPATH=python .venv/bin/python bench/vo_bench.py [SEQ_DIR] [--frames N]
"""
import argparse
import os
import sys
import time

import numpy as np

sys.path.insert(0, os.path.join(os.path.dirname(__file__), "..", "python"))
from libsfm import replay  # noqa: E402
from libsfm.vo import STAGES, VisualOdometry  # noqa: E402


def main():
    ap = argparse.ArgumentParser()
    ap.add_argument("seq", nargs="?", default="build/demo/sequence")
    ap.add_argument("--frames", type=int, default=240)
    ap.add_argument("--features", type=int, default=500)
    ap.add_argument("--window", type=int, default=5)
    a = ap.parse_args()
    import cv2
    rec = replay.open_recording(a.seq)
    frames = [(t, cv2.imread(p, cv2.IMREAD_GRAYSCALE)) for t, p in rec.frames[:a.frames]]
    h, w = frames[0][1].shape
    # the demo's settings (mk/85-vo.mk, VO_DEMO_SET)
    vo = VisualOdometry(w, h, rec.camera, max_features=a.features, window=a.window, n_levels=3,
                        point_min_parallax_deg=1.0)
    ms, st, ba = [], [], []
    for t, img in frames:
        t0 = time.perf_counter()
        r = vo.push(img, t, gravity=None)
        ms.append((time.perf_counter() - t0) * 1e3)
        st.append([r.stage_seconds[s] * 1e3 for s in STAGES])
        if r.is_keyframe and r.stage_seconds["ba"] > 0:
            ba.append(r.stage_seconds["ba"] * 1e3)
    st = np.array(st)
    share = st.sum(0) / st.sum()
    K = np.array([[rec.camera[0], 0, rec.camera[2]], [0, rec.camera[1], rec.camera[3]], [0, 0, 1.0]])
    base = {}
    for nf in (500, 2000):
        orb = cv2.ORB_create(nf)
        bf = cv2.BFMatcher(cv2.NORM_HAMMING, crossCheck=True)
        prev, bms = None, []
        for _, img in frames:
            t0 = time.perf_counter()
            kp, des = orb.detectAndCompute(img, None)
            if prev is not None and des is not None and prev[1] is not None:
                m = bf.match(prev[1], des)
                if len(m) >= 5:
                    p0 = np.float64([prev[0][x.queryIdx].pt for x in m])
                    p1 = np.float64([kp[x.trainIdx].pt for x in m])
                    E, mask = cv2.findEssentialMat(p0, p1, K, method=cv2.RANSAC, prob=0.999, threshold=1.0)
                    if E is not None:
                        cv2.recoverPose(E[:3], p0, p1, K, mask=mask)
            bms.append((time.perf_counter() - t0) * 1e3)
            prev = (kp, des)
        base[nf] = bms
    print("VO speed, %d frames %dx%d (%s), single thread" % (len(frames), w, h, a.seq))
    print("%-44s %9s %9s" % ("", "median ms", "p95 ms"))
    print("%-44s %9.2f %9.2f" % ("libsfm VO (%d features, %d-keyframe window)" % (a.features, a.window),
                                 np.median(ms), np.percentile(ms, 95)))
    for nf, b in base.items():
        print("%-44s %9.2f %9.2f" % ("OpenCV ORB-%d + BF cross-check + E RANSAC" % nf, np.median(b), np.percentile(b, 95)))
    print("libsfm share per stage: " + ", ".join("%s %.0f%%" % (s, 100 * v) for s, v in zip(STAGES, share)))
    print("libsfm median ms per stage: " + ", ".join("%s %.2f" % (s, v) for s, v in zip(STAGES, np.median(st, 0))))
    if ba:
        print("windowed BA: %d calls, median %.2f ms, p95 %.2f ms per call" % (len(ba), np.median(ba), np.percentile(ba, 95)))
    fps_ok = 1e3 / np.median(ms), 1e3 / np.percentile(ms, 95)
    print("libsfm frames per second: %.1f at the median, %.1f at the 95th percentile" % fps_ok)


if __name__ == "__main__":
    main()
