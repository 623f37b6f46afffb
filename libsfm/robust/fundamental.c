/*
 * Fundamental matrix by RANSAC over 7-point samples, scored on the Sampson
 * error in pixels; LO by a normalised 8-point least-squares refit on the
 * points handed over, then a few Levenberg-Marquardt steps on their Sampson
 * error (fundamental_lm.c: rank 2 kept exactly, Cauchy loss of scale tau);
 * and DEGENSAC (Chum, Werner & Matas, "Two-view geometry estimation
 * unaffected by a dominant plane", CVPR 2005).
 *
 * DEGENSAC: every so-far-best sample is tested for H-degeneracy: when a
 * homography through four of its seven points explains five or more of them
 * (forward transfer within 2 tau), the sample is H-degenerate and the 7-point
 * F may be any member of the family [e']x H. (The test of the paper, a
 * homography from three points and F itself, H = [e']x F - e' (M^-1 b)^T,
 * Hartley & Zisserman result 13.6, inherits the noise of an F fitted to
 * nearly coplanar points and misses most degenerate samples once the points
 * carry half a pixel of noise.) H is refitted (DLT) on every point within
 * 2 tau of it, and F is re-estimated by plane and parallax: from H and two points
 * off the plane, e' = (H x1 x x1') x (H x2 x x2') and F = [e']x H; the best
 * of DEGENSAC_PAIRS pairs by MSAC replaces the model when it scores better.
 *
 * Model: f_model below (F and whether plane-and-parallax produced it).
 * SFM_RANSAC_FLAG_DEGENSAC is raised when at least half of the final F's
 * inliers lie on one plane (DEGENSAC's, or one found among those inliers),
 * so a chance coplanar sample in a general scene does not raise it.
 *
 * LO and the final polish run on the points within two thresholds (Cauchy
 * loss of scale tau): with noise near the threshold, a refit on the points
 * within tau only keeps those that already agree with the model and settles
 * near it.
 */
#include <math.h>
#include <string.h>

#include "robust/epipolar.h"
#include "robust/estimator.h"
#include "robust/fundamental_lm.h"
#include "robust/pixel_pairs.h"
#include "robust/support_check.h"
#include "sfm/sfm_solvers.h"
#include "solvers/normalize.h"

#define FMODEL SFM_RANSAC_FUNDAMENTAL_MODEL
/* Pairs of off-plane points tried by plane-and-parallax. */
#define DEGENSAC_PAIRS 100
/* Homographies tried on the final inliers when DEGENSAC found no plane. */
#define PLANE_TRIES 50
/* LM steps per refinement round. */
#define F_LM_STEPS 6

/* The model the engine carries (it copies models as bytes, FMODEL doubles). */
typedef struct f_model {
    double F[9];            /* unit Frobenius norm */
    int32_t plane_parallax; /* 1: DEGENSAC's plane and parallax produced F */
    int32_t unused;
} f_model;
_Static_assert(sizeof(f_model) == FMODEL * sizeof(double), "f_model is the engine's model size");

typedef struct f_ctx {
    const double *p1, *p2;
    double *g1, *g2;
    int *idx;
    int n;
    double tau, tau2;
    double plane[9]; /* the best-supported plane DEGENSAC found */
    int plane_on;    /* its support (0: none found) */
} f_ctx;

