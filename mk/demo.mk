# make demo: the three-view pipeline (frames -> features -> 3-view association
# -> trifocal RANSAC -> calibrated poses -> sparse points) on data the project
# makes itself, then, when ../shared/data/herzjesu-p8 is present, on a real
# triplet of it against its ground truth.
#   build/bin/three_view_demo     firmware_examples/linux/three_view_demo.c
#   build/demo/synthetic/         rendered by tools/gen_demo_scene.py (a replay
#                                 directory plus ground_truth.txt)
#   build/demo/herzjesu/          Herz-Jesu-P8 views 0000-0002 at 1024x683
#                                 (tools/prep_demo_herzjesu.py)
#   make test-demo                the errors on the synthetic scene, bounded

DEMO_DIR := $(BUILD)/demo
DEMO_BIN := $(BUILD)/bin/three_view_demo
DEMO_SYN := $(DEMO_DIR)/synthetic
DEMO_HJ := $(DEMO_DIR)/herzjesu
DEMO_HJ_SRC ?= ../shared/data/herzjesu-p8

$(DEMO_BIN): firmware_examples/linux/three_view_demo.c $(BUILD)/libsfm_capture.a $(BUILD)/libsfm.a $(CAP_CONFIG)
	@mkdir -p $(@D)
	$(CC) $(native_CFLAGS) -Iinclude $(DEPFLAGS) $(LDFLAGS) -o $@ $< $(BUILD)/libsfm_capture.a $(BUILD)/libsfm.a $(CAPTURE_LDLIBS)
-include $(DEMO_BIN).d

# The generator needs numpy and OpenCV from the venv: when they are missing,
# only those are installed (python/requirements-demo.txt); `make test` adds
# the rest of what the tests need.
demo-deps:
	@$(PYTHON) -c "import numpy, cv2" 2>/dev/null || sh tools/setup_deps.sh demo

$(DEMO_SYN)/ground_truth.txt: tools/gen_demo_scene.py | demo-deps
	@rm -rf $(DEMO_SYN)
	$(PYTHON) tools/gen_demo_scene.py $(DEMO_SYN)

$(DEMO_HJ)/ground_truth.txt: tools/prep_demo_herzjesu.py | demo-deps
	@rm -rf $(DEMO_HJ)
	$(PYTHON) tools/prep_demo_herzjesu.py $(DEMO_HJ_SRC) $(DEMO_HJ)

demo: all capture $(DEMO_BIN) $(DEMO_SYN)/ground_truth.txt
	@echo "=== synthetic room, 640x480, three views (tools/gen_demo_scene.py)"
	$(DEMO_BIN) $(DEMO_SYN) --gt $(DEMO_SYN)/ground_truth.txt --ply $(DEMO_SYN)/points.ply
	@if [ -d $(DEMO_HJ_SRC)/images ]; then \
	  $(MAKE) --no-print-directory $(DEMO_HJ)/ground_truth.txt && \
	  echo "=== Herz-Jesu-P8 views 0000 0001 0002 reduced 3x to 1024x682 ($(DEMO_HJ_SRC))" && \
	  echo "$(DEMO_BIN) $(DEMO_HJ) --gt $(DEMO_HJ)/ground_truth.txt --ply $(DEMO_HJ)/points.ply" && \
	  $(DEMO_BIN) $(DEMO_HJ) --gt $(DEMO_HJ)/ground_truth.txt --ply $(DEMO_HJ)/points.ply; \
	else \
	  echo "=== real data skipped: $(DEMO_HJ_SRC) not found (Herz-Jesu-P8 is not part of the project)"; \
	fi
	@$(MAKE) --no-print-directory demo-vo

TEST_STEPS += test-demo
test-demo: $(DEMO_BIN) $(DEMO_SYN)/ground_truth.txt
	sh tests/demo/run.sh $(DEMO_BIN) $(DEMO_SYN)

.PHONY: demo demo-deps test-demo
