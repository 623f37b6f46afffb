# The calibration-file reader of the C programs (firmware_examples/linux/
# calib_file.c, a tools layer: it reads files, so it is not in the core):
#   build/tools/calib_file.o   linked into build/bin/three_view_demo (--calib)
#   build/bin/sfm-calib        prints the camera a calibration file gives
# tests/python/test_calib.py holds the reader to Python's on the same files,
# so test-python needs the tool; test-fuzz replays its fuzz target's corpus.
# (Named to be read after the fragments whose variables it extends.)

CALIB_SRC := firmware_examples/linux/calib_file.c
CALIB_HDR := firmware_examples/linux/calib_file.h
CALIB_OBJ := $(BUILD)/tools/calib_file.o
CALIB_TOOL := $(BUILD)/bin/sfm-calib

$(CALIB_OBJ): $(CALIB_SRC) $(CALIB_HDR) $(PUBLIC_HEADERS)
	@mkdir -p $(@D)
	cc $(native_CFLAGS) -Iinclude -c $< -o $@

$(CALIB_TOOL): firmware_examples/linux/sfm_calib.c $(CALIB_OBJ) $(BUILD)/libsfm.a
	@mkdir -p $(@D)
	cc $(native_CFLAGS) -Iinclude -o $@ firmware_examples/linux/sfm_calib.c $(CALIB_OBJ) $(BUILD)/libsfm.a -lm

# The demo's own rule links the capture and core libraries; the reader comes
# after them, with the core once more for the symbols it needs.
$(DEMO_BIN): $(CALIB_OBJ) $(CALIB_HDR)
$(DEMO_BIN): CAPTURE_LDLIBS += $(CALIB_OBJ) $(BUILD)/libsfm.a -lm

test-python: $(CALIB_TOOL)
capture: $(CALIB_TOOL)

FUZZ_TARGETS += calib
$(BUILD)/fuzz/fuzz_calib: tests/fuzz/fuzz_calib.c $(CALIB_SRC) $(CALIB_HDR) $(BUILD)/libsfm.a
	@mkdir -p $(@D)
	$(FUZZ_CC) $(FUZZ_CFLAGS) -Ifirmware_examples/linux -o $@ tests/fuzz/fuzz_calib.c $(CALIB_SRC) $(BUILD)/libsfm.a -lm
test-fuzz fuzz: $(BUILD)/fuzz/fuzz_calib
