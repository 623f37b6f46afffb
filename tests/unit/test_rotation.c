/*
 * Rotations against truth: matrices written down by hand, the textbook
 * Rodrigues formula evaluated here in long form (cos, sin, outer products),
 * half-angle quaternions, and round trips at 0, 1e-12, pi - 1e-9 and pi.
 */
#include <float.h>
#include <string.h>

#include "sfm/sfm.h"
#include "sfm_test.h"

#define PI 3.14159265358979323846
#define EPS DBL_EPSILON

static double max_diff(const double *a, const double *b, int n)
{
    double m = 0.0;
    for (int i = 0; i < n; i++)
        m = fmax(m, fabs(a[i] - b[i]));
    return m;
}

/* Independent reference: R = cos t I + sin t [n]x + (1 - cos t) n n^T. */
static void ref_rotation(const double n[3], double th, double R[9])
{
    const double c = cos(th), s = sin(th), C = 1.0 - c;
    const double x = n[0], y = n[1], z = n[2];
    const double Rr[9] = {c + C * x * x,     C * x * y - s * z, C * x * z + s * y,
                          C * x * y + s * z, c + C * y * y,     C * y * z - s * x,
                          C * x * z - s * y, C * y * z + s * x, c + C * z * z};
    memcpy(R, Rr, sizeof Rr);
}

static void check_rotation_matrix(sfm_test_ctx *t, const double *R, double tol)
{
    double RRt[9];
    for (int i = 0; i < 3; i++)
        for (int j = 0; j < 3; j++)
            RRt[3 * i + j] = R[3 * i] * R[3 * j] + R[3 * i + 1] * R[3 * j + 1] +
                             R[3 * i + 2] * R[3 * j + 2];
    const double I[9] = {1, 0, 0, 0, 1, 0, 0, 0, 1};
    SFM_CHECK(max_diff(RRt, I, 9) <= tol);
    const double det = R[0] * (R[4] * R[8] - R[5] * R[7]) - R[1] * (R[3] * R[8] - R[5] * R[6]) +
                       R[2] * (R[3] * R[7] - R[4] * R[6]);
    SFM_CHECK_NEAR(det, 1.0, tol);
}

SFM_TEST(rot_known_matrices)
{
    double R[9], aa[3];
    const double z90[3] = {0.0, 0.0, PI / 2};
    const double Rz90[9] = {0, -1, 0, 1, 0, 0, 0, 0, 1};
    SFM_CHECK_EQ_INT(sfm_rot_from_axis_angle(z90, R), SFM_OK);
    SFM_CHECK(max_diff(R, Rz90, 9) <= 2 * EPS);
    SFM_CHECK_EQ_INT(sfm_rot_to_axis_angle(Rz90, aa), SFM_OK);
    SFM_CHECK(max_diff(aa, z90, 3) <= 4 * EPS);
    /* exactly pi about x: diag(1, -1, -1); the axis comes back up to sign */
    const double Rx180[9] = {1, 0, 0, 0, -1, 0, 0, 0, -1};
    SFM_CHECK_EQ_INT(sfm_rot_to_axis_angle(Rx180, aa), SFM_OK);
    SFM_CHECK_NEAR(fabs(aa[0]), PI, 4 * EPS);
    SFM_CHECK_NEAR(aa[1], 0.0, 0.0);
    SFM_CHECK_NEAR(aa[2], 0.0, 0.0);
    const double x180[3] = {PI, 0.0, 0.0};
    SFM_CHECK_EQ_INT(sfm_rot_from_axis_angle(x180, R), SFM_OK);
    SFM_CHECK(max_diff(R, Rx180, 9) <= 4 * EPS);
    /* zero rotation both ways */
    const double zero[3] = {0, 0, 0}, I[9] = {1, 0, 0, 0, 1, 0, 0, 0, 1};
    SFM_CHECK_EQ_INT(sfm_rot_from_axis_angle(zero, R), SFM_OK);
    SFM_CHECK(max_diff(R, I, 9) == 0.0);
    SFM_CHECK_EQ_INT(sfm_rot_to_axis_angle(I, aa), SFM_OK);
    SFM_CHECK(max_diff(aa, zero, 3) == 0.0);
    /* 120 degrees about (1,1,1)/sqrt3 permutes the axes: x -> y -> z */
    const double s = 2.0 * PI / 3.0 / sqrt(3.0), perm[3] = {s, s, s};
    const double P[9] = {0, 0, 1, 1, 0, 0, 0, 1, 0};
    SFM_CHECK_EQ_INT(sfm_rot_from_axis_angle(perm, R), SFM_OK);
    SFM_CHECK(max_diff(R, P, 9) <= 4 * EPS);
    SFM_CHECK_EQ_INT(sfm_rot_to_axis_angle(P, aa), SFM_OK);
    SFM_CHECK(max_diff(aa, perm, 3) <= 8 * EPS);
}

