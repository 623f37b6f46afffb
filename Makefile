# libsfm: one entry point.
#   make            build/libsfm.a and build/libsfm.so (the core, no capture)
#   make test       install what is missing, build and run every test, one summary line
#   make demo       the three-view pipeline on bundled data
#   make bench      benchmarks beside their anchors
#   make cross      build/aarch64/libsfm.a
#   make firmware   build/cortex-m7/libsfm.a
#   make install PREFIX=/usr/local
#   make fuzz       run the fuzz targets for a while
#
# Variables: NATIVE=1 adds -march=native (off by default: a library built on
# one machine must run on another).

.DEFAULT_GOAL := all
SHELL := /bin/bash

BUILD ?= build
PREFIX ?= /usr/local
PYTHON_VENV ?= .venv
PYTHON ?= $(PYTHON_VENV)/bin/python

# Modules of the core library, in layer order (data flows left to right; no
# module includes a header of a module to its right).
CORE_MODULES := core solvers robust refine recon features vo
LIB_SRCS := $(foreach m,$(CORE_MODULES),$(wildcard libsfm/$(m)/*.c) $(wildcard libsfm/$(m)/generated/*.c))
PUBLIC_HEADERS := $(wildcard include/sfm/*.h)
# Objects depend on every header, public and internal: coarse, but a changed
# constant in an internal header can never leave a stale object behind.
LIB_HEADERS := $(PUBLIC_HEADERS) $(wildcard libsfm/*/*.h libsfm/*/*/*.h)

WARN := -Wall -Wextra -Wpedantic -Werror -Wshadow -Wdouble-promotion
STD := -std=c11 -ffp-contract=off
OPT ?= -O2
ifeq ($(NATIVE),1)
OPT += -march=native
endif
CPPFLAGS_LIB := -Iinclude -Ilibsfm
CPPFLAGS_TEST := $(CPPFLAGS_LIB) -Itests/harness

# tests/unit: portable tests that run on every target (no files, no threads,
# modest memory). tests/native: host-only tests (real data in ../shared/data,
# threads, large problems), same harness, own runner.
UNIT_SRCS := $(wildcard tests/harness/*.c) $(wildcard tests/unit/*.c)
NATIVE_TEST_SRCS := $(wildcard tests/harness/*.c) $(wildcard tests/native/*.c)

# ---------------------------------------------------------------------------
# Build variants. $(call variant,NAME,DIR,CC,CFLAGS,LDFLAGS) defines
#   DIR/libsfm.a                 the core library
#   DIR/tests/unit_tests         the unit test runner
define variant
$(1)_DIR := $(2)
$(1)_CC := $(3)
$(1)_CFLAGS := $(4)
$(1)_LDFLAGS := $(5)
$(1)_OBJS := $$(patsubst %.c,$(2)/obj/%.o,$$(LIB_SRCS))
$(1)_TEST_OBJS := $$(patsubst %.c,$(2)/obj/%.o,$$(UNIT_SRCS)) $(2)/obj/tests/registry.o

$(2)/obj/libsfm/%.o: libsfm/%.c $$(LIB_HEADERS) | $(2)/.dir
	@mkdir -p $$(@D)
	$$($(1)_CC) $$($(1)_CFLAGS) $$(CPPFLAGS_LIB) -c $$< -o $$@

$(2)/obj/tests/%.o: tests/%.c $$(LIB_HEADERS) $$(wildcard tests/*/*.h) | $(2)/.dir
	@mkdir -p $$(@D)
	$$($(1)_CC) $$($(1)_CFLAGS) $$(CPPFLAGS_TEST) -c $$< -o $$@

$(2)/obj/tests/registry.o: $(2)/tests/registry.c
	@mkdir -p $$(@D)
	$$($(1)_CC) $$($(1)_CFLAGS) $$(CPPFLAGS_TEST) -c $$< -o $$@

# The list of test files is recorded so that deleting one also rebuilds.
$$(shell mkdir -p $(2)/tests; echo '$$(UNIT_SRCS)' | cmp -s - $(2)/tests/srclist || echo '$$(UNIT_SRCS)' > $(2)/tests/srclist)
$(2)/tests/registry.c: $$(UNIT_SRCS) $(2)/tests/srclist tools/gen_test_registry.sh | $(2)/.dir
	@mkdir -p $$(@D)
	sh tools/gen_test_registry.sh $$(UNIT_SRCS) > $$@

$$(shell mkdir -p $(2); echo '$$(LIB_SRCS)' | cmp -s - $(2)/lib_srclist || echo '$$(LIB_SRCS)' > $(2)/lib_srclist)
$(2)/libsfm.a: $$($(1)_OBJS) $(2)/lib_srclist
	@rm -f $$@
	$$(AR_$(1)) rcs $$@ $$($(1)_OBJS)

$(2)/tests/unit_tests: $$($(1)_TEST_OBJS) $(2)/libsfm.a
	@mkdir -p $$(@D)
	$$($(1)_CC) $$($(1)_CFLAGS) -o $$@ $$($(1)_TEST_OBJS) $(2)/libsfm.a $$($(1)_LDFLAGS) -lm

$(2)/.dir:
	@mkdir -p $(2)
	@touch $$@
endef

ASAN_LDFLAGS := -fsanitize=address,undefined
ASAN_CFLAGS := $(STD) -O1 -g $(WARN) $(ASAN_LDFLAGS) -fno-sanitize-recover=all -fno-omit-frame-pointer
AR_native := ar
AR_asan := ar
$(eval $(call variant,native,$(BUILD),cc,$(STD) $(OPT) $(WARN) -fPIC -fvisibility=hidden,))
$(eval $(call variant,asan,$(BUILD)/asan,cc,$(ASAN_CFLAGS),$(ASAN_LDFLAGS)))

$(BUILD)/libsfm.so: $(native_OBJS) $(BUILD)/lib_srclist
	cc -shared -Wl,--no-undefined -o $@ $(native_OBJS) -lm

# The cdef the Python binding reads: the public headers after the
# preprocessor, plus the integer macros, kept beside the library it describes.
$(BUILD)/sfm_cdef.h: $(PUBLIC_HEADERS) tools/gen_cdef.sh | $(BUILD)/.dir
	sh tools/gen_cdef.sh include/sfm/sfm.h > $@

all: $(BUILD)/libsfm.a $(BUILD)/libsfm.so $(BUILD)/sfm_cdef.h

# ---------------------------------------------------------------------------
# Tests. Each fragment in mk/ appends its steps to TEST_STEPS; `make test`
# runs them all (a failing step does not stop the others) and ends with the
# summary line of tools/run_tests.sh.
TEST_STEPS := test-unit test-asan test-native test-heapfree

NATIVE_TEST_OBJS := $(patsubst %.c,$(BUILD)/obj/%.o,$(NATIVE_TEST_SRCS)) $(BUILD)/obj/tests/native_registry.o
$(shell mkdir -p $(BUILD)/tests; echo '$(NATIVE_TEST_SRCS)' | cmp -s - $(BUILD)/tests/native_srclist || echo '$(NATIVE_TEST_SRCS)' > $(BUILD)/tests/native_srclist)
$(BUILD)/tests/native_registry.c: $(NATIVE_TEST_SRCS) $(BUILD)/tests/native_srclist tools/gen_test_registry.sh | $(BUILD)/.dir
	@mkdir -p $(@D)
	sh tools/gen_test_registry.sh $(NATIVE_TEST_SRCS) > $@
$(BUILD)/obj/tests/native_registry.o: $(BUILD)/tests/native_registry.c
	cc $(native_CFLAGS) $(CPPFLAGS_TEST) -c $< -o $@
$(BUILD)/tests/native_tests: $(NATIVE_TEST_OBJS) $(BUILD)/libsfm.a
	cc $(native_CFLAGS) -o $@ $(NATIVE_TEST_OBJS) $(BUILD)/libsfm.a -lm -lpthread

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

-include $(sort $(wildcard mk/*.mk))

bench: all
	@set -e; for s in $(BENCH_STEPS); do echo "=== $$s"; $(MAKE) --no-print-directory $$s; done

deps:
	sh tools/setup_deps.sh

test: deps
	@bash tools/run_tests.sh $(TEST_STEPS)

clean:
	rm -rf $(BUILD)

.PHONY: all test deps clean bench $(TEST_STEPS) $(BENCH_STEPS)
