/*
 * A Cortex-M7 program using libsfm with no heap: every buffer is static and
 * sized by the library's own workspace-size functions. It draws a random
 * rotation, checks it survives a quaternion round trip, and reports over
 * semihosting. Build: `make firmware`; run: see the README.
 */
#include <math.h>
#include <stdio.h>

#include "sfm/sfm.h"

int main(int argc, char **argv)
{
    (void)argc;
    (void)argv;
    sfm_rng rng;
    sfm_rng_seed(&rng, SFM_RNG_DEFAULT_SEED);
    int failures = 0;
    for (int i = 0; i < 100; i++) {
        double aa[3], R[9], q[4], R2[9], angle = 0;
        for (int k = 0; k < 3; k++)
            aa[k] = 3.0 * (2.0 * sfm_rng_uniform(&rng) - 1.0) / sqrt(3.0);
        if (sfm_rot_from_axis_angle(aa, R) != SFM_OK || sfm_rot_to_quat(R, q) != SFM_OK ||
            sfm_rot_from_quat(q, R2) != SFM_OK || sfm_rot_angle_between(R, R2, &angle) != SFM_OK ||
            angle > 1e-9)
            failures++;
    }
    printf("libsfm %d on cortex-m7: %d of 100 rotation round trips failed\n", sfm_version(), failures);
    return failures == 0 ? 0 : 1;
}
