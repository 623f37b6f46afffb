# Cross builds: the same sources and unit tests for an aarch64 Linux board
# (run under qemu-user) and for a Cortex-M7 (run under qemu-system-arm with
# semihosting: the proof that the core needs no OS and no heap).

AARCH64_CC ?= aarch64-linux-gnu-gcc
AARCH64_AR ?= aarch64-linux-gnu-ar
$(eval $(call variant,aarch64,$(BUILD)/aarch64,$(AARCH64_CC),$(STD) $(OPT) $(WARN),-static,$(AARCH64_AR)))

M7_ARCH := -mcpu=cortex-m7 -mfpu=fpv5-d16 -mfloat-abi=hard -mthumb
M7_CC ?= arm-none-eabi-gcc
M7_AR ?= arm-none-eabi-ar
M7_CFLAGS := $(STD) $(OPT) $(WARN) $(M7_ARCH) -ffunction-sections -fdata-sections -DSFM_TEST_REDUCED
M7_DIR := firmware_examples/cortex-m7
M7_LDFLAGS := -nostartfiles --specs=rdimon.specs -T $(M7_DIR)/mps2_an500.ld -Wl,--gc-sections $(M7_DIR)/startup.c
$(eval $(call variant,cortexm7,$(BUILD)/cortex-m7,$(M7_CC),$(M7_CFLAGS),$(M7_LDFLAGS),$(M7_AR)))

$(BUILD)/cortex-m7/tests/unit_tests: $(M7_DIR)/startup.c $(M7_DIR)/mps2_an500.ld

cross: $(BUILD)/aarch64/libsfm.a
firmware: $(BUILD)/cortex-m7/libsfm.a $(BUILD)/cortex-m7/examples/relpose_demo.elf

$(BUILD)/cortex-m7/examples/relpose_demo.elf: $(M7_DIR)/main.c $(BUILD)/cortex-m7/libsfm.a $(M7_DIR)/startup.c $(M7_DIR)/mps2_an500.ld
	@mkdir -p $(@D)
	$(M7_CC) $(M7_CFLAGS) -Iinclude -o $@ $(M7_DIR)/main.c $(BUILD)/cortex-m7/libsfm.a $(M7_LDFLAGS) -lm

TEST_STEPS += test-aarch64 test-cortex-m7 test-heapfree-cross

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

# Flash and RAM the core takes on a Cortex-M7 (text+rodata / data+bss),
# as arm-none-eabi-size reports for the archive's objects.
footprint: $(BUILD)/cortex-m7/libsfm.a
	@arm-none-eabi-size -t $(BUILD)/cortex-m7/libsfm.a | tail -n 1 | \
	  awk '{printf "cortex-m7 libsfm.a: flash %d bytes (text), RAM %d bytes (data+bss)\n", $$1, $$2 + $$3}'

.PHONY: cross firmware footprint test-aarch64 test-cortex-m7 test-heapfree-cross
