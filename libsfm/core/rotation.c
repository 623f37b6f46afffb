/*
 * Rotations: axis-angle (Rodrigues), unit quaternions (w, x, y, z), nearest
 * rotation, skew matrices, geodesic distance.
 *
 * Matrix to axis-angle goes through the quaternion: Shepperd's choice of the
 * largest of w, x, y, z as pivot (Shepperd, "Quaternion from rotation
 * matrix", J. Guidance and Control 1(3), 1978) keeps the extraction accurate
 * everywhere, and the angle 2 atan2(|v|, w) keeps full relative accuracy both
 * near 0 (where acos((tr R - 1) / 2) loses half the digits) and near pi.
 * Quaternion convention: R(q) as in Hamilton's product, the one scipy and
 * Eigen use (scipy stores it scalar-last).
 *
 * Every function computes into locals and writes its outputs last, so in
 * practice outputs may alias inputs, though the header does not promise it.
 */
#include <float.h>
#include <math.h>
#include <string.h>

#include "sfm/sfm_linalg.h"
#include "sfm/sfm_rotation.h"
#include "core/dmath.h"

static int finite_n(const double *v, int n)
{
    for (int i = 0; i < n; i++)
        if (!isfinite(v[i]))
            return 0;
    return 1;
}

int sfm_skew(const double v[3], double S[9])
{
    if (!v || !S)
        return SFM_E_ARGUMENT;
    if (!finite_n(v, 3))
        return SFM_E_NONFINITE;
    const double x = v[0], y = v[1], z = v[2];
    S[0] = 0.0;
    S[1] = -z;
    S[2] = y;
    S[3] = z;
    S[4] = 0.0;
    S[5] = -x;
    S[6] = -y;
    S[7] = x;
    S[8] = 0.0;
    return SFM_OK;
}

int sfm_rot_from_axis_angle(const double aa[3], double R[9])
{
    if (!aa || !R)
        return SFM_E_ARGUMENT;
    if (!finite_n(aa, 3))
        return SFM_E_NONFINITE;
    const double x = aa[0], y = aa[1], z = aa[2];
    const double th2 = x * x + y * y + z * z, th = sqrt(th2);
    if (!isfinite(th2))
        return SFM_E_NONFINITE; /* |aa| beyond 1e154 overflows */
    /* R = I + a K + b K^2, a = sin(th)/th, b = (1 - cos th)/th^2 written as
     * 2 sin^2(th/2)/th^2, which has no cancellation. */
    double a, b;
    if (th < 1e-4) { /* Taylor: the terms dropped are below eps */
        a = 1.0 - th2 / 6.0 + th2 * th2 / 120.0;
        b = 0.5 - th2 / 24.0 + th2 * th2 / 720.0;
    } else {
        const double sh = sfmi_sin(0.5 * th) / th;
        a = sfmi_sin(th) / th;
        b = 2.0 * sh * sh;
    }
    double M[9];
    /* K^2 = v v^T - th^2 I */
    M[0] = 1.0 + b * (x * x - th2);
    M[1] = -a * z + b * x * y;
    M[2] = a * y + b * x * z;
    M[3] = a * z + b * x * y;
    M[4] = 1.0 + b * (y * y - th2);
    M[5] = -a * x + b * y * z;
    M[6] = -a * y + b * x * z;
    M[7] = a * x + b * y * z;
    M[8] = 1.0 + b * (z * z - th2);
    memcpy(R, M, sizeof M);
    return SFM_OK;
}

/* Shepperd's method; q normalised, w >= 0. R assumed finite. */
static void quat_of(const double *R, double q[4])
{
    const double tr = R[0] + R[4] + R[8];
    double w, x, y, z;
    if (tr >= R[0] && tr >= R[4] && tr >= R[8]) {
        const double s = 2.0 * sqrt(fmax(1.0 + tr, 0.0)); /* 4w */
        w = 0.25 * s;
        x = (R[7] - R[5]) / s;
        y = (R[2] - R[6]) / s;
        z = (R[3] - R[1]) / s;
    } else if (R[0] >= R[4] && R[0] >= R[8]) {
        const double s = 2.0 * sqrt(fmax(1.0 + R[0] - R[4] - R[8], 0.0)); /* 4x */
        w = (R[7] - R[5]) / s;
        x = 0.25 * s;
        y = (R[1] + R[3]) / s;
        z = (R[2] + R[6]) / s;
    } else if (R[4] >= R[8]) {
        const double s = 2.0 * sqrt(fmax(1.0 + R[4] - R[0] - R[8], 0.0)); /* 4y */
        w = (R[2] - R[6]) / s;
        x = (R[1] + R[3]) / s;
        y = 0.25 * s;
        z = (R[5] + R[7]) / s;
    } else {
        const double s = 2.0 * sqrt(fmax(1.0 + R[8] - R[0] - R[4], 0.0)); /* 4z */
        w = (R[3] - R[1]) / s;
        x = (R[2] + R[6]) / s;
        y = (R[5] + R[7]) / s;
        z = 0.25 * s;
    }
    double n = sqrt(w * w + x * x + y * y + z * z);
    if (!(n > 0.0) || !isfinite(n)) { /* not a rotation at all: identity */
        w = 1.0;
        x = y = z = 0.0;
        n = 1.0;
    }
    if (w < 0.0)
        n = -n;
    q[0] = w / n;
    q[1] = x / n;
    q[2] = y / n;
    q[3] = z / n;
}

