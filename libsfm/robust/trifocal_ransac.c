/*
 * Trifocal RANSAC estimator: minimal 6-triplet samples (up to three
 * solutions each, solvers/trifocal_6pt.c), three-view reprojection
 * error after optimal triangulation for scoring (the error BoofCV's study of
 * trifocal estimation found most reliable), gold-standard LO.
 * Model: tf_model below (T and the compatible cameras P2, P3; P1 = [I | 0]).
 */
#include <math.h>
#include <string.h>

#include "core/linalg_util.h"
#include "core/arena.h"
#include "robust/estimator.h"
#include "robust/support_check.h"
#include "robust/trifocal_ransac.h"
#include "robust/trifocal_refine.h"
#include "sfm/sfm_linalg.h"
#include "sfm/sfm_rotation.h"
#include "solvers/normalize.h"
#include "solvers/trifocal_internal.h"
#include "sfm/sfm_ransac_trifocal.h"
#include "sfm/sfm_trifocal.h"

/* LO_POINTS: the most inliers a local optimisation refits on. Each refit
 * is a gold-standard adjustment whose cost grows with its points, and on
 * large triplets these refits were two thirds of the run; an LO only has to
 * move a model into the right basin, so it refits on evenly spread inliers
 * and the final polish (POLISH_ROUNDS refits on every inlier at tau, kept
 * while the MSAC cost drops) restores the full fit. */
/* SAMPLE: the minimal sample, six triplets with up to MAX_SOLUTIONS
 * solutions. Against the 7-point linear solution and its algebraic step
 * (sfm_trifocal_7pt) it needs 1 / w fewer samples at inlier share w, and a
 * solution costs a cubic and a few 3x3 steps instead of two null spaces of
 * 27 x 27 and 15 x 15 Gram matrices (bench/README.md has the figures). The
 * refits and every count that defines a model keep MIN_FIT, the 7 triplets
 * of the public contract. */
enum {
    MODEL = 51,
    SAMPLE = 6,
    MAX_SOLUTIONS = 3,
    MIN_FIT = SFM_TRIFOCAL_MIN_POINTS,
    LO_ITERS = 8,
    LO_POINTS = 192,
    POLISH_ROUNDS = 1
};

/* The model the engine carries (it copies models as bytes, MODEL doubles). */
typedef struct tf_model {
    double T[27];
    double P2[12], P3[12]; /* cameras compatible with T, P1 = [I | 0] */
} tf_model;
_Static_assert(sizeof(tf_model) == MODEL * sizeof(double), "tf_model is the engine's model size");

/* The residuals of the last model asked about (see tf_residual). */
typedef struct tf_memo {
    double key[24];      /* its P2, P3 */
    double F21[9], F31[9]; /* x2^T F21 x1 = 0, x3^T F31 x1 = 0 */
    double h21, h31;     /* bounds on the norms of the constraints' Hessians */
    double reject;       /* sum of squares over three views beyond every band */
    double *r2;          /* n: residuals, valid where stamp == cur */
    double *X;           /* 4n: their triangulated points (where r2 is finite) */
    uint32_t *stamp;     /* n */
    uint32_t cur;        /* 0: no model yet */
    int n;
} tf_memo;

typedef struct tf_ctx {
    const double *x1, *x2, *x3;
    sfmi_tf_refine_ws refine;
    int *thin; /* LO_POINTS */
    int full;  /* refit on every point given (the polish) */
    tf_memo memo;
} tf_ctx;

/* Scratch of the final support checks. */
typedef struct tf_support_ws {
    int *idx;        /* n */
    double *g;       /* 3 x 2n: the inliers of each view, gathered */
    double *AtA, *V; /* 27 x 27 */
    double *w;       /* 27 */
    void *eig;
    size_t eig_size;
} tf_support_ws;

typedef struct tf_layout_out {
    tf_support_ws sup;
    int *thin;
    double *memo_r2, *memo_X;
    uint32_t *memo_stamp;
    void *ransac_ws;
    size_t ransac_size;
    sfmi_tf_refine_ws refine;
} tf_layout_out;

