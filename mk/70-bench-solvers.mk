# Benchmarks of the epipolar and homography solvers: C timing table,
# callgrind instructions per call, and libsfm beside PoseLib/OpenCV from
# Python in one run. Same flags as the library (-O2, no -march).
BENCH_STEPS += bench-solvers

$(BUILD)/bench/solvers_bench: bench/solvers_bench.c $(BUILD)/libsfm.a $(PUBLIC_HEADERS)
	@mkdir -p $(@D)
	cc $(STD) $(OPT) $(WARN) $(CPPFLAGS_LIB) -o $@ $< $(BUILD)/libsfm.a -lm

bench-solvers: $(BUILD)/bench/solvers_bench all
	$(BUILD)/bench/solvers_bench
	sh bench/callgrind_solvers.sh $(BUILD)/bench/solvers_bench
	PYTHONPATH=python $(PYTHON) bench/solvers_vs_poselib.py

.PHONY: bench-solvers
