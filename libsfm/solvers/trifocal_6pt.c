/*
 * Projective cameras of three views from six point triplets, the minimal
 * problem (Quan, "Invariants of six points and projective reconstruction
 * from three uncalibrated images", PAMI 1995; Hartley & Zisserman, 2nd ed.,
 * sec. 20.2.4 and alg. 20.1, through Carlsson-Weinshall duality).
 *
 * In each view the first four points are sent to the canonical basis e1,
 * e2, e3, (1,1,1) (a homography H_v); in space the first five points are
 * the frame E1..E4, (1,1,1,1) and the sixth is X6 = (p1, p2, p3, p4). A
 * camera that maps E1..E4 to the image basis is
 *   P = [l1 0 0 l4; 0 l2 0 l4; 0 0 l3 l4],
 * and P X = [X1 0 0 X4; 0 X2 0 X4; 0 0 X3 X4] l: the roles of point and
 * camera swap. The three cameras become three dual points l_v seen by two
 * dual cameras, A of X5 = (1,1,1,1) and B of X6, whose images are the
 * transformed points 5 and 6 of each view; E1..E4 are four more dual points
 * imaged at the canonical basis in both. The dual fundamental matrix F
 * (b^T F a = 0) therefore has a zero diagonal (e_i^T F e_i = 0) and entries
 * summing to zero ((1,1,1) F (1,1,1)^T = 0); the three views give three
 * more linear equations, which leaves a pencil g + a h, and
 * det F = F01 F12 F20 + F02 F10 F21 = 0 is a cubic in a: up to three
 * solutions. For each, the epipoles of F give X6 (the centre of A is
 * (1,1,1,-1), imaged by B at (p_i - p4); the centre of B imaged by A is
 * proportional to (p_i - p4) / p_i), and each view's l from its two dual
 * images. Every solution reproduces the six triplets exactly; the cameras
 * are returned in the frame P1 = [I | 0].
 */
#include <math.h>
#include <string.h>

#include "core/linalg_util.h"
#include "solvers/normalize.h"
#include "solvers/small_math.h"
#include "solvers/trifocal_internal.h"
#include "sfm/sfm_poly.h"
#include "sfm/sfm_common.h"

/* Relative size below which a determinant, pivot or null vector counts as
 * zero: the sample is degenerate (three of the first four points collinear
 * in a view, a point on a line of the basis, coincident dual points). */
#define TINY 1e-12

/* Inverse of a 3x3 matrix (sfmi_mat3_inverse); 0 when |det| is below TINY
 * of the product of the column norms (a nearly singular basis). */
static int inv3(const double M[9], double Mi[9])
{
    double n = 1.0;
    for (int c = 0; c < 3; c++)
        n *= M[c] * M[c] + M[3 + c] * M[3 + c] + M[6 + c] * M[6 + c];
    return sfmi_mat3_inverse(M, Mi, TINY * sqrt(n));
}

/* One view: the Hartley similarity N of its six points (sfmi_hartley_2d)
 * and the basis B with B e_i ~ y_i (i < 3) and B (1,1,1) = y_3 for the
 * normalised points y = N x; a5, a6 the points 5 and 6 in that canonical
 * frame (B^-1 y); G = N^-1 B maps the canonical frame to pixels. 0 when the
 * first four points do not form a projective basis. */
