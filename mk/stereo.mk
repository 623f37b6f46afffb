# Dense stereo beside OpenCV's StereoSGBM and StereoBM, single thread, one run.
#   make bench-stereo
BENCH_STEPS += bench-stereo

bench-stereo: all
	PYTHONPATH=python $(PYTHON) bench/stereo_bench.py
.PHONY: bench-stereo
