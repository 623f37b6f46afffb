/*
 * Rectification from the fundamental matrix alone: Hartley, "Theory and
 * practice of projective rectification", IJCV 35 (1999); Hartley &
 * Zisserman, Multiple View Geometry, 2nd ed., section 11.12.
 *
 * H2 = G R T: T moves image 2's centre to the origin, R turns the epipole
 * onto the negative x axis (so that, as in the calibrated case, image 1 is
 * the left one), G = [1 0 0; 0 1 0; -1/e 0 1] sends the epipole (e, 0, 1)
 * to infinity and is first-order a rigid motion at the centre. H1 = H_A H2 M
 * with F = [e2]_x M, the matching transform (both send epipolar lines to the
 * same rows); H_A = [a b c; 0 1 0; 0 0 1] minimises the squared horizontal
 * disparities of the matches. A final common shift moves the smallest
 * disparity of the matches to zero and the centre back.
 */
#include <math.h>
#include <string.h>

#include "sfm/sfm_linalg.h"
#include "sfm/sfm_stereo.h"
#include "solvers/small_math.h"

static int dehom(const double *H, const double *px, double *out)
{
    double p[3] = {px[0], px[1], 1.0}, q[3];
    sfmi_matvec3(H, p, q);
    if (!(fabs(q[2]) > 1e-12 * (fabs(q[0]) + fabs(q[1]) + fabs(q[2]))))
        return 0;
    out[0] = q[0] / q[2];
    out[1] = q[1] / q[2];
    return 1;
}