static int view_frame(const double *xs, const int *idx, double G[9], double a5[3], double a6[3])
{
    double x[12], t[3];
    for (int k = 0; k < 6; k++) {
        const int i = idx != NULL ? idx[k] : k;
        x[2 * k] = xs[2 * i];
        x[2 * k + 1] = xs[2 * i + 1];
    }
    if (sfmi_hartley_2d(x, 6, t) != 0)
        return 0;
    const double s = t[0], cx = -t[1] / s, cy = -t[2] / s;
    double y[6][3];
    for (int k = 0; k < 6; k++) {
        y[k][0] = s * x[2 * k] + t[1];
        y[k][1] = s * x[2 * k + 1] + t[2];
        y[k][2] = 1.0;
    }
    double M[9], Mi[9], l[3];
    for (int r = 0; r < 3; r++)
        for (int c = 0; c < 3; c++)
            M[3 * r + c] = y[c][r];
    if (!inv3(M, Mi))
        return 0;
    sfmi_matvec3(Mi, y[3], l);
    if (!(fabs(l[0]) > TINY && fabs(l[1]) > TINY && fabs(l[2]) > TINY))
        return 0;
    double B[9], Bi[9];
    for (int r = 0; r < 3; r++)
        for (int c = 0; c < 3; c++)
            B[3 * r + c] = M[3 * r + c] * l[c];
    for (int r = 0; r < 3; r++)
        for (int c = 0; c < 3; c++)
            Bi[3 * r + c] = Mi[3 * r + c] / l[r];
    sfmi_matvec3(Bi, y[4], a5);
    sfmi_matvec3(Bi, y[5], a6);
    /* G = N^-1 B, N^-1 = [1/s 0 cx; 0 1/s cy; 0 0 1] */
    for (int c = 0; c < 3; c++) {
        G[c] = B[c] / s + cx * B[6 + c];
        G[3 + c] = B[3 + c] / s + cy * B[6 + c];
        G[6 + c] = B[6 + c];
    }
    return 1;
}

/* The zero-diagonal F of the six off-diagonal entries f (F01, F02, F10,
 * F12, F20, F21). */
static void full_f(const double f[6], double F[9])
{
    F[0] = 0.0;
    F[1] = f[0];
    F[2] = f[1];
    F[3] = f[2];
    F[4] = 0.0;
    F[5] = f[3];
    F[6] = f[4];
    F[7] = f[5];
    F[8] = 0.0;
}

/* Two vectors spanning the null space of the 4 x 6 matrix A (rows scaled to
 * unit length by the caller), by Gauss-Jordan elimination with full
 * pivoting. 0 when A has rank below 4. */
static int null2(double A[4][6], double g[6], double h[6])
{
    int col[6] = {0, 1, 2, 3, 4, 5};
    for (int k = 0; k < 4; k++) {
        int pr = k, pc = k;
        double best = 0.0;
        for (int r = k; r < 4; r++)
            for (int c = k; c < 6; c++)
                if (fabs(A[r][col[c]]) > best) {
                    best = fabs(A[r][col[c]]);
                    pr = r;
                    pc = c;
                }
        if (!(best > TINY))
            return 0;
        if (pr != k)
            for (int c = 0; c < 6; c++) {
                double t = A[k][c];
                A[k][c] = A[pr][c];
                A[pr][c] = t;
            }
        int t = col[k];
        col[k] = col[pc];
        col[pc] = t;
        const int ck = col[k];
        const double inv = 1.0 / A[k][ck];
        for (int c = 0; c < 6; c++)
            A[k][c] *= inv;
        for (int r = 0; r < 4; r++) {
            if (r == k || A[r][ck] == 0.0)
                continue;
            const double m = A[r][ck];
            for (int c = 0; c < 6; c++)
                A[r][c] -= m * A[k][c];
        }
    }
    /* free columns col[4], col[5]: x_free = e, x_pivot(k) = -A[k][free] */
    double *out[2] = {g, h};
    for (int q = 0; q < 2; q++) {
        double *v = out[q];
        memset(v, 0, 6 * sizeof(double));
        v[col[4 + q]] = 1.0;
        for (int k = 0; k < 4; k++)
            v[col[k]] = -A[k][col[4 + q]];
    }
    return 1;
}

/* det of the zero-diagonal matrix of f. */
static double det_f(const double f[6])
{
    return f[0] * f[3] * f[4] + f[1] * f[2] * f[5];
}

