# Robust estimation beside PoseLib and OpenCV (bench/ransac_bench.py).
BENCH_STEPS += bench-ransac

bench-ransac: all
	PYTHONPATH=python $(PYTHON) bench/ransac_bench.py
