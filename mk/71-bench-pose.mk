# Pose solver and triangulation benchmarks (bench/pose_bench.c,
# bench/pose_callgrind.sh, bench/pose_vs_poselib.py).
#   make bench-pose            CPU-time table: us/call, solutions/call, truth rate
#   make bench-pose-callgrind  instructions per call (callgrind, two call counts)
#   make bench-pose-poselib    libsfm (cffi) beside PoseLib (pip) on the same inputs
BENCH_STEPS += bench-pose bench-pose-callgrind bench-pose-poselib

$(BUILD)/bench/pose_bench: bench/pose_bench.c $(BUILD)/libsfm.a $(PUBLIC_HEADERS)
	@mkdir -p $(@D)
	cc $(STD) $(OPT) $(WARN) $(CPPFLAGS_LIB) -o $@ $< $(BUILD)/libsfm.a -lm

bench-pose: $(BUILD)/bench/pose_bench
	$(BUILD)/bench/pose_bench

bench-pose-callgrind: $(BUILD)/bench/pose_bench
	sh bench/pose_callgrind.sh $(BUILD)/bench/pose_bench

bench-pose-poselib: all
	PYTHONPATH=python $(PYTHON) bench/pose_vs_poselib.py

.PHONY: bench-pose bench-pose-callgrind bench-pose-poselib
