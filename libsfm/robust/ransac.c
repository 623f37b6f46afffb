/*
 * The RANSAC engine: sampling (uniform or PROSAC), SPRT verification, MSAC
 * scoring with early exit, LO-RANSAC and adaptive termination.
 *
 * References: Fischler & Bolles 1981 (RANSAC); Torr & Zisserman 2000 (MSAC);
 * Chum, Matas & Kittler 2003 (LO-RANSAC); Chum & Matas 2005 (PROSAC) and 2008
 * (SPRT, "Optimal randomized RANSAC").
 */
#include <math.h>
#include <string.h>

#include "core/arena.h"
#include "robust/prosac.h"
#include "robust/sprt.h"
#include "sfm/sfm_ransac.h"
#include "core/dmath.h"

/* Builds for size (the Cortex-M7's) leave the estimators' block residuals
 * unused: none has one there, and the point-by-point residual gives the
 * same values. */
#if defined(__OPTIMIZE_SIZE__)
#define USE_BLOCKS 0
#else
#define USE_BLOCKS 1
#endif

/* Initial SPRT parameters; SPRT only starts once a best model exists and
 * sets eps from its support. */
#define SPRT_EPS0 0.1
#define SPRT_DELTA0 0.05

typedef struct engine {
    const sfm_ransac_estimator *est;
    int n, k, m, s;
    double tau2;
    double wide; /* LO / polish band in thresholds, >= 1 */
    int thin;    /* LO may refit on a subset: a full polish follows */
    int *perm;    /* verification order: a seeded random permutation */
    int *pos;     /* pos[perm[j]] = j */
    int *order;   /* PROSAC ranking (points by decreasing quality) */
    int *inl;     /* inlier list scratch */
    double *models;
    double *inner; /* models of the inner samples of an LO: the outer
                      sample's array, whose models are all verified by then */
    int *inner_sample;
    double *best;
    double *tmp;
    double *spare;
    int *sample;
    int *best_sample;
    int *votes;   /* per point: the near-best models holding it as an inlier at
                     tau (NULL: no consensus filter, see VOTE_MARGIN) */
    int nvotes;   /* models counted in votes */
    double *res;  /* squared residuals of the model in res_key, every point
                     (NULL: none kept; with the consensus filter only, whose
                     estimators' residuals depend on the model alone) */
    double *res_key;
    int res_ok;   /* res holds res_key's residuals */
} engine;

static int dims_ok(const sfm_ransac_dims *d)
{
    return d != NULL && d->n >= 1 && d->n <= SFM_RANSAC_MAX_POINTS && d->sample_size >= 1 &&
           d->sample_size <= SFM_RANSAC_MAX_SAMPLE && d->max_models >= 1 &&
           d->max_models <= SFM_RANSAC_MAX_MODELS && d->model_size >= 1 &&
           d->model_size <= SFM_RANSAC_MAX_MODEL_SIZE;
}

/* The one layout, used both to measure and to carve (keep in step with
 * SFM_RANSAC_WS_SIZE in the header). */
static void carve(sfmi_arena *a, const sfm_ransac_dims *d, engine *e)
{
    e->perm = SFM_ARENA_ARRAY(a, int, d->n);
    e->pos = SFM_ARENA_ARRAY(a, int, d->n);
    e->order = SFM_ARENA_ARRAY(a, int, d->n);
    e->inl = SFM_ARENA_ARRAY(a, int, d->n);
    e->models = SFM_ARENA_ARRAY(a, double, (size_t)d->max_models * (size_t)d->model_size);
    e->inner = e->models;
    e->inner_sample = SFM_ARENA_ARRAY(a, int, d->sample_size);
    e->best = SFM_ARENA_ARRAY(a, double, d->model_size);
    e->tmp = SFM_ARENA_ARRAY(a, double, d->model_size);
    e->spare = SFM_ARENA_ARRAY(a, double, d->model_size);
    e->sample = SFM_ARENA_ARRAY(a, int, d->sample_size);
    e->best_sample = SFM_ARENA_ARRAY(a, int, d->sample_size);
    e->votes = SFM_ARENA_ARRAY(a, int, d->n);
    e->res = SFM_ARENA_ARRAY(a, double, d->n);
    e->res_key = SFM_ARENA_ARRAY(a, double, d->model_size);
}

size_t sfm_ransac_workspace_size(const sfm_ransac_dims *dims)
{
    if (!dims_ok(dims))
        return 0;
    sfmi_arena a;
    engine e;
    sfmi_arena_measure(&a);
    carve(&a, dims, &e);
    return sfmi_arena_required(&a);
}

int sfm_ransac_default_options(sfm_ransac_options *opt)
{
    if (opt == NULL)
        return SFM_E_ARGUMENT;
    memset(opt, 0, sizeof *opt);
    opt->threshold = 1.0;
    opt->confidence = 0.999;
    opt->min_iterations = 0;
    opt->max_iterations = 10000;
    opt->seed = SFM_RNG_DEFAULT_SEED;
    opt->lo_rounds = 3;
    opt->wide_mult = 0.0;
    opt->polish_rounds = 8;
    opt->use_sprt = 1;
    opt->quality = NULL;
    opt->clock = NULL;
    opt->clock_ctx = NULL;
    opt->time_budget = 0.0;
    return SFM_OK;
}