SFM_TEST(rot_axis_angle_tiny_angles)
{
    /* 1e-12: R = I + [aa]x to first order; the vector must come back with
     * full relative accuracy (acos of the trace would lose it entirely) */
    for (int it = 0; it < SFM_TEST_ITERS(200); it++) {
        double n[3], aa[3], R[9], Rr[9], back[3];
        sfm_test_random_unit(t, n);
        const double th = it % 2 ? 1e-12 : pow(10.0, sfm_test_uniform(t, -15.0, -3.0));
        for (int k = 0; k < 3; k++)
            aa[k] = th * n[k];
        SFM_CHECK_EQ_INT(sfm_rot_from_axis_angle(aa, R), SFM_OK);
        ref_rotation(n, th, Rr);
        SFM_CHECK(max_diff(R, Rr, 9) <= 2 * EPS);
        SFM_CHECK_EQ_INT(sfm_rot_to_axis_angle(R, back), SFM_OK);
        SFM_CHECK(max_diff(back, aa, 3) <= 1e-15 * th + 1e-300);
    }
}

SFM_TEST(rot_axis_angle_near_pi)
{
    const double deltas[] = {0.0, 1e-12, 1e-9, 1e-6, 1e-3};
    for (int it = 0; it < SFM_TEST_ITERS(200); it++) {
        double n[3], aa[3], R[9], Rr[9], back[3];
        sfm_test_random_unit(t, n);
        const double th = PI - deltas[it % 5];
        for (int k = 0; k < 3; k++)
            aa[k] = th * n[k];
        SFM_CHECK_EQ_INT(sfm_rot_from_axis_angle(aa, R), SFM_OK);
        ref_rotation(n, th, Rr);
        SFM_CHECK(max_diff(R, Rr, 9) <= 8 * EPS);
        check_rotation_matrix(t, R, 8 * EPS);
        SFM_CHECK_EQ_INT(sfm_rot_to_axis_angle(Rr, back), SFM_OK);
        const double ang = sqrt(back[0] * back[0] + back[1] * back[1] + back[2] * back[2]);
        SFM_CHECK(ang <= PI * (1.0 + 4.0 * EPS)); /* |aa| computed here rounds too */
        SFM_CHECK_NEAR(ang, th, 8 * EPS);
        /* at exactly pi the axis sign is free; otherwise it must match */
        double sgn = th == PI && back[0] * n[0] + back[1] * n[1] + back[2] * n[2] < 0 ? -1.0 : 1.0;
        for (int k = 0; k < 3; k++)
            SFM_CHECK_NEAR(sgn * back[k], aa[k], th == PI ? 1e-7 : 1e-6);
        /* the recovered vector maps back to the same matrix, to rounding */
        double R2[9];
        SFM_CHECK_EQ_INT(sfm_rot_from_axis_angle(back, R2), SFM_OK);
        SFM_CHECK(max_diff(R2, Rr, 9) <= 16 * EPS);
    }
}

SFM_TEST(rot_axis_angle_round_trip_random)
{
    for (int it = 0; it < SFM_TEST_ITERS(2000); it++) {
        double n[3], aa[3], R[9], Rr[9], back[3];
        sfm_test_random_unit(t, n);
        const double th = sfm_test_uniform(t, 0.0, PI);
        for (int k = 0; k < 3; k++)
            aa[k] = th * n[k];
        SFM_CHECK_EQ_INT(sfm_rot_from_axis_angle(aa, R), SFM_OK);
        ref_rotation(n, th, Rr);
        SFM_CHECK(max_diff(R, Rr, 9) <= 8 * EPS);
        SFM_CHECK_EQ_INT(sfm_rot_to_axis_angle(R, back), SFM_OK);
        SFM_CHECK(max_diff(back, aa, 3) <= 1e-14 + (PI - th < 1e-3 ? 1e-9 : 0.0));
    }
    /* an angle beyond pi comes back as the equivalent one in [0, pi] */
    const double big[3] = {0.0, 1.5 * PI, 0.0}, want[3] = {0.0, -0.5 * PI, 0.0};
    double R[9], back[3];
    SFM_CHECK_EQ_INT(sfm_rot_from_axis_angle(big, R), SFM_OK);
    SFM_CHECK_EQ_INT(sfm_rot_to_axis_angle(R, back), SFM_OK);
    SFM_CHECK(max_diff(back, want, 3) <= 1e-14);
}

