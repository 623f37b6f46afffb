/*
 * P3P: absolute pose from three bearings and three world points.
 *
 * Lambda Twist: M. Persson and K. Nordberg, "Lambda Twist: An Accurate Fast
 * Robust Perspective Three Point (P3P) Solver", ECCV 2018.
 * The depths lambda_i of the three points satisfy
 *     lambda_i^2 + lambda_j^2 - 2 b_ij lambda_i lambda_j = a_ij,
 * b_ij = cosine of the angle between bearings i and j, a_ij = |X_i - X_j|^2.
 * Two homogeneous combinations D1, D2 of these quadrics span a pencil; one
 * real root gamma of det(D1 + gamma D2) = 0 gives a degenerate conic, a pair
 * of planes through the origin in lambda space (whenever a real solution
 * exists, every real root gives a real pair of planes through all of them).
 * Each plane meets the other conic in at most two lines, scaled by one of the
 * inhomogeneous equations. The depths are polished by Gauss-Newton on the
 * three equations, then R = G F^T from orthonormal frames of the point
 * triad in the camera (G) and in the world (F), and t = lambda_1 y_1 - R X_1.
 *
 * Assumptions: bearings nonzero (normalized here), points in front of the
 * camera (positive depths only). Pose convention x_cam = R X + t.
 * Stack: about 1 KiB (gcc 12 -O2 x86-64: 880 + 64 bytes), no workspace.
 */
#include <math.h>
#include <string.h>

#include "sfm/sfm_pose.h"
#include "solvers/small_math.h"

/* det of a symmetric 3x3 given by its six entries (00,01,02,11,12,22). */
#define SYM_DET(m) \
    ((m)[0] * ((m)[3] * (m)[5] - (m)[4] * (m)[4]) - (m)[1] * ((m)[1] * (m)[5] - (m)[4] * (m)[2]) + \
     (m)[2] * ((m)[1] * (m)[4] - (m)[3] * (m)[2]))

/* tr(adj(A) B) for symmetric A, B (six entries each). */
static inline double sym_adj_tr(const double A[6], const double B[6])
{
    double c00 = A[3] * A[5] - A[4] * A[4];
    double c11 = A[0] * A[5] - A[2] * A[2];
    double c22 = A[0] * A[3] - A[1] * A[1];
    double c01 = A[2] * A[4] - A[1] * A[5];
    double c02 = A[1] * A[4] - A[2] * A[3];
    double c12 = A[1] * A[2] - A[0] * A[4];
    return c00 * B[0] + c11 * B[3] + c22 * B[5] + 2.0 * (c01 * B[1] + c02 * B[2] + c12 * B[4]);
}

