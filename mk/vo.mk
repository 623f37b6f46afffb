# Visual odometry (libsfm/vo): the sequence demo and its tests.
#   make demo-vo        renders build/demo/sequence (tools/gen_demo_scene.py
#                       --sequence) once, runs python -m libsfm.replay on it:
#                       per-frame status, ATE (Sim3) / RPE against the known
#                       trajectory, ms/frame, share per stage; writes
#                       trajectory.tum, points.ply, trajectory.png beside it
#   make demo-vo-selfcal  the same without intrinsics (--self-calibrate): the
#                       focal length found by self-calibration is printed
#   make test-vo-demo   the same run, ATE and tracking held to bounds; the
#                       self-calibrated start; the fisheye sequence
#   make test-vo-kitti  ../shared/data/kitti-seq1: ATE / RPE over 20 seeds
#                       beside the OpenCV frame-to-frame baseline

VO_SEQ := $(BUILD)/demo/sequence
VO_SEQ_FRAMES ?= 240
# The demo scene is close and textured: three pyramid levels suffice, and new
# points need 1 deg of parallax (KITTI, driving forward, keeps the defaults:
# 4 levels, 0.5 deg, since its points near the focus of expansion move little).
VO_DEMO_SET := --set n_levels=3 --set point_min_parallax_deg=1.0
VO_KITTI ?= ../shared/data/kitti-seq1
# The same loop through a Kannala-Brandt fisheye lens (gen_demo_scene.py --fisheye).
VO_FISH := $(BUILD)/demo/sequence_fisheye
VO_FISH_FRAMES ?= 120

$(VO_SEQ)/ground_truth.txt: tools/gen_demo_scene.py | demo-deps
	@rm -rf $(VO_SEQ)
	$(PYTHON) tools/gen_demo_scene.py --sequence $(VO_SEQ_FRAMES) $(VO_SEQ)

$(VO_FISH)/ground_truth.txt: tools/gen_demo_scene.py | demo-deps
	@rm -rf $(VO_FISH)
	$(PYTHON) tools/gen_demo_scene.py --sequence $(VO_FISH_FRAMES) --fisheye $(VO_FISH)

vo-deps:
	@$(PYTHON) -c "import numpy, cv2, tqdm, matplotlib, cffi" 2>/dev/null || sh tools/setup_deps.sh demo

demo-vo: all vo-deps $(VO_SEQ)/ground_truth.txt
	@echo "=== visual odometry: $(VO_SEQ_FRAMES) rendered frames 640x480 along a known loop (tools/gen_demo_scene.py --sequence)"
	PYTHONPATH=python $(PYTHON) -m libsfm.replay $(VO_SEQ) --features 500 --window 5 $(VO_DEMO_SET) --every 20 --no-progress \
	  --trajectory $(VO_SEQ)/trajectory.tum --points $(VO_SEQ)/points.ply --plot $(VO_SEQ)/trajectory.png
	@echo "wrote $(VO_SEQ)/trajectory.tum (camera-to-world), $(VO_SEQ)/points.ply, $(VO_SEQ)/trajectory.png"

# The same sequence started without a camera: the pipeline self-calibrates
# (the recording's intrinsics ignored) and prints the focal length found.
demo-vo-selfcal: all vo-deps $(VO_SEQ)/ground_truth.txt
	@echo "=== visual odometry without intrinsics: self-calibration on the first good keyframe triple"
	PYTHONPATH=python $(PYTHON) -m libsfm.replay $(VO_SEQ) --self-calibrate --features 500 --window 5 $(VO_DEMO_SET) --every 20 --no-progress \
	  --trajectory $(VO_SEQ)/trajectory_selfcal.tum --plot $(VO_SEQ)/trajectory_selfcal.png

TEST_STEPS += test-vo-demo test-vo-kitti
test-vo-demo: all vo-deps $(VO_SEQ)/ground_truth.txt $(VO_FISH)/ground_truth.txt
	VO_SEQ=$(VO_SEQ) VO_FISH=$(VO_FISH) PYTHONPATH=python $(PYTHON) -m pytest -q tests/vo/test_vo_demo.py tests/vo/test_vo_replay.py tests/vo/test_vo_fisheye.py

test-vo-kitti: all vo-deps
	VO_KITTI=$(VO_KITTI) PYTHONPATH=python $(PYTHON) -m pytest -q -s tests/vo/test_vo_kitti.py tests/vo/test_vo_stills.py

.PHONY: demo-vo demo-vo-selfcal vo-deps test-vo-demo test-vo-kitti

# ---------------------------------------------------------------------------
# Firmware examples of the VO pipeline.
#   build/bin/vo-camera            firmware_examples/linux_v4l2_vo (V4L2, libcamera or replay)
#   build/bin/vo-libcamera         firmware_examples/rpi_libcamera_vo (libcamera by default)
#   build/aarch64/bin/vo-camera    the same cross-built (static; the capture library
#                                  without PNG/JPEG/libcamera: PGM replay and V4L2)
#   make test-vo-firmware          native and qemu-aarch64 runs on the rendered
#                                  sequence give the same trajectory
VO_FW := firmware_examples/linux_v4l2_vo
VO_FW_FRAMES ?= 90