/* Every point's squared residual under model, as an array: the kept one
 * when it belongs to the same model bytes (the LO band, its points, the
 * cost and the votes all ask for the same model's residuals), else computed
 * and kept. NULL when the engine keeps none. */
static const double *residuals(engine *e, const double *model)
{
    if (e->res == NULL)
        return NULL;
    const size_t bytes = sizeof(double) * (size_t)e->s;
    if (!e->res_ok || memcmp(e->res_key, model, bytes) != 0) {
        const sfm_ransac_estimator *est = e->est;
        if (USE_BLOCKS && est->residuals != NULL) {
            /* in the verification order, a block at a time (any order gives
             * the same values) */
            double blk[SFM_RANSAC_BLOCK];
            for (int j = 0; j < e->n; j += SFM_RANSAC_BLOCK) {
                const int cnt = e->n - j < SFM_RANSAC_BLOCK ? e->n - j : SFM_RANSAC_BLOCK;
                est->residuals(est->ctx, model, e->perm + j, cnt, blk);
                for (int q = 0; q < cnt; q++)
                    e->res[e->perm[j + q]] = blk[q];
            }
        } else {
            for (int i = 0; i < e->n; i++)
                e->res[i] = est->residual(est->ctx, model, i);
        }
        memcpy(e->res_key, model, bytes);
        e->res_ok = 1;
    }
    return e->res;
}

/* Squared residual of point i under model, from the array r when there is
 * one. */
static double res_at(const engine *e, const double *r, const double *model, int i)
{
    return r != NULL ? r[i] : e->est->residual(e->est->ctx, model, i);
}

/* Full MSAC score of a model; the inlier count goes to *ninl. */
static double score_full(engine *e, const double *model, int *ninl)
{
    const double *res = residuals(e, model);
    double s = 0.0;
    int c = 0;
    for (int i = 0; i < e->n; i++) {
        double r2 = res_at(e, res, model, i);
        if (r2 < e->tau2) {
            s += r2;
            c++;
        } else {
            s += e->tau2;
        }
    }
    *ninl = c;
    return s;
}

#define EVAL_BETTER 0
#define EVAL_WORSE 1
#define EVAL_SPRT 2
#define EVAL_BAIL 3

#define BAIL_STEP 32 /* a power of two */
#define BAIL_Z 3.0

/* Verify a model in the permuted order: SPRT rejection and MSAC early exit
 * once the partial cost reaches the best cost (every term is >= 0, so the
 * model cannot win any more). The sample's own points fit by construction
 * and say nothing about the model: they count in the score but not in the
 * likelihood ratio nor in the estimate of delta. own_pos holds their
 * positions in the verification order, ascending, ending with n. */
static int evaluate(engine *e, sfmi_sprt *sp, int use_sprt, const double *model,
                    const int *own_pos, double best_score, double best_eps, double *score,
                    int *ninl)
{
    const sfm_ransac_estimator *est = e->est;
    double *res = e->res;
    e->res_ok = 0; /* res is overwritten below; it becomes model's at the end */
    const double tau2 = e->tau2;
    const int sprt_on = use_sprt && sp->active && isfinite(best_score);
    const int bail_on = use_sprt && best_eps > 0.0 && best_eps < 1.0;
    const double bail_eps = best_eps, bail_var = best_eps * (1.0 - best_eps);
    const double A = sp->A, min_ = sp->mult_in, mout = sp->mult_out;
    double lambda = 1.0, s = 0.0;
    int c = 0, own = 0, own_c = 0;
    /* the residuals of the next points in blk: SFM_RANSAC_BLOCK at a time
     * with a block residual (those past an exit are computed for nothing),
     * else one */
    double blk[SFM_RANSAC_BLOCK];
    /* the tests below as positions and bounds: the SPRT bound infinite when
     * SPRT is off (lambda > inf never holds), the next own point, the next
     * bail-out point (n when there is none) */
    const double A_on = sprt_on ? A : HUGE_VAL;
    const int n = e->n, *const perm = e->perm, blocked = USE_BLOCKS && est->residuals != NULL;
    int next_own = own_pos[0], next_bail = bail_on ? BAIL_STEP - 1 : n;
    for (int j0 = 0; j0 < n;) {
        int cnt = 1;
        if (blocked) {
            cnt = n - j0 < SFM_RANSAC_BLOCK ? n - j0 : SFM_RANSAC_BLOCK;
            est->residuals(est->ctx, model, perm + j0, cnt, blk);
        } else {
            blk[0] = est->residual(est->ctx, model, perm[j0]);
        }
        const int j1 = j0 + cnt;
        for (int j = j0; j < j1; j++) {
            const double r2 = blk[j - j0];
            if (res != NULL)
                res[perm[j]] = r2;
            int in = r2 < tau2;
            s += in ? r2 : tau2;
            c += in;
            if (j == next_own) {
                own++;
                own_c += in;
                next_own = own_pos[own];
            } else {
                lambda *= in ? min_ : mout;
                if (lambda > A_on) {
                    sfmi_sprt_record_rejection(sp, j + 1 - own, c - own_c);
                    return EVAL_SPRT;
                }
            }
            if (s >= best_score)
                return EVAL_WORSE;
            /* bail-out (Capel, "An effective bail-out test for RANSAC
             * consensus scoring", BMVC 2005): every BAIL_STEP points, drop
             * the model when its inlier count so far is BAIL_Z standard
             * deviations below what the best model's inlier ratio predicts.
             * SPRT misses the models that explain a few percent of the
             * points (an epipole inside the image): they look good against
             * the rejected models' delta, and the MSAC bound only stops them
             * near the end */
            if (j == next_bail) {
                next_bail += BAIL_STEP;
                double m = (double)(j + 1 - own), deficit = m * bail_eps - (double)(c - own_c);
                if (deficit > 0.0 && deficit * deficit > BAIL_Z * BAIL_Z * m * bail_var)
                    return EVAL_BAIL;
            }
        }
        j0 = j1;
    }
    *score = s;
    *ninl = c;
    if (res != NULL) {
        memcpy(e->res_key, model, sizeof(double) * (size_t)e->s);
        e->res_ok = 1;
    }
    return EVAL_BETTER;
}

