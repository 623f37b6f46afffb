/*
 * Normal matrices of the pose refits (support_pose.h), by central
 * differences of the residuals: they are evaluated once per estimator call,
 * on its final support, where a step of 1e-6 rad (1e-6 of a unit
 * translation) resolves the Jacobian to about 1e-8 relative, far below what
 * a covariance needs.
 */
#include "robust/support_pose.h"

#include <math.h>
#include <string.h>

#include "robust/epipolar.h"
#include "sfm/sfm_rotation.h"

#define STEP 1e-6

/* Signed bearing Sampson residual C / sqrt(D) (epipolar.h's squared form). */
static double sampson_signed(const double *E, const double *b1, const double *b2)
{
    double e[3], f[3];
    for (int r = 0; r < 3; r++) {
        e[r] = E[3 * r] * b1[0] + E[3 * r + 1] * b1[1] + E[3 * r + 2] * b1[2];
        f[r] = E[r] * b2[0] + E[3 + r] * b2[1] + E[6 + r] * b2[2];
    }
    double C = b2[0] * e[0] + b2[1] * e[1] + b2[2] * e[2];
    double D = sfmi_dot3(e, e) + sfmi_dot3(f, f) - 2.0 * C * C;
    if (!(D > 1e-300))
        return 0.0;
    return C / sqrt(D);
}

/* Pose moved by parameter vector x (relpose layout of support_pose.h). */
static void rel_move(const double *R, const double *t, const double *axis, const double *e1,
                     const double *e2, const double *x, double *E)
{
    double w[3], dR[9], Rn[9], tn[3];
    int nr = axis ? 1 : 3;
    if (axis) {
        for (int k = 0; k < 3; k++)
            w[k] = x[0] * axis[k];
    } else {
        for (int k = 0; k < 3; k++)
            w[k] = x[k];
    }
    sfm_rot_from_axis_angle(w, dR);
    sfmi_matmul3(dR, R, Rn);
    for (int k = 0; k < 3; k++)
        tn[k] = t[k] + x[nr] * e1[k] + x[nr + 1] * e2[k];
    double l = sqrt(sfmi_dot3(tn, tn));
    for (int k = 0; k < 3; k++)
        tn[k] /= l;
    sfmi_essential_from_pose(Rn, tn, E);
}

int sfmi_relpose_normal(const double *b1, const double *b2, const int *idx, int m,
                        const double *R, const double *t, const double *axis, double *JtJ,
                        double *G, double *ssr)
{
    const int np = axis ? 3 : 5, nr = axis ? 1 : 3;
    double e1[3], e2[3];
    sfmi_tangent_basis(t, e1, e2);
    double E0[9], Ep[5][9], Em[5][9];
    sfmi_essential_from_pose(R, t, E0);
    for (int p = 0; p < np; p++) {
        double x[5] = {0, 0, 0, 0, 0};
        x[p] = STEP;
        rel_move(R, t, axis, e1, e2, x, Ep[p]);
        x[p] = -STEP;
        rel_move(R, t, axis, e1, e2, x, Em[p]);
    }
    memset(JtJ, 0, sizeof(double) * np * np);
    double s = 0.0;
    for (int j = 0; j < m; j++) {
        const double *x1 = b1 + 3 * idx[j], *x2 = b2 + 3 * idx[j];
        double r = sampson_signed(E0, x1, x2), J[5];
        s += r * r;
        for (int p = 0; p < np; p++)
            J[p] = (sampson_signed(Ep[p], x1, x2) - sampson_signed(Em[p], x1, x2)) / (2 * STEP);
        for (int p = 0; p < np; p++)
            for (int q = 0; q <= p; q++)
                JtJ[p * np + q] += J[p] * J[q];
    }
    for (int p = 0; p < np; p++)
        for (int q = 0; q < p; q++)
            JtJ[q * np + p] = JtJ[p * np + q];
    memset(G, 0, sizeof(double) * 6 * np);
    if (axis) {
        for (int k = 0; k < 3; k++)
            G[k * np] = axis[k];
    } else {
        for (int k = 0; k < 3; k++)
            G[k * np + k] = 1.0;
    }
    for (int k = 0; k < 3; k++) {
        G[(3 + k) * np + nr] = e1[k];
        G[(3 + k) * np + nr + 1] = e2[k];
    }
    *ssr = s;
    return np;
}

/* Tangent-plane residual (2) of one point; 0 when behind the camera. */
static int reproj(const double *R, const double *t, const double *b, const double *X, double *r,
                  double *depth)
{
    double Xc[3];
    sfmi_matvec3(R, X, Xc);
    for (int k = 0; k < 3; k++)
        Xc[k] += t[k];
    double d = sfmi_dot3(b, Xc);
    if (!(d > 0.0))
        return 0;
    double e1[3], e2[3];
    sfmi_tangent_basis(b, e1, e2);
    r[0] = sfmi_dot3(e1, Xc) / d;
    r[1] = sfmi_dot3(e2, Xc) / d;
    if (depth)
        *depth = d;
    return 1;
}

int sfmi_abspose_normal(const double *b, const double *X, const int *idx, int m,
                        const double *R, const double *t, double *JtJ, double *G, double *ssr,
                        double *mean_depth)
{
    double Rp[6][9], tp[6][3], Rm[6][9], tm[6][3];
    for (int p = 0; p < 6; p++) {
        for (int sgn = 0; sgn < 2; sgn++) {
            double *Ro = sgn ? Rm[p] : Rp[p], *to = sgn ? tm[p] : tp[p];
            double h = sgn ? -STEP : STEP;
            double w[3] = {0, 0, 0}, dR[9];
            memcpy(to, t, 3 * sizeof(double));
            if (p < 3)
                w[p] = h;
            else
                to[p - 3] += h;
            sfm_rot_from_axis_angle(w, dR);
            sfmi_matmul3(dR, R, Ro);
        }
    }
    memset(JtJ, 0, 36 * sizeof(double));
    double s = 0.0, dsum = 0.0;
    int nd = 0;
    for (int j = 0; j < m; j++) {
        const double *bb = b + 3 * idx[j], *XX = X + 3 * idx[j];
        double r[2], d, J[2][6];
        if (!reproj(R, t, bb, XX, r, &d))
            continue;
        dsum += d;
        nd++;
        s += r[0] * r[0] + r[1] * r[1];
        int ok = 1;
        for (int p = 0; p < 6 && ok; p++) {
            double a[2], c[2];
            ok = reproj(Rp[p], tp[p], bb, XX, a, NULL) && reproj(Rm[p], tm[p], bb, XX, c, NULL);
            J[0][p] = (a[0] - c[0]) / (2 * STEP);
            J[1][p] = (a[1] - c[1]) / (2 * STEP);
        }
        if (!ok)
            continue;
        for (int k = 0; k < 2; k++)
            for (int p = 0; p < 6; p++)
                for (int q = 0; q <= p; q++)
                    JtJ[p * 6 + q] += J[k][p] * J[k][q];
    }
    for (int p = 0; p < 6; p++)
        for (int q = 0; q < p; q++)
            JtJ[q * 6 + p] = JtJ[p * 6 + q];
    memset(G, 0, 36 * sizeof(double));
    for (int k = 0; k < 6; k++)
        G[7 * k] = 1.0;
    *ssr = s;
    *mean_depth = nd > 0 ? dsum / nd : 0.0;
    return 6;
}
