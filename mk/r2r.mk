# Robot-to-robot solvers: the committed elimination templates must be what
# tools/gen_r2r_templates.py writes (SymPy from the venv).
TEST_STEPS += test-r2r-generated

test-r2r-generated:
	@d=$$(mktemp -d) && $(PYTHON) tools/gen_r2r_templates.py $$d 2>/dev/null && \
	if diff -r $$d libsfm/solvers/generated >/dev/null; then \
		rm -rf $$d; echo "r2r-generated: 1 passed, 0 failed"; \
	else \
		diff -r $$d libsfm/solvers/generated | head -20; rm -rf $$d; \
		echo "libsfm/solvers/generated differs from tools/gen_r2r_templates.py output"; \
		echo "r2r-generated: 0 passed, 1 failed"; exit 1; \
	fi
