import pytest

import libsfm
from libsfm._ffi import SfmError, check, lib


def test_version_and_status_strings():
    assert libsfm.version() == "0.1.0"
    with pytest.raises(SfmError) as e:
        check(lib.SFM_E_WORKSPACE, "probe")
    assert e.value.status == -3
    assert "workspace too small" in str(e.value)