/* Points whose squared residual is below r2max: their count, and their
 * indices in list unless it is NULL. */
static int collect_within(engine *e, const double *model, double r2max, int *list)
{
    const double *res = residuals(e, model);
    int c = 0;
    for (int i = 0; i < e->n; i++)
        if (res_at(e, res, model, i) < r2max) {
            if (list)
                list[c] = i;
            c++;
        }
    return c;
}

/* Samples needed so that an all-inlier, SPRT-accepted sample has been drawn
 * with probability conf. */
static double needed_iterations(double eps, int k, double pass, double conf)
{
    double p = sfmi_pow(eps, (double)k) * pass;
    if (p >= 1.0)
        return 0.0;
    if (p <= 1e-300)
        return HUGE_VAL;
    double denom = sfmi_log1p(-p);
    if (denom >= 0.0)
        return HUGE_VAL;
    return ceil(sfmi_log(1.0 - conf) / denom);
}

static int contains(const int *a, int k, int v)
{
    for (int i = 0; i < k; i++)
        if (a[i] == v)
            return 1;
    return 0;
}

/* Points a local optimisation refits on at most when a final polish
 * follows. LO then only has to move a model into the right basin (the
 * polish refits on every point), and its cost grows with the list: a fixed
 * cap keeps an LO at N = 1000 as cheap as at N = 200. */
#define LO_MAX_POINTS 128

/* Keeps LO_MAX_POINTS entries of list[0..c) spread evenly over it (the list
 * is in index order, and the points' order carries no meaning); returns the
 * new count. */
static int thin_out(int *list, int c)
{
    if (c <= LO_MAX_POINTS)
        return c;
    for (int j = 0; j < LO_MAX_POINTS; j++)
        list[j] = list[(int)(((long long)j * c) / LO_MAX_POINTS)];
    return LO_MAX_POINTS;
}

/* Bins of the residual histogram behind the noise estimate. */
#define SPREAD_BINS 64
/* The band in robust standard deviations of the model's residuals: for the
 * estimators with a loss scale (set_scale; measured on the relative-pose
 * bench over 200 scenes per row, 2.0 to 3.5: 3.0 keeps every 1 px row's 90th
 * percentile within the anchors' and is the best of them at 2 px), and for
 * the others' final polish (as it was before the band followed the noise). */
#define BAND_SIGMAS 3.0
#define POLISH_SIGMAS 3.5
/* Cauchy scale in robust standard deviations: 2.385 sigma gives the Cauchy
 * M-estimator 95 % efficiency on Gaussian residuals (Holland & Welsch 1977). */
#define LOSS_SIGMAS 2.385

/* Robust standard deviation of a model's residuals: 1.4826 times the median
 * residual among the points within wide_mult thresholds (read from a
 * histogram, so no sort and no scratch). The median is taken as for a
 * one-dimensional residual; two-dimensional ones (reprojection, transfer)
 * come out about 1.18 times wider, which only widens the band. 0 when no
 * point is in the band. */
static double noise_sigma(engine *e, const double *model)
{
    const double *res = residuals(e, model);
    const double wide = sqrt(e->tau2) * e->wide, wide2 = wide * wide;
    int hist[SPREAD_BINS] = {0};
    int m = 0;
    for (int i = 0; i < e->n; i++) {
        double r2 = res_at(e, res, model, i);
        if (!(r2 < wide2))
            continue;
        int b = (int)(sqrt(r2) / wide * SPREAD_BINS);
        hist[b < SPREAD_BINS ? b : SPREAD_BINS - 1]++;
        m++;
    }
    if (m == 0)
        return 0.0;
    double half = 0.5 * (double)m, below = 0.0, med = wide;
    for (int b = 0; b < SPREAD_BINS; b++) {
        if (below + (double)hist[b] >= half) {
            med = ((double)b + (half - below) / (double)hist[b]) * wide / SPREAD_BINS;
            break;
        }
        below += (double)hist[b];
    }
    return 1.4826 * med;
}

