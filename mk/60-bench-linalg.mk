# make bench-linalg: SVD 3x3/9x9/27x27 and the 10x10 nonsymmetric eigenproblem,
# libsfm beside Eigen in one run (wall-clock us per call), then callgrind
# instruction counts per call for each (repeatable on a shared machine).
# Built with the library's optimization flags (-O2, no -march).
# GCC 12 reports maybe-uninitialized inside Eigen's fixed-size JacobiSVD: a false positive.
BENCH_CXXFLAGS := -std=c++17 $(OPT) -ffp-contract=off -Wall -Wextra -Werror -Wno-maybe-uninitialized -isystem $(EIGEN_INC) -Iinclude

$(BUILD)/bench/linalg_bench: bench/linalg_bench.cc $(BUILD)/libsfm.a $(PUBLIC_HEADERS)
	@mkdir -p $(@D)
	$(ORACLE_CXX) $(BENCH_CXXFLAGS) -g -o $@ $< $(BUILD)/libsfm.a -lm

BENCH_STEPS += bench-linalg
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

.PHONY: bench-linalg
