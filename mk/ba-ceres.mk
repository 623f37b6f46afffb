# Bundle adjustment: the Ceres oracle test and the benchmark against Ceres.
# Ceres (Debian libceres-dev) is linked only into these programs, never into
# the library.
TEST_STEPS += test-ba-ceres
BENCH_STEPS += bench-ba bench-ba-callgrind

BA_CXX ?= g++
BA_CXXFLAGS := -std=c++17 -O2 -DNDEBUG -Wall -Wextra -Werror -Wno-unused-function -Iinclude -Itests/harness -Itests/oracle \
  $(shell pkg-config --cflags eigen3 2>/dev/null || echo -I/usr/include/eigen3)
BA_CERES_LIBS := -lceres -lglog -lgflags -lpthread -lm

$(BUILD)/oracle/test_ba_ceres: tests/oracle/test_ba_ceres.cc tests/oracle/ba_ceres_problem.h tests/oracle/ba_scene_cc.h tests/unit/ba_scene.h $(BUILD)/obj/tests/harness/sfm_test.o $(BUILD)/libsfm.a
	@mkdir -p $(@D)
	$(BA_CXX) $(BA_CXXFLAGS) -o $@ $< $(BUILD)/obj/tests/harness/sfm_test.o $(BUILD)/libsfm.a $(BA_CERES_LIBS)

$(BUILD)/bench/ba_bench: bench/ba_bench.cc tests/oracle/ba_ceres_problem.h tests/oracle/ba_scene_cc.h tests/unit/ba_scene.h $(BUILD)/obj/tests/harness/sfm_test.o $(BUILD)/libsfm.a
	@mkdir -p $(@D)
	$(BA_CXX) $(BA_CXXFLAGS) -o $@ $< $(BUILD)/obj/tests/harness/sfm_test.o $(BUILD)/libsfm.a $(BA_CERES_LIBS)

test-ba-ceres: $(BUILD)/oracle/test_ba_ceres
	$(BUILD)/oracle/test_ba_ceres

bench-ba: $(BUILD)/bench/ba_bench
	$(BUILD)/bench/ba_bench

.PHONY: test-ba-ceres bench-ba

# Instruction counts beside Ceres (valgrind): `make bench-ba-callgrind`.
bench-ba-callgrind: $(BUILD)/bench/ba_bench
	sh bench/ba_callgrind.sh $(BUILD)/bench/ba_bench
.PHONY: bench-ba-callgrind