int sfm_stereo_rectify_uncalibrated(const sfm_mat3 *F_in, const double *x1, const double *x2, int n,
                                    int width, int height, sfm_mat3 *H1_out, sfm_mat3 *H2_out)
{
    const double *F = F_in ? F_in->m : NULL;
    double *H1 = H1_out ? H1_out->m : NULL;
    double *H2 = H2_out ? H2_out->m : NULL;
    if (!F || !x1 || !x2 || !H1 || !H2 || n < 8 || width < 8 || height < 8 ||
        width > 32767 || height > 32767)
        return SFM_E_ARGUMENT;
    if (!sfmi_all_finite9(F))
        return SFM_E_NONFINITE;
    for (int i = 0; i < 2 * n; i++)
        if (!isfinite(x1[i]) || !isfinite(x2[i]))
            return SFM_E_NONFINITE;

    double fn = 0.0;
    for (int i = 0; i < 9; i++)
        fn += F[i] * F[i];
    fn = sqrt(fn);
    if (!(fn > 0.0))
        return SFM_E_SINGULAR;
    double Fs[9];
    for (int i = 0; i < 9; i++)
        Fs[i] = F[i] / fn;
    unsigned char svd_ws[1024];
    if (sfm_svd_workspace_size(3, 3) > sizeof svd_ws)
        return SFM_E_WORKSPACE;
    double U[9], S[3];
    if (sfm_svd(Fs, 3, 3, U, S, NULL, svd_ws, sizeof svd_ws) != SFM_OK)
        return SFM_E_SINGULAR;
    if (!(S[1] > 1e-8 * S[0]) || !(S[2] < 1e-3 * S[1]))
        return SFM_E_SINGULAR; /* not of rank 2 */
    double e2[3] = {U[2], U[5], U[8]}; /* e2^T F = 0 */

    const double cx = 0.5 * (width - 1), cy = 0.5 * (height - 1);
    /* Epipole relative to the centre, homogeneous. */
    double ex = e2[0] - cx * e2[2], ey = e2[1] - cy * e2[2], ez = e2[2];
    double r = sqrt(ex * ex + ey * ey);
    if (!(r > 0.0))
        return SFM_E_SINGULAR; /* epipole at the image centre */
    /* Inside image 2's bounds enlarged by half: no planar rectification
     * keeps the image bounded. */
    if (fabs(ez) * 1.5 * cx >= fabs(ex) && fabs(ez) * 1.5 * cy >= fabs(ey))
        return SFM_E_SINGULAR;
    /* R sends (ex, ey) to (-r, 0). */
    double c = -ex / r, s = -ey / r;
    double Rm[9] = {c, s, 0, -s, c, 0, 0, 0, 1};
    double T[9] = {1, 0, -cx, 0, 1, -cy, 0, 0, 1};
    double G[9] = {1, 0, 0, 0, 1, 0, 0, 0, 1};
    /* Rotated epipole (-r, 0, ez) ~ (-r / ez, 0, 1). */
    if (fabs(ez) > 1e-12 * r)
        G[6] = ez / r; /* -1 / e with e = -r / ez */
    double GR[9], H2a[9];
    sfmi_matmul3(G, Rm, GR);
    sfmi_matmul3(GR, T, H2a);

    /* M = [e2]_x F + e2 v^T, v = (1, 1, 1): nonsingular for a general v. */
    double en = sqrt(sfmi_dot3(e2, e2));
    double eu[3] = {e2[0] / en, e2[1] / en, e2[2] / en};
    double Ex[9] = {0, -eu[2], eu[1], eu[2], 0, -eu[0], -eu[1], eu[0], 0};
    double M[9];
    sfmi_matmul3(Ex, Fs, M);
    for (int i = 0; i < 3; i++)
        for (int j = 0; j < 3; j++)
            M[3 * i + j] += eu[i];
    double H0[9];
    sfmi_matmul3(H2a, M, H0);

    /* Normal equations of min sum (a u1 + b v1 + c - u2)^2. Coordinates are
     * near the image centre, so the 3x3 system is well scaled. */
    double A[9] = {0}, rhs[3] = {0};
    int used = 0;
    for (int i = 0; i < n; i++) {
        double p1[2], p2[2];
        if (!dehom(H0, x1 + 2 * i, p1) || !dehom(H2a, x2 + 2 * i, p2))
            continue;
        double row[3] = {p1[0], p1[1], 1.0};
        for (int a = 0; a < 3; a++) {
            rhs[a] += row[a] * p2[0];
            for (int b = 0; b < 3; b++)
                A[3 * a + b] += row[a] * row[b];
        }
        used++;
    }
    if (used < 8)
        return SFM_E_SINGULAR;
    if (sfm_cholesky_factor(A, 3) != SFM_OK || sfm_cholesky_solve(A, 3, rhs, 1) != SFM_OK)
        return SFM_E_SINGULAR;
    double HA[9] = {rhs[0], rhs[1], rhs[2], 0, 1, 0, 0, 0, 1};
    double H1a[9];
    sfmi_matmul3(HA, H0, H1a);
    if (!sfmi_all_finite9(H1a))
        return SFM_E_SINGULAR;

    /* The smallest disparity of the matches goes to zero (image 2 moves),
     * then both go back around the image centre. */
    double dmin = HUGE_VAL;
    for (int i = 0; i < n; i++) {
        double p1[2], p2[2];
        if (!dehom(H1a, x1 + 2 * i, p1) || !dehom(H2a, x2 + 2 * i, p2))
            continue;
        double d = p1[0] - p2[0];
        if (d < dmin)
            dmin = d;
    }
    if (!isfinite(dmin))
        return SFM_E_SINGULAR;
    double Tb1[9] = {1, 0, cx, 0, 1, cy, 0, 0, 1};
    double Tb2[9] = {1, 0, cx + dmin, 0, 1, cy, 0, 0, 1};
    double o1[9], o2[9];
    sfmi_matmul3(Tb1, H1a, o1);
    sfmi_matmul3(Tb2, H2a, o2);
    if (!sfmi_all_finite9(o1) || !sfmi_all_finite9(o2))
        return SFM_E_SINGULAR;
    memcpy(H1, o1, sizeof o1);
    memcpy(H2, o2, sizeof o2);
    return SFM_OK;
}