static int solve7(void *ctx, const int *s, double *models)
{
    const f_ctx *c = ctx;
    double a[14], b[14];
    sfmi_robust_gather(c->p1, 2, s, 7, a);
    sfmi_robust_gather(c->p2, 2, s, 7, b);
    sfm_mat3 F[SFM_FUNDAMENTAL_7PT_MAX_SOLUTIONS];
    int ns = sfm_fundamental_7pt(a, b, F);
    if (ns < 0)
        return ns == SFM_E_NONFINITE ? 0 : ns;
    double h1[21], h2[21];
    for (int i = 0; i < 7; i++) {
        h1[3 * i] = a[2 * i];
        h1[3 * i + 1] = a[2 * i + 1];
        h1[3 * i + 2] = 1.0;
        h2[3 * i] = b[2 * i];
        h2[3 * i + 1] = b[2 * i + 1];
        h2[3 * i + 2] = 1.0;
    }
    int kept = 0;
    for (int k = 0; k < ns; k++) {
        if (!sfmi_oriented_epipolar(F[k].m, h1, h2, 7))
            continue;
        f_model *m = (f_model *)models + kept;
        memcpy(m->F, F[k].m, sizeof m->F);
        sfmi_normalize9(m->F);
        m->plane_parallax = 0;
        m->unused = 0;
        kept++;
    }
    return kept;
}

static double residual(void *ctx, const double *model, int i)
{
    const f_ctx *c = ctx;
    const f_model *m = (const f_model *)model;
    return sfmi_sampson_pixel2(m->F, c->p1 + 2 * i, c->p2 + 2 * i);
}

/* Linear refit, then LM from whichever of it and the current model has the
 * lower robust cost. Only F changes: the plane-and-parallax mark stays. */
static int refine(void *ctx, const int *inl, int n, double *model)
{
    f_ctx *c = ctx;
    f_model *m = (f_model *)model;
    if (n < 8)
        return -1;
    double F[9];
    memcpy(F, m->F, sizeof F);
    sfmi_pixel_pairs_refit(c->p1, c->p2, inl, n, c->tau, sfm_fundamental_8pt,
                           sfmi_robust_fundamental_cost, c->g1, c->g2, F);
    (void)sfmi_robust_fundamental_lm(c->g1, c->g2, n, c->tau, F_LM_STEPS, F);
    memcpy(m->F, F, sizeof F);
    return 0;
}

static double score(const f_ctx *c, const double *F)
{
    double s = 0.0;
    for (int i = 0; i < c->n; i++) {
        double r2 = sfmi_sampson_pixel2(F, c->p1 + 2 * i, c->p2 + 2 * i);
        s += r2 < c->tau2 ? r2 : c->tau2;
    }
    return s;
}

/* A homography through four of the seven sample points that explains five
 * or more of them within 2 tau (a homography from four noisy points
 * extrapolates with errors of the order of the noise, well beyond it near
 * the edges of the sample); 0 when the sample is not H-degenerate. */
static int degenerate_h(const f_ctx *c, const int *s, double *H)
{
    const double lim = 4.0 * c->tau2;
    int best = 4;
    for (int a = 0; a < 7; a++)
        for (int b = a + 1; b < 7; b++)
            for (int d = b + 1; d < 7; d++)
                for (int e = d + 1; e < 7; e++) {
                    const int q[4] = {s[a], s[b], s[d], s[e]};
                    double x[8], y[8];
                    sfmi_robust_gather(c->p1, 2, q, 4, x);
                    sfmi_robust_gather(c->p2, 2, q, 4, y);
                    sfm_mat3 G;
                    if (sfm_homography_4pt(x, y, &G) != 1)
                        continue;
                    int cnt = 0;
                    for (int j = 0; j < 7; j++)
                        cnt += sfmi_transfer2(G.m, c->p1 + 2 * s[j], c->p2 + 2 * s[j]) < lim;
                    if (cnt > best) {
                        best = cnt;
                        memcpy(H, G.m, sizeof G.m);
                        if (cnt == 7)
                            return 1;
                    }
                }
    return best > 4;
}

/* H refitted (DLT) on every point within 2 tau of it, twice (kept as is
 * when a refit fails), and remembered when it has the largest support so
 * far. 2 tau: a plane point with noise sigma in both images transfers
 * within tau = 3 sigma with probability ~ 0.99 under the true H only; under
 * an H from four noisy points, a band of tau loses a good part of the plane.
 * Leaves the points off the plane (beyond 2 tau) in c->idx; returns their
 * count. */
