# Benchmarks: libsfm beside its anchors (Eigen, PoseLib, OpenCV) and
# instruction counts under callgrind. Timings are printed, never asserted.
# Figures and how they were taken: bench/README.md.
#   make bench-solvers            epipolar and homography solvers: C table, callgrind, PoseLib/OpenCV from Python
#   make bench-pose               pose solvers and triangulation: us/call, solutions/call, truth rate
#   make bench-pose-callgrind     instructions per call
#   make bench-pose-poselib       libsfm (cffi) beside PoseLib on the same inputs
#   make bench-ransac             robust estimation beside PoseLib and OpenCV
#   make bench-trifocal           the trifocal 7-point solver and RANSAC
#   make bench-trifocal-callgrind instructions per sfm_trifocal_7pt call
#   make bench-linalg             SVD and eigen beside Eigen, wall clock and callgrind
#   make bench-r2r                robot-to-robot: us per sfm_r2r_solve per base system, then callgrind
BENCH_STEPS += bench-solvers bench-pose bench-pose-callgrind bench-pose-poselib bench-ransac \
    bench-trifocal bench-trifocal-callgrind bench-linalg bench-r2r

# One rule for every C benchmark: bench/NAME.c -> build/bench/NAME, built with
# the library's flags (-O2, no -march unless NATIVE=1), headers tracked per file.
$(BUILD)/bench/%: bench/%.c $(BUILD)/libsfm.a $(BUILD)/flags.stamp
	@mkdir -p $(@D)
	$(CC) $(HOST_CFLAGS) $(CPPFLAGS_LIB) $(DEPFLAGS) -o $@ $< $(BUILD)/libsfm.a $(LDFLAGS) -lm
-include $(patsubst bench/%.c,$(BUILD)/bench/%.d,$(wildcard bench/*.c))

bench-solvers: $(BUILD)/bench/solvers_bench all
	$(BUILD)/bench/solvers_bench
	sh bench/callgrind_solvers.sh $(BUILD)/bench/solvers_bench
	PYTHONPATH=python $(PYTHON) bench/solvers_vs_poselib.py

bench-pose: $(BUILD)/bench/pose_bench
	$(BUILD)/bench/pose_bench

bench-pose-callgrind: $(BUILD)/bench/pose_bench
	sh bench/pose_callgrind.sh $(BUILD)/bench/pose_bench

bench-pose-poselib: all
	PYTHONPATH=python $(PYTHON) bench/pose_vs_poselib.py

bench-ransac: all
	PYTHONPATH=python $(PYTHON) bench/ransac_bench.py

bench-trifocal: $(BUILD)/bench/trifocal_bench
	$(BUILD)/bench/trifocal_bench

bench-trifocal-callgrind: $(BUILD)/bench/trifocal_callgrind
	sh bench/trifocal_callgrind.sh $(BUILD)/bench/trifocal_callgrind

# SVD 3x3/9x9/27x27 and the 10x10 nonsymmetric eigenproblem beside Eigen in
# one run (wall-clock us per call), then callgrind instructions per call.
# GCC 12 reports maybe-uninitialized inside Eigen's fixed-size JacobiSVD: a
# false positive.
BENCH_CXXFLAGS = -std=c++17 $(OPT) $(NATIVE_ARCH) -ffp-contract=off -Wall -Wextra -Werror -Wno-maybe-uninitialized \
    -isystem $(EIGEN_INC) -Iinclude $(CXXFLAGS)
$(BUILD)/bench/linalg_bench: bench/linalg_bench.cc $(BUILD)/libsfm.a $(BUILD)/flags.stamp
	@mkdir -p $(@D)
	$(ORACLE_CXX) $(BENCH_CXXFLAGS) $(DEPFLAGS) -g -o $@ $< $(BUILD)/libsfm.a $(LDFLAGS) -lm
-include $(BUILD)/bench/linalg_bench.d

bench-linalg: $(BUILD)/bench/linalg_bench
	$(BUILD)/bench/linalg_bench
	@if command -v valgrind >/dev/null; then \
	  echo; echo "callgrind: instructions per call (valgrind --tool=callgrind --collect-atstart=no)"; \
	  printf '%-10s %-18s %12s %10s\n' case impl Ir/call ratio; \
	  $(BUILD)/bench/linalg_bench --list | while IFS='|' read -r c i; do \
	    out=$(BUILD)/bench/cg.out; \
	    n=$$(valgrind --tool=callgrind --collect-atstart=no --callgrind-out-file=$$out \
	         $(BUILD)/bench/linalg_bench --callgrind "$$c" "$$i" 2>/dev/null); \
	    ir=$$(sed -n 's/^totals: *\([0-9]*\).*/\1/p' $$out); \
	    per=$$((ir / n)); [ "$$i" = libsfm ] && base=$$per; \
	    awk -v c="$$c" -v i="$$i" -v p=$$per -v b=$$base 'BEGIN{printf "%-10s %-18s %12d %10.2f\n", c, i, p, p/b}'; \
	  done; rm -f $(BUILD)/bench/cg.out; \
	else echo "valgrind not installed: no instruction counts"; fi

bench-r2r: $(BUILD)/bench/r2r_bench
	$(BUILD)/bench/r2r_bench
	@if command -v valgrind >/dev/null; then sh bench/r2r_callgrind.sh $(BUILD)/bench/r2r_bench; \
	else echo "valgrind not installed: no instruction counts"; fi

.PHONY: bench-solvers bench-pose bench-pose-callgrind bench-pose-poselib bench-ransac \
    bench-trifocal bench-trifocal-callgrind bench-linalg bench-r2r
