# make install PREFIX=...: headers, both libraries, pkg-config file, CMake
# package, and the cdef the Python binding reads.
SFM_VERSION_STR := $(shell sed -n 's/^\#define SFM_VERSION_\(MAJOR\|MINOR\|PATCH\) \([0-9]*\)/\2/p' include/sfm/sfm_common.h | paste -sd.)

install: all
	install -d $(DESTDIR)$(PREFIX)/include/sfm $(DESTDIR)$(PREFIX)/lib/pkgconfig \
	  $(DESTDIR)$(PREFIX)/lib/cmake/sfm $(DESTDIR)$(PREFIX)/share/sfm
	install -m 644 $(PUBLIC_HEADERS) $(wildcard include/sfm/*.hpp) $(DESTDIR)$(PREFIX)/include/sfm/
	install -m 644 $(BUILD)/libsfm.a $(DESTDIR)$(PREFIX)/lib/
	install -m 755 $(BUILD)/libsfm.so $(DESTDIR)$(PREFIX)/lib/
	install -m 644 $(BUILD)/sfm_cdef.h $(DESTDIR)$(PREFIX)/share/sfm/
	sed -e 's|@PREFIX@|$(PREFIX)|' -e 's|@VERSION@|$(SFM_VERSION_STR)|' tools/install/sfm.pc.in \
	  > $(DESTDIR)$(PREFIX)/lib/pkgconfig/sfm.pc
	install -m 644 tools/install/sfmConfig.cmake.in $(DESTDIR)$(PREFIX)/lib/cmake/sfm/sfmConfig.cmake
	sed -e 's|@VERSION@|$(SFM_VERSION_STR)|' tools/install/sfmConfigVersion.cmake.in \
	  > $(DESTDIR)$(PREFIX)/lib/cmake/sfm/sfmConfigVersion.cmake

TEST_STEPS += test-install
test-install: all
	sh tests/install/run.sh

.PHONY: install test-install
