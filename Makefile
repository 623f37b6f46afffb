# libsfm: one entry point.
#   make            build/libsfm.a and build/libsfm.so (the core, no capture)
#   make test       install what is missing, build and run every test, one summary line
#   make demo       the three-view pipeline on bundled data
#   make bench      benchmarks beside their anchors
#   make cross      build/aarch64/libsfm.a
#   make firmware   build/cortex-m7/libsfm.a and the relative-pose example
#   make install PREFIX=/usr/local [DESTDIR=...]   (make uninstall undoes it)
#   make fuzz       run the fuzz targets for a while
#
# Variables:
#   CC, CXX, AR, CPPFLAGS, CFLAGS, CXXFLAGS, LDFLAGS  the host toolchain and
#       the user's flags, added after the project's own (CFLAGS=-O3 wins over
#       the default -O2); the cross builds use their own compilers.
#   OPT=-O2      the host optimisation level.
#   NATIVE=1     adds -march=native to the host build (off by default: a
#                library built on one machine must run on another).
#   HAVE_LIBJPEG=, HAVE_LIBPNG=, HAVE_LIBCAMERA=  force an optional
#       dependency of the capture library off (or =1 on); by default each is
#       found with pkg-config. What was found is recorded in
#       build/capture/config.stamp, so a dependency installed later rebuilds
#       the objects that use it.

.DEFAULT_GOAL := all
SHELL := /bin/bash

BUILD ?= build
PREFIX ?= /usr/local
PYTHON_VENV ?= .venv
PYTHON ?= $(PYTHON_VENV)/bin/python

