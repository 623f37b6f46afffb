"""Builds libsfm with the project's own Makefile and ships it in the package.

`pip install ./python` or `python -m build python` runs `make all capture` in
a private build directory (the checkout's build/ is left alone), then copies
libsfm.so.<major>, libsfm_capture.so.<major> (when the capture library
builds: a C++ compiler is needed; libjpeg/libpng/libcamera are optional) and
their cdefs into the package. The binding is cffi in ABI mode, so one wheel
serves every Python 3 on the platform: it is tagged py3-none-<platform>.

The C sources come from the checkout this directory sits in, from the copy an
sdist carries (csrc/), or from LIBSFM_SOURCE_DIR. LIBSFM_MAKE_JOBS sets
make's -j (default 2); LIBSFM_MAKE_ARGS adds make variables (for example
"NATIVE=1" or "HAVE_LIBCAMERA=").
"""
import glob
import os
import re
import shlex
import shutil
import subprocess

from setuptools import Distribution, setup
from setuptools.command.build_py import build_py
from setuptools.command.sdist import sdist

try:
    from setuptools.command.bdist_wheel import bdist_wheel
except ImportError:  # setuptools < 70.1
    from wheel.bdist_wheel import bdist_wheel

HERE = os.path.dirname(os.path.abspath(__file__))
# What an sdist carries of the C tree (csrc/), enough for `make all capture`.
C_TREE = ["Makefile", "mk", "include", "libsfm", "tools", "firmware_examples/linux"]


def c_source_dir():
    for d in (os.environ.get("LIBSFM_SOURCE_DIR"), os.path.dirname(HERE), os.path.join(HERE, "csrc")):
        if d and os.path.exists(os.path.join(d, "Makefile")) and os.path.isdir(os.path.join(d, "libsfm")):
            return os.path.abspath(d)
    raise RuntimeError("libsfm C sources not found (a checkout's python/, an sdist's csrc/, or LIBSFM_SOURCE_DIR)")


def header_version():
    """MAJOR.MINOR.PATCH from include/sfm/sfm_common.h: the package is the library's version."""
    with open(os.path.join(c_source_dir(), "include", "sfm", "sfm_common.h")) as f:
        hdr = f.read()
    return ".".join(re.search(r"#define SFM_VERSION_%s (\d+)" % k, hdr).group(1) for k in ("MAJOR", "MINOR", "PATCH"))


class BuildPyWithLibrary(build_py):
    def run(self):
        super().run()
        src = c_source_dir()
        out = os.path.abspath(os.path.join(self.build_lib, "libsfm"))
        cbuild = os.path.abspath(os.path.join(os.path.dirname(self.build_lib), "libsfm-c"))
        jobs = os.environ.get("LIBSFM_MAKE_JOBS", "2")
        base = ["make", "-C", src, "-j" + jobs, "BUILD=" + cbuild] + shlex.split(os.environ.get("LIBSFM_MAKE_ARGS", ""))
        subprocess.check_call(base + ["all"])
        if subprocess.call(base + ["capture"]) != 0:
            print("libsfm: the capture library did not build; the package ships without it")
        for stem, cdef in (("libsfm", "sfm_cdef.h"), ("libsfm_capture", "sfm_capture_cdef.h")):
            real = sorted(glob.glob(os.path.join(cbuild, stem + ".so.*.*.*")))
            if not real or not os.path.exists(os.path.join(cbuild, cdef)):
                continue
            major = os.path.basename(real[-1]).split(".so.")[1].split(".")[0]
            # Under its SONAME, the name the dynamic loader and libsfm_capture look for.
            shutil.copyfile(real[-1], os.path.join(out, "%s.so.%s" % (stem, major)))
            os.chmod(os.path.join(out, "%s.so.%s" % (stem, major)), 0o755)
            shutil.copyfile(os.path.join(cbuild, cdef), os.path.join(out, cdef))


class SdistWithSources(sdist):
    def make_release_tree(self, base_dir, files):
        super().make_release_tree(base_dir, files)
        src = c_source_dir()
        for item in C_TREE:
            a, b = os.path.join(src, item), os.path.join(base_dir, "csrc", item)
            os.makedirs(os.path.dirname(b), exist_ok=True)
            if os.path.isdir(a):
                shutil.copytree(a, b, ignore=shutil.ignore_patterns("__pycache__", "*.o", "*.d"))
            else:
                shutil.copyfile(a, b)


class PlatformWheel(bdist_wheel):
    def finalize_options(self):
        super().finalize_options()
        self.root_is_pure = False

    def get_tag(self):
        return ("py3", "none", super().get_tag()[2])


class BinaryDistribution(Distribution):
    def has_ext_modules(self):
        return True


setup(version=header_version(), distclass=BinaryDistribution,
      cmdclass={"build_py": BuildPyWithLibrary, "sdist": SdistWithSources, "bdist_wheel": PlatformWheel})
