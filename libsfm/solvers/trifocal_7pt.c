/*
 * Trifocal tensor from n >= 7 point triplets: Hartley & Zisserman, 2nd ed.,
 * alg. 16.2 (normalized linear solution, then algebraic minimization with
 * fixed epipoles: one pass, as the algorithm states; iterating on the
 * epipoles changed no test outcome and tripled the cost). Each triplet gives
 * the four equations
 *   sum_{i,q,r} x^i [x']_x[s][q] [x'']_x[r][t] T_i^{qr} = 0,   s, t in {0, 1}
 * (rows 0 and 1 of a skew matrix of a point with third coordinate 1 are
 * independent). The 4n x 27 design matrix is never stored: blocks of rows are
 * folded into a 27x27 triangular factor by Householder QR, which has the same
 * singular values and right singular vectors. The null vectors of the
 * triangular factors come from inverse iteration (core/tri_null.h), with the
 * SVD kept for samples where it does not settle.
 */
#include <math.h>
#include <string.h>

#include "core/linalg_util.h"
#include "core/arena.h"
#include "core/tri_null.h"
#include "sfm/sfm_linalg.h"
#include "sfm/sfm_rotation.h"
#include "sfm/sfm_solvers.h"
#include "solvers/normalize.h"
#include "solvers/small_math.h"
#include "sfm/sfm_trifocal.h"
#include "solvers/trifocal_internal.h"

enum { NU = 27, BLOCK = 16, ROWS = NU + 4 * BLOCK, ALG_ITERS = 1 };
/* the algebraic step's basis: 5 vectors for each of the 3 blocks */
enum { NB = 5, NA = 3 * NB };

typedef struct tf_ws {
    double *buf;  /* ROWS x 27: running R on top, new rows below */
    double *tau;  /* 27 */
    double *R;    /* 27 x 27 reduced design matrix */
    double *V;    /* 27 x 27 */
    double *S;    /* 27 */
    double *M;    /* 27 x 15 of the algebraic step, reduced to 15 x 15 */
    void *svd;    /* SVD scratch for up to 27 x 27, when inverse iteration
                     does not settle */
    size_t svd_size;
} tf_ws;

static void tf_layout(sfmi_arena *a, tf_ws *w)
{
    w->buf = SFM_ARENA_ARRAY(a, double, ROWS * NU);
    w->tau = SFM_ARENA_ARRAY(a, double, NU);
    w->R = SFM_ARENA_ARRAY(a, double, NU * NU);
    w->V = SFM_ARENA_ARRAY(a, double, NU * NU);
    w->S = SFM_ARENA_ARRAY(a, double, NU);
    w->M = SFM_ARENA_ARRAY(a, double, NU * NA);
    w->svd_size = sfm_svd_workspace_size(NU, NU);
    w->svd = sfmi_arena_alloc(a, w->svd_size);
}

size_t sfm_trifocal_7pt_workspace_size(void)
{
    sfmi_arena a;
    tf_ws w;
    sfmi_arena_measure(&a);
    tf_layout(&a, &w);
    return sfmi_arena_required(&a);
}

/* The normalizing similarity of one view as a matrix (shared Hartley
 * normalization of the solvers). */
static int normalizer(const double *x, int n, double H[9])
{
    double t[3];
    if (sfmi_hartley_2d(x, n, t) != 0)
        return SFM_E_SINGULAR;
    sfmi_hartley_matrix(t, H);
    return SFM_OK;
}

static void apply(const double H[9], const double *x, double p[3])
{
    p[0] = H[0] * x[0] + H[2];
    p[1] = H[4] * x[1] + H[5];
    p[2] = 1.0;
}

/* Folds the rows buf[NU .. rows) into the triangular factor held in the
 * first NU rows; returns the new row count (NU). */
static int fold(tf_ws *w, int rows)
{
    sfm_qr_factor(w->buf, rows, NU, w->tau);
    for (int r = 0; r < NU; r++)
        for (int c = 0; c < r; c++)
            w->buf[r * NU + c] = 0.0;
    return NU;
}

/* Right singular vector of the smallest singular value of A (m x n), by the
 * SVD. */
static int smallest_right(tf_ws *w, const double *A, int m, int n, double *v)
{
    int st = sfm_svd(A, m, n, NULL, w->S, w->V, w->svd, w->svd_size);
    if (st < 0)
        return st;
    for (int r = 0; r < n; r++)
        v[r] = w->V[r * n + (n - 1)];
    return SFM_OK;
}