# Modules of the core library, in layer order (data flows left to right; no
# module includes a header of a module to its right).
CORE_MODULES := core solvers robust refine recon features stereo vo
LIB_SRCS := $(foreach m,$(CORE_MODULES),$(wildcard libsfm/$(m)/*.c) $(wildcard libsfm/$(m)/generated/*.c))
PUBLIC_HEADERS := $(wildcard include/sfm/*.h)

# Version from the public header; the shared object is libsfm.so.$(SFM_MAJOR).
SFM_VERSION_PART = $(shell sed -n 's/^\#define SFM_VERSION_$(1) \([0-9]*\).*/\1/p' include/sfm/sfm_common.h)
SFM_MAJOR := $(call SFM_VERSION_PART,MAJOR)
SFM_VERSION_STR := $(SFM_MAJOR).$(call SFM_VERSION_PART,MINOR).$(call SFM_VERSION_PART,PATCH)

WARN := -Wall -Wextra -Wpedantic -Werror -Wshadow -Wdouble-promotion
STD := -std=c11 -ffp-contract=off
OPT ?= -O2
# Kept apart from OPT so that `make OPT=-O3 NATIVE=1` keeps both.
NATIVE_ARCH := $(if $(filter 1,$(NATIVE)),-march=native)
HOST_CFLAGS := $(STD) $(OPT) $(NATIVE_ARCH) $(WARN) $(CPPFLAGS) $(CFLAGS)
CPPFLAGS_LIB := -Iinclude -Ilibsfm
CPPFLAGS_TEST := $(CPPFLAGS_LIB) -Itests/harness
# Per-file header dependencies (written beside each object, read below).
DEPFLAGS = -MMD -MP

# tests/unit: portable tests that run on every target (no files, no threads,
# modest memory). tests/native: host-only tests (real data in ../shared/data,
# threads, large problems), same harness, own runner.
UNIT_SRCS := $(wildcard tests/harness/*.c) $(wildcard tests/unit/*.c)
NATIVE_TEST_SRCS := $(wildcard tests/harness/*.c) $(wildcard tests/native/*.c)

# A stamp holding a value: $(call value_stamp,FILE,TEXT) rewrites FILE only
# when TEXT differs from what it holds, so what depends on FILE is rebuilt
# exactly when the value changed (a list of sources, flags, optional
# dependencies found). The rule runs on every make, never at parse time.
value_stamp = mkdir -p $(dir $(1)); printf '%s\n' '$(2)' | cmp -s - $(1) 2>/dev/null || printf '%s\n' '$(2)' > $(1)
FORCE:

# ---------------------------------------------------------------------------
# Build variants. $(call variant,NAME,DIR,CC,CFLAGS,LDFLAGS[,AR]) defines
# (the archiver: AR given, else AR_NAME, else $(AR))
#   DIR/libsfm.a                 the core library
#   DIR/tests/unit_tests         the unit test runner
# Objects are rebuilt when a header they include, the compiler or the flags
# change (DIR/flags.stamp), and the archive when a source is added or removed.
# Sources listed in NAME_COLD_SRCS get NAME_COLD_OPT after the flags (code
# off the hot paths, built for size where flash is scarce).
define variant
$(1)_DIR := $(2)
$(1)_CC := $(3)
$(1)_CFLAGS := $(4)
$(1)_LDFLAGS := $(5)
$(1)_AR := $(or $(6),$(AR_$(1)),$(AR))
$(1)_OBJS := $$(patsubst %.c,$(2)/obj/%.o,$$(LIB_SRCS))
$(1)_TEST_OBJS := $$(patsubst %.c,$(2)/obj/%.o,$$(UNIT_SRCS)) $(2)/obj/tests/registry.o

$(2)/flags.stamp: FORCE
	@$$(call value_stamp,$$@,$$($(1)_CC) $$($(1)_CFLAGS) $$($(1)_COLD_OPT) $$($(1)_COLD_SRCS))
$(2)/lib_srclist: FORCE
	@$$(call value_stamp,$$@,$$(LIB_SRCS))
$(2)/tests/srclist: FORCE
	@$$(call value_stamp,$$@,$$(UNIT_SRCS))

$(2)/obj/libsfm/%.o: libsfm/%.c $(2)/flags.stamp
	@mkdir -p $$(@D)
	$$($(1)_CC) $$($(1)_CFLAGS) $$(if $$(filter $$<,$$($(1)_COLD_SRCS)),$$($(1)_COLD_OPT)) $$(CPPFLAGS_LIB) $$(DEPFLAGS) -c $$< -o $$@

$(2)/obj/tests/%.o: tests/%.c $(2)/flags.stamp
	@mkdir -p $$(@D)
	$$($(1)_CC) $$($(1)_CFLAGS) $$(CPPFLAGS_TEST) $$(DEPFLAGS) -c $$< -o $$@

$(2)/obj/tests/registry.o: $(2)/tests/registry.c $(2)/flags.stamp
	@mkdir -p $$(@D)
	$$($(1)_CC) $$($(1)_CFLAGS) $$(CPPFLAGS_TEST) -c $$< -o $$@

$(2)/tests/registry.c: $$(UNIT_SRCS) $(2)/tests/srclist tools/gen_test_registry.sh
	@mkdir -p $$(@D)
	sh tools/gen_test_registry.sh $$(UNIT_SRCS) > $$@

$(2)/libsfm.a: $$($(1)_OBJS) $(2)/lib_srclist
	@rm -f $$@
	$$($(1)_AR) rcs $$@ $$($(1)_OBJS)

$(2)/tests/unit_tests: $$($(1)_TEST_OBJS) $(2)/libsfm.a
	@mkdir -p $$(@D)
	$$($(1)_CC) $$($(1)_CFLAGS) -o $$@ $$($(1)_TEST_OBJS) $(2)/libsfm.a $$($(1)_LDFLAGS) -lm

-include $$($(1)_OBJS:.o=.d) $$($(1)_TEST_OBJS:.o=.d)
endef

ASAN_LDFLAGS := -fsanitize=address,undefined
ASAN_CFLAGS := $(STD) -O1 -g $(WARN) $(ASAN_LDFLAGS) -fno-sanitize-recover=all -fno-omit-frame-pointer
$(eval $(call variant,native,$(BUILD),$(CC),$(HOST_CFLAGS) -fPIC -fvisibility=hidden,$(LDFLAGS),$(AR)))
# float-cast-overflow is not in gcc's "undefined": a double out of an int's
# range converted to int (a pixel coordinate of 1e300) is caught only so.
$(eval $(call variant,asan,$(BUILD)/asan,$(CC),$(ASAN_CFLAGS) -fsanitize=float-cast-overflow,$(ASAN_LDFLAGS),$(AR)))

# The shared object: the real file carries the full version, the SONAME the
# major one; libsfm.so.$(SFM_MAJOR) and libsfm.so are links to it.
SFM_SO := libsfm.so.$(SFM_VERSION_STR)
$(BUILD)/$(SFM_SO): $(native_OBJS) $(BUILD)/lib_srclist
	$(CC) -shared -Wl,--no-undefined -Wl,-soname,libsfm.so.$(SFM_MAJOR) $(LDFLAGS) -o $@ $(native_OBJS) -lm
$(BUILD)/libsfm.so.$(SFM_MAJOR) $(BUILD)/libsfm.so: $(BUILD)/$(SFM_SO)
	ln -sf $(SFM_SO) $@

# The cdef the Python binding reads: the public headers after the
# preprocessor, plus the integer macros, kept beside the library it describes.
$(BUILD)/sfm_cdef.h: $(PUBLIC_HEADERS) tools/gen_cdef.sh
	@mkdir -p $(@D)
	CC="$(CC)" sh tools/gen_cdef.sh include/sfm/sfm.h > $@

all: $(BUILD)/libsfm.a $(BUILD)/libsfm.so $(BUILD)/libsfm.so.$(SFM_MAJOR) $(BUILD)/sfm_cdef.h

# ---------------------------------------------------------------------------
# Tests. Each fragment in mk/ appends its steps to TEST_STEPS; `make test`
# runs them all (a failing step does not stop the others) and ends with the
# summary line of tools/run_tests.sh.
TEST_STEPS := test-unit test-asan test-native test-heapfree

NATIVE_TEST_OBJS := $(patsubst %.c,$(BUILD)/obj/%.o,$(NATIVE_TEST_SRCS)) $(BUILD)/obj/tests/native_registry.o
$(BUILD)/tests/native_srclist: FORCE
	@$(call value_stamp,$@,$(NATIVE_TEST_SRCS))
$(BUILD)/tests/native_registry.c: $(NATIVE_TEST_SRCS) $(BUILD)/tests/native_srclist tools/gen_test_registry.sh
	@mkdir -p $(@D)
	sh tools/gen_test_registry.sh $(NATIVE_TEST_SRCS) > $@
$(BUILD)/obj/tests/native_registry.o: $(BUILD)/tests/native_registry.c $(BUILD)/flags.stamp
	$(CC) $(native_CFLAGS) $(CPPFLAGS_TEST) -c $< -o $@
$(BUILD)/tests/native_tests: $(NATIVE_TEST_OBJS) $(BUILD)/libsfm.a
	$(CC) $(native_CFLAGS) $(LDFLAGS) -o $@ $(NATIVE_TEST_OBJS) $(BUILD)/libsfm.a -lm -lpthread

# Host-only tests run from the project root so ../shared/data resolves.
test-native: $(BUILD)/tests/native_tests
	$(BUILD)/tests/native_tests

test-unit: $(BUILD)/tests/unit_tests
	$(BUILD)/tests/unit_tests

test-asan: $(BUILD)/asan/tests/unit_tests
	ASAN_OPTIONS=detect_leaks=0 UBSAN_OPTIONS=print_stacktrace=1 $(BUILD)/asan/tests/unit_tests

# The core never calls an allocator: no object of it may reference one.
test-heapfree: $(BUILD)/libsfm.a
	sh tools/check_heapfree.sh $(BUILD)/libsfm.a

# Benchmarks: fragments append to BENCH_STEPS; `make bench` runs them in turn.
BENCH_STEPS :=

# Every fragment in mk/ joins, named by what it builds.
include $(sort $(wildcard mk/*.mk))

bench: all
	@set -e; for s in $(BENCH_STEPS); do echo "=== $$s"; $(MAKE) --no-print-directory $$s; done

deps:
	sh tools/setup_deps.sh

# The longest steps start first (tools/run_tests.sh runs two or more at once).
TEST_FIRST ?= test-python test-vo-kitti test-cortex-m7 test-asan test-vo-demo
test: deps
	@TEST_FIRST="$(TEST_FIRST)" bash tools/run_tests.sh $(TEST_STEPS)

clean:
	rm -rf $(BUILD)

.PHONY: all test deps clean bench FORCE $(TEST_STEPS) $(BENCH_STEPS)