static void layout(sfmi_arena *a, int n, tf_layout_out *o)
{
    sfm_ransac_dims d = {n, SAMPLE, MAX_SOLUTIONS, MODEL};
    o->ransac_size = sfm_ransac_workspace_size(&d);
    o->ransac_ws = sfmi_arena_alloc(a, o->ransac_size);
    sfmi_tf_refine_layout(a, n, &o->refine);
    o->thin = SFM_ARENA_ARRAY(a, int, LO_POINTS);
    o->memo_r2 = SFM_ARENA_ARRAY(a, double, n);
    o->memo_X = SFM_ARENA_ARRAY(a, double, 4 * (size_t)n);
    o->memo_stamp = SFM_ARENA_ARRAY(a, uint32_t, n);
    o->sup.idx = SFM_ARENA_ARRAY(a, int, n);
    o->sup.g = SFM_ARENA_ARRAY(a, double, 6 * (size_t)n);
    o->sup.AtA = SFM_ARENA_ARRAY(a, double, 27 * 27);
    o->sup.V = SFM_ARENA_ARRAY(a, double, 27 * 27);
    o->sup.w = SFM_ARENA_ARRAY(a, double, 27);
    o->sup.eig_size = sfm_sym_eig_workspace_size(27);
    o->sup.eig = sfmi_arena_alloc(a, o->sup.eig_size);
}

size_t sfm_ransac_trifocal_workspace_size(int n)
{
    if (n < MIN_FIT || n > SFM_RANSAC_MAX_POINTS)
        return 0;
    sfmi_arena a;
    tf_layout_out o;
    sfmi_arena_measure(&a);
    layout(&a, n, &o);
    return sfmi_arena_required(&a);
}

#define P1 sfmi_tf_P1

static int tf_solve(void *vctx, const int *sample, double *models)
{
    tf_ctx *c = (tf_ctx *)vctx;
    double P2[MAX_SOLUTIONS][12], P3[MAX_SOLUTIONS][12];
    const int ns = sfmi_trifocal_6pt(c->x1, c->x2, c->x3, sample, P2, P3); /* 0: degenerate */
    int kept = 0;
    for (int k = 0; k < ns; k++) {
        tf_model *m = (tf_model *)models + kept;
        if (sfm_trifocal_from_cameras(sfmi_tf_P1, P2[k], P3[k], m->T) != SFM_OK)
            continue; /* coincident centres */
        memcpy(m->P2, P2[k], sizeof m->P2);
        memcpy(m->P3, P3[k], sizeof m->P3);
        kept++;
    }
    return kept;
}

/* F = [a]x A for P1 = [I | 0] and P = [A | a] (x^T F x1 = 0), and the
 * Frobenius norm of its upper-left 2x2 block. */
static double tf_fundamental(const double P[12], double F[9])
{
    for (int c = 0; c < 3; c++) {
        F[c] = P[7] * P[8 + c] - P[11] * P[4 + c];
        F[3 + c] = P[11] * P[c] - P[3] * P[8 + c];
        F[6 + c] = P[3] * P[4 + c] - P[7] * P[c];
    }
    return sqrt(F[0] * F[0] + F[1] * F[1] + F[3] * F[3] + F[4] * F[4]);
}

/* A lower bound on the squared distance in R^4 from the pixel pair (p, q)
 * to the epipolar variety q^T F p = 0, hence on the summed squared
 * reprojection error in those two views of any point X (its projections lie
 * on the variety). The constraint c is quadratic in (p, q), with gradient g
 * at the data and a constant Hessian of spectral norm at most h (the
 * Frobenius norm of F's upper-left 2x2 block), so at distance d
 * |c| <= |g| d + h d^2 / 2, which solved for d gives the bound: the Sampson
 * distance when h = 0, never above the true distance. */
static double tf_epipolar_lower2(const double F[9], double h, const double *p, const double *q)
{
    double l0 = F[0] * p[0] + F[1] * p[1] + F[2];
    double l1 = F[3] * p[0] + F[4] * p[1] + F[5];
    double l2 = F[6] * p[0] + F[7] * p[1] + F[8];
    double m0 = F[0] * q[0] + F[3] * q[1] + F[6];
    double m1 = F[1] * q[0] + F[4] * q[1] + F[7];
    double c = fabs(q[0] * l0 + q[1] * l1 + l2);
    double g = sqrt(l0 * l0 + l1 * l1 + m0 * m0 + m1 * m1);
    double d = 2.0 * c / (g + sqrt(g * g + 2.0 * h * c));
    return d * d;
}

