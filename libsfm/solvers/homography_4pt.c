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

/* Triple products of the four points a, b, c, e: d[0] = det[q1 q2 q3] and
 * d[i] = det with column i replaced by q4, all from the differences to a
 * (d[1] by the identity d[0] = d[1] + d[2] + d[3]). Returns 0 when a triple
 * is collinear relative to the squared spread of the points about a. A
 * non-finite coordinate makes the spread NaN or infinite, so the test fails
 * for it too. */
static inline int triples(const double *p, double d[4])
{
    const double bx = p[2] - p[0], by = p[3] - p[1];
    const double cx = p[4] - p[0], cy = p[5] - p[1];
    const double ex = p[6] - p[0], ey = p[7] - p[1];
    d[0] = bx * cy - by * cx;
    d[2] = ex * cy - ey * cx;
    d[3] = bx * ey - by * ex;
    d[1] = d[0] - d[2] - d[3];
    const double tol = 1e-12 * ((bx * bx + by * by) + (cx * cx + cy * cy) + (ex * ex + ey * ey));
    double m0 = fabs(d[0]), m1 = fabs(d[1]), m2 = fabs(d[2]), m3 = fabs(d[3]);
    m0 = m1 < m0 ? m1 : m0;
    m2 = m3 < m2 ? m3 : m2;
    m0 = m2 < m0 ? m2 : m0;
    return m0 > tol;
}

int sfm_homography_4pt(const double *p1, const double *p2, sfm_mat3 *H)
{
    if (!p1 || !p2 || !H)
        return SFM_E_ARGUMENT;
    /* Non-finite input always ends on the degenerate path, which tells the
     * two apart: the finiteness scan costs nothing on the common path. */
    double d1[4], d2[4];
    if (!triples(p2, d2) || !triples(p1, d1)) {
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
    /* H = [r1 r2 r3] C with r_i = (u'_i, v'_i, 1): the last row is a sum.
     * Written out (no arrays) so that everything stays in registers. */
    const double a0 = p2[0], a1 = p2[2], a2 = p2[4], b0 = p2[1], b1 = p2[3], b2 = p2[5];
    const double h0 = a0 * C[0] + a1 * C[3] + a2 * C[6];
    const double h1 = a0 * C[1] + a1 * C[4] + a2 * C[7];
    const double h2 = a0 * C[2] + a1 * C[5] + a2 * C[8];
    const double h3 = b0 * C[0] + b1 * C[3] + b2 * C[6];
    const double h4 = b0 * C[1] + b1 * C[4] + b2 * C[7];
    const double h5 = b0 * C[2] + b1 * C[5] + b2 * C[8];
    const double h6 = C[0] + C[3] + C[6];
    const double h7 = C[1] + C[4] + C[7];
    const double h8 = C[2] + C[5] + C[8];
    /* det(H) = d2[0] k0 k1 k2 d1[0]^2, of the sign of d2[0] d2[1] d2[2] d2[3]
     * (k0 k1 k2 = d2[1] d2[2] d2[3] (d1[1] d1[2] d1[3])^2). The product's sign
     * bit is exact even when it overflows or underflows to a signed zero. */
    const double sgn = (d2[0] * d2[1]) * (d2[2] * d2[3]);
    double s = ((h0 * h0 + h1 * h1) + (h2 * h2 + h3 * h3)) +
               ((h4 * h4 + h5 * h5) + (h6 * h6 + h7 * h7)) + h8 * h8;
    if (!(s > 0.0 && s <= 1.7976931348623157e308))
        return 0; /* zero, or overflow of the unnormalized entries */
    s = copysign(1.0 / sqrt(s), sgn);
    H->m[0] = h0 * s; H->m[1] = h1 * s; H->m[2] = h2 * s;
    H->m[3] = h3 * s; H->m[4] = h4 * s; H->m[5] = h5 * s;
    H->m[6] = h6 * s; H->m[7] = h7 * s; H->m[8] = h8 * s;
    return 1;
}