/* Squared radius of the band an LO or the polish refits on, for a model
 * whose residuals have robust deviation sigma: BAND_SIGMAS sigma
 * (POLISH_SIGMAS for estimators without set_scale), between
 * tau and wide_mult tau. With a threshold well above the noise the full
 * wide band lets in outliers that a band fitted to the inliers' own spread
 * keeps out; with noise near tau the band stays wide. When the estimator
 * takes a loss scale (set_scale), the refit's Cauchy scale follows the same
 * estimate, LOSS_SIGMAS sigma, at most tau: with a threshold well above the
 * noise a Cauchy loss at tau weighs the band's outliers nearly as much as
 * the inliers and the fit stays biased even when started from the truth;
 * with noise near tau a scale above tau (measured: 2.4 px at a 1 px
 * threshold and 1 px noise) lets the points of the wider band pull along
 * the rotation-translation valley of a small baseline (90th percentile of
 * the direction error 1.45 against 1.27 deg at tau). Without set_scale the band is the full wide band and the
 * estimator's own scale applies, and only the final polish (polishing)
 * narrows the band. */
static double lo_band2(engine *e, const double *model, int polishing)
{
    const sfm_ransac_estimator *est = e->est;
    const double wide2 = e->tau2 * e->wide * e->wide;
    if (est->set_scale == NULL && !polishing)
        return wide2;
    double sigma = noise_sigma(e, model);
    if (!(sigma > 0.0))
        return wide2;
    double band = (est->set_scale != NULL ? BAND_SIGMAS : POLISH_SIGMAS) * sigma,
           band2 = band * band;
    if (band2 < e->tau2)
        band2 = e->tau2;
    if (band2 > wide2)
        band2 = wide2;
    if (est->set_scale != NULL) {
        double scale = LOSS_SIGMAS * sigma;
        if (scale * scale > e->tau2)
            scale = sqrt(e->tau2);
        est->set_scale(est->ctx, scale);
    }
    return band2;
}

/* The consensus filter of the final polish, for the estimators with
 * set_scale (relative and upright pose). At a small baseline the cost is
 * flat along the rotation-translation valley, and the search, which keeps
 * the lowest MSAC cost among many models of that valley, ends on the one
 * that best gathers chance outliers into its band: on the relative-pose
 * bench (small class, 50 % outliers, 2 px) the bad results hold 1 to 8
 * matches more than 4 px off the true model, and those few points hold the
 * polish 1-3 deg off (the same least squares on the true model's band gives
 * 0.25 / 0.65 deg median / p90, against 0.55 / 1.49 from the search's
 * winner; a likelihood with known noise and outlier density prefers the
 * winner in 6 of 10 of those scenes, so no score can tell them apart). True
 * inliers fit every model of the valley; a chance outlier fits the few that
 * moved to it. So every model close to the best (each new best, and each
 * inner-RANSAC candidate that comes that close) votes for its points within
 * VOTE_SIGMAS robust deviations of its residuals, the votes start again when
 * a new best leaves the old one out of that margin (a new basin), and once
 * VOTE_MIN models have voted the polish refits only on the band's points
 * that at least half of the votes hold. "Close": a cost within VOTE_MARGIN
 * of what the best model saves against explaining no point (n tau^2 minus
 * its cost; a share of the cost itself would mean far more models at 75 %
 * outliers, where the cost is mostly the outliers' constant). The vote band
 * at 2 robust deviations is tau itself at 2 px and 1 px noise; voting at
 * tau when tau is the noise (1 px) drops a third of the true inliers
 * (measured: p90 0.70 -> 0.88 deg, unit class, N = 200, 25 %). Margins
 * measured over 60 scenes per row: 0.15, 0.25, 0.35, 0.5 of the saving give
 * the same figures within noise at 25 and 50 %, 0.15 is worse at 75 %. */
#define VOTE_MARGIN 0.35
#define VOTE_SIGMAS 2.0
#define VOTE_MIN 2

/* What a model of MSAC cost score saves against explaining no point. */
static double saving(const engine *e, double score)
{
    return (double)e->n * e->tau2 - score;
}

/* The highest cost that still votes beside a best model of cost best. */
static double vote_bound(const engine *e, double best)
{
    return best + VOTE_MARGIN * saving(e, best);
}

/* A new best of cost new_score replaces one of old_score: the votes start
 * again when the old one is no longer close to it. */
static void votes_new_basin(engine *e, double new_score, double old_score)
{
    if (e->votes != NULL && !(old_score <= vote_bound(e, new_score))) {
        memset(e->votes, 0, sizeof(int) * (size_t)e->n);
        e->nvotes = 0;
    }
}

/* model votes for its points within VOTE_SIGMAS robust deviations (at most
 * the wide band; tau when no point is in the wide band). */
static void vote(engine *e, const double *model)
{
    if (e->votes == NULL)
        return;
    const double sigma = noise_sigma(e, model), wide2 = e->tau2 * e->wide * e->wide;
    double band2 = sigma > 0.0 ? VOTE_SIGMAS * VOTE_SIGMAS * sigma * sigma : e->tau2;
    band2 = band2 < wide2 ? band2 : wide2;
    const double *res = residuals(e, model);
    for (int i = 0; i < e->n; i++)
        if (res_at(e, res, model, i) < band2)
            e->votes[i]++;
    e->nvotes++;
}