/* The squared residual of triplet i under model: the three-view
 * reprojection error after triangulation (sfm_trifocal_point_error), as a
 * mean over the views. Two exact shortcuts:
 * - a triplet whose epipolar lower bound (tf_epipolar_lower2) in views 1-2
 *   or 1-3 already exceeds every band the engine and the checks below use
 *   (wide_mult thresholds) gets HUGE_VAL without the triangulation: beyond
 *   the bands its value is never read (MSAC counts tau^2 for it), so every
 *   score, inlier set and band is the same as with the full error. Most
 *   triplets are outliers of most hypotheses, and the bound costs a
 *   hundredth of the triangulation.
 * - the engine and the final checks ask for the same model's residuals
 *   several times over (the LO band, its inliers, its cost, the support
 *   checks, the mask); the last model's residuals are kept, keyed by its
 *   cameras' bytes, with the triangulated points, which start the refit of
 *   that model (tf_refine). */
static double tf_residual(void *vctx, const double *model, int i)
{
    tf_ctx *c = (tf_ctx *)vctx;
    tf_memo *mo = &c->memo;
    const tf_model *m = (const tf_model *)model;
    if (mo->cur == 0 || memcmp(mo->key, m->P2, sizeof mo->key) != 0) {
        memcpy(mo->key, m->P2, sizeof mo->key);
        mo->h21 = tf_fundamental(m->P2, mo->F21);
        mo->h31 = tf_fundamental(m->P3, mo->F31);
        if (++mo->cur == 0) { /* the stamps wrapped: forget them all */
            memset(mo->stamp, 0, sizeof(uint32_t) * (size_t)mo->n);
            mo->cur = 1;
        }
    } else if (mo->stamp[i] == mo->cur) {
        return mo->r2[i];
    }
    const double *p1 = &c->x1[2 * i], *p2 = &c->x2[2 * i], *p3 = &c->x3[2 * i];
    double e = HUGE_VAL;
    if (!(tf_epipolar_lower2(mo->F21, mo->h21, p1, p2) > mo->reject) &&
        !(tf_epipolar_lower2(mo->F31, mo->h31, p1, p3) > mo->reject) &&
        sfm_trifocal_point_error(P1, m->P2, m->P3, p1, p2, p3, &e, &mo->X[4 * (size_t)i]) == SFM_OK)
        e /= 3.0;
    else
        e = HUGE_VAL;
    mo->r2[i] = e;
    mo->stamp[i] = mo->cur;
    return e;
}

static int tf_refine(void *vctx, const int *inliers, int n_inliers, double *model)
{
    tf_ctx *c = (tf_ctx *)vctx;
    tf_model *m = (tf_model *)model;
    if (n_inliers < MIN_FIT)
        return -1;
    if (!c->full && n_inliers > LO_POINTS) {
        for (int j = 0; j < LO_POINTS; j++)
            c->thin[j] = inliers[(int)(((long long)j * n_inliers) / LO_POINTS)];
        inliers = c->thin;
        n_inliers = LO_POINTS;
    }
    /* the points triangulated when this model was scored start the refit
     * (the listed points are its inliers, so all of them are known) */
    const tf_memo *mo = &c->memo;
    int have = mo->cur != 0 && memcmp(mo->key, m->P2, sizeof mo->key) == 0;
    for (int j = 0; j < n_inliers && have; j++)
        have = mo->stamp[inliers[j]] == mo->cur && mo->r2[inliers[j]] < HUGE_VAL;
    double P2[12], P3[12], T[27];
    memcpy(P2, m->P2, sizeof P2);
    memcpy(P3, m->P3, sizeof P3);
    int st;
    sfmi_tf_refine(c->x1, c->x2, c->x3, inliers, n_inliers, have ? mo->X : NULL, P2, P3, LO_ITERS,
                   &c->refine, &st);
    if (st < 0)
        return st;
    if (sfm_trifocal_from_cameras(P1, P2, P3, T) != SFM_OK)
        return -1;
    memcpy(m->T, T, sizeof T);
    memcpy(m->P2, P2, sizeof P2);
    memcpy(m->P3, P3, sizeof P3);
    return 0;
}

#define TF_DESIGN_FLOOR_RATIO 4.0

