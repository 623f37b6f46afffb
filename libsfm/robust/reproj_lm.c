/*
 * Levenberg-Marquardt for absolute pose on the reprojection error measured in
 * the tangent plane of each observed bearing (equal to the normalised image
 * plane error at the image centre of a pinhole camera, and defined for any
 * central camera, fisheye included). d r_k / d Xc = (e_k - r_k b) / (b . Xc);
 * d Xc / d w = -[R X]x; d Xc / d t = I.
 */
#include "robust/reproj_lm.h"

#include <math.h>
#include <string.h>

#include "core/lm.h"
#include "robust/epipolar.h"
#include "sfm/sfm_linalg.h"
#include "sfm/sfm_rotation.h"

double sfmi_robust_reproj2(const double R[9], const double t[3], const double *b,
                          const double *X)
{
    double Xc0 = R[0] * X[0] + R[1] * X[1] + R[2] * X[2] + t[0];
    double Xc1 = R[3] * X[0] + R[4] * X[1] + R[5] * X[2] + t[1];
    double Xc2 = R[6] * X[0] + R[7] * X[1] + R[8] * X[2] + t[2];
    double d = b[0] * Xc0 + b[1] * Xc1 + b[2] * Xc2;
    if (!(d > 0.0))
        return SFM_ROBUST_HUGE;
    /* |Xc/d - b|^2 = |Xc|^2/d^2 - 1, computed without the cancellation */
    double u0 = Xc0 / d - b[0], u1 = Xc1 / d - b[1], u2 = Xc2 / d - b[2];
    return u0 * u0 + u1 * u1 + u2 * u2;
}

/* Residual block j: the two tangent-plane coordinates of point idx[j]; left
 * out behind the camera (as the score leaves it out). */
static int reproj_residual(const void *user, const double *const *x, int j, double *r, double *J)
{
    const sfmi_reproj_problem *d = user;
    const double *R = x[0], *t = x[1];
    const double *bb = d->b + 3 * d->idx[j], *XX = d->X + 3 * d->idx[j];
    double RX[3], Xc[3], e[2][3];
    sfmi_matvec3(R, XX, RX);
    Xc[0] = RX[0] + t[0];
    Xc[1] = RX[1] + t[1];
    Xc[2] = RX[2] + t[2];
    double dd = sfmi_dot3(bb, Xc);
    if (!(dd > 0.0))
        return 0;
    sfmi_tangent_basis(bb, e[0], e[1]);
    for (int k = 0; k < 2; k++) {
        r[k] = sfmi_dot3(e[k], Xc) / dd;
        if (J == NULL)
            continue;
        double a[3]; /* d r / d Xc */
        for (int c = 0; c < 3; c++)
            a[c] = (e[k][c] - r[k] * bb[c]) / dd;
        /* d r / d w = a . (-[RX]x) = (RX x a) */
        double *Jk = J + 6 * k;
        sfmi_cross3(RX, a, Jk);
        Jk[3] = a[0];
        Jk[4] = a[1];
        Jk[5] = a[2];
    }
    return 1;
}

void sfmi_reproj_lm_problem(const double *b, const double *X, const int *idx, int n, double scale,
                            double R[9], double t[3], sfmi_reproj_problem *rp)
{
    rp->b = b;
    rp->X = X;
    rp->idx = idx;
    const sfmi_lm_block rb = {R, 9, SFMI_LM_SO3, 0, NULL, NULL};
    const sfmi_lm_block tb = {t, 3, SFMI_LM_EUCLIDEAN, 0, NULL, NULL};
    rp->blocks[0] = rb;
    rp->blocks[1] = tb;
    const sfmi_lm_problem prob = {rp->blocks, 2, n, 2, reproj_residual, rp,
                                  scale > 0.0 ? SFMI_LM_LOSS_CAUCHY : SFMI_LM_LOSS_SQUARED, scale, NULL};
    rp->prob = prob;
}

int sfmi_robust_reproj_lm(const double *b, const double *X, const int *idx, int n, double scale,
                         int iters, double R[9], double t[3])
{
    sfmi_reproj_problem rp;
    sfmi_reproj_lm_problem(b, X, idx, n, scale, R, t, &rp);
    double ws[SFMI_LM_DENSE_WS_DOUBLES(12, 6, 2)];
    return sfmi_lm_refine(&rp.prob, iters, 1e-10, ws, sizeof ws);
}
