/*
 * The four (R, t) decompositions of an essential matrix E = [t]x R and the
 * cheirality choice over a set of bearing pairs.
 *
 * R. Hartley and A. Zisserman, "Multiple View Geometry", 2nd ed., result 9.19:
 * with E = U diag(s, s, 0) V^T (U, V proper rotations) and
 * W = [[0,-1,0],[1,0,0],[0,0,1]], R in {U W V^T, U W^T V^T}, t = +-u3.
 * The SVD of this 3x3 comes from a cyclic Jacobi eigen-decomposition of
 * E^T E (accurate for the well-separated spectrum of an essential matrix):
 * v1, v2 are the dominant right vectors, u1 = E v1 / |E v1|, u2 the
 * normalized part of E v2 orthogonal to u1, u3 = u1 x u2, v3 = v1 x v2.
 * A noisy E is thereby replaced by its nearest essential matrix.
 *
 * The depth test is the minimal one, with no division: for x2 ~ R x1 + t the
 * depths along x1 and x2 have the signs of -(t x x2).(R x1 x x2) and
 * -(t x R x1).(R x1 x x2); a point whose rays are parallel (at infinity or on
 * the baseline) gives zero and is not counted in front.
 * Stack: about 1 KiB (gcc 12 -O2 x86-64: 1024 bytes).
 */
#include <math.h>
#include <string.h>

#include "core/linalg_util.h"
#include "sfm/sfm_pose.h"
#include "solvers/small_math.h"

/* Cyclic Jacobi on a symmetric 3x3 A (overwritten): eigenvalues w (unsorted),
 * eigenvectors as the columns of V. */
static void jacobi3(double A[9], double w[3], double V[9])
{
    static const double I3[9] = {1, 0, 0, 0, 1, 0, 0, 0, 1};
    memcpy(V, I3, sizeof I3);
    for (int sweep = 0; sweep < 30; sweep++) {
        double off = A[1] * A[1] + A[2] * A[2] + A[5] * A[5];
        double diag = A[0] * A[0] + A[4] * A[4] + A[8] * A[8];
        if (off <= 1e-36 * diag || off == 0.0)
            break;
        for (int p = 0; p < 2; p++) {
            for (int q = p + 1; q < 3; q++) {
                double apq = A[3 * p + q];
                if (apq == 0.0)
                    continue;
                double app = A[4 * p], aqq = A[4 * q];
                double theta = (aqq - app) / (2.0 * apq);
                double tt = copysign(1.0, theta) / (fabs(theta) + sqrt(theta * theta + 1.0));
                double c = 1.0 / sqrt(tt * tt + 1.0), s = tt * c;
                /* A <- J^T A J with J the rotation in the (p, q) plane
                 * (columns p, q, then rows p, q), V <- V J */
                sfmi_la_rotate(&A[p], &A[q], 3, 3, c, s);
                sfmi_la_rotate(&A[3 * p], &A[3 * q], 3, 1, c, s);
                sfmi_la_rotate(&V[p], &V[q], 3, 3, c, s);
            }
        }
    }
    w[0] = A[0];
    w[1] = A[4];
    w[2] = A[8];
}

/* Points in front of both cameras for x2 ~ R x1 + t. */
static int count_front(const double R[9], const double t[3], const double *x1, const double *x2,
                       int n)
{
    int cnt = 0;
    for (int i = 0; i < n; i++) {
        const double *a = x1 + 3 * i, *b = x2 + 3 * i;
        double v[3] = {R[0] * a[0] + R[1] * a[1] + R[2] * a[2],
                       R[3] * a[0] + R[4] * a[1] + R[5] * a[2],
                       R[6] * a[0] + R[7] * a[1] + R[8] * a[2]};
        double r[3], tb[3], tv[3];
        sfmi_cross3(v, b, r);
        sfmi_cross3(t, b, tb);
        sfmi_cross3(t, v, tv);
        double s1 = -sfmi_dot3(tb, r), s2 = -sfmi_dot3(tv, r);
        if (s1 > 0.0 && s2 > 0.0)
            cnt++;
    }
    return cnt;
}