/* The design test of support_check.h on the trifocal point constraints
 * (the rows of sfm_trifocal_7pt, four per triplet), Hartley-normalised per
 * view: their Gram matrix as the 7-point solver sums it
 * (sfmi_trifocal_gram), mirrored into the lower triangle the eigensolver
 * reads. */
static int tf_design_degenerate(tf_support_ws *w, int m, double tau)
{
    double h[3][3], H[3][9];
    const double *g[3] = {w->g, w->g + 2 * (size_t)m, w->g + 4 * (size_t)m};
    for (int v = 0; v < 3; v++) {
        if (sfmi_hartley_2d(g[v], m, h[v]) != 0)
            return 1;
        sfmi_hartley_matrix(h[v], H[v]);
    }
    sfmi_trifocal_gram(g, m, &H[0][0], w->AtA);
    for (int a = 0; a < 27; a++)
        for (int b = 0; b < a; b++)
            w->AtA[27 * a + b] = w->AtA[27 * b + a];
    const double s = (h[0][0] + h[1][0] + h[2][0]) / 3.0 * tau / 3.0;
    double ab[2];
    int st = sfmi_design_degenerate(w->AtA, 27, 4 * m, s * s, w->V, w->w, w->eig, w->eig_size,
                                    ab);
    if (st < 0)
        return st;
    /* The second direction must not rest on a handful of triplets: a
     * minimal sample that holds a stray match fits it exactly, and a few
     * strays in the support of a plane or of a pure rotation fill the null
     * directions the scene leaves (measured: two strays among 155 points of
     * a pure rotation). The second eigenvalue, the sum over the triplets of
     * their weight along its eigenvector v, is held without the SAMPLE
     * triplets that weigh most on v. */
    const int j2 = 1; /* sfm_sym_eig: eigenvalues ascending, V's columns in step */
    double top[SAMPLE] = {0.0}, b2 = ab[1];
    for (int q = 0; q < m; q++) {
        const double *xq[3] = {g[0] + 2 * q, g[1] + 2 * q, g[2] + 2 * q};
        sfmi_trifocal_gram(xq, 1, &H[0][0], w->AtA); /* upper triangle */
        double c = 0.0; /* v^T G v from the upper triangle, v = V's column j2 */
        for (int i = 0; i < 27; i++) {
            double r = 0.0;
            for (int k = i; k < 27; k++)
                r += (k == i ? 1.0 : 2.0) * w->AtA[27 * i + k] * w->V[27 * k + j2];
            c += w->V[27 * i + j2] * r;
        }
        int lo = 0; /* the smallest of the kept weights gives way */
        for (int k = 1; k < SAMPLE; k++)
            lo = top[k] < top[lo] ? k : lo;
        top[lo] = c > top[lo] ? c : top[lo];
    }
    for (int k = 0; k < SAMPLE; k++)
        b2 -= top[k];
    const double ms2 = 4.0 * m * s * s; /* rows times one coordinate's variance */
    if (b2 > SFMI_DESIGN_RHO * ms2)
        return 0;
    /* A trifocal row is a product of three coordinates, so its noise is
     * several times that of one coordinate and the bound above, in units of
     * one coordinate's variance, refuses determined scenes at small
     * baselines (the demo room: 6.6 deg parallax, 29 % of the points off its
     * dominant plane, the second eigenvalue 9.9 m s2 and 16 times the
     * smallest). The second eigenvalue is then held instead against the
     * smallest, the noise floor the data show: a plane leaves several null
     * directions at that floor (ratio 1 to 3), a determined scene one. */
    const double floor = fmax(ab[0], 0.1 * ms2);
    return !(b2 > TF_DESIGN_FLOOR_RATIO * floor);
}

double sfmi_trifocal_chance(const double *x2, const double *x3, int n, double tau)
{
    /* a random triplet is an inlier when its view-2 point lands in an
     * epipolar band and its view-3 point in a disc, each about sqrt(3) tau
     * (the threshold bounds the mean over three views) */
    double d2, d3;
    double a2 = sfmi_bbox_area(x2, 2, n, &d2), a3 = sfmi_bbox_area(x3, 2, n, &d3);
    return sfmi_chance_band(a2, d2, 2.0 * 1.7320508075688772 * tau) *
           sfmi_chance_disc(a3, 1.7320508075688772 * tau);
}

