/*
 * Trifocal tensor from n >= 7 point triplets: Hartley & Zisserman, 2nd ed.,
 * alg. 16.2 (normalized linear solution, then algebraic minimization with
 * fixed epipoles: one pass, as the algorithm states; iterating on the
 * epipoles changed no test outcome and tripled the cost). Each triplet gives
 * the four equations
 *   sum_{i,q,r} x^i [x']_x[s][q] [x'']_x[r][t] T_i^{qr} = 0,   s, t in {0, 1}
 * (rows 0 and 1 of a skew matrix of a point with third coordinate 1 are
 * independent). The 4n x 27 design matrix A is never stored: each row is a
 * Kronecker product x (x) a_s (x) b_t (a_s row s of [x']_x, b_t column t of
 * [x'']_x), so a triplet's four rows add to A^T A the product
 * (x x^T) (x) (sum_s a_s a_s^T) (x) (sum_t b_t b_t^T), about a quarter of
 * the work of folding the rows into a triangular factor by QR (the same
 * holds for the algebraic step's U^T A^T A U). The Cholesky factor R of
 * A^T A as formed (pivots floored at rounding) has A's right singular
 * vectors up to that rounding; the null vectors come from inverse iteration
 * on R (core/tri_null.h), with the SVD of R kept for samples where it does
 * not settle. Forming A^T A squares the condition number: the null vector
 * carries an error of about eps (s_1 / s_26)^2 (1e-6 at worst over 1000
 * noise-free minimal problems, 1e-11 from a QR of A), which one Newton step
 * with A^T A applied through the rows (gram_apply, correct_null) brings down
 * to 3e-10 (2.4e-9 at the tolerances below); the algebraic step, whose
 * vector the linear one's epipoles constrain, needs none (measured: the
 * same worst error with or without). Minimal samples of
 * real triplets leave the smallest singular values close (s_27 / s_26 0.25
 * at the median over random samples of a Herz-Jesu-P8 triplet), so the
 * inverse iteration stops at the tolerances below, well inside the noise,
 * rather than at rounding.
 */
#include <float.h>
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

enum { NU = 27 };
/* Inverse-iteration tolerances (core/tri_null.h) of the linear solution
 * (followed by the correction step, which takes most of what is left out)
 * and of the algebraic step. Against 1e-13 for both: 19 % fewer
 * instructions per minimal sample of a Herz-Jesu-P8 triplet, noise-free
 * tensors within 2.4e-9 at worst over 1000 minimal problems (3e-10 at
 * 1e-13), tensors of real samples that differ by 1e-11 on average. */
#define TOL_LIN 1e-6
#define TOL_ALG 1e-10
/* the algebraic step's basis: 5 vectors for each of the 3 blocks */
enum { NB = 5, NA = 3 * NB };

typedef struct tf_ws {
    double *R;    /* 27 x 27: A^T A (upper triangle, the lower part zero),
                     then its Cholesky factor */
    double *V;    /* 27 x 27 */
    double *S;    /* 27 */
    double *M;    /* 15 x 15: U^T A^T A U of the algebraic step, then its
                     factor */
    void *svd;    /* SVD scratch for up to 27 x 27, when inverse iteration
                     does not settle */
    size_t svd_size;
} tf_ws;