SFM_TEST(rot_quaternion_known_and_round_trip)
{
    /* half-angle form: q = (cos t/2, sin t/2 n) */
    for (int it = 0; it < SFM_TEST_ITERS(2000); it++) {
        double n[3], Rr[9], R[9], q[4], back[4];
        sfm_test_random_unit(t, n);
        const double th = it == 0 ? PI : it == 1 ? 0.0 : it == 2 ? 1e-12 : sfm_test_uniform(t, 0.0, PI);
        const double qt[4] = {cos(th / 2), sin(th / 2) * n[0], sin(th / 2) * n[1], sin(th / 2) * n[2]};
        ref_rotation(n, th, Rr);
        SFM_CHECK_EQ_INT(sfm_rot_from_quat(qt, R), SFM_OK);
        SFM_CHECK(max_diff(R, Rr, 9) <= 8 * EPS);
        /* scaled and negated: the same rotation */
        const double s = it % 2 ? -3.7 : 1e-5;
        for (int k = 0; k < 4; k++)
            q[k] = s * qt[k];
        SFM_CHECK_EQ_INT(sfm_rot_from_quat(q, R), SFM_OK);
        SFM_CHECK(max_diff(R, Rr, 9) <= 8 * EPS);
        SFM_CHECK_EQ_INT(sfm_rot_to_quat(Rr, back), SFM_OK);
        SFM_CHECK(back[0] >= 0.0);
        SFM_CHECK_NEAR(back[0] * back[0] + back[1] * back[1] + back[2] * back[2] + back[3] * back[3],
                       1.0, 4 * EPS);
        double sg = back[0] * qt[0] + back[1] * qt[1] + back[2] * qt[2] + back[3] * qt[3] < 0 ? -1 : 1;
        for (int k = 0; k < 4; k++)
            SFM_CHECK_NEAR(sg * back[k], qt[k], 4 * EPS);
    }
    const double z[4] = {0, 0, 0, 0};
    double R[9];
    sfm_test_fill_canary(R, sizeof R);
    SFM_CHECK_EQ_INT(sfm_rot_from_quat(z, R), SFM_E_ARGUMENT);
    SFM_CHECK(sfm_test_canary_intact(R, sizeof R));
    /* tiny and huge but finite quaternions normalise without under/overflow */
    const double tiny[4] = {0, 1e-300, 0, 0}, huge[4] = {1e300, 0, 0, 1e300};
    const double Rx180[9] = {1, 0, 0, 0, -1, 0, 0, 0, -1};
    SFM_CHECK_EQ_INT(sfm_rot_from_quat(tiny, R), SFM_OK);
    SFM_CHECK(max_diff(R, Rx180, 9) <= 0.0);
    SFM_CHECK_EQ_INT(sfm_rot_from_quat(huge, R), SFM_OK);
    const double Rz90[9] = {0, -1, 0, 1, 0, 0, 0, 0, 1};
    SFM_CHECK(max_diff(R, Rz90, 9) <= 4 * EPS);
}

