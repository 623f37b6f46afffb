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
    $(if $(HAVE_LIBCAMERA),$(shell pkg-config --cflags libcamera))

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
.PHONY: capture test-capture test-capture-asan
