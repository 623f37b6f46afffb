# make install PREFIX=... [DESTDIR=...] [LIBDIR=...]: headers; libsfm and
# libsfm_capture, each as an archive and as a shared object with its SONAME
# (libsfm.so.$(SFM_MAJOR)) and the usual links; the tools sfm-record and
# sfm-replay; pkg-config files sfm.pc and sfm-capture.pc; the CMake package
# (find_package(sfm): sfm::sfm, sfm::sfm_static, sfm::capture,
# sfm::capture_static); the cdefs the Python binding reads.
# The pkg-config and CMake files locate the prefix from where they sit, so an
# installed tree can be moved. `make uninstall` removes exactly these files.
LIBDIR ?= $(PREFIX)/lib
INCLUDEDIR ?= $(PREFIX)/include
BINDIR ?= $(PREFIX)/bin
DATADIR ?= $(PREFIX)/share/sfm
CMAKEDIR ?= $(LIBDIR)/cmake/sfm
PKGCONFIGDIR ?= $(LIBDIR)/pkgconfig
INSTALL_HEADERS := $(PUBLIC_HEADERS) $(wildcard include/sfm/*.hpp)
# pkg-config and CMake find the prefix relative to their own directory.
PC_PREFIX_REL = $(shell realpath -m --relative-to=$(PKGCONFIGDIR) $(PREFIX))
CMAKE_PREFIX_REL = $(shell realpath -m --relative-to=$(CMAKEDIR) $(PREFIX))
LIBDIR_REL = $(shell realpath -m --relative-to=$(PREFIX) $(LIBDIR))
INCLUDEDIR_REL = $(shell realpath -m --relative-to=$(PREFIX) $(INCLUDEDIR))

INSTALL_SUBST = sed -e 's|@PREFIX_FROM_PC@|$(PC_PREFIX_REL)|' -e 's|@PREFIX_FROM_CMAKE@|$(CMAKE_PREFIX_REL)|' \
    -e 's|@LIBDIR@|$(LIBDIR_REL)|' -e 's|@INCLUDEDIR@|$(INCLUDEDIR_REL)|' \
    -e 's|@VERSION@|$(SFM_VERSION_STR)|' -e 's|@MAJOR@|$(SFM_MAJOR)|' \
    -e 's|@CAPTURE_LIBS@|$(strip $(CAPTURE_LDLIBS))|' \
    -e 's|@CAPTURE_REQUIRES@|$(strip $(if $(HAVE_LIBJPEG),libjpeg) $(if $(HAVE_LIBPNG),libpng) $(if $(HAVE_LIBCAMERA),libcamera))|'

install: all capture
	install -d $(DESTDIR)$(INCLUDEDIR)/sfm $(DESTDIR)$(LIBDIR) $(DESTDIR)$(PKGCONFIGDIR) \
	  $(DESTDIR)$(CMAKEDIR) $(DESTDIR)$(DATADIR) $(DESTDIR)$(BINDIR)
	install -m 644 $(INSTALL_HEADERS) $(DESTDIR)$(INCLUDEDIR)/sfm/
	install -m 644 $(BUILD)/libsfm.a $(BUILD)/libsfm_capture.a $(DESTDIR)$(LIBDIR)/
	install -m 755 $(BUILD)/$(SFM_SO) $(BUILD)/$(CAPTURE_SO) $(DESTDIR)$(LIBDIR)/
	for l in libsfm libsfm_capture; do \
	  ln -sf $$l.so.$(SFM_VERSION_STR) $(DESTDIR)$(LIBDIR)/$$l.so.$(SFM_MAJOR) && \
	  ln -sf $$l.so.$(SFM_MAJOR) $(DESTDIR)$(LIBDIR)/$$l.so || exit 1; done
	install -m 755 $(CAPTURE_TOOLS) $(DESTDIR)$(BINDIR)/
	install -m 644 $(BUILD)/sfm_cdef.h $(BUILD)/sfm_capture_cdef.h $(DESTDIR)$(DATADIR)/
	$(INSTALL_SUBST) tools/install/sfm.pc.in > $(DESTDIR)$(PKGCONFIGDIR)/sfm.pc
	$(INSTALL_SUBST) tools/install/sfm-capture.pc.in > $(DESTDIR)$(PKGCONFIGDIR)/sfm-capture.pc
	$(INSTALL_SUBST) tools/install/sfmConfig.cmake.in > $(DESTDIR)$(CMAKEDIR)/sfmConfig.cmake
	$(INSTALL_SUBST) tools/install/sfmConfigVersion.cmake.in > $(DESTDIR)$(CMAKEDIR)/sfmConfigVersion.cmake

INSTALLED_FILES = $(addprefix $(INCLUDEDIR)/sfm/,$(notdir $(INSTALL_HEADERS))) \
    $(foreach l,libsfm libsfm_capture,$(addprefix $(LIBDIR)/$(l),.a .so .so.$(SFM_MAJOR) .so.$(SFM_VERSION_STR))) \
    $(addprefix $(BINDIR)/,$(notdir $(CAPTURE_TOOLS))) \
    $(DATADIR)/sfm_cdef.h $(DATADIR)/sfm_capture_cdef.h \
    $(PKGCONFIGDIR)/sfm.pc $(PKGCONFIGDIR)/sfm-capture.pc \
    $(CMAKEDIR)/sfmConfig.cmake $(CMAKEDIR)/sfmConfigVersion.cmake

# Removes the files `make install` wrote with the same PREFIX/DESTDIR, then
# the project's own directories when they are left empty.
uninstall:
	rm -f $(addprefix $(DESTDIR),$(INSTALLED_FILES))
	-rmdir $(DESTDIR)$(INCLUDEDIR)/sfm $(DESTDIR)$(CMAKEDIR) $(DESTDIR)$(DATADIR) 2>/dev/null

TEST_STEPS += test-install test-wheel
test-install: all capture
	sh tests/install/run.sh

# The Python wheel (python/setup.py builds the C library into it), installed
# in a fresh venv outside the repository and used from another directory.
test-wheel:
	sh tests/install/wheel.sh

.PHONY: install uninstall test-install test-wheel