/* The refits of an LO: refine on the points within the LO band (lo_band2:
 * wide_mult thresholds, or the noise-tied band and scale for estimators with
 * set_scale), or on the inliers at tau when wide_mult <= 1; keep the
 * result while the MSAC cost at tau drops. The wider set follows the
 * iterative least squares of Chum, Matas & Kittler (which start at a
 * multiple of the threshold): with noise near the threshold, a model from a
 * noisy sample sees only part of its inliers at tau and converges from the
 * wider set. */
static void refits(engine *e, int rounds, double *model, double *score, int *ninl)
{
    const sfm_ransac_estimator *est = e->est;
    for (int r = 0; r < rounds; r++) {
        int c = collect_within(e, model, lo_band2(e, model, 0), e->inl);
        if (c < e->k)
            return;
        if (e->thin)
            c = thin_out(e->inl, c);
        memcpy(e->tmp, model, sizeof(double) * (size_t)e->s);
        if (est->refine(est->ctx, e->inl, c, e->tmp) < 0)
            return;
        int c2;
        double s2 = score_full(e, e->tmp, &c2);
        if (!(s2 < *score))
            return;
        memcpy(model, e->tmp, sizeof(double) * (size_t)e->s);
        *score = s2;
        *ninl = c2;
    }
}

/* Minimal samples an inner RANSAC draws. */
#define INNER_SAMPLES 40
/* Inner RANSACs in a row while each improves the best model. */
#define INNER_REPEATS 3

/* Inner RANSAC of LO-RANSAC (Chum, Matas & Kittler 2003, section 3): minimal
 * samples drawn from the model's points within the LO band, solved and
 * scored on all points; the best model replaces *model when it is better.
 * A noisy sample often lands in a wrong local minimum that explains part of
 * the inliers (for relative pose: along the rotation-translation valley);
 * the refits cannot leave it, but most samples from its support are clean
 * and reach the right one. The candidates within VOTE_MARGIN of the cost
 * vote (the polish's consensus filter). Returns 1 when *model changed. */
static int inner_ransac(engine *e, int early, sfm_rng *rng, double *model, double *score,
                        int *ninl)
{
    const sfm_ransac_estimator *est = e->est;
    int c = collect_within(e, model, lo_band2(e, model, 0), e->inl);
    if (c < 2 * e->k)
        return 0;
    sfmi_sprt off;
    sfmi_sprt_init(&off, 0.0, 0.0); /* inactive: inner models are not the bad
                                      models SPRT's delta describes; the
                                      bail-out still applies */
    const int own_none = e->n;
    int changed = 0;
    for (int it = 0; it < INNER_SAMPLES; it++) {
        for (int i = 0; i < e->k; i++) {
            int v;
            do {
                v = e->inl[sfm_rng_bounded(rng, (uint32_t)c)];
            } while (contains(e->inner_sample, i, v));
            e->inner_sample[i] = v;
        }
        int nm = est->solve(est->ctx, e->inner_sample, e->inner);
        if (nm < 0)
            continue;
        if (nm > e->m)
            nm = e->m;
        for (int mi = 0; mi < nm; mi++) {
            const double *cand = e->inner + (size_t)mi * (size_t)e->s;
            double sc;
            int ci;
            const double bound = e->votes != NULL ? vote_bound(e, *score) : *score;
            if (evaluate(e, &off, early, cand, &own_none, bound, (double)*ninl / (double)e->n, &sc,
                         &ci) != EVAL_BETTER)
                continue;
            vote(e, cand);
            if (!(sc < *score))
                continue;
            memcpy(model, cand, sizeof(double) * (size_t)e->s);
            *score = sc;
            *ninl = ci;
            changed = 1;
        }
    }
    return changed;
}

/* Order-dependent hash of an index list (FNV-1a over the indices): the
 * polish stops when the refit set repeats. */
static uint64_t list_hash(const int *list, int c)
{
    uint64_t h = 1469598103934665603ull;
    for (int j = 0; j < c; j++) {
        h ^= (uint64_t)(uint32_t)list[j];
        h *= 1099511628211ull;
    }
    return h ^ (uint64_t)(uint32_t)c;
}

/* A refit that moves no model entry by more than this has converged (the
 * models are unit-norm matrices, rotations and unit vectors: 1e-7 is about
 * 1e-5 deg). With a loss scale that follows the noise estimate (set_scale),
 * POLISH_STILL_SCALED (about 6e-4 deg): once the band's points repeat, each
 * further round only follows the estimate's small drift, and the model
 * creeps by a factor of 3 or 4 less per round (relative pose: 1e-5, 3e-6,
 * 1e-6, ..., 6 to 8 rounds to reach 1e-7); stopping at 1e-5 moves the
 * bench's direction errors by at most 0.001 deg and takes 2-4 rounds. */
#define POLISH_STILL 1e-7
#define POLISH_STILL_SCALED 1e-5

