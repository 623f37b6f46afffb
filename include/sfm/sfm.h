/* libsfm: multi-view geometry for robots. Umbrella header. */
#ifndef SFM_H
#define SFM_H

#include "sfm/sfm_common.h"
#include "sfm/sfm_rng.h"
#include "sfm/sfm_linalg.h"
#include "sfm/sfm_poly.h"
#include "sfm/sfm_rotation.h"
#include "sfm/sfm_camera.h"
#include "sfm/sfm_solvers.h"
#include "sfm/sfm_pose.h"
#include "sfm/sfm_ransac.h"
#include "sfm/sfm_triangulate.h"
#include "sfm/sfm_trifocal.h"
#include "sfm/sfm_ransac_trifocal.h"
#include "sfm/sfm_features.h"
#include "sfm/sfm_three_view.h"
#include "sfm/sfm_ba.h"
#include "sfm/sfm_stereo.h"
#include "sfm/sfm_factorize.h"
#include "sfm/sfm_selfcal.h"
#include "sfm/sfm_uncalibrated.h"
#include "sfm/sfm_vo.h"
#include "sfm/sfm_r2r.h"
#include "sfm/sfm_r2r_motion.h"

#endif
