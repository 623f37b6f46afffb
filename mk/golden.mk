# Golden outputs (tests/golden/golden.c): fixed-seed estimators on fixed
# synthetic inputs print one hash per output; every target must print the
# lines of the one committed file tests/golden/golden.txt.
#   make test-golden     native (gcc), clang, x86-64-v3 (FMA-capable ISA),
#                        aarch64 under qemu-aarch64, Cortex-M7 under
#                        qemu-system-arm: all compared with the file
#   make golden-update   regenerate the file natively (after an intended change
#                        of an estimator's results), then check the others agree
GOLDEN_FILE := tests/golden/golden.txt
GOLDEN_SRC := tests/golden/golden.c
GOLDEN_DIR := $(BUILD)/golden

$(GOLDEN_DIR)/golden: $(GOLDEN_SRC) $(BUILD)/libsfm.a $(PUBLIC_HEADERS)
	@mkdir -p $(@D)
	cc $(STD) $(OPT) $(WARN) -Iinclude -o $@ $< $(BUILD)/libsfm.a -lm
$(GOLDEN_DIR)/golden-clang: $(GOLDEN_SRC) $(BUILD)/clang/libsfm.a $(PUBLIC_HEADERS)
	@mkdir -p $(@D)
	$(CLANG) $(STD) $(OPT) $(WARN) -Iinclude -o $@ $< $(BUILD)/clang/libsfm.a -lm
$(GOLDEN_DIR)/golden-x86-64-v3: $(GOLDEN_SRC) $(BUILD)/x86-64-v3/libsfm.a $(PUBLIC_HEADERS)
	@mkdir -p $(@D)
	cc $(STD) $(OPT) -march=x86-64-v3 $(WARN) -Iinclude -o $@ $< $(BUILD)/x86-64-v3/libsfm.a -lm
$(GOLDEN_DIR)/golden-aarch64: $(GOLDEN_SRC) $(BUILD)/aarch64/libsfm.a $(PUBLIC_HEADERS)
	@mkdir -p $(@D)
	$(AARCH64_CC) $(STD) $(OPT) $(WARN) -Iinclude -static -o $@ $< $(BUILD)/aarch64/libsfm.a -lm
$(GOLDEN_DIR)/golden-cortex-m7.elf: $(GOLDEN_SRC) $(BUILD)/cortex-m7/libsfm.a $(PUBLIC_HEADERS) $(M7_DIR)/startup.c $(M7_DIR)/mps2_an500.ld
	@mkdir -p $(@D)
	$(M7_CC) $(M7_CFLAGS) -Iinclude -o $@ $< $(BUILD)/cortex-m7/libsfm.a $(M7_LDFLAGS) -lm

GOLDEN_BINS := $(GOLDEN_DIR)/golden $(GOLDEN_DIR)/golden-clang $(GOLDEN_DIR)/golden-x86-64-v3 \
	$(GOLDEN_DIR)/golden-aarch64 $(GOLDEN_DIR)/golden-cortex-m7.elf
GOLDEN_RUNS := native=$(GOLDEN_DIR)/golden clang=$(GOLDEN_DIR)/golden-clang \
	x86-64-v3=$(GOLDEN_DIR)/golden-x86-64-v3 \
	aarch64="qemu-aarch64 $(GOLDEN_DIR)/golden-aarch64" \
	cortex-m7="timeout 600 $(QEMU_M7) $(GOLDEN_DIR)/golden-cortex-m7.elf"

TEST_STEPS += test-golden
test-golden: $(GOLDEN_BINS)
	sh tools/golden_compare.sh $(GOLDEN_FILE) $(GOLDEN_RUNS)

golden-update: $(GOLDEN_BINS)
	GOLDEN_UPDATE=1 sh tools/golden_compare.sh $(GOLDEN_FILE) $(GOLDEN_RUNS)

.PHONY: test-golden golden-update