static int plane_refit(f_ctx *c, double *H)
{
    const double lim = 4.0 * c->tau2;
    for (int round = 0; round < 2; round++) {
        int on = 0;
        for (int i = 0; i < c->n; i++)
            if (sfmi_transfer2(H, c->p1 + 2 * i, c->p2 + 2 * i) < lim)
                c->idx[on++] = i;
        if (on < 5)
            break;
        sfmi_robust_gather(c->p1, 2, c->idx, on, c->g1);
        sfmi_robust_gather(c->p2, 2, c->idx, on, c->g2);
        sfm_mat3 G;
        if (sfm_homography_dlt(c->g1, c->g2, on, &G) != 1 || sfmi_normalize9(G.m) != 0)
            break;
        memcpy(H, G.m, sizeof G.m);
    }
    int off = 0;
    for (int i = 0; i < c->n; i++)
        if (!(sfmi_transfer2(H, c->p1 + 2 * i, c->p2 + 2 * i) < lim))
            c->idx[off++] = i;
    if (c->n - off > c->plane_on) {
        c->plane_on = c->n - off;
        memcpy(c->plane, H, sizeof c->plane);
    }
    return off;
}

static int fix_best(void *ctx, const int *s, double *model, sfm_rng *rng)
{
    f_ctx *c = ctx;
    f_model *m = (f_model *)model;
    double H[9];
    if (!degenerate_h(c, s, H))
        return 0;
    int off = plane_refit(c, H);
    if (off < 2)
        return 0;
    double best = score(c, m->F), bestF[9];
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
            sfmi_matvec3(H, x, Hx);
            sfmi_cross3(Hx, y, l[j]);
        }
        double ep[3], F[9];
        sfmi_cross3(l[0], l[1], ep);
        for (int r = 0; r < 3; r++)
            for (int k = 0; k < 3; k++) {
                int r1 = (r + 1) % 3, r2 = (r + 2) % 3;
                F[3 * r + k] = ep[r1] * H[3 * r2 + k] - ep[r2] * H[3 * r1 + k];
            }
        if (sfmi_normalize9(F) != 0)
            continue;
        double sc = score(c, F);
        if (sc < best) {
            best = sc;
            memcpy(bestF, F, sizeof F);
            improved = 1;
        }
    }
    if (!improved)
        return 0;
    memcpy(m->F, bestF, sizeof bestF);
    m->plane_parallax = 1;
    return 1;
}

/* Points of the list idx[0..m) within 2 tau of H. */
static int plane_support(const f_ctx *c, const double *H, const int *idx, int m)
{
    int on = 0;
    for (int j = 0; j < m; j++)
        on += sfmi_transfer2(H, c->p1 + 2 * idx[j], c->p2 + 2 * idx[j]) < 4.0 * c->tau2;
    return on;
}

/* A dominant plane: at least half of the inliers of the final F within
 * 2 tau of one homography: DEGENSAC's plane when it found one, else the best
 * of PLANE_TRIES homographies through four inliers drawn with rng (the final
 * F may come from a sample with few plane points, which DEGENSAC never
 * sees). */
static int dominant_plane(f_ctx *c, const double *F, sfm_rng *rng)
{
    int in = 0;
    for (int i = 0; i < c->n; i++)
        if (sfmi_sampson_pixel2(F, c->p1 + 2 * i, c->p2 + 2 * i) < c->tau2)
            c->idx[in++] = i;
    if (in < 8)
        return 0;
    if (c->plane_on > 0 && 2 * plane_support(c, c->plane, c->idx, in) >= in)
        return 1;
    for (int it = 0; it < PLANE_TRIES; it++) {
        int q[4];
        for (int k = 0; k < 4; k++) {
            int v, dup;
            do {
                v = c->idx[sfm_rng_bounded(rng, (uint32_t)in)];
                dup = 0;
                for (int j = 0; j < k; j++)
                    dup |= q[j] == v;
            } while (dup);
            q[k] = v;
        }
        double x[8], y[8];
        sfmi_robust_gather(c->p1, 2, q, 4, x);
        sfmi_robust_gather(c->p2, 2, q, 4, y);
        sfm_mat3 G;
        if (sfm_homography_4pt(x, y, &G) == 1 && 2 * plane_support(c, G.m, c->idx, in) >= in)
            return 1;
    }
    return 0;
}

