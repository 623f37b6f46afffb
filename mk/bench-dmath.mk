# make bench-dmath: the library's elementary functions (core/dmath.c) beside
# the platform's libm, ns per call and the ratio (bench/dmath_bench.c).
BENCH_STEPS += bench-dmath

$(BUILD)/bench/dmath_bench: bench/dmath_bench.c $(BUILD)/libsfm.a libsfm/core/dmath.h
	@mkdir -p $(@D)
	cc $(STD) $(OPT) $(WARN) $(CPPFLAGS_LIB) -o $@ $< $(BUILD)/libsfm.a -lm

bench-dmath: $(BUILD)/bench/dmath_bench
	$(BUILD)/bench/dmath_bench

.PHONY: bench-dmath
