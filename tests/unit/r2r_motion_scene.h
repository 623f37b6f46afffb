/* Shared by the leader-follower filter tests (unit and native): random
 * covariances, and the cost at one follower translation through the public
 * sfm_r2r_motion_cost, the oracle the next-motion tests search a grid of the
 * admissible disk with. */
#ifndef SFM_TEST_R2R_MOTION_SCENE_H
#define SFM_TEST_R2R_MOTION_SCENE_H

#include <math.h>

#include "sfm/sfm_r2r_motion.h"
#include "sfm_test.h"

/* P = L L^T + ridge I, L with entries N(0, s^2), s uniform in [s_lo, s_hi]. */
static inline void r2r_random_spd(sfm_test_ctx *t, double s_lo, double s_hi, double ridge, double P[9])
{
    double L[9];
    const double s = sfm_test_uniform(t, s_lo, s_hi);
    for (int i = 0; i < 9; i++)
        L[i] = sfm_test_normal(t, s);
    for (int i = 0; i < 3; i++)
        for (int j = 0; j < 3; j++) {
            double v = 0.0;
            for (int k = 0; k < 3; k++)
                v += L[3 * i + k] * L[3 * j + k];
            P[3 * i + j] = v + (i == j ? ridge : 0.0);
        }
}

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