/* MSAC cost of model at tau2 and its inliers (r2 < tau2) in idx. */
static double tf_msac(tf_ctx *c, int n, const double *model, double tau2, int *idx, int *m)
{
    double cost = 0.0;
    int k = 0;
    for (int i = 0; i < n; i++) {
        double r2 = tf_residual(c, model, i);
        if (r2 < tau2) {
            idx[k++] = i;
            cost += r2;
        } else {
            cost += tau2;
        }
    }
    *m = k;
    return cost;
}

/* The final polish (see LO_POINTS): refits on every inlier while the MSAC
 * cost drops and the inlier set changes; returns the inlier count. Only
 * needed when an LO can have thinned its points. */
static int tf_polish(tf_ctx *c, int n, double *model, double tau2, int *idx, sfm_ransac_stats *rs)
{
    int m;
    double cost = tf_msac(c, n, model, tau2, idx, &m);
    if (m <= LO_POINTS)
        return m;
    double cand[MODEL];
    for (int r = 0; r < POLISH_ROUNDS; r++) {
        memcpy(cand, model, sizeof cand);
        c->full = 1;
        int st = tf_refine(c, idx, m, cand);
        c->full = 0;
        if (st < 0)
            break;
        int m2;
        double cost2 = tf_msac(c, n, cand, tau2, idx, &m2);
        if (!(cost2 < cost)) {
            tf_msac(c, n, model, tau2, idx, &m);
            break;
        }
        memcpy(model, cand, sizeof cand);
        cost = cost2;
        rs->polished = 1;
        rs->polish_rounds = r + 1;
        int same = m2 == m;
        m = m2;
        if (same)
            break;
    }
    rs->score = cost;
    rs->num_inliers = m;
    return m;
}

/* Moves the drop points of g (m 2-vectors) farthest from their centroid to
 * its end. */
static void drop_farthest(double *g, int m, int drop)
{
    double cx = 0.0, cy = 0.0;
    for (int j = 0; j < m; j++) {
        cx += g[2 * j];
        cy += g[2 * j + 1];
    }
    cx /= m;
    cy /= m;
    for (int e = m - 1; e >= m - drop; e--) {
        int far = 0;
        double best = -1.0;
        for (int j = 0; j <= e; j++) {
            const double dx = g[2 * j] - cx, dy = g[2 * j + 1] - cy;
            if (dx * dx + dy * dy > best) {
                best = dx * dx + dy * dy;
                far = j;
            }
        }
        for (int k = 0; k < 2; k++) {
            const double t = g[2 * far + k];
            g[2 * far + k] = g[2 * e + k];
            g[2 * e + k] = t;
        }
    }
}

/* The support checks of sfm_ransac.h on the inliers of model. */
static int tf_support(tf_ctx *c, tf_support_ws *w, int n, const tf_model *model, double tau,
                      int checks)
{
    const double tau2 = tau * tau;
    int m = 0;
    for (int i = 0; i < n; i++)
        if (tf_residual(c, (const double *)model, i) < tau2)
            w->idx[m++] = i;
    const double *x[3] = {c->x1, c->x2, c->x3};
    double diag[3];
    for (int v = 0; v < 3; v++)
        sfmi_bbox_area(x[v], 2, n, &diag[v]);
    double p = sfmi_trifocal_chance(c->x2, c->x3, n, tau);
    if ((checks & SFMI_TF_CHECK_CHANCE) && !sfmi_above_chance(n, MIN_FIT, m, p))
        return SFM_E_NO_MODEL;
    for (int v = 0; v < 3; v++)
        sfmi_robust_gather(x[v], 2, w->idx, m, w->g + 2 * (size_t)m * v);
    if (checks & SFMI_TF_CHECK_DESIGN) {
        int st = tf_design_degenerate(w, m, tau);
        if (st < 0)
            return st;
        if (st)
            return SFM_E_DEGENERATE;
    }
    /* the spread without the SAMPLE farthest points of each view (a tenth
     * at most): a minimal sample with a stray match fits it exactly, and the
     * stray alone would make a cluster or a line look spread. The views'
     * points are reordered apart from here on, so after the design test. */
    const int drop = SAMPLE < m / 10 ? SAMPLE : m / 10;
    for (int v = 0; v < 3; v++) {
        double *g = w->g + 2 * (size_t)m * v, lo, hi;
        drop_farthest(g, m, drop);
        sfmi_spread(g, 2, NULL, m - drop, &lo, &hi);
        if (sfmi_spread_collinear(lo, hi, tau) || hi < SFMI_CLUSTER_RATIO * diag[v])
            return SFM_E_DEGENERATE;
    }
    return SFM_OK;
}