static void tf_layout(sfmi_arena *a, tf_ws *w)
{
    w->R = SFM_ARENA_ARRAY(a, double, NU * NU);
    w->V = SFM_ARENA_ARRAY(a, double, NU * NU);
    w->S = SFM_ARENA_ARRAY(a, double, NU);
    w->M = SFM_ARENA_ARRAY(a, double, NA * NA);
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

/* y[j] += f x[j] for j < m. Four entries a pass where the build is for
 * speed (the same operations, so the same bits, as the plain loop of a
 * build for size). */
static inline void axpy(double *y, double f, const double *x, int m)
{
    int j = 0;
#if !defined(__OPTIMIZE_SIZE__)
    for (; j + 4 <= m; j += 4) {
        y[j] += f * x[j];
        y[j + 1] += f * x[j + 1];
        y[j + 2] += f * x[j + 2];
        y[j + 3] += f * x[j + 3];
    }
#endif
    for (; j < m; j++)
        y[j] += f * x[j];
}

/* The factors of triplet p's four rows (see the top): its normalised view-1
 * point u, Sa = [v]x with its last row zeroed (rows a_0, a_1) and
 * Sb = [q]x with its last column zeroed (columns b_0, b_1), v and q the
 * normalised points of views 2 and 3; with Av, Bq (may be NULL) the 3 x 3
 * sums Sa^T Sa = a_0 a_0^T + a_1 a_1^T and Sb Sb^T = b_0 b_0^T + b_1 b_1^T. */
typedef struct tf_norm {
    const double *x[3];
    double H[3][9];
} tf_norm;

typedef struct tf_rows {
    double u[3], Sa[9], Sb[9];
} tf_rows;

static void triplet_factors(const tf_norm *d, int p, tf_rows *f, double Av[9], double Bq[9])
{
    double v[3], q[3];
    apply(d->H[0], &d->x[0][2 * p], f->u);
    apply(d->H[1], &d->x[1][2 * p], v);
    apply(d->H[2], &d->x[2][2 * p], q);
    sfm_skew(v, f->Sa);
    sfm_skew(q, f->Sb);
    for (int k = 0; k < 3; k++) {
        f->Sa[6 + k] = 0.0;
        f->Sb[3 * k + 2] = 0.0;
    }
    if (Av == NULL)
        return;
    sfmi_matmul3_tn(f->Sa, f->Sa, Av);
    sfmi_matmul3_nt(f->Sb, f->Sb, Bq);
}

/* g = A^T A t, from the triplets' factors: the four rows of triplet p times
 * t are the upper-left 2 x 2 block of Sa (sum_i u_i T_i) Sb, and A^T maps
 * that block Q to u (x) Sa^T Q Sb^T. With the rows' own rounding only,
 * unlike A^T A formed: the product the correction step (correct_null)
 * needs. */
static void gram_apply(const tf_norm *d, int n, const double t[NU], double g[NU])
{
    memset(g, 0, sizeof(double) * NU);
    for (int p = 0; p < n; p++) {
        tf_rows f;
        triplet_factors(d, p, &f, NULL, NULL);
        double Q[9];
        for (int c = 0; c < 9; c++)
            Q[c] = f.u[0] * t[c] + f.u[1] * t[9 + c] + f.u[2] * t[18 + c];
        sfmi_matmul3(f.Sa, Q, Q);
        sfmi_matmul3(Q, f.Sb, Q);
        sfmi_matmul3_tn(f.Sa, Q, Q);
        sfmi_matmul3_nt(Q, f.Sb, Q);
        for (int i = 0; i < 3; i++)
            axpy(g + 9 * i, f.u[i], Q, 9);
    }
}

/* One correction of the unit vector y (m entries) that inverse iteration on
 * R (R^T R the Gram matrix G as formed, m x m) left, given g = G y computed
 * without forming G (gram_apply), and R's reciprocal pivots dinv
 * (smallest_right_tri; dinv[0] = 0, after an SVD: no correction):
 * y <- y - P (R^T R)^-1 P g, P the
 * projection off y, renormalised: a Newton step on the Rayleigh quotient
 * with R^T R in place of G. It takes out the error that forming G left in
 * y (of order eps (s_1 / s_{m-1})^2) down to the accuracy of the rows
 * themselves, and shrinks the rest as one inverse-iteration step would. */
static void correct_null(const double *R, int m, const double *dinv, const double *g, double *y)
{
    double h[NU], z[NU], rho = 0.0, c = 0.0;
    if (dinv[0] == 0.0)
        return;
    for (int k = 0; k < m; k++)
        rho += y[k] * g[k];
    for (int k = 0; k < m; k++)
        h[k] = g[k] - rho * y[k];
    sfmi_la_tri_gram_solve(R, m, dinv, h);
    for (int k = 0; k < m; k++)
        c += h[k] * y[k];
    for (int k = 0; k < m; k++)
        z[k] = y[k] - (h[k] - c * y[k]);
    if (sfmi_trifocal_normalize(z, m) == SFM_OK)
        memcpy(y, z, sizeof(double) * (size_t)m);
}

/* E^T S E for the 3 x 3 S and E of the columns e[0], e[1], e[2]. */
static void congruence3(const double S[9], const double *const e[3], double out[9])
{
    double E[9];
    for (int k = 0; k < 9; k++)
        E[k] = e[k % 3][k / 3];
    sfmi_matmul3(S, E, out);
    sfmi_matmul3_tn(E, out, out);
}

/* Sums of Kronecker products (u u^T) (x) W over the triplets, u u^T and W
 * symmetric (W bs x bs), kept per distinct entry: acc[a][w] += (u u^T)_a
 * W_w over the 6 entries a of u u^T on and above its diagonal and the
 * bs (bs + 1) / 2 entries w of W (Wp, packed row by row), so a triplet
 * costs one product per distinct entry of the sum (270 for the 27 x 27
 * Gram matrix, against 378 on its upper triangle); kron_unpack writes the
 * upper triangle of the sum once, with the same bits. */
static void kron_pack(double *acc, int nw, const double u[3], const double *Wp)
{
    for (int i = 0, a = 0; i < 3; i++)
        for (int i2 = i; i2 < 3; i2++, a++)
            axpy(acc + a * nw, u[i] * u[i2], Wp, nw);
}

static void kron_unpack(double *dst, int ld, int bs, const double *acc)
{
    for (int i = 0; i < 3; i++)
        for (int i2 = i; i2 < 3; i2++)
            for (int c = 0; c < bs; c++)
                for (int c2 = c; c2 < bs; c2++) {
                    const double v = *acc++;
                    dst[(i * bs + c) * ld + i2 * bs + c2] = v;
                    if (i2 > i) /* W symmetric: the entry (c2, c) of the block too */
                        dst[(i * bs + c2) * ld + i2 * bs + c] = v;
                }
}

/* In place: the upper triangle of the symmetric positive semi-definite
 * n x n G (row-major; the strict lower part zero and not read) becomes R,
 * upper triangular with R^T R = G. A pivot at or below eps times G's
 * largest diagonal entry (G singular to rounding: the null vector sought) is
 * raised to it, as the inverse iteration floors R's pivots. Row by row, each
 * entry G_kj less the products R_pk R_pj of the rows above in the order of p
 * (the sequence of updates a right-looking elimination applies to it, so
 * the same bits), then scaled: the sum stays in a register. */
static void gram_factor(double *G, int n)
{
    double dmax = 0.0;
    for (int k = 0; k < n; k++)
        dmax = fmax(dmax, G[k * n + k]);
    const double floor = DBL_EPSILON * dmax;
    for (int k = 0; k < n; k++) {
        double *rk = G + k * n;
        double d = rk[k];
        for (int p = 0; p < k; p++)
            d -= G[p * n + k] * G[p * n + k];
        d = d > floor ? d : floor;
        const double r = sqrt(d), inv = 1.0 / r;
        rk[k] = r;
        for (int j = k + 1; j < n; j++) {
            double s = rk[j];
            const double *a = G + k, *b = G + j;
            int p = 0;
#if !defined(__OPTIMIZE_SIZE__)
            for (; p + 4 <= k; p += 4) {
                s -= a[p * n] * b[p * n];
                s -= a[(p + 1) * n] * b[(p + 1) * n];
                s -= a[(p + 2) * n] * b[(p + 2) * n];
                s -= a[(p + 3) * n] * b[(p + 3) * n];
            }
#endif
            for (; p < k; p++)
                s -= a[p * n] * b[p * n];
            rk[j] = s * inv;
        }
    }
}

/* Right singular vector of the smallest singular value of the n x n upper
 * triangular A (strict lower part zero): inverse iteration to tol, and the
 * SVD only when that does not settle (the two smallest singular values too
 * close). dinv (may be NULL) receives A's reciprocal floored pivots
 * (sfmi_la_tri_gram_solve) when the iteration settled; dinv[0] = 0 when the
 * SVD gave v. */
static int smallest_right_tri(tf_ws *w, const double *A, int n, double tol, double *v, double *dinv)
{
    double scratch[5 * NU];
    const int ok = sfmi_la_tri_smallest_right(A, n, tol, v, scratch);
    if (dinv != NULL)
        dinv[0] = 0.0;
    if (ok) {
        if (dinv != NULL)
            memcpy(dinv, scratch + 4 * n, sizeof(double) * (size_t)n);
        return SFM_OK;
    }
    int st = sfm_svd(A, n, n, NULL, w->S, w->V, w->svd, w->svd_size);
    if (st < 0)
        return st;
    for (int r = 0; r < n; r++)
        v[r] = w->V[r * n + (n - 1)];
    return SFM_OK;
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
 * T_i^{jk} = a_i^j e''^k - e'^j b_i^k, minimize |A E a| subject to |E a| = 1.
 * t is replaced by the minimizer. The columns of E span, for each i, the
 * 9-vectors x (x) e'' and e' (x) y (Kronecker products over j, k): with unit
 * epipoles completed to orthonormal bases {e', p', q'}, {e'', p'', q''},
 * that span has the orthonormal basis e' (x) e'', p' (x) e'', q' (x) e'',
 * e' (x) p'', e' (x) q'' (the two 3-dimensional spans meet in e' (x) e'',
 * so E has rank 5 per i and 15 in all for any nonzero epipoles). The
 * problem becomes the smallest eigenvector of U^T A^T A U (15 x 15), U that
 * basis, with t = U y. A basis vector X_b (x) Y_b of that kind turns a
 * triplet's term (u u^T) (x) Av (x) Bq into u_i u_i2 (X_b^T Av X_b2)
 * (Y_b^T Bq Y_b2), so U^T A^T A U is summed over the triplets from Av and
 * Bq in the bases {e', p', q'} and {e'', p'', q''}. e2, e3 receive the
 * epipoles held, which are those of the new t. */
static int algebraic_step(tf_ws *w, const tf_norm *d, int n, double t[NU], double e2[3], double e3[3])
{
    int st = sfm_trifocal_epipoles(t, e2, e3);
    if (st < 0)
        return st;
    double p2[3], q2[3], p3[3], q3[3];
    complete_basis(e2, p2, q2);
    complete_basis(e3, p3, q3);
    const double *E2[3] = {e2, p2, q2}, *E3[3] = {e3, p3, q3};
    /* basis vector b is E2[xb[b]] (x) E3[yb[b]] */
    static const unsigned char xb[NB] = {0, 1, 2, 0, 0}, yb[NB] = {0, 0, 0, 1, 2};
    enum { NG = NB * (NB + 1) / 2 };
    double *M = w->M, acc[6 * NG];
    memset(acc, 0, sizeof acc);
    for (int p = 0; p < n; p++) {
        tf_rows f;
        double Av[9], Bq[9], Ae[9], Be[9], Gp[NG];
        triplet_factors(d, p, &f, Av, Bq);
        congruence3(Av, E2, Ae);
        congruence3(Bq, E3, Be);
        for (int b = 0, g = 0; b < NB; b++)
            for (int b2 = b; b2 < NB; b2++, g++)
                Gp[g] = Ae[xb[b] * 3 + xb[b2]] * Be[yb[b] * 3 + yb[b2]];
        kron_pack(acc, NG, f.u, Gp);
    }
    memset(M, 0, sizeof(double) * NA * NA);
    kron_unpack(M, NA, NB, acc);
    gram_factor(M, NA);
    double y[NA];
    st = smallest_right_tri(w, M, NA, TOL_ALG, y, NULL);
    if (st < 0)
        return st;
    for (int i = 0; i < 3; i++)
        for (int j = 0; j < 3; j++)
            for (int k = 0; k < 3; k++) {
                double s = 0;
                for (int b = 0; b < NB; b++)
                    s += E2[xb[b]][j] * E3[yb[b]][k] * y[i * NB + b];
                t[i * 9 + j * 3 + k] = s;
            }
    return sfmi_trifocal_normalize(t, NU);
}

/* out = in with one index contracted with a 3 x 3 matrix C: the index of
 * stride `stride` (9: i, 3: j, 1: k), out[.. a ..] = sum_q C[a][q] in[.. q ..],
 * C = M, or M^T when tr. */
static void contract(const double *in, const double M[9], int tr, int stride, double *out)
{
    for (int e = 0; e < NU; e++) {
        const int a = e / stride % 3, base = e - a * stride;
        double acc = 0;
        for (int q = 0; q < 3; q++)
            acc += (tr ? M[q * 3 + a] : M[a * 3 + q]) * in[base + q * stride];
        out[e] = acc;
    }
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

void sfmi_trifocal_gram(const double *const x[3], int n, const double *H, double *G)
{
    /* per triplet (u u^T) (x) Av (x) Bq (triplet_factors), W = Av (x) Bq
     * over the index pairs (j k), (j2 k2), kept as distinct entries
     * (kron_pack) */
    enum { NW = 45 };
    tf_norm d = {{x[0], x[1], x[2]}, {{0}}};
    double acc[6 * NW];
    memcpy(d.H, H, sizeof d.H);
    memset(acc, 0, sizeof acc);
    for (int p = 0; p < n; p++) {
        tf_rows f;
        double Av[9], Bq[9], Wp[NW];
        triplet_factors(&d, p, &f, Av, Bq);
#if defined(__OPTIMIZE_SIZE__)
        for (int c = 0, w = 0; c < 9; c++)
            for (int c2 = c; c2 < 9; c2++, w++)
                Wp[w] = Av[(c / 3) * 3 + c2 / 3] * Bq[(c % 3) * 3 + c2 % 3];
#else
        /* the same products, their indices read from a table instead of
         * divisions by 3 */
        static const unsigned char ia[NW] = {0, 0, 0, 1, 1, 1, 2, 2, 2, 0, 0, 1, 1, 1, 2,
                                             2, 2, 0, 1, 1, 1, 2, 2, 2, 4, 4, 4, 5, 5, 5,
                                             4, 4, 5, 5, 5, 4, 5, 5, 5, 8, 8, 8, 8, 8, 8};
        static const unsigned char ib[NW] = {0, 1, 2, 0, 1, 2, 0, 1, 2, 4, 5, 3, 4, 5, 3,
                                             4, 5, 8, 6, 7, 8, 6, 7, 8, 0, 1, 2, 0, 1, 2,
                                             4, 5, 3, 4, 5, 8, 6, 7, 8, 0, 1, 2, 4, 5, 8};
        for (int w = 0; w < NW; w++)
            Wp[w] = Av[ia[w]] * Bq[ib[w]];
#endif
        kron_pack(acc, NW, f.u, Wp);
    }
    memset(G, 0, sizeof(double) * NU * NU);
    kron_unpack(G, NU, 9, acc);
}

int sfm_trifocal_7pt(const double *x1, const double *x2, const double *x3, int n, double T[27],
                     void *ws, size_t ws_size)
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

    tf_norm d = {{x1, x2, x3}, {{0}}};
    if (normalizer(x1, n, d.H[0]) < 0 || normalizer(x2, n, d.H[1]) < 0 || normalizer(x3, n, d.H[2]) < 0)
        return SFM_E_SINGULAR;
    const double *H1 = d.H[0], *H2 = d.H[1], *H3 = d.H[2];
    if (degenerate_points(x1, x2, x3, n, H1, H2, H3))
        return SFM_E_SINGULAR;

    sfmi_trifocal_gram(d.x, n, &d.H[0][0], w.R);
    gram_factor(w.R, NU);

    double t[NU], g[NU], dinv[NU];
    int st = smallest_right_tri(&w, w.R, NU, TOL_LIN, t, dinv);
    if (st < 0)
        return st;
    gram_apply(&d, n, t, g);
    correct_null(w.R, NU, dinv, g, t);
    double eh2[3], eh3[3];
    st = algebraic_step(&w, &d, n, t, eh2, eh3);
    if (st < 0)
        return st;

    /* Denormalize: T_i^{jk} = H1[r][i] H2^-1[j][s] H3^-1[k][t] That_r^{st}. */
    double H2i[9] = {1 / H2[0], 0, -H2[2] / H2[0], 0, 1 / H2[4], -H2[5] / H2[4], 0, 0, 1};
    double H3i[9] = {1 / H3[0], 0, -H3[2] / H3[0], 0, 1 / H3[4], -H3[5] / H3[4], 0, 0, 1};
    double tmp1[NU], tmp2[NU], out[NU];
    contract(t, H3i, 0, 1, tmp1);   /* k with H3^-1 */
    contract(tmp1, H2i, 0, 3, tmp2); /* j with H2^-1 */
    contract(tmp2, H1, 1, 9, out);   /* i with H1 (transposed) */
    if (sfmi_trifocal_normalize(out, NU) != SFM_OK || !sfmi_la_all_finite(out, NU))
        return SFM_E_SINGULAR;
    sfmi_trifocal_fix_sign(out, NU);
    memcpy(T, out, sizeof out);
    return SFM_OK;
}
