# make test-symbols: libsfm.a defines only public sfm_ names (each declared in
# include/sfm/*.h) and internal sfmi_ ones (tools/check_symbols.sh).
TEST_STEPS += test-symbols
test-symbols: $(BUILD)/libsfm.a
	@sh tools/check_symbols.sh $(BUILD)/libsfm.a

.PHONY: test-symbols
