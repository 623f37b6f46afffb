# Cross builds: the same sources and unit tests for an aarch64 Linux board
# (run under qemu-user) and for a Cortex-M7 (run under qemu-system-arm with
# semihosting: the proof that the core needs no OS and no heap).

AARCH64_CC ?= aarch64-linux-gnu-gcc
AARCH64_AR ?= aarch64-linux-gnu-ar
AR_aarch64 := $(AARCH64_AR)
# Its unit tests run under qemu-user, some twenty times slower than the host:
# like the Cortex-M7 build they run a tenth of the randomized loops
# (SFM_TEST_REDUCED, tests only; the library does not read it). The full
# statistics run natively and under ASan; the golden outputs prove the
# aarch64 results bit for bit.
$(eval $(call variant,aarch64,$(BUILD)/aarch64,$(AARCH64_CC),$(STD) $(OPT) $(WARN) -DSFM_TEST_REDUCED,-static,$(AARCH64_AR)))

M7_ARCH := -mcpu=cortex-m7 -mfpu=fpv5-d16 -mfloat-abi=hard -mthumb
M7_CC ?= arm-none-eabi-gcc
M7_AR ?= arm-none-eabi-ar
AR_cortexm7 := $(M7_AR)
M7_CFLAGS := $(STD) $(OPT) $(WARN) $(M7_ARCH) -ffunction-sections -fdata-sections -DSFM_TEST_REDUCED
M7_DIR := firmware_examples/cortex-m7
M7_LDFLAGS := -nostartfiles --specs=rdimon.specs -L $(M7_DIR) -T $(M7_DIR)/mps2_an500.ld -Wl,--gc-sections $(M7_DIR)/startup.c
# Flash is the scarce resource on a microcontroller: the code a robot runs per
# sample and per point keeps OPT, every other source (contracts, set-up,
# decompositions off the loop, refinement, three-view, new modules until
# listed here) is built for size. The list is what callgrind shows taking
# >= 1 % of a relative-pose RANSAC run. With the support checks, the LM
# driver and the library's own elementary functions in the pose path, only
# the 5-point solver (the largest share of a run) still fits the 128 KB
# budget at OPT: the rest, the feature pipeline included, is built for size.
# Built for size, the helpers of the internal headers are shared, not copied
# into every object (core/inline.h). The budget holds the whole core as it
# was when it was set, recon's calibrated three-view pose included
# (tools/footprint.sh lists the objects): 131,070 B of 131,072.
# M7_HOT_SRCS= builds everything for size.
M7_HOT_SRCS ?= libsfm/solvers/relpose_5pt.c
cortexm7_COLD_SRCS := $(filter-out $(M7_HOT_SRCS),$(LIB_SRCS))
cortexm7_COLD_OPT := -Os
$(eval $(call variant,cortexm7,$(BUILD)/cortex-m7,$(M7_CC),$(M7_CFLAGS),$(M7_LDFLAGS),$(M7_AR)))

$(BUILD)/cortex-m7/tests/unit_tests: $(M7_DIR)/startup.c $(M7_DIR)/mps2_an500.ld $(M7_DIR)/mps2_sections.ld

cross: $(BUILD)/aarch64/libsfm.a
# Builds the archive and the example, then prints the footprint table of the
# README (tools/footprint.sh).
firmware: $(BUILD)/cortex-m7/libsfm.a $(BUILD)/cortex-m7/examples/relpose_demo.elf
	@sh tools/footprint.sh $(BUILD)/cortex-m7 "$(CORE_MODULES)"

# The example is what a part with 64 KB of flash and 32 KB of RAM takes: the
# library built for size throughout with link-time optimisation
# (build/cortex-m7/size/libsfm.a), newlib-nano (no floating-point printf: the
# library never prints, the example prints integers). Its linker script
# bounds flash and RAM (data, bss, heap and stack); the RAM it used is
# measured at run time.
$(eval $(call variant,cortexm7size,$(BUILD)/cortex-m7/size,$(M7_CC),$(M7_CFLAGS) -Os -flto,$(M7_LDFLAGS),$(M7_CC:gcc=gcc-ar)))
M7_EXAMPLE_LDFLAGS := -nostartfiles --specs=nano.specs --specs=rdimon.specs -L $(M7_DIR) -T $(M7_DIR)/relpose_demo.ld \
    -Wl,--gc-sections -Wl,-Map=$(BUILD)/cortex-m7/examples/relpose_demo.map $(M7_DIR)/startup.c
$(BUILD)/cortex-m7/examples/relpose_demo.elf: $(M7_DIR)/main.c $(BUILD)/cortex-m7/size/libsfm.a $(M7_DIR)/startup.c \
    $(M7_DIR)/relpose_demo.ld $(M7_DIR)/mps2_sections.ld
	@mkdir -p $(@D)
	$(M7_CC) $(M7_CFLAGS) -Os -flto=auto -Iinclude -o $@ $(M7_DIR)/main.c $(BUILD)/cortex-m7/size/libsfm.a $(M7_EXAMPLE_LDFLAGS) -lm

TEST_STEPS += test-aarch64 test-cortex-m7 test-heapfree-cross test-footprint

test-aarch64: $(BUILD)/aarch64/tests/unit_tests
	qemu-aarch64 $(BUILD)/aarch64/tests/unit_tests

# Full-system emulation of an MPS2 AN500 board; output and exit status travel
# over semihosting. A fault or a failed test ends the run with status 1.
QEMU_M7 := qemu-system-arm -M mps2-an500 -cpu cortex-m7 -nographic -monitor none -serial none \
	-semihosting-config enable=on,target=native -kernel
test-cortex-m7: $(BUILD)/cortex-m7/tests/unit_tests $(BUILD)/cortex-m7/examples/relpose_demo.elf
	timeout 600 $(QEMU_M7) $(BUILD)/cortex-m7/examples/relpose_demo.elf
	timeout 900 $(QEMU_M7) $(BUILD)/cortex-m7/tests/unit_tests

test-heapfree-cross: $(BUILD)/aarch64/libsfm.a $(BUILD)/cortex-m7/libsfm.a
	NM=aarch64-linux-gnu-nm sh tools/check_heapfree.sh $(BUILD)/aarch64/libsfm.a
	NM=arm-none-eabi-nm sh tools/check_heapfree.sh $(BUILD)/cortex-m7/libsfm.a

# The budget: the whole core (tools/footprint.sh --budget) <= 128 KB of
# flash, the example <= 64 KB of flash and <= 32 KB of RAM
# (tests/firmware/footprint.sh).
test-footprint: $(BUILD)/cortex-m7/libsfm.a $(BUILD)/cortex-m7/examples/relpose_demo.elf
	sh tests/firmware/footprint.sh $(BUILD)/cortex-m7

.PHONY: cross firmware test-aarch64 test-cortex-m7 test-heapfree-cross test-footprint
