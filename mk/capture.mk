# The capture library (libsfm/capture): its own archive and shared object,
# built on the core only, with the image libraries found by pkg-config.
#   make capture        build/libsfm_capture.{a,so}, build/sfm_capture_cdef.h,
#                       build/bin/sfm-record, build/bin/sfm-replay
#   make test-capture   the capture tests (simulated V4L2 driver, parsers,
#                       converters, replay/record round trips), also under ASan
#   make test-capture-config  an optional dependency installed after a first
#                       build is picked up by the next one
# Link a program against it with:
#   -Lbuild -lsfm_capture -lsfm $(CAPTURE_LDLIBS)

CAPTURE_C_SRCS := $(wildcard libsfm/capture/*.c)
CAPTURE_CXX_SRCS := $(wildcard libsfm/capture/*.cpp)
CAP_DIR := $(BUILD)/capture

# Optional dependencies, found when make starts (a value given on the command
# line wins: HAVE_LIBCAMERA= builds without libcamera).
HAVE_LIBJPEG ?= $(shell pkg-config --exists libjpeg && echo 1)
HAVE_LIBPNG ?= $(shell pkg-config --exists libpng && echo 1)
HAVE_LIBCAMERA ?= $(shell pkg-config --exists libcamera && echo 1)

CAPTURE_DEFS := $(if $(HAVE_LIBJPEG),-DSFM_HAVE_LIBJPEG) $(if $(HAVE_LIBPNG),-DSFM_HAVE_LIBPNG) \
    $(if $(HAVE_LIBCAMERA),-DSFM_HAVE_LIBCAMERA)
CAPTURE_LDLIBS := $(if $(HAVE_LIBJPEG),-ljpeg) $(if $(HAVE_LIBPNG),$(shell pkg-config --libs libpng)) \
    $(if $(HAVE_LIBCAMERA),$(shell pkg-config --libs libcamera)) \
    $(if $(CAPTURE_CXX_SRCS),-lstdc++) -lm
CAPTURE_CXXFLAGS := -std=c++17 $(OPT) $(NATIVE_ARCH) -Wall -Wextra -Werror -Wshadow -fPIC -fvisibility=hidden \
    $(if $(HAVE_LIBCAMERA),$(patsubst -I%,-isystem %,$(shell pkg-config --cflags libcamera))) $(CPPFLAGS) $(CXXFLAGS)

# What the configuration found, and the flags: every capture object, library,
# tool and test depends on it, so `make demo` on a machine without
# libcamera-dev followed by `make test` after installing it rebuilds them.
CAP_CONFIG := $(CAP_DIR)/config.stamp
CAP_CONFIG_VALUE = HAVE_LIBJPEG=$(HAVE_LIBJPEG) HAVE_LIBPNG=$(HAVE_LIBPNG) HAVE_LIBCAMERA=$(HAVE_LIBCAMERA) \
    $(CC) $(native_CFLAGS) $(CXX) $(CAPTURE_CXXFLAGS) $(CAPTURE_LDLIBS)
$(CAP_CONFIG): FORCE
	@$(call value_stamp,$@,$(CAP_CONFIG_VALUE))

CAPTURE_OBJS := $(patsubst libsfm/capture/%.c,$(CAP_DIR)/obj/%.o,$(CAPTURE_C_SRCS)) \
    $(patsubst libsfm/capture/%.cpp,$(CAP_DIR)/obj/%.o,$(CAPTURE_CXX_SRCS))
CAPTURE_ASAN_OBJS := $(patsubst libsfm/capture/%.c,$(CAP_DIR)/asan/%.o,$(CAPTURE_C_SRCS)) \
    $(patsubst libsfm/capture/%.cpp,$(CAP_DIR)/obj/%.o,$(CAPTURE_CXX_SRCS))

$(CAP_DIR)/obj/%.o: libsfm/capture/%.c $(CAP_CONFIG)
	@mkdir -p $(@D)
	$(CC) $(native_CFLAGS) $(CPPFLAGS_LIB) $(CAPTURE_DEFS) $(DEPFLAGS) -c $< -o $@
$(CAP_DIR)/obj/%.o: libsfm/capture/%.cpp $(CAP_CONFIG)
	@mkdir -p $(@D)
	$(CXX) $(CAPTURE_CXXFLAGS) $(CPPFLAGS_LIB) $(CAPTURE_DEFS) $(DEPFLAGS) -c $< -o $@
$(CAP_DIR)/asan/%.o: libsfm/capture/%.c $(CAP_CONFIG)
	@mkdir -p $(@D)
	$(CC) $(ASAN_CFLAGS) $(CPPFLAGS_LIB) $(CAPTURE_DEFS) $(DEPFLAGS) -c $< -o $@

$(BUILD)/libsfm_capture.a: $(CAPTURE_OBJS)
	@rm -f $@
	$(AR) rcs $@ $^
$(CAP_DIR)/libsfm_capture_asan.a: $(CAPTURE_ASAN_OBJS)
	@rm -f $@
	$(AR) rcs $@ $^

# The shared object, versioned as the core's; it needs libsfm.so.$(SFM_MAJOR),
# found beside it through $ORIGIN (build tree, Python package) or in the
# installed prefix.
CAPTURE_SO := libsfm_capture.so.$(SFM_VERSION_STR)
$(BUILD)/$(CAPTURE_SO): $(CAPTURE_OBJS) $(BUILD)/libsfm.so $(BUILD)/libsfm.so.$(SFM_MAJOR) $(CAP_CONFIG)
	$(CC) -shared -Wl,-soname,libsfm_capture.so.$(SFM_MAJOR) $(LDFLAGS) -o $@ $(CAPTURE_OBJS) \
	  -L$(BUILD) -lsfm -Wl,-rpath,'$$ORIGIN' $(CAPTURE_LDLIBS)
$(BUILD)/libsfm_capture.so.$(SFM_MAJOR) $(BUILD)/libsfm_capture.so: $(BUILD)/$(CAPTURE_SO)
	ln -sf $(CAPTURE_SO) $@

# cffi cdef of the capture header, generated as the core's is.
$(BUILD)/sfm_capture_cdef.h: include/sfm/sfm_capture.h include/sfm/sfm_common.h tools/gen_cdef.sh
	@mkdir -p $(@D)
	CC="$(CC)" sh tools/gen_cdef.sh include/sfm/sfm_capture.h > $@

# Command-line tools.
CAPTURE_TOOLS := $(BUILD)/bin/sfm-record $(BUILD)/bin/sfm-replay
$(BUILD)/bin/sfm-%: firmware_examples/linux/sfm_%.c $(BUILD)/libsfm_capture.a $(BUILD)/libsfm.a $(CAP_CONFIG)
	@mkdir -p $(@D)
	$(CC) $(native_CFLAGS) -Iinclude $(DEPFLAGS) $(LDFLAGS) -o $@ $< $(BUILD)/libsfm_capture.a $(BUILD)/libsfm.a $(CAPTURE_LDLIBS)

capture: $(BUILD)/libsfm_capture.a $(BUILD)/libsfm_capture.so $(BUILD)/libsfm_capture.so.$(SFM_MAJOR) \
    $(BUILD)/sfm_capture_cdef.h $(CAPTURE_TOOLS)

# Tests: tests/capture/*.c with the common harness. The allocation counters
# of the tests wrap malloc and friends for the library's objects.
CAPTURE_TEST_SRCS := $(wildcard tests/harness/*.c) $(wildcard tests/capture/*.c)
CAPTURE_TEST_WRAP := -Wl,--wrap=malloc,--wrap=calloc,--wrap=realloc,--wrap=free
$(CAP_DIR)/tests/srclist: FORCE
	@$(call value_stamp,$@,$(CAPTURE_TEST_SRCS))
$(CAP_DIR)/tests/registry.c: $(CAPTURE_TEST_SRCS) $(CAP_DIR)/tests/srclist tools/gen_test_registry.sh
	@mkdir -p $(@D)
	sh tools/gen_test_registry.sh $(CAPTURE_TEST_SRCS) > $@
$(CAP_DIR)/tests/obj/%.o: tests/%.c $(CAP_CONFIG)
	@mkdir -p $(@D)
	$(CC) $(native_CFLAGS) $(CPPFLAGS_TEST) $(CAPTURE_DEFS) $(DEPFLAGS) -c $< -o $@
$(CAP_DIR)/tests/asan/%.o: tests/%.c $(CAP_CONFIG)
	@mkdir -p $(@D)
	$(CC) $(ASAN_CFLAGS) $(CPPFLAGS_TEST) $(CAPTURE_DEFS) $(DEPFLAGS) -c $< -o $@
$(CAP_DIR)/tests/obj/registry.o: $(CAP_DIR)/tests/registry.c
	$(CC) $(native_CFLAGS) $(CPPFLAGS_TEST) -c $< -o $@
$(CAP_DIR)/tests/asan/registry.o: $(CAP_DIR)/tests/registry.c
	$(CC) $(ASAN_CFLAGS) $(CPPFLAGS_TEST) -c $< -o $@

CAPTURE_TEST_OBJS := $(patsubst tests/%.c,$(CAP_DIR)/tests/obj/%.o,$(CAPTURE_TEST_SRCS)) $(CAP_DIR)/tests/obj/registry.o
CAPTURE_TEST_ASAN_OBJS := $(patsubst tests/%.c,$(CAP_DIR)/tests/asan/%.o,$(CAPTURE_TEST_SRCS)) $(CAP_DIR)/tests/asan/registry.o
-include $(CAPTURE_OBJS:.o=.d) $(CAPTURE_ASAN_OBJS:.o=.d) $(CAPTURE_TEST_OBJS:.o=.d) $(CAPTURE_TEST_ASAN_OBJS:.o=.d) \
    $(CAPTURE_TOOLS:=.d)

$(BUILD)/tests/capture_tests: $(CAPTURE_TEST_OBJS) $(BUILD)/libsfm_capture.a $(BUILD)/libsfm.a
	@mkdir -p $(@D)
	$(CC) $(native_CFLAGS) $(CAPTURE_TEST_WRAP) $(LDFLAGS) -o $@ $(CAPTURE_TEST_OBJS) $(BUILD)/libsfm_capture.a $(BUILD)/libsfm.a $(CAPTURE_LDLIBS)
$(BUILD)/asan/tests/capture_tests: $(CAPTURE_TEST_ASAN_OBJS) $(CAP_DIR)/libsfm_capture_asan.a $(BUILD)/asan/libsfm.a
	@mkdir -p $(@D)
	$(CC) $(ASAN_CFLAGS) $(CAPTURE_TEST_WRAP) -o $@ $(CAPTURE_TEST_ASAN_OBJS) $(CAP_DIR)/libsfm_capture_asan.a $(BUILD)/asan/libsfm.a $(CAPTURE_LDLIBS)

# Run from the project root; temporary directories go under $(BUILD)/tmp.
test-capture: $(BUILD)/tests/capture_tests $(CAPTURE_TOOLS)
	SFM_TEST_TMP=$(BUILD)/tmp SFM_TEST_BIN=$(BUILD)/bin $(BUILD)/tests/capture_tests
test-capture-asan: $(BUILD)/asan/tests/capture_tests $(CAPTURE_TOOLS)
	SFM_TEST_TMP=$(BUILD)/tmp SFM_TEST_BIN=$(BUILD)/bin ASAN_OPTIONS=detect_leaks=1 \
	    UBSAN_OPTIONS=print_stacktrace=1 $(BUILD)/asan/tests/capture_tests

# The fresh-machine order (`make demo` before `make test` has installed the
# optional packages): the capture library built with a dependency hidden,
# then found, in a scratch build directory; the second build must have it.
test-capture-config: $(BUILD)/libsfm.a
	sh tests/install/capture_config.sh $(BUILD)

# The Python tests open replay directories through libsfm_capture.so.
test-python: capture

TEST_STEPS += test-capture test-capture-asan test-capture-config
.PHONY: capture test-capture test-capture-asan test-capture-config

# The link flags of the capture library, for scripts: make -s print-capture-ldlibs
print-capture-ldlibs:
	@echo $(CAPTURE_LDLIBS)
.PHONY: print-capture-ldlibs