int sfm_ransac_trifocal(const double *x1, const double *x2, const double *x3, int n,
                        const sfm_ransac_options *opt, double T[27], double *P,
                        uint8_t *inlier_mask, sfm_ransac_stats *stats, void *ws, size_t ws_size)
{
    return sfmi_ransac_trifocal(x1, x2, x3, n, opt, T, P, inlier_mask, stats, ws, ws_size,
                                SFMI_TF_CHECK_CHANCE | SFMI_TF_CHECK_DESIGN);
}

int sfmi_ransac_trifocal(const double *x1, const double *x2, const double *x3, int n,
                         const sfm_ransac_options *opt, double T[27], double *P,
                         uint8_t *inlier_mask, sfm_ransac_stats *stats, void *ws, size_t ws_size,
                         int checks)
{
    if (x1 == NULL || x2 == NULL || x3 == NULL || T == NULL || ws == NULL || n < MIN_FIT ||
        n > SFM_RANSAC_MAX_POINTS)
        return SFM_E_ARGUMENT;
    if (!sfmi_la_all_finite(x1, 2 * n) || !sfmi_la_all_finite(x2, 2 * n) || !sfmi_la_all_finite(x3, 2 * n))
        return SFM_E_NONFINITE;
    sfm_ransac_options o;
    if (opt != NULL)
        o = *opt;
    else
        sfm_ransac_default_options(&o);
    sfmi_arena a;
    tf_layout_out lay;
    sfmi_arena_init(&a, ws, ws_size);
    layout(&a, n, &lay);
    if (!sfmi_arena_ok(&a))
        return SFM_E_WORKSPACE;
    tf_ctx ctx;
    memset(&ctx, 0, sizeof ctx);
    ctx.x1 = x1;
    ctx.x2 = x2;
    ctx.x3 = x3;
    ctx.refine = lay.refine;
    ctx.thin = lay.thin;
    ctx.memo.r2 = lay.memo_r2;
    ctx.memo.X = lay.memo_X;
    ctx.memo.stamp = lay.memo_stamp;
    ctx.memo.n = n;
    memset(ctx.memo.stamp, 0, sizeof(uint32_t) * (size_t)n);
    /* the widest band: wide_mult thresholds (read as 1 below 1, as the
     * engine does), as a sum over three views, with room for rounding */
    {
        const double wide = o.threshold * (o.wide_mult > 1.0 ? o.wide_mult : 1.0);
        ctx.memo.reject = 3.0 * wide * wide * (1.0 + 1e-6);
    }
    sfm_ransac_estimator est = {SAMPLE, MAX_SOLUTIONS, MODEL, tf_solve, tf_residual, tf_refine, NULL, NULL, &ctx, NULL, NULL, NULL};
    tf_model model;
    sfm_ransac_stats rs;
    int cnt = sfm_ransac_run(&est, n, &o, (double *)&model, NULL, &rs, lay.ransac_ws, lay.ransac_size);
    if (cnt < 0)
        return cnt;
    cnt = tf_polish(&ctx, n, (double *)&model, o.threshold * o.threshold, lay.sup.idx, &rs);
    int st = tf_support(&ctx, &lay.sup, n, &model, o.threshold, checks);
    if (st < 0)
        return st;
    /* outputs from here on: nothing can fail any more */
    if (inlier_mask != NULL)
        for (int i = 0; i < n; i++)
            inlier_mask[i] = (uint8_t)(tf_residual(&ctx, (const double *)&model, i) < o.threshold * o.threshold);
    if (stats != NULL)
        *stats = rs;
    memcpy(T, model.T, sizeof model.T);
    if (P != NULL) {
        memcpy(P, P1, sizeof P1);
        memcpy(&P[12], model.P2, sizeof model.P2);
        memcpy(&P[24], model.P3, sizeof model.P3);
    }
    return cnt;
}