SFM_TEST(rot_nearest_known_answers)
{
    double R0[9], S[9], M[9], R[9];
    for (int it = 0; it < SFM_TEST_ITERS(500); it++) {
        sfm_test_random_rotation(t, R0);
        /* M = R0 P with P symmetric positive definite: the polar factor R0 is
         * the nearest rotation */
        double a[9];
        for (int k = 0; k < 9; k++)
            a[k] = sfm_test_uniform(t, -1.0, 1.0);
        for (int i = 0; i < 3; i++)
            for (int j = 0; j < 3; j++)
                S[3 * i + j] = a[i] * a[j] + a[3 + i] * a[3 + j] + a[6 + i] * a[6 + j] +
                               (i == j ? 0.1 : 0.0);
        for (int i = 0; i < 3; i++)
            for (int j = 0; j < 3; j++)
                M[3 * i + j] = R0[3 * i] * S[j] + R0[3 * i + 1] * S[3 + j] + R0[3 * i + 2] * S[6 + j];
        SFM_CHECK_EQ_INT(sfm_rot_nearest(M, R), SFM_OK);
        SFM_CHECK(max_diff(R, R0, 9) <= 1e-11);
        check_rotation_matrix(t, R, 8 * EPS);
    }
    /* a reflection: diag(3, 2, -1) -> identity (the smallest singular
     * direction is flipped) */
    const double D[9] = {3, 0, 0, 0, 2, 0, 0, 0, -1}, I[9] = {1, 0, 0, 0, 1, 0, 0, 0, 1};
    SFM_CHECK_EQ_INT(sfm_rot_nearest(D, R), SFM_OK);
    SFM_CHECK(max_diff(R, I, 9) <= 4 * EPS);
    /* rank 2 still has a unique answer */
    const double r2[9] = {1, 0, 0, 0, 2, 0, 0, 0, 0};
    SFM_CHECK_EQ_INT(sfm_rot_nearest(r2, R), SFM_OK);
    SFM_CHECK(max_diff(R, I, 9) <= 4 * EPS);
    /* rank 1 and zero do not */
    const double r1[9] = {1, 2, 3, 2, 4, 6, -1, -2, -3}, r0[9] = {0};
    sfm_test_fill_canary(R, sizeof R);
    SFM_CHECK_EQ_INT(sfm_rot_nearest(r1, R), SFM_E_SINGULAR);
    SFM_CHECK_EQ_INT(sfm_rot_nearest(r0, R), SFM_E_SINGULAR);
    SFM_CHECK(sfm_test_canary_intact(R, sizeof R));
    /* the 3x3 SVD workspace fits the fixed buffer the function carries */
    SFM_CHECK(sfm_svd_workspace_size(3, 3) <= 1024);
}

SFM_TEST(rot_skew_and_angle_between)
{
    for (int it = 0; it < SFM_TEST_ITERS(500); it++) {
        double v[3], w[3], S[9];
        for (int k = 0; k < 3; k++) {
            v[k] = sfm_test_uniform(t, -5, 5);
            w[k] = sfm_test_uniform(t, -5, 5);
        }
        SFM_CHECK_EQ_INT(sfm_skew(v, S), SFM_OK);
        const double cx[3] = {v[1] * w[2] - v[2] * w[1], v[2] * w[0] - v[0] * w[2],
                              v[0] * w[1] - v[1] * w[0]};
        for (int i = 0; i < 3; i++)
            SFM_CHECK_NEAR(S[3 * i] * w[0] + S[3 * i + 1] * w[1] + S[3 * i + 2] * w[2], cx[i], 1e-13);
        for (int i = 0; i < 3; i++)
            for (int j = 0; j < 3; j++)
                SFM_CHECK(S[3 * i + j] == -S[3 * j + i]);
    }
    const double angles[] = {0.0, 1e-12, 1e-6, 0.3, 2.0, PI - 1e-9, PI};
    for (int it = 0; it < SFM_TEST_ITERS(70); it++) {
        double R1[9], n[3], D[9], R2[9], ang;
        const double th = angles[it % 7];
        sfm_test_random_rotation(t, R1);
        sfm_test_random_unit(t, n);
        ref_rotation(n, th, D);
        for (int i = 0; i < 3; i++) /* R2 = R1 D */
            for (int j = 0; j < 3; j++)
                R2[3 * i + j] = R1[3 * i] * D[j] + R1[3 * i + 1] * D[3 + j] + R1[3 * i + 2] * D[6 + j];
        SFM_CHECK_EQ_INT(sfm_rot_angle_between(R1, R2, &ang), SFM_OK);
        SFM_CHECK(ang >= 0.0 && ang <= PI);
        /* R2 itself carries rounding of order eps: absolute tolerance */
        SFM_CHECK_NEAR(ang, th, 1e-14);
        SFM_CHECK_EQ_INT(sfm_rot_angle_between(R1, R1, &ang), SFM_OK);
        SFM_CHECK_NEAR(ang, 0.0, 1e-15);
    }
}

