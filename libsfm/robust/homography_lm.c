/*
 * Levenberg-Marquardt on the Sampson error of a homography (Hartley &
 * Zisserman 4.2.6): for y ~ H x the algebraic error of a pair is
 *   e = (y2 u3 - u2, u1 - y1 u3),  u = H (x1, x2, 1),
 * with Jacobian J (2 x 4) in the four coordinates (x1, x2, y1, y2), and the
 * Sampson error is e^T (J J^T)^-1 e, the first-order squared distance of the
 * pair to the variety of H: noise in both images, as the gold standard. The
 * residual is the whitened 2-vector r = L^-1 e with J J^T = L L^T (2 x 2
 * Cholesky), so |r|^2 is the Sampson error.
 *
 * Parameters: the entries of H_n = T2 H T1^-1 in Hartley-normalised
 * coordinates (Hartley 1997), with its largest entry (at the start) held
 * fixed, which fixes the scale and leaves 8 degrees of freedom. Distances
 * stay in pixels: the Jacobian's columns of x and y are scaled by the
 * normalisations' scales s1 and s2 (d x_n / d x = s1).
 *
 * Along entry (k, l) of H_n: du = e_k x_l, de and dJ follow linearly, and
 * for J J^T = [a b; b c], L = [l11 0; l21 l22]:
 *   dl11 = da / (2 l11), dl21 = (db - l21 dl11) / l11,
 *   dl22 = (dc - 2 l21 dl21) / (2 l22),
 *   dr1 = (de1 - r1 dl11) / l11, dr2 = (de2 - dl21 r1 - l21 dr1 - r2 dl22) / l22.
 */
#include "robust/homography_lm.h"

#include <math.h>
#include <string.h>

#include "core/lm.h"
#include "sfm/sfm_common.h"
#include "robust/epipolar.h"
#include "robust/estimator.h"
#include "solvers/normalize.h"

#define NP 8

/* The Sampson pieces of one pair: e, J (rows J1, J2), the Cholesky factor
 * and r. xs, ys: d(coordinate) / d(pixel) in the two images.
 * Returns 0 when J J^T is singular. */
typedef struct hs_pair {
    double u[3], e[2], J1[4], J2[4], l11, l21, l22, r[2];
} hs_pair;

static int sampson_pair(const double *H, const double *x, const double *y, double xs, double ys,
                        hs_pair *P)
{
    const double X[3] = {x[0], x[1], 1.0};
    sfmi_matvec3(H, X, P->u);
    const double *u = P->u;
    P->e[0] = y[1] * u[2] - u[1];
    P->e[1] = u[0] - y[0] * u[2];
    P->J1[0] = xs * (y[1] * H[6] - H[3]);
    P->J1[1] = xs * (y[1] * H[7] - H[4]);
    P->J1[2] = 0.0;
    P->J1[3] = ys * u[2];
    P->J2[0] = xs * (H[0] - y[0] * H[6]);
    P->J2[1] = xs * (H[1] - y[0] * H[7]);
    P->J2[2] = -ys * u[2];
    P->J2[3] = 0.0;
    double a = 0.0, b = 0.0, c = 0.0;
    for (int k = 0; k < 4; k++) {
        a += P->J1[k] * P->J1[k];
        b += P->J1[k] * P->J2[k];
        c += P->J2[k] * P->J2[k];
    }
    if (!(a > 1e-300))
        return 0;
    P->l11 = sqrt(a);
    P->l21 = b / P->l11;
    double d = c - P->l21 * P->l21;
    if (!(d > 1e-300 * (c > 1.0 ? c : 1.0)))
        return 0;
    P->l22 = sqrt(d);
    P->r[0] = P->e[0] / P->l11;
    P->r[1] = (P->e[1] - P->l21 * P->r[0]) / P->l22;
    return 1;
}

/* e^T (J J^T)^-1 e in closed form (the 2 x 2 inverse), for scoring. */
double sfmi_robust_homography_sampson2(const double H[9], const double *x, const double *y)
{
    const double u0 = H[0] * x[0] + H[1] * x[1] + H[2];
    const double u1 = H[3] * x[0] + H[4] * x[1] + H[5];
    const double u2 = H[6] * x[0] + H[7] * x[1] + H[8];
    const double e0 = y[1] * u2 - u1, e1 = u0 - y[0] * u2;
    const double j0 = y[1] * H[6] - H[3], j1 = y[1] * H[7] - H[4];
    const double k0 = H[0] - y[0] * H[6], k1 = H[1] - y[0] * H[7];
    const double w = u2 * u2;
    const double a = j0 * j0 + j1 * j1 + w, b = j0 * k0 + j1 * k1, c = k0 * k0 + k1 * k1 + w;
    const double det = a * c - b * b;
    if (!(det > 1e-300))
        return SFM_ROBUST_HUGE;
    return (c * e0 * e0 - 2.0 * b * e0 * e1 + a * e1 * e1) / det;
}

double sfmi_robust_homography_cost(const double *p1, const double *p2, int n, double scale,
                                  const double H[9])
{
    return sfmi_robust_pair_cost(p1, p2, n, scale, H, sfmi_robust_homography_sampson2);
}

typedef sfmi_homography_problem hnorm;

static void normalise(const hnorm *N, const double *p, const double *q, double *xn, double *yn)
{
    xn[0] = N->t1[0] * p[0] + N->t1[1];
    xn[1] = N->t1[0] * p[1] + N->t1[2];
    yn[0] = N->t2[0] * q[0] + N->t2[1];
    yn[1] = N->t2[0] * q[1] + N->t2[2];
}