/* Coefficients (descending) of det(g + a h) as a cubic in a. */
static void det_cubic(const double g[6], const double h[6], double c[4])
{
    /* (g0 + a h0)(g3 + a h3)(g4 + a h4) + (g1 + a h1)(g2 + a h2)(g5 + a h5) */
    static const int ix[2][3] = {{0, 3, 4}, {1, 2, 5}};
    c[0] = c[1] = c[2] = c[3] = 0.0;
    for (int t = 0; t < 2; t++) {
        const double g0 = g[ix[t][0]], g1 = g[ix[t][1]], g2 = g[ix[t][2]];
        const double h0 = h[ix[t][0]], h1 = h[ix[t][1]], h2 = h[ix[t][2]];
        c[0] += h0 * h1 * h2;
        c[1] += g0 * h1 * h2 + h0 * g1 * h2 + h0 * h1 * g2;
        c[2] += g0 * g1 * h2 + g0 * h1 * g2 + h0 * g1 * g2;
        c[3] += g0 * g1 * g2;
    }
}

/* One solution: cameras P[3][12] (pixels, the canonical space frame) from
 * the dual F; 0 when a step is degenerate. */
static int cameras_from_dual(const double f[6], double G[3][9], double a5[3][3], double a6[3][3],
                             double P[3][12])
{
    double F[9], eA[3], eB[3], Ft[9];
    full_f(f, F);
    /* eA: F eA = 0; eB: eB^T F = 0 */
    if (!(sfmi_rank2_null3(&F[0], &F[3], &F[6], 1e-6, eA) > 0.0))
        return 0;
    for (int r = 0; r < 3; r++)
        for (int c = 0; c < 3; c++)
            Ft[3 * r + c] = F[3 * c + r];
    if (!(sfmi_rank2_null3(&Ft[0], &Ft[3], &Ft[6], 1e-6, eB) > 0.0))
        return 0;
    /* X6 = (d + m u_i, d): v_i (d + m u_i) - k u_i = 0, u = eB, v = eA */
    double rows[3][3], dmk[3];
    for (int i = 0; i < 3; i++) {
        rows[i][0] = eA[i];
        rows[i][1] = eA[i] * eB[i];
        rows[i][2] = -eB[i];
    }
    if (!(sfmi_rank2_null3(rows[0], rows[1], rows[2], 1e-6, dmk) > 0.0))
        return 0;
    const double p[4] = {dmk[0] + dmk[1] * eB[0], dmk[0] + dmk[1] * eB[1], dmk[0] + dmk[1] * eB[2],
                         dmk[0]};
    for (int v = 0; v < 3; v++) {
        /* A l = s a5, B l = t a6 with l_i = s a5_i - l4:
         * p_i a5_i s + (p4 - p_i) l4 - a6_i t = 0 */
        double q[3][3], n[3];
        for (int i = 0; i < 3; i++) {
            q[i][0] = p[i] * a5[v][i];
            q[i][1] = p[3] - p[i];
            q[i][2] = -a6[v][i];
        }
        if (!(sfmi_rank2_null3(q[0], q[1], q[2], 1e-6, n) > 0.0))
            return 0;
        const double l[4] = {n[0] * a5[v][0] - n[1], n[0] * a5[v][1] - n[1], n[0] * a5[v][2] - n[1],
                             n[1]};
        /* P_v = G_v [l1 0 0 l4; 0 l2 0 l4; 0 0 l3 l4] */
        for (int r = 0; r < 3; r++) {
            for (int c = 0; c < 3; c++)
                P[v][4 * r + c] = G[v][3 * r + c] * l[c];
            P[v][4 * r + 3] = (G[v][3 * r] + G[v][3 * r + 1] + G[v][3 * r + 2]) * l[3];
        }
    }
    return 1;
}

/* P2, P3 of the frame where P1 = [I | 0]: P_v H with H = [M^-1, -M^-1 m;
 * 0, 1] for P1 = [M | m]; each scaled to unit Frobenius norm. */
