# Instructions per sfm_trifocal_7pt call (valgrind): make bench-trifocal-callgrind
BENCH_STEPS += bench-trifocal-callgrind

$(BUILD)/bench/trifocal_callgrind: bench/trifocal_callgrind.c bench/trifocal_scene.h $(BUILD)/libsfm.a $(PUBLIC_HEADERS)
	@mkdir -p $(@D)
	cc $(STD) $(OPT) $(WARN) $(CPPFLAGS_LIB) -o $@ $< $(BUILD)/libsfm.a -lm

bench-trifocal-callgrind: $(BUILD)/bench/trifocal_callgrind
	sh bench/trifocal_callgrind.sh $(BUILD)/bench/trifocal_callgrind

.PHONY: bench-trifocal-callgrind
