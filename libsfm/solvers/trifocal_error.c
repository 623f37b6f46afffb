/*
 * Three-view reprojection error of a point triplet: linear triangulation
 * from the three projective cameras (sfm_triangulate_dlt),
 * then Gauss-Newton on the summed squared pixel error. The point stays
 * homogeneous (unit 4-vector, updated in its 3-dimensional tangent space,
 * the basis of the LM driver's sphere update, core/lm.h) so
 * points at infinity of a projective frame need no special case. BoofCV's
 * evaluation of trifocal estimators found this error the most reliable for
 * scoring; it is the geometric (gold standard) error for fixed cameras.
 */
#include <math.h>
#include <string.h>

#include "core/linalg_util.h"
#include "core/lm.h"
#include "sfm/sfm_triangulate.h"
#include "sfm/sfm_trifocal.h"
#include "solvers/trifocal_internal.h"

enum { GN_ITERS = 4 };

int sfmi_trifocal_residual(const double P[12], const double X[4], const double x[2], double r[2],
                          double JX[8], double cam[3])
{
    return sfmi_tf_residual_impl(P, X, x, r, JX, cam);
}

/* Summed squared residual of the three views at X, with the rows of
 * d r / d X (6x4) in J; HUGE_VAL when a view cannot project X. */
static double cost_jac(const double *P[3], const double *x[3], const double X[4], double r[6],
                       double J[24])
{
    double c = 0;
    for (int v = 0; v < 3; v++) {
        if (!sfmi_tf_residual(P[v], X, x[v], &r[2 * v], &J[8 * v], NULL))
            return HUGE_VAL;
        c += r[2 * v] * r[2 * v] + r[2 * v + 1] * r[2 * v + 1];
    }
    return c;
}

int sfm_trifocal_point_error(const double P1[12], const double P2[12], const double P3[12],
                             const double x1[2], const double x2[2], const double x3[2],
                             double *err2, double Xout[4])
{
    if (P1 == NULL || P2 == NULL || P3 == NULL || x1 == NULL || x2 == NULL || x3 == NULL ||
        err2 == NULL)
        return SFM_E_ARGUMENT;
    const double *P[3] = {P1, P2, P3};
    const double *x[3] = {x1, x2, x3};
    /* Linear start from the three views; a point at infinity of the
     * projective frame comes back as a direction, homogeneous (d, 0).
     * sfm_triangulate_dlt tests the same cameras and pixels for NaN and Inf
     * first (SFM_E_NONFINITE, nothing written), so they are not tested here
     * again: RANSAC asks for this error thousands of times a run. */
    double Ps[36], xv[6], X3[3], X[4];
    int flag;
    for (int v = 0; v < 3; v++) {
        memcpy(&Ps[12 * v], P[v], 12 * sizeof(double));
        xv[2 * v] = x[v][0];
        xv[2 * v + 1] = x[v][1];
    }
    int st = sfm_triangulate_dlt(3, Ps, 1, xv, X3, &flag);
    if (st < 0)
        return st;
    double w = (flag & SFM_TRI_INFINITY) ? 0.0 : 1.0;
    double nrm = sqrt(X3[0] * X3[0] + X3[1] * X3[1] + X3[2] * X3[2] + w * w);
    for (int k = 0; k < 3; k++)
        X[k] = X3[k] / nrm;
    X[3] = w / nrm;
    /* Gauss-Newton; each trial point's cost comes with its Jacobian, which
     * the next step uses when the trial is kept */
    double r[6], J[24], rn[6], Jn[24];
    double c0 = cost_jac(P, x, X, r, J);
    if (!(c0 < HUGE_VAL))
        return SFM_E_SINGULAR;
    for (int it = 0; it < GN_ITERS; it++) {
        double B[12], H[9] = {0}, Hi[9], g[3] = {0}, d[3];
        sfmi_tf_sphere_basis4(X, B);
        for (int h = 0; h < 6; h++) {
            const double *j = &J[4 * h];
            double jb[3];
            for (int c = 0; c < 3; c++)
                jb[c] = j[0] * B[c] + j[1] * B[3 + c] + j[2] * B[6 + c] + j[3] * B[9 + c];
            for (int a = 0; a < 3; a++) {
                g[a] += jb[a] * r[h];
                for (int b = 0; b <= a; b++)
                    H[a * 3 + b] += jb[a] * jb[b];
            }
        }
        H[1] = H[3];
        H[2] = H[6];
        H[5] = H[7];
        /* H is symmetric positive semi-definite: closed-form inverse, and
         * no step when it is singular */
        if (!sfmi_mat3_inverse(H, Hi, 0.0))
            break;
        double pred = 0;
        for (int a = 0; a < 3; a++) {
            d[a] = Hi[a * 3] * g[0] + Hi[a * 3 + 1] * g[1] + Hi[a * 3 + 2] * g[2];
            pred += g[a] * d[a];
        }
        /* converged: the step's predicted decrease g^T H^-1 g is below the
         * tolerance the achieved decrease is held to below */
        if (!(pred >= 1e-12 * (1.0 + c0)))
            break;
        double Xn[4], nn = 0;
        for (int k = 0; k < 4; k++) {
            Xn[k] = X[k] - (B[k * 3] * d[0] + B[k * 3 + 1] * d[1] + B[k * 3 + 2] * d[2]);
            nn += Xn[k] * Xn[k];
        }
        nn = sqrt(nn);
        for (int k = 0; k < 4; k++)
            Xn[k] /= nn;
        double c1 = cost_jac(P, x, Xn, rn, Jn);
        if (!(c1 < c0))
            break;
        int done = c0 - c1 < 1e-12 * (1.0 + c0);
        memcpy(X, Xn, sizeof X);
        memcpy(r, rn, sizeof r);
        memcpy(J, Jn, sizeof J);
        c0 = c1;
        if (done)
            break;
    }
    *err2 = c0;
    if (Xout != NULL)
        memcpy(Xout, X, sizeof X);
    return SFM_OK;
}
