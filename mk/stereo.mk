# Dense stereo beside OpenCV's StereoSGBM and StereoBM, single thread, one run,
# and the instruction counts of one frame of each matcher.
#   make bench-stereo   make bench-stereo-callgrind
BENCH_STEPS += bench-stereo

bench-stereo: all
	PYTHONPATH=python $(PYTHON) bench/stereo_bench.py
.PHONY: bench-stereo

# Instructions of one 640x480 frame of each matcher on the benchmark's pair
# (callgrind, counted inside the matcher's call only; repeatable where wall
# time on a shared machine is not), with the workspace and a hash of the
# disparities (equal hashes: equal outputs).
BENCH_STEPS += bench-stereo-callgrind
STEREO_BENCH_DIR := $(BUILD)/bench
bench-stereo-callgrind: all $(BUILD)/bench/stereo_callgrind
	@PYTHONPATH=python:bench $(PYTHON) -c "import stereo_bench as B; \
		L, R, _ = B.pair(); L.tofile('$(STEREO_BENCH_DIR)/stereo_left.raw'); \
		R.tofile('$(STEREO_BENCH_DIR)/stereo_right.raw')"
	@for m in block sgm5 sgm8; do \
		fn=sfm_stereo_sgm; [ $$m = block ] && fn=sfm_stereo_block; \
		valgrind --tool=callgrind --toggle-collect=$$fn \
			--callgrind-out-file=$(STEREO_BENCH_DIR)/stereo_$$m.callgrind \
			$(STEREO_BENCH_DIR)/stereo_callgrind $$m $(STEREO_BENCH_DIR)/stereo_left.raw \
			$(STEREO_BENCH_DIR)/stereo_right.raw 640 480 2>&1 | grep -E "valid|I *refs"; \
	done
.PHONY: bench-stereo-callgrind
