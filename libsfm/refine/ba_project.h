/*
 * Internal: the bundle adjustment camera model and its analytic Jacobian,
 * shared by the solver and its tests. See sfm_ba.h for the model.
 *
 * Local camera-side columns of J (2 x SFM_BA_NLOC, row-major): 0-2 rotation
 * w (R <- exp([w]_x) R), 3-5 translation, 6 focal fx (fy = fx * fy0/fx0),
 * 7-8 cx, cy, 9-10 k1, k2. Jp (2 x 3) is d(u, v)/d(X_world).
 */
#ifndef SFM_REFINE_BA_PROJECT_H
#define SFM_REFINE_BA_PROJECT_H

#define SFM_BA_NLOC 11
#define NLOC SFM_BA_NLOC

/* Projects X by camera (R, t, K). J (2 x NLOC, local columns) and Jp (2 x 3)
 * may be NULL. Returns 0 when z == 0. */
static inline int sfm_ba_project(const double *R, const double *t, const double *K, const double *X,
                   double uv[2], double *J, double *Jp)
{
    double a0 = R[0] * X[0] + R[1] * X[1] + R[2] * X[2];
    double a1 = R[3] * X[0] + R[4] * X[1] + R[5] * X[2];
    double a2 = R[6] * X[0] + R[7] * X[1] + R[8] * X[2];
    double x = a0 + t[0], y = a1 + t[1], z = a2 + t[2];
    if (z == 0.0)
        return 0;
    double iz = 1.0 / z;
    double xn = x * iz, yn = y * iz;
    double fx = K[0], fy = K[1], k1 = K[4], k2 = K[5];
    double r2 = xn * xn + yn * yn;
    double d = 1.0 + r2 * (k1 + k2 * r2);
    uv[0] = fx * d * xn + K[2];
    uv[1] = fy * d * yn + K[3];
    if (J == NULL && Jp == NULL)
        return 1;
    double g = 2.0 * (k1 + 2.0 * k2 * r2);
    double A00 = fx * (d + g * xn * xn), A01 = fx * g * xn * yn;
    double A10 = fy * g * xn * yn, A11 = fy * (d + g * yn * yn);
    double P00 = A00 * iz, P01 = A01 * iz, P02 = -(A00 * xn + A01 * yn) * iz;
    double P10 = A10 * iz, P11 = A11 * iz, P12 = -(A10 * xn + A11 * yn) * iz;
    if (J != NULL) {
        double *j0 = J, *j1 = J + NLOC;
        /* d x_cam / d w = -[R X]_x */
        j0[0] = -P01 * a2 + P02 * a1;
        j0[1] = P00 * a2 - P02 * a0;
        j0[2] = -P00 * a1 + P01 * a0;
        j1[0] = -P11 * a2 + P12 * a1;
        j1[1] = P10 * a2 - P12 * a0;
        j1[2] = -P10 * a1 + P11 * a0;
        j0[3] = P00; j0[4] = P01; j0[5] = P02;
        j1[3] = P10; j1[4] = P11; j1[5] = P12;
        double asp = fy / fx;
        j0[6] = d * xn;          j1[6] = asp * d * yn;
        j0[7] = 1.0;             j1[7] = 0.0;
        j0[8] = 0.0;             j1[8] = 1.0;
        j0[9] = fx * xn * r2;    j1[9] = fy * yn * r2;
        j0[10] = fx * xn * r2 * r2; j1[10] = fy * yn * r2 * r2;
    }
    if (Jp != NULL) {
        Jp[0] = P00 * R[0] + P01 * R[3] + P02 * R[6];
        Jp[1] = P00 * R[1] + P01 * R[4] + P02 * R[7];
        Jp[2] = P00 * R[2] + P01 * R[5] + P02 * R[8];
        Jp[3] = P10 * R[0] + P11 * R[3] + P12 * R[6];
        Jp[4] = P10 * R[1] + P11 * R[4] + P12 * R[7];
        Jp[5] = P10 * R[2] + P11 * R[5] + P12 * R[8];
    }
    return 1;
}

#endif
