# Uncalibrated three-view benchmark (bench/uncal_bench.c): make bench-uncal
BENCH_STEPS += bench-uncal

$(BUILD)/bench/uncal_bench: bench/uncal_bench.c $(BUILD)/libsfm.a $(PUBLIC_HEADERS)
	@mkdir -p $(@D)
	cc $(STD) $(OPT) $(WARN) $(CPPFLAGS_LIB) -o $@ $< $(BUILD)/libsfm.a -lm

bench-uncal: $(BUILD)/bench/uncal_bench
	$(BUILD)/bench/uncal_bench

.PHONY: bench-uncal

# The same triplets beside BoofCV 1.2.2 in one run (needs java, javac, mvn;
# SKIP otherwise): make bench-uncal-boofcv
BENCH_STEPS += bench-uncal-boofcv

bench-uncal-boofcv: $(BUILD)/bench/uncal_bench
	sh bench/uncal_vs_boofcv.sh $(BUILD)/bench/uncal_bench $(BUILD)

.PHONY: bench-uncal-boofcv
