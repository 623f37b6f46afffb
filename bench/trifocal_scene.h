/* Shared by the trifocal benchmarks: a camera P = K [R | -R C] near the
 * identity (K: f 600, 640x480), and a projection that returns 1 for a point
 * seen inside the image, 0 otherwise (behind the camera: x not written). */
#ifndef SFM_BENCH_TRIFOCAL_SCENE_H
#define SFM_BENCH_TRIFOCAL_SCENE_H

#include "sfm/sfm.h"

static inline void camera(sfm_rng *r, double P[12])
{
    double aa[3], R[9], C[3], K[9] = {600, 0, 320, 0, 600, 240, 0, 0, 1};
    for (int k = 0; k < 3; k++) {
        aa[k] = 0.1 * sfm_rng_normal(r);
        C[k] = 0.5 * sfm_rng_normal(r);
    }
    sfm_rot_from_axis_angle(aa, R);
    for (int i = 0; i < 3; i++)
        for (int c = 0; c < 4; c++) {
            double s = 0;
            for (int k = 0; k < 3; k++)
                s += K[i * 3 + k] * (c < 3 ? R[k * 3 + c] : -(R[k * 3] * C[0] + R[k * 3 + 1] * C[1] + R[k * 3 + 2] * C[2]));
            P[i * 4 + c] = s;
        }
}

static inline int project(const double P[12], const double X[3], double *x)
{
    double p[3];
    for (int r = 0; r < 3; r++)
        p[r] = P[r * 4] * X[0] + P[r * 4 + 1] * X[1] + P[r * 4 + 2] * X[2] + P[r * 4 + 3];
    if (!(p[2] > 0))
        return 0;
    x[0] = p[0] / p[2];
    x[1] = p[1] / p[2];
    return x[0] > 0 && x[0] < 640 && x[1] > 0 && x[1] < 480;
}

#endif