/* The influence test of the polish (estimators with prune): drops from the
 * refit list e->inl[0..c) the points whose Cook's distance under e->spare is
 * too high for the noise of its residuals (noise_sigma). The consensus filter
 * keeps the chance outliers that only the search's winner holds out; at a
 * small baseline a few chance outliers and high-leverage points that every
 * model of the valley holds still pull the refit along it (relative pose,
 * small class, 25 %, 2 px: a least-squares refit from the polished model on
 * its 3 px band stays at p90 0.79 deg, on the true inliers it reaches 0.47,
 * with the points of high Cook's distance left out 0.60; 100 scenes). With
 * the filter on (filtered) the test runs once, on the first round's list,
 * and the dropped points lose their votes, so that the later rounds' filter
 * keeps them out without the test's two passes over the band (run every
 * round: 3-20 % more instructions a call on the bench's rows, against 0-7 %
 * once); without the filter, every round. Returns the count left. */
static int prune_band(engine *e, int c, int filtered)
{
    const sfm_ransac_estimator *est = e->est;
    const double sigma = noise_sigma(e, e->spare);
    if (!filtered)
        return est->prune(est->ctx, e->spare, e->inl, c, sigma * sigma);
    /* mark the list (~votes < 0), unmark what the test keeps, clear the rest */
    for (int j = 0; j < c; j++)
        e->votes[e->inl[j]] = ~e->votes[e->inl[j]];
    c = est->prune(est->ctx, e->spare, e->inl, c, sigma * sigma);
    for (int j = 0; j < c; j++)
        e->votes[e->inl[j]] = ~e->votes[e->inl[j]];
    for (int i = 0; i < e->n; i++)
        if (e->votes[i] < 0)
            e->votes[i] = 0;
    return c;
}

/* Final polish of e->best to a fixed point: collect the band (lo_band2,
 * from the current model's residuals), refine on it, and repeat until the
 * set of points in the band stops changing and the last refit no longer
 * moved the model (refine takes a few steps only), at most `rounds`
 * times. The
 * MSAC cost at tau is not asked (it prefers models fitted to the points
 * inside tau only); the result is kept when it loses at most 5 % of the
 * inliers. With the consensus filter on (VOTE_MARGIN), only the band's
 * points that at least half of the votes hold are refitted on, less those
 * the influence test (prune_band) drops. Returns the rounds run (0: not
 * kept). */
static int polish(engine *e, int rounds, int best_inl)
{
    const sfm_ransac_estimator *est = e->est;
    memcpy(e->spare, e->best, sizeof(double) * (size_t)e->s);
    uint64_t last = 0;
    int done = 0;
    const double still = est->set_scale != NULL ? POLISH_STILL_SCALED : POLISH_STILL;
    double moved = HUGE_VAL; /* largest change of a model entry in the last refit */
    for (int r = 0; r < rounds; r++) {
        int c = collect_within(e, e->spare, lo_band2(e, e->spare, 1), e->inl);
        const int filtered = e->votes != NULL && e->nvotes >= VOTE_MIN;
        if (filtered) {
            int kept = 0;
            for (int j = 0; j < c; j++)
                if (2 * e->votes[e->inl[j]] >= e->nvotes)
                    e->inl[kept++] = e->inl[j];
            c = kept;
        }
        if (est->prune != NULL && (r == 0 || !filtered))
            c = prune_band(e, c, filtered);
        if (c < e->k)
            break;
        uint64_t h = list_hash(e->inl, c);
        if (r > 0 && h == last && moved < still)
            break;
        last = h;
        memcpy(e->tmp, e->spare, sizeof(double) * (size_t)e->s);
        if (est->refine(est->ctx, e->inl, c, e->spare) < 0)
            break;
        moved = 0.0;
        for (int j = 0; j < e->s; j++) {
            double d = fabs(e->spare[j] - e->tmp[j]);
            moved = d > moved ? d : moved;
        }
        done++;
    }
    if (done == 0)
        return 0;
    int ci;
    (void)score_full(e, e->spare, &ci);
    if ((double)ci < 0.95 * (double)best_inl)
        return 0;
    memcpy(e->best, e->spare, sizeof(double) * (size_t)e->s);
    return done;
}

/* e->spare (ninl inliers at tau, MSAC cost score) becomes the best model,
 * replacing one of cost old_score, and votes (votes_new_basin, vote).
 * SPRT (which tests consistency at tau) is re-tuned with the inlier ratio at
 * tau, the stopping rule with the ratio in the wide band: with noise near
 * tau, the count at tau misses a third or more of the true inliers, and
 * eps^k would then ask for 2^k times the samples an all-inlier draw needs.
 * The ratio the rule used goes to *share. Returns the samples the
 * confidence now needs (counted by the caller from this sample on). */
static double new_best(engine *e, const sfm_ransac_options *opt, sfmi_sprt *sprt, int ninl,
                       double score, double old_score, double *share)
{
    memcpy(e->best, e->spare, sizeof(double) * (size_t)e->s);
    double eps = (double)ninl / (double)e->n;
    sprt->eps = eps;
    sfmi_sprt_update(sprt);
    double eps_stop =
        e->wide > 1.0 ? (double)collect_within(e, e->best, e->tau2 * e->wide * e->wide, NULL) / (double)e->n
                      : eps;
    *share = eps_stop;
    const double k = needed_iterations(eps_stop, e->k,
                                       opt->use_sprt ? sfmi_sprt_pass_probability(sprt) : 1.0,
                                       opt->confidence);
    votes_new_basin(e, score, old_score);
    vote(e, e->best);
    return k;
}

