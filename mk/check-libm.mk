# make test-no-libm: no source of the core library calls a transcendental
# function of libm directly; they go through core/dmath.h (tools/check_no_libm.sh).
TEST_STEPS += test-no-libm
test-no-libm:
	@sh tools/check_no_libm.sh $(foreach m,$(CORE_MODULES),libsfm/$(m))

.PHONY: test-no-libm
