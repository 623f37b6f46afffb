/*
 * Homography from four point pairs by the projective-basis construction
 * (Hartley & Zisserman, "Multiple View Geometry", 2nd ed., sec. 4.1 and
 * exercise 4.2; Heckbert 1989): the matrix M = [q1 q2 q3] diag(lambda) with
 * lambda = [q1 q2 q3]^-1 q4 maps the canonical frame e1, e2, e3, (1,1,1) to
 * the four homogeneous points q_i. Then H = M2 M1^-1. Written with adjugates
 * the scale factors are triple products of the points, so no division is
 * needed until the final normalization:
 *     mu_i = det of [q1 q2 q3] with column i replaced by q4,
 *     H ~ [r1 r2 r3] diag(mu2_i * mu1_j * mu1_k) adj([q1 q2 q3]).
 * Three collinear points make a triple product vanish: the sample is then
 * degenerate (0 solutions). Points are (u, v) lifted to (u, v, 1).
 */
#include <math.h>

#include "core/linalg_util.h"
#include "sfm/sfm_solvers.h"
#include "solvers/normalize.h"

/* Twice the signed area of triangle (a, b, c). */
static double tri(const double *a, const double *b, const double *c)
{
    return (b[0] - a[0]) * (c[1] - a[1]) - (b[1] - a[1]) * (c[0] - a[0]);
}

/* Triple products of the four points: d[0] = det[q1 q2 q3] and d[i] =
 * det with column i replaced by q4. Returns 0 when a triple is collinear
 * relative to the squared spread of the points. */
static inline int triples(const double *p, double d[4])
{
    const double *a = p, *b = p + 2, *c = p + 4, *e = p + 6;
    d[0] = tri(a, b, c);
    d[1] = tri(e, b, c);
    d[2] = tri(a, e, c);
    d[3] = tri(a, b, e);
    double s = 0.0;
    for (int i = 1; i < 4; i++) {
        double dx = p[2 * i] - p[0], dy = p[2 * i + 1] - p[1];
        s += dx * dx + dy * dy;
    }
    double tol = 1e-12 * s;
    return fabs(d[0]) > tol && fabs(d[1]) > tol && fabs(d[2]) > tol && fabs(d[3]) > tol;
}

int sfm_homography_4pt(const double *p1, const double *p2, sfm_mat3 *H)
{
    if (!p1 || !p2 || !H)
        return SFM_E_ARGUMENT;
    /* Non-finite input makes a triple product NaN or the tolerance infinite,
     * so it always ends on the degenerate path, which tells the two apart:
     * the finiteness scan costs nothing on the common path. */
    double d1[4], d2[4];
    if (!triples(p1, d1) || !triples(p2, d2)) {
        if (!sfm_la_all_finite(p1, 8) || !sfm_la_all_finite(p2, 8))
            return SFM_E_NONFINITE;
        return 0;
    }

    /* Rows of adj([q1 q2 q3]) for q_i = (u_i, v_i, 1), each scaled by the
     * ratio of canonical-frame weights k_i (image 2 over image 1, times a
     * common factor): C = diag(k) adj(M1). */
    const double u0 = p1[0], v0 = p1[1], u1 = p1[2], v1 = p1[3], u2 = p1[4], v2 = p1[5];
    const double k0 = d2[1] * d1[2] * d1[3];
    const double k1 = d2[2] * d1[1] * d1[3];
    const double k2 = d2[3] * d1[1] * d1[2];
    const double C[9] = {
        k0 * (v1 - v2), k0 * (u2 - u1), k0 * (u1 * v2 - u2 * v1), /* q2 x q3 */
        k1 * (v2 - v0), k1 * (u0 - u2), k1 * (u2 * v0 - u0 * v2), /* q3 x q1 */
        k2 * (v0 - v1), k2 * (u1 - u0), k2 * (u0 * v1 - u1 * v0), /* q1 x q2 */
    };
    /* H = [r1 r2 r3] C with r_i = (u'_i, v'_i, 1): the last row is a sum. */
    double h[9];
    for (int c = 0; c < 3; c++) {
        h[c] = p2[0] * C[c] + p2[2] * C[3 + c] + p2[4] * C[6 + c];
        h[3 + c] = p2[1] * C[c] + p2[3] * C[3 + c] + p2[5] * C[6 + c];
        h[6 + c] = C[c] + C[3 + c] + C[6 + c];
    }
    /* det(H) = det[r1 r2 r3] k0 k1 k2 det(M1)^2 = d2[0] k0 k1 k2 d1[0]^2:
     * its sign without forming the product (which could overflow). */
    int neg = (d2[0] < 0.0) ^ (k0 < 0.0) ^ (k1 < 0.0) ^ (k2 < 0.0);
    double s = 0.0;
    for (int i = 0; i < 9; i++)
        s += h[i] * h[i];
    if (!(s > 0.0) || !isfinite(s))
        return 0;
    s = 1.0 / sqrt(s);
    if (neg)
        s = -s;
    for (int i = 0; i < 9; i++)
        H->m[i] = h[i] * s;
    return 1;
}
