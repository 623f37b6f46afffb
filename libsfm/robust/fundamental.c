/*
 * Fundamental matrix by RANSAC over 7-point samples, scored on the Sampson
 * error in pixels, LO by a normalised 8-point least-squares refit on the
 * inliers, and DEGENSAC (Chum, Werner & Matas, "Two-view geometry estimation
 * unaffected by a dominant plane", CVPR 2005): for every so-far-best sample,
 * five triplets of its points each define a homography compatible with F,
 * H = A - e' (M^-1 b)^T with A = [e']x F (Hartley & Zisserman 13.2.2, result
 * 13.6); when one of them explains five or more of the seven points the
 * sample is H-degenerate, and F is re-estimated by plane and parallax: from
 * H and two points off the plane, e' = (H x1 x x1') x (H x2 x x2') and
 * F = [e']x H.
 * Model: F[9], then 1 when plane-and-parallax produced it, else 0.
 */
#include <math.h>
#include <string.h>

#include "robust/epipolar.h"
#include "robust/estimator.h"
#include "robust/pixel_pairs.h"
#include "sfm/sfm_solvers.h"
#include "solvers/normalize.h"

#define FMODEL SFM_RANSAC_FUNDAMENTAL_MODEL
/* Pairs of off-plane points tried by plane-and-parallax. */
#define DEGENSAC_PAIRS 100

typedef struct f_ctx {
    const double *p1, *p2;
    double *g1, *g2;
    int *idx;
    int n;
    double tau2;
} f_ctx;

static int solve7(void *ctx, const int *s, double *models)
{
    const f_ctx *c = ctx;
    double a[14], b[14];
    sfm_robust_gather(c->p1, 2, s, 7, a);
    sfm_robust_gather(c->p2, 2, s, 7, b);
    sfm_mat3 F[SFM_RELPOSE_7PT_MAX_SOLUTIONS];
    int ns = sfm_relpose_7pt(a, b, F);
    if (ns < 0)
        return ns == SFM_E_NONFINITE ? 0 : ns;
    for (int k = 0; k < ns; k++) {
        memcpy(models + FMODEL * k, F[k].m, 9 * sizeof(double));
        sfm__normalize9(models + FMODEL * k);
        models[FMODEL * k + 9] = 0.0;
    }
    return ns;
}

static double residual(void *ctx, const double *m, int i)
{
    const f_ctx *c = ctx;
    return sfm_sampson_pixel2(m, c->p1 + 2 * i, c->p2 + 2 * i);
}

/* A linear refit, unweighted: it runs on the inliers at tau only (the
 * estimator forces wide_mult 1: no wide band, no final polish). */
static int refine(void *ctx, const int *inl, int n, double *m)
{
    f_ctx *c = ctx;
    if (n < 8)
        return -1;
    sfm_robust_gather(c->p1, 2, inl, n, c->g1);
    sfm_robust_gather(c->p2, 2, inl, n, c->g2);
    sfm_mat3 F;
    if (sfm_fundamental_8pt(c->g1, c->g2, n, &F) != 1)
        return -1;
    memcpy(m, F.m, sizeof F.m);
    sfm__normalize9(m);
    return 0; /* keeps m[9]: the refit stays in the same family */
}

static double score(const f_ctx *c, const double *F)
{
    double s = 0.0;
    for (int i = 0; i < c->n; i++) {
        double r2 = sfm_sampson_pixel2(F, c->p1 + 2 * i, c->p2 + 2 * i);
        s += r2 < c->tau2 ? r2 : c->tau2;
    }
    return s;
}

/* e' with e'^T F = 0: the largest cross product of two columns of F. */
static int left_epipole(const double *F, double *e)
{
    double c[3][3], best = 0.0;
    for (int k = 0; k < 3; k++) {
        c[k][0] = F[k];
        c[k][1] = F[3 + k];
        c[k][2] = F[6 + k];
    }
    const int pa[3][2] = {{0, 1}, {0, 2}, {1, 2}};
    for (int p = 0; p < 3; p++) {
        double x[3];
        sfm_cross3(c[pa[p][0]], c[pa[p][1]], x);
        double l = sfm_dot3(x, x);
        if (l > best) {
            best = l;
            e[0] = x[0];
            e[1] = x[1];
            e[2] = x[2];
        }
    }
    if (!(best > 0.0))
        return 0;
    best = 1.0 / sqrt(best);
    e[0] *= best;
    e[1] *= best;
    e[2] *= best;
    return 1;
}

static int inv3(const double *a, double *v)
{
    double det = sfm_adj3(a, v);
    if (!(fabs(det) > 1e-300))
        return 0;
    for (int k = 0; k < 9; k++)
        v[k] /= det;
    return 1;
}

