/* The leader-follower cost at one follower translation, through the public
 * sfm_r2r_motion_cost: the oracle the next-motion tests (unit and native)
 * search a grid of the admissible disk with. */
#ifndef SFM_TEST_R2R_MOTION_COST_H
#define SFM_TEST_R2R_MOTION_COST_H

#include <math.h>

#include "sfm/sfm_r2r_motion.h"

/* The posterior trace with u0's follower translation replaced by (fx, fy);
 * HUGE_VAL when the call refuses. */
static inline double r2r_cost_at(const double x[3], const double P[9], const sfm_r2r_motion_step *u0,
                                 const sfm_r2r_motion_noise *nz, int sensor, double fx, double fy)
{
    sfm_r2r_motion_step u = *u0;
    u.follower_d.v[0] = fx;
    u.follower_d.v[1] = fy;
    double tr = HUGE_VAL;
    if (sfm_r2r_motion_cost(x, P, &u, nz, sensor, &tr) != SFM_OK)
        return HUGE_VAL;
    return tr;
}

#endif