static int to_first_frame(double P[3][12], double P2[12], double P3[12])
{
    double M[9], Mi[9], m[3], w[3];
    for (int r = 0; r < 3; r++) {
        for (int c = 0; c < 3; c++)
            M[3 * r + c] = P[0][4 * r + c];
        m[r] = P[0][4 * r + 3];
    }
    if (!inv3(M, Mi))
        return 0;
    sfmi_matvec3(Mi, m, w);
    double *out[2] = {P2, P3};
    for (int v = 1; v < 3; v++) {
        double *Q = out[v - 1];
        for (int r = 0; r < 3; r++) {
            const double *pr = &P[v][4 * r];
            for (int c = 0; c < 3; c++)
                Q[4 * r + c] = pr[0] * Mi[c] + pr[1] * Mi[3 + c] + pr[2] * Mi[6 + c];
            Q[4 * r + 3] = pr[3] - (pr[0] * w[0] + pr[1] * w[1] + pr[2] * w[2]);
        }
        if (sfmi_trifocal_normalize(Q, 12) != SFM_OK)
            return 0;
    }
    return 1;
}

int sfmi_trifocal_6pt(const double *x1, const double *x2, const double *x3, const int *idx,
                      double P2[][12], double P3[][12])
{
    const double *x[3] = {x1, x2, x3};
    double G[3][9], a5[3][3], a6[3][3];
    for (int v = 0; v < 3; v++)
        if (!view_frame(x[v], idx, G[v], a5[v], a6[v]))
            return 0;
    /* the dual constraints: a6^T F a5 = 0 per view, and the entries' sum */
    double A[4][6];
    for (int v = 0; v < 3; v++) {
        const double *a = a5[v], *b = a6[v];
        double *r = A[v];
        r[0] = b[0] * a[1];
        r[1] = b[0] * a[2];
        r[2] = b[1] * a[0];
        r[3] = b[1] * a[2];
        r[4] = b[2] * a[0];
        r[5] = b[2] * a[1];
        if (sfmi_trifocal_normalize(r, 6) != SFM_OK)
            return 0;
    }
    for (int c = 0; c < 6; c++)
        A[3][c] = 0.4082482904638631; /* 1 / sqrt 6 */
    double g[6], h[6];
    if (!null2(A, g, h))
        return 0;
    /* orthonormal pencil, then the chart g' + a h' whose leading
     * coefficient det h' is the largest of four directions, so that no
     * solution sits at a = infinity */
    if (sfmi_trifocal_normalize(g, 6) != SFM_OK)
        return 0;
    double gh = 0.0, hh = 0.0;
    for (int c = 0; c < 6; c++)
        gh += g[c] * h[c];
    for (int c = 0; c < 6; c++) {
        h[c] -= gh * g[c];
        hh += h[c] * h[c];
    }
    if (!(hh > TINY) || sfmi_trifocal_normalize(h, 6) != SFM_OK)
        return 0;
    static const double dir[4][2] = {{1.0, 0.0}, {0.0, 1.0}, {0.7071067811865476, 0.7071067811865476},
                                     {0.7071067811865476, -0.7071067811865476}};
    int bestd = 0;
    double bestv = -1.0;
    for (int d = 0; d < 4; d++) {
        double hv[6];
        for (int c = 0; c < 6; c++)
            hv[c] = dir[d][0] * g[c] + dir[d][1] * h[c];
        const double v = fabs(det_f(hv));
        if (v > bestv) {
            bestv = v;
            bestd = d;
        }
    }
    double gp[6], hp[6];
    for (int c = 0; c < 6; c++) {
        hp[c] = dir[bestd][0] * g[c] + dir[bestd][1] * h[c];
        gp[c] = -dir[bestd][1] * g[c] + dir[bestd][0] * h[c];
    }
    double cub[4], roots[3];
    det_cubic(gp, hp, cub);
    int nr = sfm_poly_roots3(cub, roots);
    int out = 0;
    for (int k = 0; k < nr; k++) {
        double f[6], P[3][12];
        for (int c = 0; c < 6; c++)
            f[c] = gp[c] + roots[k] * hp[c];
        if (!cameras_from_dual(f, G, a5, a6, P))
            continue;
        if (!to_first_frame(P, P2[out], P3[out]))
            continue;
        out++;
    }
    return out;
}