$(BUILD)/bin/vo-camera: $(VO_FW)/vo_main.c $(PUBLIC_HEADERS) $(BUILD)/libsfm_capture.a $(BUILD)/libsfm.a
	@mkdir -p $(@D)
	cc $(native_CFLAGS) -Iinclude -o $@ $< $(BUILD)/libsfm_capture.a $(BUILD)/libsfm.a $(CAPTURE_LDLIBS)

$(BUILD)/bin/vo-libcamera: firmware_examples/rpi_libcamera_vo/main.c $(VO_FW)/vo_main.c $(PUBLIC_HEADERS) $(BUILD)/libsfm_capture.a $(BUILD)/libsfm.a
	@mkdir -p $(@D)
	cc $(native_CFLAGS) -Iinclude -o $@ $< $(BUILD)/libsfm_capture.a $(BUILD)/libsfm.a $(CAPTURE_LDLIBS)

VO_A64_CAP_SRCS := $(CAPTURE_C_SRCS)
VO_A64_CAP_OBJS := $(patsubst libsfm/capture/%.c,$(BUILD)/aarch64/capture/%.o,$(VO_A64_CAP_SRCS))
$(BUILD)/aarch64/capture/%.o: libsfm/capture/%.c $(CAPTURE_HEADERS)
	@mkdir -p $(@D)
	$(AARCH64_CC) $(STD) $(OPT) $(WARN) $(CPPFLAGS_LIB) -c $< -o $@
$(BUILD)/aarch64/libsfm_capture.a: $(VO_A64_CAP_OBJS)
	@rm -f $@
	$(AR_aarch64) rcs $@ $^
$(BUILD)/aarch64/bin/vo-camera: $(VO_FW)/vo_main.c $(PUBLIC_HEADERS) $(BUILD)/aarch64/libsfm_capture.a $(BUILD)/aarch64/libsfm.a
	@mkdir -p $(@D)
	$(AARCH64_CC) $(STD) $(OPT) $(WARN) -DVO_NO_LIBCAMERA -Iinclude -o $@ $< $(BUILD)/aarch64/libsfm_capture.a $(BUILD)/aarch64/libsfm.a -static -lm

vo-firmware: $(BUILD)/bin/vo-camera $(BUILD)/bin/vo-libcamera $(BUILD)/aarch64/bin/vo-camera

TEST_STEPS += test-vo-firmware
test-vo-firmware: vo-firmware $(VO_SEQ)/ground_truth.txt
	sh tests/vo/run_firmware.sh $(BUILD) $(VO_SEQ) $(VO_FW_FRAMES)

.PHONY: vo-firmware test-vo-firmware

# ---------------------------------------------------------------------------
# firmware_examples/cortex_m_relpose: bare-metal 5-point RANSAC on matches
# streamed from a semihosting file, under qemu-system-arm (MPS2 AN500).
VO_M7 := firmware_examples/cortex_m_relpose
$(BUILD)/cortex-m7/examples/cortex_m_relpose.elf: $(VO_M7)/main.c $(BUILD)/cortex-m7/libsfm.a $(M7_DIR)/startup.c $(M7_DIR)/mps2_an500.ld
	@mkdir -p $(@D)
	$(M7_CC) $(M7_CFLAGS) -Iinclude -o $@ $(VO_M7)/main.c $(BUILD)/cortex-m7/libsfm.a $(M7_LDFLAGS) -lm
$(BUILD)/cortex-m7/examples/matches.bin: tools/gen_relpose_stream.py
	@mkdir -p $(@D)
	$(PYTHON) tools/gen_relpose_stream.py $@

firmware: $(BUILD)/cortex-m7/examples/cortex_m_relpose.elf
TEST_STEPS += test-cortex-m-relpose
# -icount shift=0: one instruction per virtual nanosecond, so SysTick ticks
# count instructions (x40). The example reads matches.bin relative to cwd.
test-cortex-m-relpose: $(BUILD)/cortex-m7/examples/cortex_m_relpose.elf $(BUILD)/cortex-m7/examples/matches.bin
	cd $(BUILD)/cortex-m7/examples && timeout 600 qemu-system-arm -M mps2-an500 -cpu cortex-m7 -nographic \
	  -monitor none -serial none -semihosting-config enable=on,target=native -icount shift=0 \
	  -kernel cortex_m_relpose.elf && echo "1 passed, 0 failed" || { echo "0 passed, 1 failed"; exit 1; }
	@arm-none-eabi-size $(BUILD)/cortex-m7/examples/cortex_m_relpose.elf

.PHONY: test-cortex-m-relpose

# make bench: VO ms/frame and per-stage shares beside the OpenCV baseline.
BENCH_STEPS += bench-vo
bench-vo: all vo-deps $(VO_SEQ)/ground_truth.txt
	PYTHONPATH=python $(PYTHON) bench/vo_bench.py $(VO_SEQ)
.PHONY: bench-vo