/* The same for an n x n upper triangular A whose strict lower part is zero:
 * inverse iteration, and the SVD only when that does not settle (the two
 * smallest singular values too close). */
static int smallest_right_tri(tf_ws *w, const double *A, int n, double *v)
{
    double scratch[4 * NU];
    if (sfmi_la_tri_smallest_right(A, n, v, scratch))
        return SFM_OK;
    return smallest_right(w, A, n, n, v);
}

/* An orthonormal pair completing the unit vector e to a basis of R^3. */
static void complete_basis(const double e[3], double p[3], double q[3])
{
    int a = 0; /* the axis least aligned with e */
    for (int k = 1; k < 3; k++)
        if (fabs(e[k]) < fabs(e[a]))
            a = k;
    double ax[3] = {0, 0, 0};
    ax[a] = 1.0;
    sfmi_cross3(e, ax, p);
    double s = 1.0 / sqrt(p[0] * p[0] + p[1] * p[1] + p[2] * p[2]);
    for (int k = 0; k < 3; k++)
        p[k] *= s;
    sfmi_cross3(e, p, q);
}

/* Algebraic minimization with the epipoles of t held fixed: t = E a with
 * T_i^{jk} = a_i^j e''^k - e'^j b_i^k, minimize |R E a| subject to |E a| = 1.
 * t is replaced by the minimizer. The columns of E span, for each i, the
 * 9-vectors x (x) e'' and e' (x) y (Kronecker products over j, k): with unit
 * epipoles completed to orthonormal bases {e', p', q'}, {e'', p'', q''},
 * that span has the orthonormal basis e' (x) e'', p' (x) e'', q' (x) e'',
 * e' (x) p'', e' (x) q'' (the two 3-dimensional spans meet in e' (x) e'',
 * so E has rank 5 per i and 15 in all for any nonzero epipoles). The
 * problem becomes the smallest right singular vector of R U (27 x 15), U
 * that basis, with t = U y. e2, e3 receive the epipoles held, which are
 * those of the new t. */
static int algebraic_step(tf_ws *w, double t[NU], double e2[3], double e3[3])
{
    int st = sfm_trifocal_epipoles(t, e2, e3);
    if (st < 0)
        return st;
    double p2[3], q2[3], p3[3], q3[3];
    complete_basis(e2, p2, q2);
    complete_basis(e3, p3, q3);
    const double *X[NB] = {e2, p2, q2, e2, e2};
    const double *Y[NB] = {e3, e3, e3, p3, q3};
    double B[NB][9]; /* the basis of one i-block, B[b][j*3+k] = X_b[j] Y_b[k] */
    for (int b = 0; b < NB; b++)
        for (int j = 0; j < 3; j++)
            for (int k = 0; k < 3; k++)
                B[b][j * 3 + k] = X[b][j] * Y[b][k];
    /* M = R U (27 x 15); U is block diagonal and R upper triangular. */
    double *M = w->M;
    for (int a = 0; a < NU; a++)
        for (int i = 0; i < 3; i++)
            for (int b = 0; b < NB; b++) {
                double s = 0;
                for (int c = 0; c < 9; c++) {
                    int k = i * 9 + c;
                    if (k >= a)
                        s += w->R[a * NU + k] * B[b][c];
                }
                M[a * NA + i * NB + b] = s;
            }
    /* M = Q R2: the same right singular vectors as the 15 x 15 R2. */
    st = sfm_qr_factor(M, NU, NA, w->tau);
    if (st < 0)
        return st;
    for (int r = 0; r < NA; r++)
        for (int c = 0; c < r; c++)
            M[r * NA + c] = 0.0;
    double y[NA];
    st = smallest_right_tri(w, M, NA, y);
    if (st < 0)
        return st;
    for (int i = 0; i < 3; i++)
        for (int c = 0; c < 9; c++) {
            double s = 0;
            for (int b = 0; b < NB; b++)
                s += B[b][c] * y[i * NB + b];
            t[i * 9 + c] = s;
        }
    return sfmi_trifocal_normalize(t, NU);
}

/* Transfer error of x2 ~ H x1, squared. */
static double transfer2(const double H[9], const double *a, const double *b)
{
    double w = H[6] * a[0] + H[7] * a[1] + H[8];
    double u = (H[0] * a[0] + H[1] * a[1] + H[2]) / w - b[0];
    double v = (H[3] * a[0] + H[4] * a[1] + H[5]) / w - b[1];
    return u * u + v * v;
}