size_t sfm_ransac_fundamental_workspace_size(int n)
{
    if (n < 8)
        return 0;
    return sfmi_pixel_pairs_workspace_size(n, 7, SFM_FUNDAMENTAL_7PT_MAX_SOLUTIONS, FMODEL);
}

int sfm_ransac_fundamental(const double *px1, const double *px2, int n, const sfm_camera *cam1,
                           const sfm_camera *cam2, const sfm_ransac_options *opt, sfm_mat3 *F_out,
                           uint8_t *inlier_mask, sfm_ransac_stats *stats, void *ws,
                           size_t ws_size)
{
    double *F = F_out ? F_out->m : NULL;
    if (F == NULL || n < 8)
        return SFM_E_ARGUMENT;
    pixel_pairs pp;
    sfm_ransac_options eopt;
    int st = sfmi_pixel_pairs_setup(px1, px2, n, cam1, cam2, opt, 7, SFM_FUNDAMENTAL_7PT_MAX_SOLUTIONS,
                                   FMODEL, ws, ws_size, &pp, &eopt);
    if (st < 0)
        return st;
    eopt.wide_mult = 2.0;
    f_ctx c;
    memset(&c, 0, sizeof c);
    c.p1 = pp.p1;
    c.p2 = pp.p2;
    c.g1 = pp.g1;
    c.g2 = pp.g2;
    c.idx = pp.idx;
    c.n = n;
    c.tau = eopt.threshold;
    c.tau2 = eopt.threshold * eopt.threshold;
    sfm_ransac_estimator est = {7, SFM_FUNDAMENTAL_7PT_MAX_SOLUTIONS, FMODEL, solve7, residual,
                                refine, NULL, fix_best, &c, NULL, NULL, NULL};
    f_model model;
    sfm_ransac_stats s;
    int ni = sfm_ransac_run(&est, n, &eopt, (double *)&model, NULL, &s, pp.eng, pp.eng_size);
    if (ni < 0)
        return ni;
    int m = 0;
    for (int i = 0; i < n; i++)
        if (sfmi_sampson_pixel2(model.F, c.p1 + 2 * i, c.p2 + 2 * i) < c.tau2)
            pp.idx[m++] = i;
    /* a random pair is an inlier when it lands in a band of about
     * 2 sqrt(2) tau across image 2 (the Sampson error splits the distance
     * to the epipolar line over both images) */
    double diag, area = sfmi_bbox_area(pp.p2, 2, n, &diag);
    st = sfmi_pixel_pairs_support(&pp, n, 7, m,
                                 sfmi_chance_band(area, diag, 2.8284271247461903 * c.tau), 0,
                                 c.tau);
    if (st < 0)
        return st;
    /* outputs from here on: nothing can fail any more */
    if (inlier_mask != NULL)
        for (int i = 0; i < n; i++)
            inlier_mask[i] = (uint8_t)(sfmi_sampson_pixel2(model.F, c.p1 + 2 * i, c.p2 + 2 * i) < c.tau2);
    memcpy(F, model.F, sizeof model.F);
    if (stats != NULL) {
        sfm_rng rng;
        sfm_rng_seed(&rng, eopt.seed ^ 0x9e3779b97f4a7c15u);
        *stats = s;
        stats->flags = dominant_plane(&c, model.F, &rng) ? SFM_RANSAC_FLAG_DEGENSAC : 0;
    }
    return ni;
}