/* H_n <- H_n + d on the eight free entries. */
static void entries_plus(const double *x, const double *d, double *out, const void *user)
{
    const hnorm *N = user;
    memcpy(out, x, 9 * sizeof(double));
    for (int p = 0; p < NP; p++)
        out[N->ent[p]] += d[p];
}

/* Residual block i: the whitened Sampson 2-vector of pair i; left out where
 * J J^T is singular. */
static int homography_residual(const void *user, const double *const *x, int i, double *r,
                               double *J)
{
    const hnorm *N = user;
    const double *Hn = x[0];
    const double xs = N->t1[0], ys = N->t2[0];
    double xn[2], yn[2];
    hs_pair P;
    normalise(N, N->p1 + 2 * i, N->p2 + 2 * i, xn, yn);
    if (!sampson_pair(Hn, xn, yn, xs, ys, &P))
        return 0;
    r[0] = P.r[0];
    r[1] = P.r[1];
    if (J == NULL)
        return 1;
    const double X[3] = {xn[0], xn[1], 1.0};
    for (int p = 0; p < NP; p++) {
        const int k = N->ent[p] / 3, l = N->ent[p] % 3;
        double du[3] = {0.0, 0.0, 0.0};
        du[k] = X[l];
        const double de0 = yn[1] * du[2] - du[1], de1 = du[0] - yn[0] * du[2];
        /* dJ: the entries of J that hold H (k, l) */
        double dJ1[4] = {0.0, 0.0, 0.0, ys * du[2]};
        double dJ2[4] = {0.0, 0.0, -ys * du[2], 0.0};
        if (l < 2) {
            if (k == 2) {
                dJ1[l] = xs * yn[1];
                dJ2[l] = -xs * yn[0];
            } else if (k == 1) {
                dJ1[l] = -xs;
            } else {
                dJ2[l] = xs;
            }
        }
        double da = 0.0, db = 0.0, dc = 0.0;
        for (int m = 0; m < 4; m++) {
            da += 2.0 * P.J1[m] * dJ1[m];
            db += P.J1[m] * dJ2[m] + dJ1[m] * P.J2[m];
            dc += 2.0 * P.J2[m] * dJ2[m];
        }
        const double dl11 = da / (2.0 * P.l11);
        const double dl21 = (db - P.l21 * dl11) / P.l11;
        const double dl22 = (dc - 2.0 * P.l21 * dl21) / (2.0 * P.l22);
        const double dr0 = (de0 - P.r[0] * dl11) / P.l11;
        J[p] = dr0;
        J[NP + p] = (de1 - dl21 * P.r[0] - P.l21 * dr0 - P.r[1] * dl22) / P.l22;
    }
    return 1;
}

int sfmi_homography_lm_problem(const double *p1, const double *p2, int n, double scale,
                               const double H[9], sfmi_homography_problem *N)
{
    if (n < 4 || sfmi_hartley_2d(p1, n, N->t1) < 0 || sfmi_hartley_2d(p2, n, N->t2) < 0)
        return -1;
    N->p1 = p1;
    N->p2 = p2;
    /* H_n = T2 H T1^-1 */
    double ti1[3], T1i[9], T2[9], tmp[9];
    double *Hn = N->Hn;
    sfmi_hartley_inverse(N->t1, ti1);
    sfmi_hartley_matrix(ti1, T1i);
    sfmi_hartley_matrix(N->t2, T2);
    sfmi_matmul3(T2, H, tmp);
    sfmi_matmul3(tmp, T1i, Hn);
    if (sfmi_normalize9(Hn) != 0)
        return -1;
    int fixed = 0;
    for (int k = 1; k < 9; k++)
        if (fabs(Hn[k]) > fabs(Hn[fixed]))
            fixed = k;
    for (int k = 0, p = 0; k < 9; k++)
        if (k != fixed)
            N->ent[p++] = k;
    const sfmi_lm_block block = {Hn, 9, SFMI_LM_CUSTOM, NP, entries_plus, N};
    N->block = block;
    const sfmi_lm_problem prob = {&N->block, 1, n, 2, homography_residual, N,
                                  scale > 0.0 ? SFMI_LM_LOSS_CAUCHY : SFMI_LM_LOSS_SQUARED, scale, NULL};
    N->prob = prob;
    return 0;
}

int sfmi_robust_homography_lm(const double *p1, const double *p2, int n, double scale, int iters,
                             double H[9])
{
    hnorm N;
    if (sfmi_homography_lm_problem(p1, p2, n, scale, H, &N) < 0)
        return -1;
    double ws[SFMI_LM_DENSE_WS_DOUBLES(9, NP, 2)];
    int st = sfmi_lm_refine(&N.prob, iters, 1e-6, ws, sizeof ws);
    if (st != 0)
        return st;
    /* H = T2^-1 H_n T1 */
    double ti2[3], T2i[9], T1[9], Hp[9], tmp[9];
    sfmi_hartley_inverse(N.t2, ti2);
    sfmi_hartley_matrix(ti2, T2i);
    sfmi_hartley_matrix(N.t1, T1);
    sfmi_matmul3(T2i, N.Hn, tmp);
    sfmi_matmul3(tmp, T1, Hp);
    if (sfmi_normalize9(Hp) != 0 || !sfmi_all_finite9(Hp))
        return -1;
    memcpy(H, Hp, sizeof Hp);
    return 0;
}
