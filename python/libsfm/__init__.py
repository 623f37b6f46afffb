"""libsfm: multi-view geometry for robots (cffi ABI binding over libsfm.so).

Arrays go in and come out as float64 numpy arrays (real only: complex input
is refused); matrices are row-major as in C. Poses are world-to-camera,
x_cam = R X + t; quaternions are w-first. Pixels have their origin at the
centre of the top-left pixel. Arguments are checked before any C call
(ValueError or TypeError naming the argument; every integer is range-checked
against the C int it becomes); a negative C status raises SfmError, which
carries the status, its name and, when the binding can tell, the argument.

Seeds: every function taking a seed accepts any Python int, taken modulo
2**64; the default is the C library's (SFM_RNG_DEFAULT_SEED). Options are
keyword arguments whose defaults are read from the C default-options
functions (RANSAC_DEFAULTS, FEATURE_DEFAULTS, MATCH_DEFAULTS).

Cameras: every function taking intrinsics accepts a Camera ("pinhole",
"brown" Brown-Conrady, "fisheye" Kannala-Brandt) or a 3x3 K with an optional
OpenCV distortion vector. Camera.from_file reads OpenCV FileStorage YAML/XML,
ROS camera_info, Kalibr camchain, EuRoC sensor.yaml and KITTI calib.txt
(libsfm.calib).

Robust estimators (one Result type; see Result):
  estimate_relative_pose, estimate_relative_pose_upright,
  estimate_absolute_pose, estimate_fundamental, estimate_homography,
  estimate_trifocal, estimate_three_view_pose
Minimal and linear solvers:
  relpose_5pt, fundamental_7pt, essential_8pt, fundamental_8pt,
  homography_4pt, homography_dlt, p3p, relpose_upright_3pt,
  essential_to_poses, triangulate
Trifocal tensor:
  trifocal_from_cameras, trifocal_7pt, trifocal_epipoles,
  trifocal_fundamentals, cameras_from_trifocal, trifocal_transfer,
  trifocal_point_error
Features: detect_and_describe, match, associate_three_views
Refinement: bundle_adjust
Robot to robot (distances and bearings between two robots): r2r_solve,
  r2r_predict, r2r_classify; r2r_refine (maximum likelihood, covariance),
  r2r_ransac (outlier measurements)
Geometry: poly_roots, rot_from_axis_angle, rot_to_axis_angle, rot_from_quat,
  rot_to_quat, rot_nearest, skew, rot_angle_between
Submodules: linalg (small dense linear algebra), frames (replay, cameras,
  recording), calib (calibration files)
Leader-follower formations (libsfm.formation): leader_follower_next_motion,
  leader_follower_propagate, leader_follower_update, leader_follower_cost;
  python -m libsfm.leader_follower_demo
"""
from ._ffi import SfmError, ffi, lib  # noqa: F401
from .camera import Camera
from .results import Result
from .features import (ALIGN_DEFAULTS, FEATURE_DEFAULTS, MATCH_DEFAULTS, align_points,
                       associate_three_views, detect_and_describe, match)
from .solvers import (essential_8pt, fundamental_7pt, fundamental_8pt, homography_4pt,
                      homography_dlt, relpose_5pt)
from . import frames  # noqa: F401
from .pose import essential_to_poses, p3p, relpose_upright_3pt, triangulate
from .trifocal import (cameras_from_trifocal, estimate_three_view_pose, estimate_trifocal,
                       trifocal_7pt, trifocal_epipoles, trifocal_from_cameras,
                       trifocal_fundamentals, trifocal_point_error, trifocal_transfer)
from . import linalg  # noqa: F401
from .geometry import (POLY_MAX_DEGREE, poly_roots, rot_angle_between, rot_from_axis_angle,
                       rot_from_quat, rot_nearest, rot_to_axis_angle, rot_to_quat, skew)
from . import ba as _ba
from .ba import bundle_adjust
from .robust import (RANSAC_DEFAULTS, estimate_absolute_pose, estimate_fundamental,
                     estimate_homography, estimate_relative_pose, estimate_relative_pose_upright)
from . import calib  # noqa: F401
from .recon import (factorize_projective, reconstruct_three_view, reconstruct_three_view_images,
                    reconstruct_two_view, self_calibrate)
from .vo import VisualOdometry
from .r2r import R2R_MAX_SOLUTIONS, R2R_SYSTEMS, r2r_classify, r2r_predict, r2r_solve
from .r2r_refine import R2R_LOSSES, r2r_ransac, r2r_refine
from . import stereo as _stereo
from .stereo import (disparity_block, disparity_sgm, disparity_to_depth, disparity_to_points,
                     homography_maps, rectification_error, rectify_pair, rectify_uncalibrated, remap)
from .formation import (leader_follower_cost, leader_follower_next_motion,
                        leader_follower_propagate, leader_follower_update)


def version():
    """The C library's version string "MAJOR.MINOR.PATCH" (sfm_version)."""
    v = lib.sfm_version()
    return "%d.%d.%d" % (v // 10000, v // 100 % 100, v % 100)


def replay_many(dirs, client=None, **kw):
    """Many recordings on Dask distributed; see libsfm.replay.replay_many."""
    from .replay import replay_many as _rm
    return _rm(dirs, client=client, **kw)


if not bundle_adjust.__doc__:
    # its layout and options are written once, in the module's docstring
    bundle_adjust.__doc__ = "Bundle adjustment (sfm_ba_solve).\n" + (_ba.__doc__ or "")

#: The version of the C library this package drives.
__version__ = version()

__all__ = [
    "__version__", "version", "SfmError", "Camera", "Result",
    "estimate_relative_pose", "estimate_relative_pose_upright", "estimate_absolute_pose",
    "estimate_fundamental", "estimate_homography", "estimate_trifocal",
    "estimate_three_view_pose", "RANSAC_DEFAULTS",
    "relpose_5pt", "fundamental_7pt", "essential_8pt", "fundamental_8pt", "homography_4pt",
    "homography_dlt", "p3p", "relpose_upright_3pt", "essential_to_poses", "triangulate",
    "trifocal_from_cameras", "trifocal_7pt", "trifocal_epipoles", "trifocal_fundamentals",
    "cameras_from_trifocal", "trifocal_transfer", "trifocal_point_error",
    "detect_and_describe", "match", "associate_three_views", "align_points", "FEATURE_DEFAULTS",
    "MATCH_DEFAULTS", "ALIGN_DEFAULTS", "bundle_adjust",
    "poly_roots", "rot_from_axis_angle", "rot_to_axis_angle", "rot_from_quat", "rot_to_quat",
    "rot_nearest", "skew", "rot_angle_between", "POLY_MAX_DEGREE",
    "factorize_projective", "self_calibrate", "reconstruct_three_view", "reconstruct_two_view",
    "reconstruct_three_view_images", "VisualOdometry", "replay_many",
    "leader_follower_next_motion", "leader_follower_propagate", "leader_follower_update",
    "leader_follower_cost",
    "linalg", "frames", "calib",
] + list(_stereo.__all__)
