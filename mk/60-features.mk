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