int sfm_p3p(const double x[9], const double X[9], sfm_pose poses[SFM_P3P_MAX_SOLUTIONS])
{
    if (!x || !X || !poses)
        return SFM_E_ARGUMENT;
    if (!(sfmi_all_finite9(x) && sfmi_all_finite9(X)))
        return SFM_E_NONFINITE;

    double y[3][3];
    for (int i = 0; i < 3; i++) {
        double n2 = x[3 * i] * x[3 * i] + x[3 * i + 1] * x[3 * i + 1] + x[3 * i + 2] * x[3 * i + 2];
        if (!(n2 > 0.0))
            return 0;
        double inv = 1.0 / sqrt(n2);
        y[i][0] = x[3 * i] * inv;
        y[i][1] = x[3 * i + 1] * inv;
        y[i][2] = x[3 * i + 2] * inv;
    }

    double X12[3] = {X[0] - X[3], X[1] - X[4], X[2] - X[5]};
    double X13[3] = {X[0] - X[6], X[1] - X[7], X[2] - X[8]};
    double X23[3] = {X[3] - X[6], X[4] - X[7], X[5] - X[8]};
    double a12 = sfmi_dot3(X12, X12), a13 = sfmi_dot3(X13, X13), a23 = sfmi_dot3(X23, X23);
    double Xn[3];
    sfmi_cross3(X12, X13, Xn);
    double xn2 = sfmi_dot3(Xn, Xn);
    /* Coincident or collinear world points: no unique pose. */
    if (!(xn2 > 1e-24 * a12 * a13) || !(a23 > 0.0))
        return 0;

    double b12 = sfmi_dot3(y[0], y[1]), b13 = sfmi_dot3(y[0], y[2]), b23 = sfmi_dot3(y[1], y[2]);
    /* Coincident bearings: depths undetermined. */
    if (b12 > 1.0 - 1e-15 || b13 > 1.0 - 1e-15 || b23 > 1.0 - 1e-15)
        return 0;

    /* D1 = a23 M12 - a12 M23, D2 = a23 M13 - a13 M23 (six entries each). */
    double D1[6] = {a23, -a23 * b12, 0.0, a23 - a12, a12 * b23, -a12};
    double D2[6] = {a23, 0.0, -a23 * b13, -a13, a13 * b23, a23 - a13};
    double c3 = SYM_DET(D2), c0 = SYM_DET(D1);
    double c2 = sym_adj_tr(D2, D1), c1 = sym_adj_tr(D1, D2);

    /* det(D1 + g D2) = c3 g^3 + c2 g^2 + c1 g + c0. Solve in g, or in the
     * reciprocal when that has the larger leading coefficient. */
    double D0[6];
    const double *Dq; /* the other conic, used to cut the pair of planes */
    if (fabs(c3) >= fabs(c0)) {
        if (c3 == 0.0)
            return 0;
        double ic = 1.0 / c3;
        double g = sfmi_cubic_largest_root(c2 * ic, c1 * ic, c0 * ic);
        for (int k = 0; k < 6; k++)
            D0[k] = D1[k] + g * D2[k];
        Dq = fabs(g) >= 1.0 ? D1 : D2;
    } else {
        double ic = 1.0 / c0;
        double g = sfmi_cubic_largest_root(c1 * ic, c2 * ic, c3 * ic);
        for (int k = 0; k < 6; k++)
            D0[k] = g * D1[k] + D2[k];
        Dq = fabs(g) >= 1.0 ? D2 : D1;
    }

    /* Eigen-decomposition of the rank-2 D0: the null vector is the cross
     * product of two rows (the best pair when the first is poor). */
    double r0[3] = {D0[0], D0[1], D0[2]}, r1[3] = {D0[1], D0[3], D0[4]},
           r2[3] = {D0[2], D0[4], D0[5]};
    double nb[3];
    double mb = sfmi_rank2_null3(r0, r1, r2, 1e-4, nb);
    if (!(mb > 0.0))
        return 0;
    double tr = D0[0] + D0[3] + D0[5];
    double mi = (D0[0] * D0[3] - D0[1] * D0[1]) + (D0[0] * D0[5] - D0[2] * D0[2]) +
                (D0[3] * D0[5] - D0[4] * D0[4]);
    /* Real planes need an indefinite D0 (sigma1 sigma2 = mi < 0). */
    if (!(mi < 0.0))
        return 0;
    double sig1 = 0.5 * tr + sqrt(0.25 * tr * tr - mi); /* > 0 */
    double sig2 = mi / sig1;                             /* < 0 */
    /* e1: largest column of D0 - sig2 (I - n n^T / |n|^2) = (sig1 - sig2) e1 e1^T. */
    double e1[3], e2[3];
    {
        double sn = sig2 / mb;
        double d0 = D0[0] - sig2 + sn * nb[0] * nb[0];
        double d1 = D0[3] - sig2 + sn * nb[1] * nb[1];
        double d2 = D0[5] - sig2 + sn * nb[2] * nb[2];
        if (d0 >= d1 && d0 >= d2) {
            e1[0] = d0;
            e1[1] = D0[1] + sn * nb[0] * nb[1];
            e1[2] = D0[2] + sn * nb[0] * nb[2];
        } else if (d1 >= d2) {
            e1[0] = D0[1] + sn * nb[0] * nb[1];
            e1[1] = d1;
            e1[2] = D0[4] + sn * nb[1] * nb[2];
        } else {
            e1[0] = D0[2] + sn * nb[0] * nb[2];
            e1[1] = D0[4] + sn * nb[1] * nb[2];
            e1[2] = d2;
        }
        double m1 = sfmi_dot3(e1, e1);
        if (!(m1 > 0.0))
            return 0;
        double inv = 1.0 / sqrt(m1);
        e1[0] *= inv;
        e1[1] *= inv;
        e1[2] *= inv;
        sfmi_cross3(nb, e1, e2);
        double ne = 1.0 / sqrt(mb);
        e2[0] *= ne;
        e2[1] *= ne;
        e2[2] *= ne;
    }
    double sr = sqrt(-sig2 / sig1);
    double asum = a12 + a13 + a23;

    /* Orthonormal world frame (F1, F2, F3) of the triad; the camera frame of
     * the same triad gives R = G F^T, a proper rotation by construction. For
     * the exact depths |Y12| = |X12| and |Y12 x Y13| = |X12 x X13|, so the
     * world norms serve both frames. */
    double i1 = 1.0 / sqrt(a12), i3 = 1.0 / sqrt(xn2);
    double F1[3] = {X12[0] * i1, X12[1] * i1, X12[2] * i1};
    double F3[3] = {Xn[0] * i3, Xn[1] * i3, Xn[2] * i3};
    double F2[3];
    sfmi_cross3(F3, F1, F2);

    /* Full symmetric Dq for indexed access. */
    const double Dm[9] = {Dq[0], Dq[1], Dq[2], Dq[1], Dq[3], Dq[4], Dq[2], Dq[4], Dq[5]};
    int nsol = 0;
    for (int side = 0; side < 2; side++) {
        double sg = side ? sr : -sr;
        double u[3] = {e1[0] + sg * e2[0], e1[1] + sg * e2[1], e1[2] + sg * e2[2]};
        /* Plane u . lambda = 0: eliminate the component k with the largest
         * |u_k|: lambda = al v1 + be v2, v1 = e_i - (u_i/u_k) e_k,
         * v2 = e_j - (u_j/u_k) e_k. */
        int k = 0;
        double au0 = fabs(u[0]), au1 = fabs(u[1]), au2 = fabs(u[2]);
        if (au1 > au0)
            k = 1;
        if (au2 > (k ? au1 : au0))
            k = 2;
        int i = k == 0 ? 1 : 0, j = k == 2 ? 1 : 2;
        double iu = 1.0 / u[k];
        double wa = -u[i] * iu, wb = -u[j] * iu;
        double Dii = Dm[4 * i], Djj = Dm[4 * j], Dkk = Dm[4 * k];
        double Dij = Dm[3 * i + j], Dik = Dm[3 * i + k], Djk = Dm[3 * j + k];
        double q11 = Dii + wa * (2.0 * Dik + wa * Dkk);
        double q22 = Djj + wb * (2.0 * Djk + wb * Dkk);
        double q12 = Dij + wa * Djk + wb * Dik + wa * wb * Dkk;
        double disc = q12 * q12 - q11 * q22;
        if (disc < 0.0)
            continue;
        double rr = -q12 - copysign(sqrt(disc), q12);
        double ab[2][2] = {{rr, q11}, {q22, rr}};
        for (int r = 0; r < 2; r++) {
            double al = ab[r][0], be = ab[r][1];
            double l[3];
            l[i] = al;
            l[j] = be;
            l[k] = wa * al + wb * be;
            /* positive depths only (up to the common sign) */
            if (l[0] < 0.0) {
                l[0] = -l[0];
                l[1] = -l[1];
                l[2] = -l[2];
            }
            if (!(l[0] > 0.0 && l[1] > 0.0 && l[2] > 0.0))
                continue;
            double den = (l[0] * l[0] + l[1] * l[1] + l[2] * l[2]) -
                         (b12 * l[0] * l[1] + b13 * l[0] * l[2] + b23 * l[1] * l[2]);
            double sc = sqrt(0.5 * asum / den);
            l[0] *= sc;
            l[1] *= sc;
            l[2] *= sc;
            /* Gauss-Newton on the three depth equations. */
            for (int it = 0; it < 5; it++) {
                double f0 = l[0] * l[0] + l[1] * l[1] - 2.0 * b12 * l[0] * l[1] - a12;
                double f1 = l[0] * l[0] + l[2] * l[2] - 2.0 * b13 * l[0] * l[2] - a13;
                double f2 = l[1] * l[1] + l[2] * l[2] - 2.0 * b23 * l[1] * l[2] - a23;
                if (fabs(f0) + fabs(f1) + fabs(f2) < 1e-15 * asum)
                    break;
                double j00 = l[0] - b12 * l[1], j01 = l[1] - b12 * l[0];
                double j10 = l[0] - b13 * l[2], j12 = l[2] - b13 * l[0];
                double j21 = l[1] - b23 * l[2], j22 = l[2] - b23 * l[1];
                /* J = 2 [[j00 j01 0]; [j10 0 j12]; [0 j21 j22]] */
                double det = j00 * (-j12 * j21) - j01 * (j10 * j22);
                if (det == 0.0)
                    break;
                double id = 0.5 / det;
                double d0 = (-j12 * j21 * f0 - j01 * j22 * f1 + j01 * j12 * f2) * id;
                double d1 = (-j10 * j22 * f0 + j00 * j22 * f1 - j00 * j12 * f2) * id;
                double d2 = (j10 * j21 * f0 - j00 * j21 * f1 - j01 * j10 * f2) * id;
                l[0] -= d0;
                l[1] -= d1;
                l[2] -= d2;
            }
            /* also rejects NaN (den <= 0 gives NaN or Inf above) */
            if (!(l[0] > 0.0 && l[1] > 0.0 && l[2] > 0.0 && l[0] < HUGE_VAL &&
                  l[1] < HUGE_VAL && l[2] < HUGE_VAL))
                continue;
            double Y1[3] = {l[0] * y[0][0], l[0] * y[0][1], l[0] * y[0][2]};
            double G1[3] = {(Y1[0] - l[1] * y[1][0]) * i1, (Y1[1] - l[1] * y[1][1]) * i1,
                            (Y1[2] - l[1] * y[1][2]) * i1};
            double Y13[3] = {Y1[0] - l[2] * y[2][0], Y1[1] - l[2] * y[2][1],
                             Y1[2] - l[2] * y[2][2]};
            double G3[3], G2[3];
            sfmi_cross3(G1, Y13, G3);
            double s3 = i3 / i1;
            G3[0] *= s3;
            G3[1] *= s3;
            G3[2] *= s3;
            sfmi_cross3(G3, G1, G2);
            double *R = poses[nsol].R, *t = poses[nsol].t;
#define P3P_RROW(rw)                                                           \
    R[3 * (rw)] = G1[rw] * F1[0] + G2[rw] * F2[0] + G3[rw] * F3[0];            \
    R[3 * (rw) + 1] = G1[rw] * F1[1] + G2[rw] * F2[1] + G3[rw] * F3[1];        \
    R[3 * (rw) + 2] = G1[rw] * F1[2] + G2[rw] * F2[2] + G3[rw] * F3[2];        \
    t[rw] = Y1[rw] - (R[3 * (rw)] * X[0] + R[3 * (rw) + 1] * X[1] + R[3 * (rw) + 2] * X[2]);
            P3P_RROW(0)
            P3P_RROW(1)
            P3P_RROW(2)
#undef P3P_RROW
            nsol++;
        }
    }
    return nsol;
}