SFM_TEST(rot_contracts)
{
    const double I[9] = {1, 0, 0, 0, 1, 0, 0, 0, 1}, v[3] = {0.1, 0.2, 0.3};
    const double q[4] = {1, 0, 0, 0};
    double out[9], ang;
    sfm_test_fill_canary(out, sizeof out);
    sfm_test_fill_canary(&ang, sizeof ang);
    SFM_CHECK_EQ_INT(sfm_rot_from_axis_angle(NULL, out), SFM_E_ARGUMENT);
    SFM_CHECK_EQ_INT(sfm_rot_from_axis_angle(v, NULL), SFM_E_ARGUMENT);
    SFM_CHECK_EQ_INT(sfm_rot_to_axis_angle(NULL, out), SFM_E_ARGUMENT);
    SFM_CHECK_EQ_INT(sfm_rot_to_axis_angle(I, NULL), SFM_E_ARGUMENT);
    SFM_CHECK_EQ_INT(sfm_rot_from_quat(NULL, out), SFM_E_ARGUMENT);
    SFM_CHECK_EQ_INT(sfm_rot_from_quat(q, NULL), SFM_E_ARGUMENT);
    SFM_CHECK_EQ_INT(sfm_rot_to_quat(NULL, out), SFM_E_ARGUMENT);
    SFM_CHECK_EQ_INT(sfm_rot_to_quat(I, NULL), SFM_E_ARGUMENT);
    SFM_CHECK_EQ_INT(sfm_rot_nearest(NULL, out), SFM_E_ARGUMENT);
    SFM_CHECK_EQ_INT(sfm_rot_nearest(I, NULL), SFM_E_ARGUMENT);
    SFM_CHECK_EQ_INT(sfm_skew(NULL, out), SFM_E_ARGUMENT);
    SFM_CHECK_EQ_INT(sfm_skew(v, NULL), SFM_E_ARGUMENT);
    SFM_CHECK_EQ_INT(sfm_rot_angle_between(NULL, I, &ang), SFM_E_ARGUMENT);
    SFM_CHECK_EQ_INT(sfm_rot_angle_between(I, NULL, &ang), SFM_E_ARGUMENT);
    SFM_CHECK_EQ_INT(sfm_rot_angle_between(I, I, NULL), SFM_E_ARGUMENT);
    const double bad[3] = {(double)NAN, (double)HUGE_VAL, -(double)HUGE_VAL};
    for (int b = 0; b < 3; b++) {
        for (int pos = 0; pos < 9; pos++) {
            double M[9];
            memcpy(M, I, sizeof M);
            M[pos] = bad[b];
            SFM_CHECK_EQ_INT(sfm_rot_to_axis_angle(M, out), SFM_E_NONFINITE);
            SFM_CHECK_EQ_INT(sfm_rot_to_quat(M, out), SFM_E_NONFINITE);
            SFM_CHECK_EQ_INT(sfm_rot_nearest(M, out), SFM_E_NONFINITE);
            SFM_CHECK_EQ_INT(sfm_rot_angle_between(M, I, &ang), SFM_E_NONFINITE);
            SFM_CHECK_EQ_INT(sfm_rot_angle_between(I, M, &ang), SFM_E_NONFINITE);
            if (pos < 4) {
                double qq[4] = {1, 0, 0, 0};
                qq[pos] = bad[b];
                SFM_CHECK_EQ_INT(sfm_rot_from_quat(qq, out), SFM_E_NONFINITE);
            }
            if (pos < 3) {
                double vv[3] = {0.1, 0.2, 0.3};
                vv[pos] = bad[b];
                SFM_CHECK_EQ_INT(sfm_rot_from_axis_angle(vv, out), SFM_E_NONFINITE);
                SFM_CHECK_EQ_INT(sfm_skew(vv, out), SFM_E_NONFINITE);
            }
        }
    }
    const double huge[3] = {1e200, 0, 0};
    SFM_CHECK_EQ_INT(sfm_rot_from_axis_angle(huge, out), SFM_E_NONFINITE);
    SFM_CHECK(sfm_test_canary_intact(out, sizeof out));
    SFM_CHECK(sfm_test_canary_intact(&ang, sizeof ang));
}
