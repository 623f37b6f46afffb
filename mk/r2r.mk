# Robot-to-robot solvers: the committed generated files must be what the
# generators write: the elimination templates (tools/gen_r2r_templates.py,
# SymPy from the venv) and the D6 homotopy's start system
# (tools/gen_r2r_d6_start.py, numpy and mpmath; about 10 s).
TEST_STEPS += test-r2r-generated

test-r2r-generated:
	@d=$$(mktemp -d) && $(PYTHON) tools/gen_r2r_templates.py $$d 2>/dev/null && \
	$(PYTHON) tools/gen_r2r_d6_start.py $$d 2>/dev/null && \
	if diff -r $$d libsfm/solvers/generated >/dev/null; then \
		rm -rf $$d; echo "r2r-generated: 1 passed, 0 failed"; \
	else \
		diff -r $$d libsfm/solvers/generated | head -20; rm -rf $$d; \
		echo "libsfm/solvers/generated differs from tools/gen_r2r_templates.py / gen_r2r_d6_start.py output"; \
		echo "r2r-generated: 0 passed, 1 failed"; exit 1; \
	fi
