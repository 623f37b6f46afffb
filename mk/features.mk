# Features: the generated BRIEF pattern must be what its generator writes, and
# the benchmark beside OpenCV's ORB on Herz-Jesu-P8.
TEST_STEPS += test-features-generated
BENCH_STEPS += bench-features

test-features-generated:
	@if python3 tools/gen_brief_pattern.py | cmp -s - libsfm/features/generated/brief_pattern.c; then \
		echo "features-generated: 1 passed, 0 failed"; \
	else \
		echo "libsfm/features/generated/brief_pattern.c differs from tools/gen_brief_pattern.py output"; \
		echo "features-generated: 0 passed, 1 failed"; exit 1; \
	fi

bench-features: all
	PYTHONPATH=python $(PYTHON) bench/features_vs_orb.py

# Instruction count of one detect+describe on Herz-Jesu-P8 view 3 at 1024 px
# (callgrind; repeatable where wall time on a shared machine is not).
BENCH_STEPS += bench-features-callgrind
FEAT_BENCH_DIR := $(BUILD)/bench
bench-features-callgrind: $(BUILD)/bench/features_callgrind
	@PYTHONPATH=bench $(PYTHON) -c "import features_vs_orb as B, sys, os; \
		d = B.DATA; \
		os.path.isdir(d) or sys.exit(print('SKIP: %s not found; the callgrind figure needs Herz-Jesu-P8' % d)); \
		v = B.load_views()[3][0]; v.tofile('$(FEAT_BENCH_DIR)/herzjesu3.raw'); \
		open('$(FEAT_BENCH_DIR)/herzjesu3.size', 'w').write('%d %d' % (v.shape[1], v.shape[0]))"
	@if [ -f $(FEAT_BENCH_DIR)/herzjesu3.raw ]; then \
		valgrind --tool=callgrind --callgrind-out-file=$(FEAT_BENCH_DIR)/features.callgrind \
			$(FEAT_BENCH_DIR)/features_callgrind $(FEAT_BENCH_DIR)/herzjesu3.raw $$(cat $(FEAT_BENCH_DIR)/herzjesu3.size) 2>&1 \
			| grep -E "keypoints|I *refs"; \
		callgrind_annotate $(FEAT_BENCH_DIR)/features.callgrind 2>/dev/null | grep -E "features/" | head -12; \
	fi

.PHONY: test-features-generated bench-features bench-features-callgrind
