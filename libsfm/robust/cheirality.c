/* Cheirality: Hartley & Zisserman, "Multiple View Geometry", 2nd ed., 9.6.3
 * (of the four decompositions of E, one puts the points in front of both
 * cameras). */
#include "robust/cheirality.h"

#include <string.h>

#include "robust/epipolar.h"
#include "sfm/sfm_pose.h"

int sfmi_robust_in_front(const double R[9], const double t[3], const double *b1,
                        const double *b2)
{
    /* lambda2 b2 = lambda1 R b1 + t: cross with b2 and with R b1 */
    double Rb1[3], a[3], c[3], tb2[3], tRb1[3];
    sfmi_matvec3(R, b1, Rb1);
    sfmi_cross3(Rb1, b2, a); /* Rb1 x b2 */
    double aa = sfmi_dot3(a, a);
    if (!(aa > 1e-24))
        return 0; /* parallel rays: point at infinity */
    sfmi_cross3(t, b2, tb2);
    double l1 = -sfmi_dot3(tb2, a);
    sfmi_cross3(b2, Rb1, c);
    sfmi_cross3(t, Rb1, tRb1);
    double l2 = sfmi_dot3(tRb1, c);
    return l1 > 0.0 && l2 > 0.0;
}

int sfmi_robust_pose_from_essential(const double E[9], const double *b1, const double *b2,
                                   const int *idx, int n, double R[9], double t[3])
{
    sfm_pose poses[SFM_ESSENTIAL_POSES];
    sfm_mat3 Em;
    memcpy(Em.m, E, sizeof Em.m);
    if (sfm_essential_to_poses(&Em, NULL, NULL, 0, poses, NULL) != SFM_ESSENTIAL_POSES)
        return -1;
    int best = -1, best_k = 0;
    for (int k = 0; k < SFM_ESSENTIAL_POSES; k++) {
        int c = 0;
        for (int j = 0; j < n; j++) {
            int i = idx ? idx[j] : j;
            c += sfmi_robust_in_front(poses[k].R, poses[k].t, b1 + 3 * i, b2 + 3 * i);
        }
        if (c > best) {
            best = c;
            best_k = k;
        }
    }
    memcpy(R, poses[best_k].R, sizeof poses[best_k].R);
    memcpy(t, poses[best_k].t, sizeof poses[best_k].t);
    return best;
}
