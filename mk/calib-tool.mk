# The calibration-file reader of the C programs (firmware_examples/linux/
# calib_file.c, a tools layer: it reads files, so it is not in the core) and
#   build/bin/sfm-calib    prints the camera a calibration file gives
# tests/python/test_calib.py holds the reader to Python's on the same files,
# so test-python needs the tool.

CALIB_TOOL := $(BUILD)/bin/sfm-calib
CALIB_SRC := firmware_examples/linux/calib_file.c

$(CALIB_TOOL): firmware_examples/linux/sfm_calib.c $(CALIB_SRC) firmware_examples/linux/calib_file.h $(PUBLIC_HEADERS) $(BUILD)/libsfm.a
	@mkdir -p $(@D)
	cc $(native_CFLAGS) -Iinclude -o $@ firmware_examples/linux/sfm_calib.c $(CALIB_SRC) $(BUILD)/libsfm.a -lm

test-python: $(CALIB_TOOL)

# Its fuzz target, replayed on tests/fuzz/corpus/calib/ by test-fuzz.
FUZZ_TARGETS += calib
$(BUILD)/fuzz/fuzz_calib: tests/fuzz/fuzz_calib.c $(CALIB_SRC) firmware_examples/linux/calib_file.h $(BUILD)/libsfm.a
	@mkdir -p $(@D)
	$(FUZZ_CC) $(FUZZ_CFLAGS) -Ifirmware_examples/linux -o $@ tests/fuzz/fuzz_calib.c $(CALIB_SRC) $(BUILD)/libsfm.a -lm
test-fuzz fuzz: $(BUILD)/fuzz/fuzz_calib