int sfm_rot_to_quat(const double R[9], double q[4])
{
    if (!R || !q)
        return SFM_E_ARGUMENT;
    if (!finite_n(R, 9))
        return SFM_E_NONFINITE;
    double t[4];
    quat_of(R, t);
    memcpy(q, t, sizeof t);
    return SFM_OK;
}

int sfm_rot_from_quat(const double q[4], double R[9])
{
    if (!q || !R)
        return SFM_E_ARGUMENT;
    if (!finite_n(q, 4))
        return SFM_E_NONFINITE;
    /* scale by the largest magnitude first: no overflow or underflow */
    double m = fmax(fmax(fabs(q[0]), fabs(q[1])), fmax(fabs(q[2]), fabs(q[3])));
    if (m == 0.0)
        return SFM_E_ARGUMENT;
    double w = q[0] / m, x = q[1] / m, y = q[2] / m, z = q[3] / m;
    const double n = sqrt(w * w + x * x + y * y + z * z);
    w /= n;
    x /= n;
    y /= n;
    z /= n;
    double M[9];
    M[0] = 1.0 - 2.0 * (y * y + z * z);
    M[1] = 2.0 * (x * y - w * z);
    M[2] = 2.0 * (x * z + w * y);
    M[3] = 2.0 * (x * y + w * z);
    M[4] = 1.0 - 2.0 * (x * x + z * z);
    M[5] = 2.0 * (y * z - w * x);
    M[6] = 2.0 * (x * z - w * y);
    M[7] = 2.0 * (y * z + w * x);
    M[8] = 1.0 - 2.0 * (x * x + y * y);
    memcpy(R, M, sizeof M);
    return SFM_OK;
}

/* Rotation vector of a unit quaternion with w >= 0: angle in [0, pi]. */
static void log_of_quat(const double q[4], double aa[3])
{
    const double s = sqrt(q[1] * q[1] + q[2] * q[2] + q[3] * q[3]);
    /* 2 atan2(s, w) / s; its limit 2 / w as s -> 0 */
    const double f = s > 0.0 ? 2.0 * sfmi_atan2(s, q[0]) / s : 2.0 / q[0];
    aa[0] = f * q[1];
    aa[1] = f * q[2];
    aa[2] = f * q[3];
}

int sfm_rot_to_axis_angle(const double R[9], double aa[3])
{
    if (!R || !aa)
        return SFM_E_ARGUMENT;
    if (!finite_n(R, 9))
        return SFM_E_NONFINITE;
    double q[4], v[3];
    quat_of(R, q);
    log_of_quat(q, v);
    memcpy(aa, v, sizeof v);
    return SFM_OK;
}

int sfm_rot_angle_between(const double R1[9], const double R2[9], double *angle)
{
    if (!R1 || !R2 || !angle)
        return SFM_E_ARGUMENT;
    if (!finite_n(R1, 9) || !finite_n(R2, 9))
        return SFM_E_NONFINITE;
    double D[9], q[4];
    for (int i = 0; i < 3; i++) /* D = R1^T R2 */
        for (int j = 0; j < 3; j++)
            D[3 * i + j] = R1[i] * R2[j] + R1[3 + i] * R2[3 + j] + R1[6 + i] * R2[6 + j];
    quat_of(D, q);
    const double s = sqrt(q[1] * q[1] + q[2] * q[2] + q[3] * q[3]);
    *angle = 2.0 * sfmi_atan2(s, q[0]);
    return SFM_OK;
}

/* Workspace of the 3x3 SVD, checked against sfm_svd_workspace_size at run
 * time (SFM_E_WORKSPACE from sfm_svd would show a mismatch). */
#define ROT_SVD_WS 1024

int sfm_rot_nearest(const double M[9], double R[9])
{
    if (!M || !R)
        return SFM_E_ARGUMENT;
    if (!finite_n(M, 9))
        return SFM_E_NONFINITE;
    double U[9], S[3], V[9];
    _Alignas(16) unsigned char ws[ROT_SVD_WS];
    int st = sfm_svd(M, 3, 3, U, S, V, ws, sizeof ws);
    if (st < 0)
        return st;
    /* the nearest rotation is unique when rank >= 2 */
    if (!(S[0] > 0.0) || S[1] <= 8.0 * DBL_EPSILON * S[0])
        return SFM_E_SINGULAR;
    /* R = U diag(1, 1, det(U V^T)) V^T (Horn, Hilden and Negahdaripour 1988;
     * Umeyama 1991) */
    const double du = U[0] * (U[4] * U[8] - U[5] * U[7]) - U[1] * (U[3] * U[8] - U[5] * U[6]) +
                      U[2] * (U[3] * U[7] - U[4] * U[6]);
    const double dv = V[0] * (V[4] * V[8] - V[5] * V[7]) - V[1] * (V[3] * V[8] - V[5] * V[6]) +
                      V[2] * (V[3] * V[7] - V[4] * V[6]);
    const double d3 = du * dv < 0.0 ? -1.0 : 1.0;
    double T[9];
    for (int i = 0; i < 3; i++)
        for (int j = 0; j < 3; j++)
            T[3 * i + j] = U[3 * i] * V[3 * j] + U[3 * i + 1] * V[3 * j + 1] +
                           d3 * U[3 * i + 2] * V[3 * j + 2];
    memcpy(R, T, sizeof T);
    return SFM_OK;
}
