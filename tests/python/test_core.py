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
    with pytest.raises(SfmError) as e:
        check(lib.SFM_E_WORKSPACE, "probe")
    assert e.value.status == -3
    assert "workspace too small" in str(e.value)
