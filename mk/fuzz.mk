# Fuzz targets (libFuzzer, clang): the PGM/PPM parser, the manifest parser
# and each pixel-format converter of the capture library; the point
# alignment, the m-view self-calibration, stereo, the leader-follower filter
# and the sequence pipeline of the core (below). `make
# test` replays the committed seed corpus (tests/fuzz/corpus/<target>/)
# once per input;
# `make fuzz` fuzzes each target for FUZZ_SECONDS, growing
# build/fuzz/corpus/<target>/ (the committed seeds stay as they are) and
# leaving any crash in build/fuzz/artifacts/.
FUZZ_SECONDS ?= 60
FUZZ_CC ?= clang
FUZZ_CFLAGS = -std=c11 -g -O1 -fno-omit-frame-pointer -fsanitize=fuzzer,address,undefined \
    -fno-sanitize-recover=all $(WARN) $(CPPFLAGS_LIB) $(CAPTURE_DEFS)
FUZZ_LIB_SRCS := libsfm/capture/pnm.c libsfm/capture/manifest.c libsfm/capture/convert.c \
    libsfm/capture/jpeg_io.c
FUZZ_LDLIBS = $(if $(HAVE_LIBJPEG),-ljpeg)
# Several sources per program: the headers they read are listed, not tracked.
FUZZ_HEADERS := include/sfm/sfm_capture.h include/sfm/sfm_common.h $(wildcard libsfm/capture/*.h)
FUZZ_TARGETS := pnm manifest convert_gray8 convert_yuyv convert_nv12 convert_rgb24 convert_mjpeg
FUZZ_BINS := $(addprefix $(BUILD)/fuzz/fuzz_,$(FUZZ_TARGETS))

$(BUILD)/fuzz/fuzz_pnm $(BUILD)/fuzz/fuzz_manifest: $(BUILD)/fuzz/fuzz_%: tests/fuzz/fuzz_%.c $(FUZZ_LIB_SRCS) $(FUZZ_HEADERS) $(CAP_CONFIG)
	@mkdir -p $(@D)
	$(FUZZ_CC) $(FUZZ_CFLAGS) -o $@ $< $(FUZZ_LIB_SRCS) $(FUZZ_LDLIBS)
$(BUILD)/fuzz/fuzz_convert_%: tests/fuzz/fuzz_convert.c $(FUZZ_LIB_SRCS) $(FUZZ_HEADERS) $(CAP_CONFIG)
	@mkdir -p $(@D)
	$(FUZZ_CC) $(FUZZ_CFLAGS) -DFUZZ_FORMAT=SFM_PIX_$$(echo $* | tr a-z A-Z) -o $@ $< $(FUZZ_LIB_SRCS) $(FUZZ_LDLIBS)

test-fuzz: $(FUZZ_BINS)
	sh tools/run_fuzz_corpus.sh $(BUILD)/fuzz tests/fuzz/corpus $(FUZZ_TARGETS)

fuzz: $(FUZZ_BINS)
	sh tools/run_fuzz.sh $(BUILD)/fuzz $(FUZZ_SECONDS) $(FUZZ_TARGETS)

TEST_STEPS += test-fuzz
.PHONY: fuzz test-fuzz

# The numeric entry points sfm_features_align_points and sfm_selfcal_solve:
# the sources they run compiled with the fuzz flags (sanitized like the
# target itself), align.c alone, the whole core for the self-calibration.
FUZZ_TARGETS += align selfcal
$(BUILD)/fuzz/fuzz_align: tests/fuzz/fuzz_align.c tests/fuzz/fuzz_reader.h libsfm/features/align.c $(PUBLIC_HEADERS)
	@mkdir -p $(@D)
	$(FUZZ_CC) $(FUZZ_CFLAGS) -o $@ tests/fuzz/fuzz_align.c libsfm/features/align.c -lm
$(BUILD)/fuzz/fuzz_selfcal: tests/fuzz/fuzz_selfcal.c $(LIB_SRCS) $(PUBLIC_HEADERS)
	@mkdir -p $(@D)
	$(FUZZ_CC) $(FUZZ_CFLAGS) -o $@ tests/fuzz/fuzz_selfcal.c $(LIB_SRCS) -lm
test-fuzz fuzz: $(BUILD)/fuzz/fuzz_align $(BUILD)/fuzz/fuzz_selfcal

# The stereo entry points (rectification, remap, both matchers) on the
# whole core compiled with the fuzz flags.
FUZZ_TARGETS += stereo
$(BUILD)/fuzz/fuzz_stereo: tests/fuzz/fuzz_stereo.c tests/fuzz/fuzz_reader.h $(LIB_SRCS) $(PUBLIC_HEADERS)
	@mkdir -p $(@D)
	$(FUZZ_CC) $(FUZZ_CFLAGS) -o $@ tests/fuzz/fuzz_stereo.c $(LIB_SRCS) -lm
test-fuzz fuzz: $(BUILD)/fuzz/fuzz_stereo

# The leader-follower filter (propagate, update, cost, next) on the whole
# core compiled with the fuzz flags.
FUZZ_TARGETS += r2r_motion
$(BUILD)/fuzz/fuzz_r2r_motion: tests/fuzz/fuzz_r2r_motion.c $(LIB_SRCS) $(PUBLIC_HEADERS)
	@mkdir -p $(@D)
	$(FUZZ_CC) $(FUZZ_CFLAGS) -o $@ tests/fuzz/fuzz_r2r_motion.c $(LIB_SRCS) -lm
test-fuzz fuzz: $(BUILD)/fuzz/fuzz_r2r_motion

# The sequence pipeline (init, push_frame, the map read-outs, reset) on the
# whole core compiled with the fuzz flags.
FUZZ_TARGETS += vo
$(BUILD)/fuzz/fuzz_vo: tests/fuzz/fuzz_vo.c tests/fuzz/fuzz_reader.h $(LIB_SRCS) $(PUBLIC_HEADERS)
	@mkdir -p $(@D)
	$(FUZZ_CC) $(FUZZ_CFLAGS) -o $@ tests/fuzz/fuzz_vo.c $(LIB_SRCS) -lm
test-fuzz fuzz: $(BUILD)/fuzz/fuzz_vo