/* The homography of the triplet tri compatible with F (result 13.6). */
static int compatible_h(const f_ctx *c, const double *F, const double *e, const int *s,
                        const int *tri, double *H)
{
    double A[9], M[9], Mi[9], bvec[3];
    for (int r = 0; r < 3; r++)
        for (int k = 0; k < 3; k++) {
            /* A = [e]x F */
            int r1 = (r + 1) % 3, r2 = (r + 2) % 3;
            A[3 * r + k] = e[r1] * F[3 * r2 + k] - e[r2] * F[3 * r1 + k];
        }
    for (int j = 0; j < 3; j++) {
        const double *p = c->p1 + 2 * s[tri[j]], *q = c->p2 + 2 * s[tri[j]];
        double x[3] = {p[0], p[1], 1.0}, y[3] = {q[0], q[1], 1.0}, Ax[3], u[3], w[3];
        M[3 * j] = x[0];
        M[3 * j + 1] = x[1];
        M[3 * j + 2] = 1.0;
        sfm_matvec3(A, x, Ax);
        sfm_cross3(y, Ax, u);
        sfm_cross3(y, e, w);
        double ww = sfm_dot3(w, w);
        if (!(ww > 1e-300))
            return 0;
        bvec[j] = sfm_dot3(u, w) / ww;
    }
    if (!inv3(M, Mi))
        return 0;
    double v[3];
    sfm_matvec3(Mi, bvec, v);
    for (int r = 0; r < 3; r++)
        for (int k = 0; k < 3; k++)
            H[3 * r + k] = A[3 * r + k] - e[r] * v[k];
    return 1;
}

static int fix_best(void *ctx, const int *s, double *model, sfm_rng *rng)
{
    f_ctx *c = ctx;
    static const int triplets[5][3] = {{0, 1, 2}, {3, 4, 5}, {0, 1, 6}, {3, 4, 6}, {2, 5, 6}};
    double e[3], H[9];
    if (!left_epipole(model, e))
        return 0;
    int found = 0;
    for (int k = 0; k < 5 && !found; k++) {
        if (!compatible_h(c, model, e, s, triplets[k], H))
            continue;
        int cnt = 0;
        for (int j = 0; j < 7; j++)
            cnt += sfm_transfer2(H, c->p1 + 2 * s[j], c->p2 + 2 * s[j]) < c->tau2;
        found = cnt >= 5;
    }
    if (!found)
        return 0;
    /* plane and parallax: pairs of points the homography does not explain */
    int off = 0;
    for (int i = 0; i < c->n; i++)
        if (!(sfm_transfer2(H, c->p1 + 2 * i, c->p2 + 2 * i) < c->tau2))
            c->idx[off++] = i;
    if (off < 2)
        return 0;
    double best = score(c, model), bestF[9];
    int improved = 0;
    for (int it = 0; it < DEGENSAC_PAIRS; it++) {
        int a = c->idx[sfm_rng_bounded(rng, (uint32_t)off)];
        int b = c->idx[sfm_rng_bounded(rng, (uint32_t)off)];
        if (a == b)
            continue;
        double l[2][3];
        for (int j = 0; j < 2; j++) {
            int i = j == 0 ? a : b;
            double x[3] = {c->p1[2 * i], c->p1[2 * i + 1], 1.0};
            double y[3] = {c->p2[2 * i], c->p2[2 * i + 1], 1.0}, Hx[3];
            sfm_matvec3(H, x, Hx);
            sfm_cross3(Hx, y, l[j]);
        }
        double ep[3], F[9];
        sfm_cross3(l[0], l[1], ep);
        for (int r = 0; r < 3; r++)
            for (int k = 0; k < 3; k++) {
                int r1 = (r + 1) % 3, r2 = (r + 2) % 3;
                F[3 * r + k] = ep[r1] * H[3 * r2 + k] - ep[r2] * H[3 * r1 + k];
            }
        double nrm = 0.0;
        for (int k = 0; k < 9; k++)
            nrm += F[k] * F[k];
        if (!(nrm > 1e-300) || !isfinite(nrm))
            continue;
        sfm__normalize9(F);
        double sc = score(c, F);
        if (sc < best) {
            best = sc;
            memcpy(bestF, F, sizeof F);
            improved = 1;
        }
    }
    if (!improved)
        return 0;
    memcpy(model, bestF, sizeof bestF);
    model[9] = 1.0;
    return 1;
}

size_t sfm_ransac_fundamental_workspace_size(int n)
{
    if (n < 8)
        return 0;
    return sfm_pixel_pairs_workspace_size(n, 7, SFM_RELPOSE_7PT_MAX_SOLUTIONS, FMODEL);
}

int sfm_ransac_fundamental(const double *px1, const double *px2, int n, const sfm_camera *cam1,
                           const sfm_camera *cam2, const sfm_ransac_options *opt, double F[9],
                           uint8_t *inlier_mask, sfm_ransac_stats *stats, void *ws,
                           size_t ws_size)
{
    if (F == NULL || n < 8)
        return SFM_E_ARGUMENT;
    pixel_pairs pp;
    sfm_ransac_options eopt;
    int st = sfm_pixel_pairs_setup(px1, px2, n, cam1, cam2, opt, 7, SFM_RELPOSE_7PT_MAX_SOLUTIONS,
                                   FMODEL, ws, ws_size, &pp, &eopt);
    if (st < 0)
        return st;
    eopt.wide_mult = 1.0;
    f_ctx c = {pp.p1, pp.p2, pp.g1, pp.g2, pp.idx, n, eopt.threshold * eopt.threshold};
    sfm_ransac_estimator est = {7, SFM_RELPOSE_7PT_MAX_SOLUTIONS, FMODEL, solve7, residual,
                                refine, NULL, fix_best, &c};
    double model[FMODEL];
    sfm_ransac_stats s;
    int ni = sfm_ransac_run(&est, n, &eopt, model, inlier_mask, &s, pp.eng, pp.eng_size);
    if (ni < 0)
        return ni;
    memcpy(F, model, 9 * sizeof(double));
    if (stats != NULL) {
        *stats = s;
        stats->flags = model[9] != 0.0 ? SFM_RANSAC_FLAG_DEGENSAC : 0;
    }
    return ni;
}
