# make test-clang: the library and the unit tests built with clang under the
# same warnings (-Werror) and -ffp-contract=off, and run. Its results must be
# the same bits as GCC's: test-golden compares them (mk/golden.mk).
CLANG ?= clang
AR_clang := ar
$(eval $(call variant,clang,$(BUILD)/clang,$(CLANG),$(STD) $(OPT) $(WARN),))

TEST_STEPS += test-clang
test-clang: $(BUILD)/clang/tests/unit_tests
	$(BUILD)/clang/tests/unit_tests

.PHONY: test-clang
