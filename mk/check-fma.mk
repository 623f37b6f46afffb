# make test-no-fma: no object of the core contains a fused multiply-add, on
# any target, even when built for an FMA-capable x86-64 (-march=x86-64-v3, what
# NATIVE=1 gives on a recent machine): -ffp-contract=off forbids contraction,
# but GCC 12's vectorizer emitted vfmaddsub in sfm_eig regardless. A fused
# operation rounds once where the others round twice, so results would differ
# between CPUs. objdump over the x86-64-v3, aarch64 and Cortex-M7 archives.
AR_fmacheck := ar
$(eval $(call variant,fmacheck,$(BUILD)/x86-64-v3,cc,$(STD) $(OPT) -march=x86-64-v3 $(WARN),))

TEST_STEPS += test-no-fma
FMA_PATTERN := \<(v?f(n)?m(add|sub)[a-z0-9]*|vfmaddsub[a-z0-9]*|vfmsubadd[a-z0-9]*|fml[as]|vfn?m[as])\>
test-no-fma: $(BUILD)/x86-64-v3/libsfm.a $(BUILD)/aarch64/libsfm.a $(BUILD)/cortex-m7/libsfm.a
	@bad=0; \
	for pair in objdump:$(BUILD)/x86-64-v3/libsfm.a aarch64-linux-gnu-objdump:$(BUILD)/aarch64/libsfm.a \
	            arm-none-eabi-objdump:$(BUILD)/cortex-m7/libsfm.a; do \
	  od=$${pair%%:*}; lib=$${pair#*:}; \
	  hits=$$($$od -d $$lib | awk '/^[^ ].*:$$/ {f=$$0} /^ /{ print f "\t" $$0 }' | grep -E '	.*$(FMA_PATTERN)' || true); \
	  if [ -n "$$hits" ]; then echo "FAIL: fused multiply-add in $$lib:"; echo "$$hits" | head -20; bad=1; \
	  else echo "ok   $$lib: no fused multiply-add"; fi; \
	done; \
	if [ $$bad = 0 ]; then echo "no-fma: 3 passed, 0 failed"; else echo "no-fma: 0 passed, 1 failed"; exit 1; fi

.PHONY: test-no-fma
