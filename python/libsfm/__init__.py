"""libsfm: multi-view geometry for robots (cffi ABI binding over libsfm.so).

Arrays go in and come out as float64 numpy arrays; matrices are row-major as
in C. Poses are world-to-camera, x_cam = R X + t. A negative C status raises
SfmError carrying the code and its description.
"""
from ._ffi import SfmError, ffi, lib  # noqa: F401
from .features import associate_three_views, detect_and_describe, match  # noqa: F401


def version():
    v = lib.sfm_version()
    return "%d.%d.%d" % (v // 10000, v // 100 % 100, v % 100)
from .solvers import (essential_8pt, fundamental_7pt, fundamental_8pt, homography_4pt,  # noqa: F401,E402
                      homography_dlt, relpose_5pt)
from . import frames  # noqa: F401,E402
from .pose import essential_to_poses, p3p, relpose_upright_3pt, triangulate  # noqa: F401,E402
from .trifocal import *  # noqa: F401,F403
from . import linalg  # noqa: F401,E402
from .geometry import *  # noqa: F401,F403,E402
from .ba import bundle_adjust  # noqa: F401,E402
from .vo import VisualOdometry  # noqa: F401,E402


def replay_many(dirs, client=None, **kw):
    """Many recordings on Dask distributed; see libsfm.replay.replay_many."""
    from .replay import replay_many as _rm
    return _rm(dirs, client=client, **kw)
from .robust import (estimate_absolute_pose, estimate_fundamental, estimate_homography,  # noqa: F401,E402
                     estimate_relative_pose, estimate_relative_pose_upright)
