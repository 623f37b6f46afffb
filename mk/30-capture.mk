# The capture library (libsfm/capture): its own archive and shared object,
# built on the core only, with the image libraries found by pkg-config.
#   make capture        build/libsfm_capture.{a,so}, build/sfm_capture_cdef.h,
#                       build/bin/sfm-record, build/bin/sfm-replay
#   make test-capture   the capture tests (simulated V4L2 driver, parsers,
#                       converters, replay/record round trips), also under ASan
#   make fuzz           each fuzz target for FUZZ_SECONDS (default 60)
# Link a program against it with:
#   -Lbuild -lsfm_capture -lsfm $(CAPTURE_LDLIBS)

CAPTURE_C_SRCS := $(wildcard libsfm/capture/*.c)
CAPTURE_CXX_SRCS := $(wildcard libsfm/capture/*.cpp)
CAPTURE_HEADERS := include/sfm/sfm_capture.h include/sfm/sfm_common.h $(wildcard libsfm/capture/*.h)
CAP_DIR := $(BUILD)/capture

HAVE_LIBJPEG ?= $(shell pkg-config --exists libjpeg && echo 1)
HAVE_LIBPNG ?= $(shell pkg-config --exists libpng && echo 1)
HAVE_LIBCAMERA ?= $(shell pkg-config --exists libcamera && echo 1)

CAPTURE_DEFS := $(if $(HAVE_LIBJPEG),-DSFM_HAVE_LIBJPEG) $(if $(HAVE_LIBPNG),-DSFM_HAVE_LIBPNG) \
    $(if $(HAVE_LIBCAMERA),-DSFM_HAVE_LIBCAMERA)
CAPTURE_LDLIBS := $(if $(HAVE_LIBJPEG),-ljpeg) $(if $(HAVE_LIBPNG),$(shell pkg-config --libs libpng)) \
    $(if $(HAVE_LIBCAMERA),$(shell pkg-config --libs libcamera)) \
    $(if $(CAPTURE_CXX_SRCS),-lstdc++) -lm
CAPTURE_CXXFLAGS := -std=c++17 $(OPT) -Wall -Wextra -Werror -Wshadow -fPIC -fvisibility=hidden \
    $(if $(HAVE_LIBCAMERA),$(patsubst -I%,-isystem %,$(shell pkg-config --cflags libcamera)))

CAPTURE_OBJS := $(patsubst libsfm/capture/%.c,$(CAP_DIR)/obj/%.o,$(CAPTURE_C_SRCS)) \
    $(patsubst libsfm/capture/%.cpp,$(CAP_DIR)/obj/%.o,$(CAPTURE_CXX_SRCS))
CAPTURE_ASAN_OBJS := $(patsubst libsfm/capture/%.c,$(CAP_DIR)/asan/%.o,$(CAPTURE_C_SRCS)) \
    $(patsubst libsfm/capture/%.cpp,$(CAP_DIR)/obj/%.o,$(CAPTURE_CXX_SRCS))

$(CAP_DIR)/obj/%.o: libsfm/capture/%.c $(CAPTURE_HEADERS) | $(BUILD)/.dir
	@mkdir -p $(@D)
	cc $(native_CFLAGS) $(CPPFLAGS_LIB) $(CAPTURE_DEFS) -c $< -o $@
$(CAP_DIR)/obj/%.o: libsfm/capture/%.cpp $(CAPTURE_HEADERS) | $(BUILD)/.dir
	@mkdir -p $(@D)
	c++ $(CAPTURE_CXXFLAGS) $(CPPFLAGS_LIB) $(CAPTURE_DEFS) -c $< -o $@
$(CAP_DIR)/asan/%.o: libsfm/capture/%.c $(CAPTURE_HEADERS) | $(BUILD)/.dir
	@mkdir -p $(@D)
	cc $(ASAN_CFLAGS) $(CPPFLAGS_LIB) $(CAPTURE_DEFS) -c $< -o $@

$(BUILD)/libsfm_capture.a: $(CAPTURE_OBJS)
	@rm -f $@
	ar rcs $@ $^
$(CAP_DIR)/libsfm_capture_asan.a: $(CAPTURE_ASAN_OBJS)
	@rm -f $@
	ar rcs $@ $^

# The shared object needs libsfm.so beside it (found through $ORIGIN).
$(BUILD)/libsfm_capture.so: $(CAPTURE_OBJS) $(BUILD)/libsfm.so
	cc -shared -o $@ $(CAPTURE_OBJS) -L$(BUILD) -lsfm -Wl,-rpath,'$$ORIGIN' $(CAPTURE_LDLIBS)

# cffi cdef of the capture header, generated as the core's is.
$(BUILD)/sfm_capture_cdef.h: include/sfm/sfm_capture.h include/sfm/sfm_common.h tools/gen_cdef.sh | $(BUILD)/.dir
	sh tools/gen_cdef.sh include/sfm/sfm_capture.h > $@

# Command-line tools.
CAPTURE_TOOLS := $(BUILD)/bin/sfm-record $(BUILD)/bin/sfm-replay
$(BUILD)/bin/sfm-%: firmware_examples/linux/sfm_%.c include/sfm/sfm_capture.h $(BUILD)/libsfm_capture.a $(BUILD)/libsfm.a
	@mkdir -p $(@D)
	cc $(native_CFLAGS) -Iinclude -o $@ $< $(BUILD)/libsfm_capture.a $(BUILD)/libsfm.a $(CAPTURE_LDLIBS)

capture: $(BUILD)/libsfm_capture.a $(BUILD)/libsfm_capture.so $(BUILD)/sfm_capture_cdef.h $(CAPTURE_TOOLS)

# make install-capture PREFIX=...: the capture library beside the core's
# (after `make install`), its header, cdef and tools.
install-capture: capture
	install -d $(DESTDIR)$(PREFIX)/include/sfm $(DESTDIR)$(PREFIX)/lib $(DESTDIR)$(PREFIX)/bin \
	  $(DESTDIR)$(PREFIX)/share/sfm
	install -m 644 include/sfm/sfm_capture.h $(DESTDIR)$(PREFIX)/include/sfm/
	install -m 644 $(BUILD)/libsfm_capture.a $(DESTDIR)$(PREFIX)/lib/
	install -m 755 $(BUILD)/libsfm_capture.so $(DESTDIR)$(PREFIX)/lib/
	install -m 644 $(BUILD)/sfm_capture_cdef.h $(DESTDIR)$(PREFIX)/share/sfm/
	install -m 755 $(CAPTURE_TOOLS) $(DESTDIR)$(PREFIX)/bin/

# Tests: tests/capture/*.c with the common harness. The allocation counters
# of the tests wrap malloc and friends for the library's objects.
CAPTURE_TEST_SRCS := $(wildcard tests/harness/*.c) $(wildcard tests/capture/*.c)
CAPTURE_TEST_WRAP := -Wl,--wrap=malloc,--wrap=calloc,--wrap=realloc,--wrap=free
$(CAP_DIR)/tests/registry.c: $(CAPTURE_TEST_SRCS) tools/gen_test_registry.sh | $(BUILD)/.dir
	@mkdir -p $(@D)
	sh tools/gen_test_registry.sh $(CAPTURE_TEST_SRCS) > $@
$(CAP_DIR)/tests/obj/%.o: tests/%.c $(CAPTURE_HEADERS) tests/harness/sfm_test.h $(wildcard tests/capture/*.h) | $(BUILD)/.dir
	@mkdir -p $(@D)
	cc $(native_CFLAGS) $(CPPFLAGS_TEST) $(CAPTURE_DEFS) -c $< -o $@
$(CAP_DIR)/tests/asan/%.o: tests/%.c $(CAPTURE_HEADERS) tests/harness/sfm_test.h $(wildcard tests/capture/*.h) | $(BUILD)/.dir
	@mkdir -p $(@D)
	cc $(ASAN_CFLAGS) $(CPPFLAGS_TEST) $(CAPTURE_DEFS) -c $< -o $@
$(CAP_DIR)/tests/obj/registry.o: $(CAP_DIR)/tests/registry.c
	cc $(native_CFLAGS) $(CPPFLAGS_TEST) -c $< -o $@
$(CAP_DIR)/tests/asan/registry.o: $(CAP_DIR)/tests/registry.c
	cc $(ASAN_CFLAGS) $(CPPFLAGS_TEST) -c $< -o $@

CAPTURE_TEST_OBJS := $(patsubst tests/%.c,$(CAP_DIR)/tests/obj/%.o,$(CAPTURE_TEST_SRCS)) $(CAP_DIR)/tests/obj/registry.o
CAPTURE_TEST_ASAN_OBJS := $(patsubst tests/%.c,$(CAP_DIR)/tests/asan/%.o,$(CAPTURE_TEST_SRCS)) $(CAP_DIR)/tests/asan/registry.o

$(BUILD)/tests/capture_tests: $(CAPTURE_TEST_OBJS) $(BUILD)/libsfm_capture.a $(BUILD)/libsfm.a
	@mkdir -p $(@D)
	cc $(native_CFLAGS) $(CAPTURE_TEST_WRAP) -o $@ $(CAPTURE_TEST_OBJS) $(BUILD)/libsfm_capture.a $(BUILD)/libsfm.a $(CAPTURE_LDLIBS)
$(BUILD)/asan/tests/capture_tests: $(CAPTURE_TEST_ASAN_OBJS) $(CAP_DIR)/libsfm_capture_asan.a $(BUILD)/asan/libsfm.a
	@mkdir -p $(@D)
	cc $(ASAN_CFLAGS) $(CAPTURE_TEST_WRAP) -o $@ $(CAPTURE_TEST_ASAN_OBJS) $(CAP_DIR)/libsfm_capture_asan.a $(BUILD)/asan/libsfm.a $(CAPTURE_LDLIBS)

# Run from the project root; temporary directories go under $(BUILD)/tmp.
test-capture: $(BUILD)/tests/capture_tests $(CAPTURE_TOOLS)
	SFM_TEST_TMP=$(BUILD)/tmp SFM_TEST_BIN=$(BUILD)/bin $(BUILD)/tests/capture_tests
test-capture-asan: $(BUILD)/asan/tests/capture_tests $(CAPTURE_TOOLS)
	SFM_TEST_TMP=$(BUILD)/tmp SFM_TEST_BIN=$(BUILD)/bin ASAN_OPTIONS=detect_leaks=1 \
	    UBSAN_OPTIONS=print_stacktrace=1 $(BUILD)/asan/tests/capture_tests

# The Python tests open replay directories through libsfm_capture.so.
test-python: capture

TEST_STEPS += test-capture test-capture-asan
.PHONY: capture install-capture test-capture test-capture-asan

# ---------------------------------------------------------------------------
# Fuzz targets (libFuzzer, clang): the PGM/PPM parser, the manifest parser
# and each pixel-format converter. `make test` replays the committed seed
# corpus (tests/fuzz/corpus/<target>/) once per input; `make fuzz` fuzzes
# each target for FUZZ_SECONDS, growing build/fuzz/corpus/<target>/ (the
# committed seeds stay as they are) and leaving any crash in
# build/fuzz/artifacts/.
FUZZ_SECONDS ?= 60
FUZZ_CC ?= clang
FUZZ_CFLAGS := -std=c11 -g -O1 -fno-omit-frame-pointer -fsanitize=fuzzer,address,undefined \
    -fno-sanitize-recover=all $(WARN) $(CPPFLAGS_LIB) $(CAPTURE_DEFS)
FUZZ_LIB_SRCS := libsfm/capture/pnm.c libsfm/capture/manifest.c libsfm/capture/convert.c \
    libsfm/capture/jpeg_io.c
FUZZ_LDLIBS := $(if $(HAVE_LIBJPEG),-ljpeg)
FUZZ_TARGETS := pnm manifest convert_gray8 convert_yuyv convert_nv12 convert_rgb24 convert_mjpeg
FUZZ_BINS := $(addprefix $(BUILD)/fuzz/fuzz_,$(FUZZ_TARGETS))

$(BUILD)/fuzz/fuzz_pnm $(BUILD)/fuzz/fuzz_manifest: $(BUILD)/fuzz/fuzz_%: tests/fuzz/fuzz_%.c $(FUZZ_LIB_SRCS) $(CAPTURE_HEADERS)
	@mkdir -p $(@D)
	$(FUZZ_CC) $(FUZZ_CFLAGS) -o $@ $< $(FUZZ_LIB_SRCS) $(FUZZ_LDLIBS)
$(BUILD)/fuzz/fuzz_convert_%: tests/fuzz/fuzz_convert.c $(FUZZ_LIB_SRCS) $(CAPTURE_HEADERS)
	@mkdir -p $(@D)
	$(FUZZ_CC) $(FUZZ_CFLAGS) -DFUZZ_FORMAT=SFM_PIX_$$(echo $* | tr a-z A-Z) -o $@ $< $(FUZZ_LIB_SRCS) $(FUZZ_LDLIBS)

test-fuzz: $(FUZZ_BINS)
	sh tools/run_fuzz_corpus.sh $(BUILD)/fuzz tests/fuzz/corpus $(FUZZ_TARGETS)

fuzz: $(FUZZ_BINS)
	sh tools/run_fuzz.sh $(BUILD)/fuzz $(FUZZ_SECONDS) $(FUZZ_TARGETS)

TEST_STEPS += test-fuzz
.PHONY: fuzz test-fuzz