int sfm_essential_to_poses(const sfm_mat3 *E_in, const double *x1, const double *x2, int n,
                           sfm_pose poses[SFM_ESSENTIAL_POSES], int n_front[SFM_ESSENTIAL_POSES])
{
    const double *E = E_in ? E_in->m : NULL;
    if (!E || !poses || n < 0 || (n > 0 && (!x1 || !x2)))
        return SFM_E_ARGUMENT;
    if (!sfmi_la_all_finite(E, 9) ||
        (n > 0 && (!sfmi_la_all_finite(x1, 3 * (size_t)n) || !sfmi_la_all_finite(x2, 3 * (size_t)n))))
        return SFM_E_NONFINITE;

    /* scale E to unit Frobenius norm (no under/overflow in E^T E) */
    double mx = 0.0;
    for (int i = 0; i < 9; i++)
        mx = fmax(mx, fabs(E[i]));
    if (!(mx > 0.0))
        return 0;
    double Es[9], fn = 0.0;
    for (int i = 0; i < 9; i++) {
        Es[i] = E[i] / mx;
        fn += Es[i] * Es[i];
    }
    double inv = 1.0 / sqrt(fn);
    for (int i = 0; i < 9; i++)
        Es[i] *= inv;

    double A[9], w[3], V[9];
    for (int r = 0; r < 3; r++)
        for (int c = 0; c < 3; c++)
            A[3 * r + c] = Es[r] * Es[c] + Es[3 + r] * Es[3 + c] + Es[6 + r] * Es[6 + c];
    jacobi3(A, w, V);
    /* order: i0, i1 the two largest eigenvalues */
    int i0 = 0, i1 = 1, i2 = 2;
    if (w[i1] > w[i0]) {
        int tmp = i0;
        i0 = i1;
        i1 = tmp;
    }
    if (w[i2] > w[i1]) {
        int tmp = i1;
        i1 = i2;
        i2 = tmp;
    }
    if (w[i1] > w[i0]) {
        int tmp = i0;
        i0 = i1;
        i1 = tmp;
    }
    /* rank below 2: no decomposition (sigma2^2 against sigma1^2; the
     * eigenvalues of E^T E carry an absolute error of a few eps of the
     * largest, so a rank-1 E shows sigma2^2 near 1e-16, and the bound sits
     * above that: sigma2 / sigma1 > 1e-7) */
    if (!(w[i1] > 1e-14 * w[i0]))
        return 0;
    double v1[3] = {V[i0], V[3 + i0], V[6 + i0]}, v2[3] = {V[i1], V[3 + i1], V[6 + i1]}, v3[3];
    sfmi_cross3(v1, v2, v3);
    double u1[3], u2[3], u3[3];
    for (int k = 0; k < 3; k++) {
        u1[k] = Es[3 * k] * v1[0] + Es[3 * k + 1] * v1[1] + Es[3 * k + 2] * v1[2];
        u2[k] = Es[3 * k] * v2[0] + Es[3 * k + 1] * v2[1] + Es[3 * k + 2] * v2[2];
    }
    double n1 = sqrt(sfmi_dot3(u1, u1));
    if (!(n1 > 0.0))
        return 0;
    for (int k = 0; k < 3; k++)
        u1[k] /= n1;
    double pr = sfmi_dot3(u1, u2);
    for (int k = 0; k < 3; k++)
        u2[k] -= pr * u1[k];
    double n2 = sqrt(sfmi_dot3(u2, u2));
    if (!(n2 > 0.0))
        return 0;
    for (int k = 0; k < 3; k++)
        u2[k] /= n2;
    sfmi_cross3(u1, u2, u3);

    /* R = U W V^T = u2 v1^T - u1 v2^T + u3 v3^T; U W^T V^T = -u2 v1^T + u1 v2^T + u3 v3^T */
    sfm_pose out[4];
    for (int r = 0; r < 3; r++) {
        for (int c = 0; c < 3; c++) {
            double a = u2[r] * v1[c] - u1[r] * v2[c], b = u3[r] * v3[c];
            out[0].R[3 * r + c] = a + b;
            out[2].R[3 * r + c] = b - a;
        }
    }
    memcpy(out[1].R, out[0].R, sizeof out[0].R);
    memcpy(out[3].R, out[2].R, sizeof out[2].R);
    for (int k = 0; k < 3; k++) {
        out[0].t[k] = out[2].t[k] = u3[k];
        out[1].t[k] = out[3].t[k] = -u3[k];
    }
    int cnt[4] = {0, 0, 0, 0}, order[4] = {0, 1, 2, 3};
    if (n > 0) {
        for (int k = 0; k < 4; k++)
            cnt[k] = count_front(out[k].R, out[k].t, x1, x2, n);
        /* stable insertion sort, largest count first */
        for (int i = 1; i < 4; i++) {
            int o = order[i], j = i;
            while (j > 0 && cnt[order[j - 1]] < cnt[o]) {
                order[j] = order[j - 1];
                j--;
            }
            order[j] = o;
        }
    }
    for (int k = 0; k < 4; k++) {
        poses[k] = out[order[k]];
        if (n_front)
            n_front[k] = cnt[order[k]];
    }
    return SFM_ESSENTIAL_POSES;
}