int sfm_ransac_run(const sfm_ransac_estimator *est, int n, const sfm_ransac_options *opt,
                   double *model, uint8_t *inlier_mask, sfm_ransac_stats *stats, void *ws,
                   size_t ws_size)
{
    if (est == NULL || opt == NULL || model == NULL || ws == NULL || est->solve == NULL ||
        est->residual == NULL)
        return SFM_E_ARGUMENT;
    sfm_ransac_dims d = {n, est->sample_size, est->max_models, est->model_size};
    if (!dims_ok(&d) || n < est->sample_size)
        return SFM_E_ARGUMENT;
    if (!isfinite(opt->threshold) || !isfinite(opt->confidence) || !isfinite(opt->wide_mult) ||
        (opt->clock != NULL && !isfinite(opt->time_budget)))
        return SFM_E_NONFINITE;
    if (!(opt->threshold > 0.0) || !(opt->confidence > 0.0 && opt->confidence < 1.0) ||
        opt->min_iterations < 0 || opt->max_iterations < 1 ||
        opt->min_iterations > opt->max_iterations || opt->lo_rounds < 0 || opt->polish_rounds < 0)
        return SFM_E_ARGUMENT;
    if (opt->quality != NULL) {
        for (int i = 0; i < n; i++)
            if (!isfinite(opt->quality[i]))
                return SFM_E_NONFINITE;
    }
    size_t need = sfm_ransac_workspace_size(&d);
    if (need == 0)
        return SFM_E_ARGUMENT;
    if (ws_size < need)
        return SFM_E_WORKSPACE;

    engine e;
    sfmi_arena a;
    sfmi_arena_init(&a, ws, ws_size);
    carve(&a, &d, &e);
    if (!sfmi_arena_ok(&a))
        return SFM_E_WORKSPACE;
    e.est = est;
    e.n = n;
    e.k = est->sample_size;
    e.m = est->max_models;
    e.s = est->model_size;
    e.tau2 = opt->threshold * opt->threshold;
    e.wide = opt->wide_mult > 1.0 ? opt->wide_mult : 1.0;
    e.thin = e.wide > 1.0 && opt->polish_rounds > 0;
    e.nvotes = 0;
    if (est->set_scale != NULL && e.thin && est->refine != NULL) {
        memset(e.votes, 0, sizeof(int) * (size_t)n);
    } else {
        e.votes = NULL;
        e.res = NULL;
    }
    e.res_ok = 0;

    sfm_rng rng;
    sfm_rng_seed(&rng, opt->seed);
    /* verification order: Fisher-Yates on the run's own stream */
    for (int i = 0; i < n; i++)
        e.perm[i] = i;
    for (int i = n - 1; i > 0; i--) {
        int j = (int)sfm_rng_bounded(&rng, (uint32_t)(i + 1));
        int tmp = e.perm[i];
        e.perm[i] = e.perm[j];
        e.perm[j] = tmp;
    }
    for (int i = 0; i < n; i++)
        e.pos[e.perm[i]] = i;
    sfmi_prosac prosac;
    const int use_prosac = opt->quality != NULL;
    if (use_prosac) {
        sfmi_prosac_sort(e.order, opt->quality, n);
        sfmi_prosac_init(&prosac, n, e.k);
    }

    sfmi_sprt sprt;
    sfmi_sprt_init(&sprt, SPRT_EPS0, SPRT_DELTA0);
    const int use_sprt = opt->use_sprt != 0;
    const int lo_on = opt->lo_rounds > 0 && est->refine != NULL;
    int inner_done = 0;

    const int use_clock = opt->clock != NULL && opt->time_budget > 0.0;
    double t0 = use_clock ? opt->clock(opt->clock_ctx) : 0.0;

    double best_score = HUGE_VAL;
    int best_inl = 0, have_best = 0;
    double k_needed = HUGE_VAL, stop_share = 0.0;
    int it_best = 0; /* samples drawn when the best model last improved */
    int it = 0, models = 0, rejected = 0, lo_runs = 0, inner_runs = 0;
    int stop = SFM_RANSAC_STOP_MAX_ITERATIONS;

    for (;;) {
        if (it >= opt->max_iterations) {
            stop = (double)(it - it_best) >= k_needed ? SFM_RANSAC_STOP_CONFIDENCE
                                          : SFM_RANSAC_STOP_MAX_ITERATIONS;
            break;
        }
        if (it >= opt->min_iterations && (double)(it - it_best) >= k_needed) {
            stop = SFM_RANSAC_STOP_CONFIDENCE;
            break;
        }
        if (use_clock && opt->clock(opt->clock_ctx) - t0 >= opt->time_budget) {
            stop = SFM_RANSAC_STOP_TIME;
            break;
        }
        int budget_left = 1; /* as of the reading above */
        it++;
        if (use_prosac) {
            sfmi_prosac_sample(&prosac, &rng, e.sample);
            for (int i = 0; i < e.k; i++)
                e.sample[i] = e.order[e.sample[i]];
        } else {
            for (int i = 0; i < e.k; i++) {
                int v;
                do {
                    v = (int)sfm_rng_bounded(&rng, (uint32_t)n);
                } while (contains(e.sample, i, v));
                e.sample[i] = v;
            }
        }
        if (est->degenerate != NULL && est->degenerate(est->ctx, e.sample))
            continue;
        /* positions of the sample in the verification order, ascending */
        int own_pos[SFM_RANSAC_MAX_SAMPLE + 1];
        for (int i = 0; i < e.k; i++) {
            int p = e.pos[e.sample[i]], q = i;
            while (q > 0 && own_pos[q - 1] > p) {
                own_pos[q] = own_pos[q - 1];
                q--;
            }
            own_pos[q] = p;
        }
        own_pos[e.k] = n;
        int nm = est->solve(est->ctx, e.sample, e.models);
        if (nm < 0)
            return nm;
        if (nm > e.m)
            nm = e.m;
        sfmi_sprt_record_models(&sprt, nm);
        for (int mi = 0; mi < nm; mi++) {
            const double *cand = e.models + (size_t)mi * (size_t)e.s;
            double sc;
            int ci;
            models++;
            int r = evaluate(&e, &sprt, use_sprt, cand, own_pos, best_score,
                             have_best ? (double)best_inl / (double)n : 0.0, &sc, &ci);
            if (r == EVAL_SPRT || r == EVAL_BAIL)
                rejected++;
            if (r != EVAL_BETTER)
                continue;
            memcpy(e.spare, cand, sizeof(double) * (size_t)e.s);
            memcpy(e.best_sample, e.sample, sizeof(int) * (size_t)e.k);
            if (est->fix_best != NULL && est->fix_best(est->ctx, e.sample, e.spare, &rng) == 1)
                sc = score_full(&e, e.spare, &ci);
            if (lo_on) {
                lo_runs++;
                refits(&e, opt->lo_rounds, e.spare, &sc, &ci);
            }
            if (!(sc < best_score))
                continue;
            k_needed = new_best(&e, opt, &sprt, ci, sc, best_score, &stop_share);
            it_best = it;
            best_score = sc;
            best_inl = ci;
            have_best = 1;
            inner_done = 0;
        }
        /* Inner RANSAC of the LO on every new best model, whatever the
         * stopping forecast, and again on its own result while it improves
         * (at most INNER_REPEATS times per outer sample). At small parallax
         * a model from a noisy all-inlier sample lies along the
         * rotation-translation valley and still explains most points; the
         * stopping rule, which assumes that any all-inlier sample gives the
         * right model, may then end the run after a dozen samples. Minimal
         * samples from that model's own support are mostly clean and reach
         * the right basin. Not once the time budget is spent (the clock read
         * at the top of this sample, then after each inner run; the inner
         * run itself is not cut). */
        for (int rep = 0; lo_on && have_best && !inner_done && rep < INNER_REPEATS && budget_left;
             rep++) {
            double sc = best_score;
            int ci = best_inl;
            inner_done = 1;
            inner_runs++;
            memcpy(e.spare, e.best, sizeof(double) * (size_t)e.s);
            if (inner_ransac(&e, use_sprt, &rng, e.spare, &sc, &ci)) {
                refits(&e, opt->lo_rounds, e.spare, &sc, &ci);
                if (sc < best_score) {
                    k_needed = new_best(&e, opt, &sprt, ci, sc, best_score, &stop_share);
                    it_best = it;
                    best_score = sc;
                    best_inl = ci;
                    inner_done = 0;
                }
            }
            if (!inner_done && use_clock)
                budget_left = opt->clock(opt->clock_ctx) - t0 < opt->time_budget;
        }
    }

    if (!have_best)
        return SFM_E_NO_CONVERGENCE;
    int polished = 0;
    if (opt->polish_rounds > 0 && est->refine != NULL && e.wide > 1.0)
        polished = polish(&e, opt->polish_rounds, best_inl);
    int ninl;
    double final_score = score_full(&e, e.best, &ninl);
    if (ninl < 1)
        return SFM_E_NO_CONVERGENCE;

    memcpy(model, e.best, sizeof(double) * (size_t)e.s);
    if (inlier_mask != NULL) {
        for (int i = 0; i < n; i++) {
            double r2 = est->residual(est->ctx, e.best, i);
            inlier_mask[i] = (uint8_t)(r2 < e.tau2);
        }
    }
    if (stats != NULL) {
        stats->iterations = it;
        stats->models = models;
        stats->sprt_rejected = rejected;
        stats->lo_runs = lo_runs;
        stats->polished = polished > 0;
        stats->polish_rounds = polished;
        stats->inner_runs = inner_runs;
        stats->stop_share = stop_share;
        stats->samples_needed = k_needed;
        stats->num_inliers = ninl;
        stats->score = final_score;
        stats->seed = opt->seed;
        stats->stop_reason = stop;
        stats->flags = 0;
        stats->has_twin = 0;
        stats->cov_dim = 0;
    }
    return ninl;
}
