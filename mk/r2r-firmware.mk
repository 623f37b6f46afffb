# Robot-to-robot calibration example and benchmark: the example
# firmware_examples/r2r_calibration, two simulated robots exchanging ranges
# and bearings, calibrated by sfm_r2r_ransac (solve + refine); built for
# Linux and for a bare-metal Cortex-M7 run under qemu-system-arm.
R2R_FW := firmware_examples/r2r_calibration

$(BUILD)/bin/r2r-calibration: $(R2R_FW)/main.c $(BUILD)/libsfm.a $(PUBLIC_HEADERS)
	@mkdir -p $(@D)
	$(CC) $(HOST_CFLAGS) -Iinclude -o $@ $< $(BUILD)/libsfm.a $(LDFLAGS) -lm

$(BUILD)/cortex-m7/examples/r2r_calibration.elf: $(R2R_FW)/main.c $(BUILD)/cortex-m7/libsfm.a $(M7_DIR)/startup.c $(M7_DIR)/mps2_an500.ld $(PUBLIC_HEADERS)
	@mkdir -p $(@D)
	$(M7_CC) $(M7_CFLAGS) -Iinclude -o $@ $< $(BUILD)/cortex-m7/libsfm.a $(M7_LDFLAGS) -lm

firmware: $(BUILD)/bin/r2r-calibration $(BUILD)/cortex-m7/examples/r2r_calibration.elf

TEST_STEPS += test-r2r-calibration test-cortex-m-r2r
test-r2r-calibration: $(BUILD)/bin/r2r-calibration
	$(BUILD)/bin/r2r-calibration && echo "r2r-calibration: 1 passed, 0 failed" || \
	  { echo "r2r-calibration: 0 passed, 1 failed"; exit 1; }

# -icount shift=0: one instruction per virtual nanosecond (SysTick x40).
test-cortex-m-r2r: $(BUILD)/cortex-m7/examples/r2r_calibration.elf
	timeout 600 qemu-system-arm -M mps2-an500 -cpu cortex-m7 -nographic \
	  -monitor none -serial none -semihosting-config enable=on,target=native -icount shift=0 \
	  -kernel $< && echo "cortex-m-r2r: 1 passed, 0 failed" || \
	  { echo "cortex-m-r2r: 0 passed, 1 failed"; exit 1; }
	@arm-none-eabi-size $<

.PHONY: test-r2r-calibration test-cortex-m-r2r

# make bench: sfm_r2r_refine beside scipy least_squares on the same cost, and
# sfm_r2r_ransac on sequences with outlier measurements (bench/README.md).
BENCH_STEPS += bench-r2r-refine
bench-r2r-refine: all
	PYTHONPATH=python $(PYTHON) bench/r2r_refine_bench.py
.PHONY: bench-r2r-refine
