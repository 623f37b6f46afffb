# Leader-follower motion (sfm_r2r_motion.h):
#   make bench-r2r-motion   the KKT next motion beside a grid search over the
#                           admissible disk: us per call, ratio, the grid's gap;
#                           then instructions per call under callgrind
#   make demo-leader-follower  the 50-trial Monte-Carlo simulation and its plot
#                           (build/leader_follower.png, build/leader_follower.txt)
BENCH_STEPS += bench-r2r-motion

bench-r2r-motion: $(BUILD)/bench/formation_bench
	$(BUILD)/bench/formation_bench
	@if command -v valgrind >/dev/null; then sh bench/formation_callgrind.sh $(BUILD)/bench/formation_bench; fi

demo-leader-follower: all
	PYTHONPATH=python $(PYTHON) -m libsfm.leader_follower_demo --out $(BUILD)

.PHONY: bench-r2r-motion demo-leader-follower
