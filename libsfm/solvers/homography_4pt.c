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
 * Each image is taken relative to its first point (H = T2^-1 G T1 with T
 * the translations): q1 becomes the origin (0, 0, 1), adj([q1 q2 q3]) has
 * two rows ending in 0, and G maps the origin to itself.
 * Three collinear points make a triple product vanish: the sample is then
 * degenerate (0 solutions). Points are (u, v) lifted to (u, v, 1).
 *
 * The triple products and the degeneracy test are the same arithmetic for
 * both images; they run in the two lanes of a vector (image 1 in lane 0,
 * image 2 in lane 1) with the GCC/Clang vector extension, which compiles to
 * SSE2 on x86-64, NEON on aarch64 and scalar code where there are no
 * two-lane doubles (Cortex-M7). Lane-wise IEEE operations, so the results
 * are the same bits as the scalar code.
 */
#include <math.h>

#include "core/linalg_util.h"
#include "sfm/sfm_solvers.h"

typedef double v2d __attribute__((vector_size(16)));
typedef long long v2i __attribute__((vector_size(16)));

int sfm_homography_4pt(const double *p1, const double *p2, sfm_mat3 *H)
{
    if (!p1 || !p2 || !H)
        return SFM_E_ARGUMENT;

    /* Differences to the first point: b = q2 - q1, c = q3 - q1, e = q4 - q1.
     * d0 = det[q1 q2 q3] and d_i = that determinant with column i replaced
     * by q4 (d1 by the identity d0 = d1 + d2 + d3). */
    const v2d x0 = {p1[0], p2[0]}, y0 = {p1[1], p2[1]};
    const v2d bx = (v2d){p1[2], p2[2]} - x0, by = (v2d){p1[3], p2[3]} - y0;
    const v2d cx = (v2d){p1[4], p2[4]} - x0, cy = (v2d){p1[5], p2[5]} - y0;
    const v2d ex = (v2d){p1[6], p2[6]} - x0, ey = (v2d){p1[7], p2[7]} - y0;
    const v2d d0 = bx * cy - by * cx;
    const v2d d2 = ex * cy - ey * cx;
    const v2d d3 = bx * ey - by * ex;
    const v2d d1 = d0 - d2 - d3;
    /* A triple is collinear when its determinant is below 1e-12 times the
     * squared spread of the points about q1 (scale invariant). Non-finite
     * input makes the spread NaN or infinite, so the test fails for it too:
     * the finiteness scan then tells the two cases apart at no cost on the
     * common path. */
    const v2d tol = 1e-12 * ((bx * bx + by * by) + (cx * cx + cy * cy) + (ex * ex + ey * ey));
    const v2i mag = {0x7fffffffffffffffLL, 0x7fffffffffffffffLL}; /* fabs */
    const v2i ok = ((v2d)((v2i)d0 & mag) > tol) & ((v2d)((v2i)d1 & mag) > tol) &
                   ((v2d)((v2i)d2 & mag) > tol) & ((v2d)((v2i)d3 & mag) > tol);
    if ((ok[0] & ok[1]) == 0) {
        if (!sfmi_la_all_finite(p1, 8) || !sfmi_la_all_finite(p2, 8))
            return SFM_E_NONFINITE;
        return 0;
    }

    /* Ratios of canonical-frame weights, image 2 over image 1, times the
     * common factor d0(2) / (d0(1) d1(1) d2(1) d3(1)). */
    const double k0 = d1[1] * (d2[0] * d3[0]);
    const double k1 = d2[1] * (d1[0] * d3[0]);
    const double k2 = d3[1] * (d1[0] * d2[0]);
    /* Columns 0 and 1 of the rows of C = diag(k) adj([q1 q2 q3]) (image 1):
     * k0 (by - cy, cx - bx, d0), k1 (cy, -cx, 0), k2 (-by, bx, 0). */
    const v2d A = k1 * (v2d){cy[0], -cx[0]};
    const v2d G = k2 * (v2d){-by[0], bx[0]};
    const v2d K = k0 * ((v2d){by[0], cx[0]} - (v2d){cy[0], bx[0]});
    /* G = [r1 r2 r3] C with r1 = (0, 0, 1), r2 = (bx, by, 1), r3 = (cx, cy, 1)
     * of image 2: rows g0 = (., ., 0), g1 = (., ., 0), g2 = (., ., k0 d0). */
    const v2d g0 = bx[1] * A + cx[1] * G;
    const v2d g1 = by[1] * A + cy[1] * G;
    const v2d g2 = K + A + G;
    /* H = T2^-1 G T1: the last column picks up -(u1 G[:,0] + v1 G[:,1]) of
     * image 1's first point, rows 0 and 1 add (u1', v1') times row 2. */
    const v2d o = {p1[0], p1[1]};
    const v2d t0 = o * g0, t1 = o * g1, t2 = o * g2;
    const double U = p2[0], V = p2[1];
    const double h8 = k0 * d0[0] - (t2[0] + t2[1]);
    const double h2 = U * h8 - (t0[0] + t0[1]);
    const double h5 = V * h8 - (t1[0] + t1[1]);
    const v2d R0 = g0 + U * g2, R1 = g1 + V * g2;
    /* det(H) = d0(2) k0 k1 k2 d0(1)^2, of the sign of d0 d1 d2 d3 of image 2
     * (k0 k1 k2 = d1 d2 d3 (2) times a square). The product's sign bit is
     * exact even when it overflows or underflows to a signed zero. */
    const v2d sg = (d0 * d1) * (d2 * d3);
    const v2d sq = (R0 * R0 + R1 * R1) + g2 * g2;
    double s = ((sq[0] + sq[1]) + (h2 * h2 + h5 * h5)) + h8 * h8;
    if (!(s > 0.0 && s <= 1.7976931348623157e308))
        return 0; /* zero, or overflow of the unnormalized entries */
    s = copysign(1.0 / sqrt(s), sg[1]);
    const v2d S0 = R0 * s, S1 = R1 * s, S2 = g2 * s;
    H->m[0] = S0[0]; H->m[1] = S0[1]; H->m[2] = h2 * s;
    H->m[3] = S1[0]; H->m[4] = S1[1]; H->m[5] = h5 * s;
    H->m[6] = S2[0]; H->m[7] = S2[1]; H->m[8] = h8 * s;
    return 1;
}
