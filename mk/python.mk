# Python binding tests (cffi ABI mode over build/libsfm.so).
TEST_STEPS += test-python

test-python: all
	PYTHONPATH=python $(PYTHON) -m pytest -q --durations=15 tests/python