/* An exactly degenerate configuration: every point on one image line in a
 * view (3D points on one line), or views 1 -> 2 and 1 -> 3 each related by
 * one homography (3D points on one plane): the linear system then has more
 * than one null vector and no tensor is determined. The test is to rounding
 * (1e-9 of the points' spread); near-degenerate supports are what the
 * robust estimators' support checks judge. H1, H2, H3: the views'
 * normalisers (Hartley). */
static int degenerate_points(const double *x1, const double *x2, const double *x3, int n,
                             const double *H1, const double *H2, const double *H3)
{
    const double *x[3] = {x1, x2, x3}, *H[3] = {H1, H2, H3};
    for (int v = 0; v < 3; v++) {
        double sxx = 0, sxy = 0, syy = 0;
        for (int p = 0; p < n; p++) {
            double q[3];
            apply(H[v], &x[v][2 * p], q);
            sxx += q[0] * q[0];
            sxy += q[0] * q[1];
            syy += q[1] * q[1];
        }
        /* centred already; the smaller eigenvalue of the scatter per point */
        double tr = 0.5 * (sxx + syy), d = sqrt(0.25 * (sxx - syy) * (sxx - syy) + sxy * sxy);
        if (!((tr - d) / n > 1e-18))
            return 1;
    }
    sfm_mat3 G2, G3;
    if (sfm_homography_4pt(x1, x2, &G2) != 1 || sfm_homography_4pt(x1, x3, &G3) != 1)
        return 0; /* three of the first four collinear: no plane test, not needed */
    const double s2 = 1.0 / (H2[0] * H2[0]), s3 = 1.0 / (H3[0] * H3[0]);
    for (int p = 4; p < n; p++)
        if (!(transfer2(G2.m, &x1[2 * p], &x2[2 * p]) < 1e-18 * s2) ||
            !(transfer2(G3.m, &x1[2 * p], &x3[2 * p]) < 1e-18 * s3))
            return 0;
    return 1;
}

/* Unit epipole of the denormalised tensor from the normalised one: points
 * map back by H^-1; the sign as sfm_trifocal_epipoles gives it. */
static int denormalize_epipole(const double H[9], const double eh[3], double e[3])
{
    e[0] = (eh[0] - H[2] * eh[2]) / H[0];
    e[1] = (eh[1] - H[5] * eh[2]) / H[4];
    e[2] = eh[2];
    if (sfmi_trifocal_normalize(e, 3) != SFM_OK)
        return SFM_E_SINGULAR;
    int m = 0;
    for (int k = 1; k < 3; k++)
        if (fabs(e[k]) > fabs(e[m]))
            m = k;
    if (e[m] < 0)
        for (int k = 0; k < 3; k++)
            e[k] = -e[k];
    return SFM_OK;
}

int sfm_trifocal_7pt(const double *x1, const double *x2, const double *x3, int n, double T[27],
                     void *ws, size_t ws_size)
{
    double e2[3], e3[3];
    return sfmi_trifocal_7pt_epipoles(x1, x2, x3, n, T, e2, e3, ws, ws_size);
}

