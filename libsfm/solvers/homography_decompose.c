/*
 * Decomposition of a calibrated plane-induced homography H = R + t n^T / d
 * into its two physically valid (R, t, n) solutions, by the singular vectors
 * of H (Faugeras & Lustman, "Motion and structure from motion in a piecewise
 * planar environment", 1988; the construction of Ma, Soatto, Kosecka &
 * Sastry, "An Invitation to 3-D Vision", 2004, sec. 5.3.3). With H scaled
 * so that its middle singular value is 1, H^T H = V diag(s1, 1, s3) V^T and
 * the unit vectors u1, u2 in the span of v1, v3 whose length H keeps are
 * (sqrt(1 - s3) v1 +- sqrt(s1 - 1) v3) / sqrt(s1 - s3). For each u,
 * U = [v2, u, v2 x u] and W = [H v2, H u, H v2 x H u] give R = W U^T,
 * n = v2 x u, t = (H - R) n; the other two of the four algebraic solutions
 * (-n, -t) put the plane behind camera 1.
 */
#include "solvers/homography_decompose.h"

#include <math.h>

#include "sfm/sfm_linalg.h"
#include "solvers/small_math.h"

/* column j of a row-major 3x3 */
static void col(const double *M, int j, double *v)
{
    v[0] = M[j];
    v[1] = M[3 + j];
    v[2] = M[6 + j];
}

int sfmi_homography_decompose(const double H[9], const double *p1, const double *p2, int m,
                              double R[2][9], double t[2][3])
{
    if (!sfmi_all_finite9(H) || m < 1)
        return 0;
    double A[9];
    for (int r = 0; r < 3; r++)
        for (int c = 0; c < 3; c++)
            A[3 * r + c] = H[r] * H[c] + H[3 + r] * H[3 + c] + H[6 + r] * H[6 + c];
    double w[3], V[9], ws[96];
    if (sfm_sym_eig_workspace_size(3) > sizeof ws || sfm_sym_eig(A, 3, w, V, ws, sizeof ws) != 0)
        return 0;
    if (!(w[1] > 0.0))
        return 0;
    /* scale to a middle singular value of 1, sign for positive depths:
     * x2 ~ H x1 with a positive factor on the plane's points */
    double side = 0.0;
    for (int i = 0; i < m; i++) {
        const double a[3] = {p1[2 * i], p1[2 * i + 1], 1.0}, b[3] = {p2[2 * i], p2[2 * i + 1], 1.0};
        double Ha[3];
        sfmi_matvec3(H, a, Ha);
        side += sfmi_dot3(b, Ha);
    }
    const double k = (side < 0.0 ? -1.0 : 1.0) / sqrt(w[1]);
    double Hn[9];
    for (int j = 0; j < 9; j++)
        Hn[j] = k * H[j];
    const double s1 = w[2] / w[1], s3 = w[0] / w[1];
    if (!(s1 - s3 > 1e-12))
        return 0; /* a rotation: no plane, no translation */
    double v1[3], v2[3], v3[3];
    col(V, 2, v1);
    col(V, 1, v2);
    col(V, 0, v3);
    const double a = sqrt(1.0 - s3 > 0.0 ? 1.0 - s3 : 0.0);
    const double b = sqrt(s1 - 1.0 > 0.0 ? s1 - 1.0 : 0.0);
    const double den = sqrt(s1 - s3);
    int out = 0;
    for (int sgn = 0; sgn < 2; sgn++) {
        double u[3], U[9], Wm[9], n[3], Hv2[3], Hu[3], c3[3];
        for (int r = 0; r < 3; r++)
            u[r] = (a * v1[r] + (sgn ? -b : b) * v3[r]) / den;
        sfmi_cross3(v2, u, n);
        sfmi_matvec3(Hn, v2, Hv2);
        sfmi_matvec3(Hn, u, Hu);
        sfmi_cross3(Hv2, Hu, c3);
        for (int r = 0; r < 3; r++) {
            U[3 * r] = v2[r];
            U[3 * r + 1] = u[r];
            U[3 * r + 2] = n[r];
            Wm[3 * r] = Hv2[r];
            Wm[3 * r + 1] = Hu[r];
            Wm[3 * r + 2] = c3[r];
        }
        double *Ro = R[out], *to = t[out];
        for (int r = 0; r < 3; r++)
            for (int c = 0; c < 3; c++)
                Ro[3 * r + c] = Wm[3 * r] * U[3 * c] + Wm[3 * r + 1] * U[3 * c + 1] +
                                Wm[3 * r + 2] * U[3 * c + 2];
        /* the side of the plane the points of image 1 see: n^T x1 > 0 */
        double front = 0.0;
        for (int i = 0; i < m; i++)
            front += n[0] * p1[2 * i] + n[1] * p1[2 * i + 1] + n[2];
        const double s = front < 0.0 ? -1.0 : 1.0;
        double HR[9];
        for (int j = 0; j < 9; j++)
            HR[j] = Hn[j] - Ro[j];
        double sn[3] = {s * n[0], s * n[1], s * n[2]};
        sfmi_matvec3(HR, sn, to);
        double l = sqrt(sfmi_dot3(to, to));
        if (!(l > 1e-12) || !sfmi_all_finite3(to))
            continue;
        for (int r = 0; r < 3; r++)
            to[r] /= l;
        out++;
    }
    return out;
}
