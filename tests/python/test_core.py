import pytest

import libsfm
from libsfm._ffi import SfmError, check, lib


def test_version_and_status_strings():
    # the library reports the version its public header declares
    import os
    import re
    hdr = open(os.path.join(os.path.dirname(__file__), "..", "..", "include", "sfm", "sfm_common.h")).read()
    parts = [re.search(r"#define SFM_VERSION_%s (\d+)" % k, hdr).group(1) for k in ("MAJOR", "MINOR", "PATCH")]
    assert libsfm.version() == ".".join(parts) == libsfm.__version__
    # the binding is written for that minor, and the package is built under that version
    from libsfm import _ffi
    assert (_ffi.SO_MAJOR, _ffi.API_MINOR) == (int(parts[0]), int(parts[1]))
    import runpy
    import setuptools
    captured = {}
    import warnings
    real_setup = setuptools.setup
    setuptools.setup = lambda **kw: captured.update(kw)
    try:
        with warnings.catch_warnings():
            warnings.simplefilter("ignore", FutureWarning)  # wheel's bdist_wheel on older setuptools
            runpy.run_path(os.path.join(os.path.dirname(__file__), "..", "..", "python", "setup.py"))
    finally:
        setuptools.setup = real_setup
    assert captured["version"] == ".".join(parts)
    with pytest.raises(SfmError) as e:
        check(lib.SFM_E_WORKSPACE, "probe")
    assert e.value.status == -3
    assert "workspace too small" in str(e.value)