int sfmi_trifocal_7pt_epipoles(const double *x1, const double *x2, const double *x3, int n,
                               double T[27], double e2[3], double e3[3], void *ws, size_t ws_size)
{
    if (x1 == NULL || x2 == NULL || x3 == NULL || T == NULL || ws == NULL ||
        n < SFM_TRIFOCAL_MIN_POINTS)
        return SFM_E_ARGUMENT;
    if (!sfmi_la_all_finite(x1, 2 * n) || !sfmi_la_all_finite(x2, 2 * n) || !sfmi_la_all_finite(x3, 2 * n))
        return SFM_E_NONFINITE;
    sfmi_arena a;
    tf_ws w;
    sfmi_arena_init(&a, ws, ws_size);
    tf_layout(&a, &w);
    if (!sfmi_arena_ok(&a))
        return SFM_E_WORKSPACE;

    double H1[9], H2[9], H3[9];
    if (normalizer(x1, n, H1) < 0 || normalizer(x2, n, H2) < 0 || normalizer(x3, n, H3) < 0)
        return SFM_E_SINGULAR;
    if (degenerate_points(x1, x2, x3, n, H1, H2, H3))
        return SFM_E_SINGULAR;

    int rows = 0;
    for (int p = 0; p < n; p++) {
        double u[3], v[3], q[3], Sv[9], Sq[9];
        apply(H1, &x1[2 * p], u);
        apply(H2, &x2[2 * p], v);
        apply(H3, &x3[2 * p], q);
        sfm_skew(v, Sv);
        sfm_skew(q, Sq);
        if (rows + 4 > ROWS)
            rows = fold(&w, rows);
        for (int s = 0; s < 2; s++)
            for (int tt = 0; tt < 2; tt++) {
                double *row = &w.buf[rows * NU];
                for (int i = 0; i < 3; i++)
                    for (int j = 0; j < 3; j++)
                        for (int k = 0; k < 3; k++)
                            row[i * 9 + j * 3 + k] = u[i] * Sv[s * 3 + j] * Sq[k * 3 + tt];
                rows++;
            }
    }
    if (rows < NU) /* cannot happen for n >= 7 (28 rows); kept as invariant */
        return SFM_E_SINGULAR;
    fold(&w, rows);
    for (int r = 0; r < NU; r++)
        for (int c = 0; c < NU; c++)
            w.R[r * NU + c] = w.buf[r * NU + c];

    double t[NU];
    int st = smallest_right_tri(&w, w.R, NU, t);
    if (st < 0)
        return st;
    double eh2[3], eh3[3];
    for (int it = 0; it < ALG_ITERS; it++) {
        double prev[NU];
        memcpy(prev, t, sizeof t);
        st = algebraic_step(&w, t, eh2, eh3);
        if (st < 0)
            return st;
        double dp = 0, dm = 0;
        for (int k = 0; k < NU; k++) {
            dp += (t[k] - prev[k]) * (t[k] - prev[k]);
            dm += (t[k] + prev[k]) * (t[k] + prev[k]);
        }
        if ((dp < dm ? dp : dm) < 1e-24)
            break;
    }

    /* Denormalize: T_i^{jk} = H1[r][i] H2^-1[j][s] H3^-1[k][t] That_r^{st}. */
    double H2i[9] = {1 / H2[0], 0, -H2[2] / H2[0], 0, 1 / H2[4], -H2[5] / H2[4], 0, 0, 1};
    double H3i[9] = {1 / H3[0], 0, -H3[2] / H3[0], 0, 1 / H3[4], -H3[5] / H3[4], 0, 0, 1};
    double tmp1[NU], tmp2[NU], out[NU];
    for (int r = 0; r < 3; r++) /* contract k with H3^-1 */
        for (int s = 0; s < 3; s++)
            for (int k = 0; k < 3; k++) {
                double acc = 0;
                for (int q = 0; q < 3; q++)
                    acc += H3i[k * 3 + q] * t[r * 9 + s * 3 + q];
                tmp1[r * 9 + s * 3 + k] = acc;
            }
    for (int r = 0; r < 3; r++) /* contract j with H2^-1 */
        for (int j = 0; j < 3; j++)
            for (int k = 0; k < 3; k++) {
                double acc = 0;
                for (int s = 0; s < 3; s++)
                    acc += H2i[j * 3 + s] * tmp1[r * 9 + s * 3 + k];
                tmp2[r * 9 + j * 3 + k] = acc;
            }
    for (int i = 0; i < 3; i++) /* contract i with H1 */
        for (int j = 0; j < 3; j++)
            for (int k = 0; k < 3; k++) {
                double acc = 0;
                for (int r = 0; r < 3; r++)
                    acc += H1[r * 3 + i] * tmp2[r * 9 + j * 3 + k];
                out[i * 9 + j * 3 + k] = acc;
            }
    if (sfmi_trifocal_normalize(out, NU) != SFM_OK || !sfmi_la_all_finite(out, NU))
        return SFM_E_SINGULAR;
    double f2[3], f3[3];
    if (denormalize_epipole(H2, eh2, f2) != SFM_OK || denormalize_epipole(H3, eh3, f3) != SFM_OK)
        return SFM_E_SINGULAR;
    memcpy(e2, f2, sizeof f2);
    memcpy(e3, f3, sizeof f3);
    int m = 0;
    for (int k = 1; k < NU; k++)
        if (fabs(out[k]) > fabs(out[m]))
            m = k;
    double sgn = out[m] < 0 ? -1.0 : 1.0;
    for (int k = 0; k < NU; k++)
        T[k] = sgn * out[k];
    return SFM_OK;
}
