# Eigen oracle (tests/oracle, C++17 against Debian's Eigen 3.4): the linear
# algebra compared with Eigen's decompositions on the same matrices, and the
# C++ interop header include/sfm/sfm_eigen.hpp. One step, one summary line.
EIGEN_INC ?= /usr/include/eigen3
ORACLE_CXX ?= g++
ORACLE_CXXFLAGS := -std=c++17 -O2 -Wall -Wextra -Werror -isystem $(EIGEN_INC) -Iinclude

# Compiling against Eigen is the slow part: objects depend on the headers
# they include only, so a library change costs a relink.
$(BUILD)/oracle/%.o: tests/oracle/%.cc
	@mkdir -p $(@D)
	@test -f $(EIGEN_INC)/Eigen/Dense || { echo "Eigen 3.4 not found in $(EIGEN_INC) (Debian: libeigen3-dev)"; exit 1; }
	$(ORACLE_CXX) $(ORACLE_CXXFLAGS) $(DEPFLAGS) -c -o $@ $<

$(BUILD)/oracle/%: $(BUILD)/oracle/%.o $(BUILD)/libsfm.a
	$(ORACLE_CXX) -o $@ $< $(BUILD)/libsfm.a -lm

ORACLE_PROGS := $(BUILD)/oracle/linalg_oracle $(BUILD)/oracle/test_sfm_eigen
-include $(ORACLE_PROGS:=.d)

TEST_STEPS += test-oracle
test-oracle: $(ORACLE_PROGS)
	@p=0; f=0; rc=0; for t in $(ORACLE_PROGS); do \
	  echo "--- $$t"; $$t > $$t.log 2>&1 || rc=1; cat $$t.log; \
	  line=$$(grep -E '^[0-9]+ passed, [0-9]+ failed' $$t.log | tail -n 1); \
	  if [ -z "$$line" ]; then f=$$((f + 1)); rc=1; else \
	    p=$$((p + $${line%% passed*})); f=$$((f + $$(echo "$$line" | sed -E 's/.* ([0-9]+) failed.*/\1/'))); fi; \
	done; echo "$$p passed, $$f failed"; exit $$rc

.PHONY: test-oracle
.SECONDARY: $(ORACLE_PROGS:=.o)
