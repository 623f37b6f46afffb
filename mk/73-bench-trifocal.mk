# Trifocal benchmark (bench/trifocal_bench.c): make bench-trifocal
BENCH_STEPS += bench-trifocal

$(BUILD)/bench/trifocal_bench: bench/trifocal_bench.c bench/trifocal_scene.h $(BUILD)/libsfm.a $(PUBLIC_HEADERS)
	@mkdir -p $(@D)
	cc $(STD) $(OPT) $(WARN) $(CPPFLAGS_LIB) -o $@ $< $(BUILD)/libsfm.a -lm

bench-trifocal: $(BUILD)/bench/trifocal_bench
	$(BUILD)/bench/trifocal_bench

.PHONY: bench-trifocal
