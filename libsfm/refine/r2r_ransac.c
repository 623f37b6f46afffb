/*
 * RANSAC for the robot-to-robot transform over individual measurements:
 * the library's engine (robust/ransac.c) with an estimator whose datum is
 * one distance or bearing of one step, whose minimal sample is any set of
 * measurements adding up to six scalar equations (solved by sfm_r2r_solve,
 * which reduces it to one of the 14 base systems of Zhou & Roumeliotis,
 * T-RO 2013), and whose refit is sfm_r2r_refine.
 *
 * The engine draws a fixed number of points per sample, while a minimal set
 * here has three (bearings only) to six (distances only) measurements: the
 * estimator draws six and takes a prefix (see sfm_r2r.h). Every subset of
 * six equations among the drawn measurements is reachable that way, and an
 * all-inlier prefix needs only its own measurements to be inliers, so the
 * engine's forecast (all six inliers) is an upper bound on the draws.
 * The file lives in refine/, beside the refit it calls: robust/ sits below
 * refine/ and may not call up into it.
 */
#include <math.h>
#include <string.h>

#include "core/linalg_util.h"
#include "core/arena.h"
#include "sfm/sfm_r2r.h"
#include "sfm/sfm_ransac.h"

#define R2R_MODEL 12 /* C (9, row-major), p (3) */
#define R2R_SAMPLE 6
#define R2R_FINAL_REFITS 4

typedef struct r2r_ctx {
    const sfm_r2r_step *steps;
    int n_steps;
    int nm;               /* measurements */
    const int *m_step;    /* step of measurement i */
    const unsigned char *m_kind; /* its bit: SFM_R2R_D, _B1 or _B2 */
    sfm_r2r_step *masked; /* n_steps: steps restricted to a measurement list */
    sfm_r2r_step sub[R2R_SAMPLE];
    sfm_r2r_transform *sol; /* SFM_R2R_MAX_SOLUTIONS */
    void *solve_ws;
    size_t solve_ws_size;
    sfm_r2r_refine_options ropt;
    double tau;
    int solved;      /* samples sfm_r2r_solve answered (>= 0) */
    int unsupported; /* samples it answered SFM_E_UNSUPPORTED */
    int degenerate;  /* samples it answered SFM_E_DEGENERATE */
} r2r_ctx;

static int eqs(unsigned kind)
{
    return kind == SFM_R2R_D ? 1 : 2;
}

static void model_from(const sfm_r2r_transform *T, double *m)
{
    memcpy(m, T->C.m, 9 * sizeof(double));
    memcpy(m + 9, T->p.v, 3 * sizeof(double));
}

static void model_to(const double *m, sfm_r2r_transform *T)
{
    memcpy(T->C.m, m, 9 * sizeof(double));
    memcpy(T->p.v, m + 9, 3 * sizeof(double));
}

static int r2r_solve_sample(void *vctx, const int *sample, double *models)
{
    r2r_ctx *c = vctx;
    const int k = c->nm < R2R_SAMPLE ? c->nm : R2R_SAMPLE;
    int neq = 0, ns = 0;
    int which[R2R_SAMPLE], order[R2R_SAMPLE], no = 0;
    /* bearings first, each kind in drawn order: the bearing-only base
     * systems are the cheap ones (B1_B1_B1 about 0.15 M instructions, the
     * distance-heavy B1_D_D_D_D about 33 M: bench/README.md), and which of
     * the drawn measurements are taken is still a function of the draw */
    for (int pass = 0; pass < 2; pass++)
        for (int j = 0; j < k; j++)
            if ((c->m_kind[sample[j]] == SFM_R2R_D) == (pass == 1))
                order[no++] = sample[j];
    for (int j = 0; j < k && neq < 6; j++) {
        const int i = order[j];
        const int e = eqs(c->m_kind[i]);
        if (neq + e > 6)
            continue;
        neq += e;
        const int st = c->m_step[i];
        int slot = -1;
        for (int q = 0; q < ns; q++)
            if (which[q] == st)
                slot = q;
        if (slot < 0) {
            slot = ns++;
            which[slot] = st;
            c->sub[slot] = c->steps[st];
            c->sub[slot].has = 0u;
        }
        c->sub[slot].has |= c->m_kind[i];
    }
    if (neq != 6)
        return 0;
    int n = sfm_r2r_solve(c->sub, ns, c->sol, c->solve_ws, c->solve_ws_size);
    if (n == SFM_E_UNSUPPORTED)
        c->unsupported++;
    if (n == SFM_E_DEGENERATE)
        c->degenerate++;
    if (n < 0) /* degenerate motion, singular template, unbuilt system */
        return 0;
    c->solved++;
    for (int j = 0; j < n; j++)
        model_from(&c->sol[j], models + (size_t)R2R_MODEL * (size_t)j);
    return n;
}

static double norm3(const double *v)
{
    return sqrt(v[0] * v[0] + v[1] * v[1] + v[2] * v[2]);
}

/* Squared normalised residual of measurement i (threshold units: sigmas). */
static double r2r_residual(void *vctx, const double *model, int i)
{
    const r2r_ctx *c = vctx;
    sfm_r2r_transform T;
    model_to(model, &T);
    const sfm_r2r_step *s = &c->steps[c->m_step[i]];
    double d;
    sfm_vec3 b1, b2;
    if (sfm_r2r_predict(s, &T, &d, &b1, &b2) != SFM_OK)
        return HUGE_VAL;
    const unsigned kind = c->m_kind[i];
    if (kind == SFM_R2R_D) {
        const double r = (d - s->d) / c->ropt.sigma_d;
        return r * r;
    }
    const double *bp = kind == SFM_R2R_B1 ? b1.v : b2.v;
    const double *bm = kind == SFM_R2R_B1 ? s->b1.v : s->b2.v;
    const double l = norm3(bm);
    double e2 = 0.0;
    for (int k = 0; k < 3; k++) {
        const double e = bp[k] - bm[k] / l;
        e2 += e * e;
    }
    return e2 / (c->ropt.sigma_b * c->ropt.sigma_b);
}

/* masked = steps restricted to the listed measurements; their equations. */
static int mask_steps(r2r_ctx *c, const int *list, int n)
{
    for (int k = 0; k < c->n_steps; k++) {
        c->masked[k] = c->steps[k];
        c->masked[k].has = 0u;
    }
    int neq = 0;
    for (int j = 0; j < n; j++) {
        c->masked[c->m_step[list[j]]].has |= c->m_kind[list[j]];
        neq += eqs(c->m_kind[list[j]]);
    }
    return neq;
}

/* Steps left without a measurement are dropped from the masked copy (the
 * refiner takes any has mask, but a step with none adds nothing). */
static int compact(r2r_ctx *c)
{
    int n = 0;
    for (int k = 0; k < c->n_steps; k++)
        if (c->masked[k].has)
            c->masked[n++] = c->masked[k];
    return n;
}

static int r2r_refine_lo(void *vctx, const int *inl, int n_inl, double *model)
{
    r2r_ctx *c = vctx;
    if (mask_steps(c, inl, n_inl) < 7)
        return -1;
    const int ns = compact(c);
    sfm_r2r_refine_options o = c->ropt;
    o.loss = SFM_R2R_LOSS_CAUCHY;
    o.loss_scale = c->tau;
    o.max_iterations = o.max_iterations < 10 ? o.max_iterations : 10;
    sfm_r2r_transform T;
    model_to(model, &T);
    if (sfm_r2r_refine(c->masked, ns, &T, &o, &T, NULL, NULL) != SFM_OK)
        return -1;
    model_from(&T, model);
    return 0;
}

int sfm_r2r_ransac_default_options(sfm_r2r_ransac_options *opt)
{
    if (opt == NULL)
        return SFM_E_ARGUMENT;
    sfm_r2r_refine_default_options(&opt->refine);
    sfm_ransac_default_options(&opt->ransac);
    opt->ransac.threshold = 3.0;
    opt->ransac.max_iterations = 2000;
    return SFM_OK;
}

typedef struct r2r_layout {
    int *m_step;
    unsigned char *m_kind;
    sfm_r2r_step *masked;
    sfm_r2r_transform *sol;
    int *list, *prev;
    void *solve_ws;
    size_t solve_ws_size;
    void *eng;
    size_t eng_size;
} r2r_layout;

static int layout(sfmi_arena *a, int n_steps, r2r_layout *L)
{
    const int nm = 3 * n_steps;
    L->m_step = SFM_ARENA_ARRAY(a, int, nm);
    L->m_kind = SFM_ARENA_ARRAY(a, unsigned char, nm);
    L->masked = SFM_ARENA_ARRAY(a, sfm_r2r_step, n_steps);
    L->sol = SFM_ARENA_ARRAY(a, sfm_r2r_transform, SFM_R2R_MAX_SOLUTIONS);
    L->list = SFM_ARENA_ARRAY(a, int, nm);
    L->prev = SFM_ARENA_ARRAY(a, int, nm);
    L->solve_ws_size = sfm_r2r_solve_workspace_size(R2R_SAMPLE);
    L->solve_ws = sfmi_arena_alloc(a, L->solve_ws_size);
    const sfm_ransac_dims d = {nm, R2R_SAMPLE, SFM_R2R_MAX_SOLUTIONS, R2R_MODEL};
    L->eng_size = sfm_ransac_workspace_size(&d);
    L->eng = sfmi_arena_alloc(a, L->eng_size);
    return L->solve_ws_size > 0 && L->eng_size > 0;
}

size_t sfm_r2r_ransac_workspace_size(int n_steps)
{
    if (n_steps < 1 || n_steps > SFM_R2R_RANSAC_MAX_STEPS)
        return 0;
    sfmi_arena a;
    r2r_layout L;
    sfmi_arena_measure(&a);
    if (!layout(&a, n_steps, &L))
        return 0;
    return sfmi_arena_required(&a);
}

/* The step checks sfm_r2r_refine applies, needed here before any sample is
 * drawn (a bad step must be refused, not outvoted). */
static int check_steps(const sfm_r2r_step *s, int n, int *neq)
{
    *neq = 0;
    for (int k = 0; k < n; k++) {
        const unsigned h = s[k].has;
        if (h & ~(SFM_R2R_D | SFM_R2R_B1 | SFM_R2R_B2))
            return SFM_E_ARGUMENT;
        if (!sfmi_la_all_finite(s[k].R1.m, 9) || !sfmi_la_all_finite(s[k].t1.v, 3) ||
            !sfmi_la_all_finite(s[k].R2.m, 9) || !sfmi_la_all_finite(s[k].t2.v, 3) ||
            ((h & SFM_R2R_D) && !isfinite(s[k].d)) ||
            ((h & SFM_R2R_B1) && !sfmi_la_all_finite(s[k].b1.v, 3)) ||
            ((h & SFM_R2R_B2) && !sfmi_la_all_finite(s[k].b2.v, 3)))
            return SFM_E_NONFINITE;
        if (((h & SFM_R2R_D) && !(s[k].d > 0.0)) ||
            ((h & SFM_R2R_B1) && !(norm3(s[k].b1.v) > 0.0)) ||
            ((h & SFM_R2R_B2) && !(norm3(s[k].b2.v) > 0.0)) ||
            !sfmi_la_is_rotation(s[k].R1.m, 1e-6) || !sfmi_la_is_rotation(s[k].R2.m, 1e-6))
            return SFM_E_ARGUMENT;
        *neq += ((h & SFM_R2R_D) ? 1 : 0) + ((h & SFM_R2R_B1) ? 2 : 0) + ((h & SFM_R2R_B2) ? 2 : 0);
    }
    return *neq >= 6 ? SFM_OK : SFM_E_ARGUMENT;
}

/* The measurements of model within the threshold into list; their count. */
static int collect(r2r_ctx *c, const double *model, int *list)
{
    int n = 0;
    const double t2 = c->tau * c->tau;
    for (int i = 0; i < c->nm; i++)
        if (r2r_residual(c, model, i) < t2)
            list[n++] = i;
    return n;
}

int sfm_r2r_ransac(const sfm_r2r_step *steps, int n_steps, const sfm_r2r_ransac_options *opt,
                   sfm_r2r_transform *out, unsigned *inliers, double *cov,
                   sfm_ransac_stats *stats, void *ws, size_t ws_size)
{
    if (steps == NULL || out == NULL || n_steps < 1 || n_steps > SFM_R2R_RANSAC_MAX_STEPS)
        return SFM_E_ARGUMENT;
    sfm_r2r_ransac_options o;
    if (opt == NULL)
        sfm_r2r_ransac_default_options(&o);
    else
        o = *opt;
    const double ov[3] = {o.refine.sigma_d, o.refine.sigma_b, o.ransac.threshold};
    if (!sfmi_la_all_finite(ov, 3))
        return SFM_E_NONFINITE;
    if (!(o.refine.sigma_d > 0.0) || !(o.refine.sigma_b > 0.0) || !(o.ransac.threshold > 0.0))
        return SFM_E_ARGUMENT;
    int neq;
    int st = check_steps(steps, n_steps, &neq);
    if (st != SFM_OK)
        return st;
    size_t need = sfm_r2r_ransac_workspace_size(n_steps);
    if (need == 0)
        return SFM_E_ARGUMENT;
    if (ws == NULL || ws_size < need)
        return SFM_E_WORKSPACE;
    sfmi_arena a;
    r2r_layout L;
    sfmi_arena_init(&a, ws, ws_size);
    if (!layout(&a, n_steps, &L) || !sfmi_arena_ok(&a))
        return SFM_E_WORKSPACE;

    r2r_ctx c;
    memset(&c, 0, sizeof c);
    c.steps = steps;
    c.n_steps = n_steps;
    int nm = 0;
    for (int k = 0; k < n_steps; k++)
        for (unsigned bit = SFM_R2R_D; bit <= SFM_R2R_B2; bit <<= 1)
            if (steps[k].has & bit) {
                L.m_step[nm] = k;
                L.m_kind[nm] = (unsigned char)bit;
                nm++;
            }
    c.nm = nm;
    c.m_step = L.m_step;
    c.m_kind = L.m_kind;
    c.masked = L.masked;
    c.sol = L.sol;
    c.solve_ws = L.solve_ws;
    c.solve_ws_size = L.solve_ws_size;
    c.ropt = o.refine;
    c.ropt.loss = SFM_R2R_LOSS_SQUARED;
    c.tau = o.ransac.threshold;

    sfm_ransac_estimator est;
    memset(&est, 0, sizeof est);
    est.sample_size = nm < R2R_SAMPLE ? nm : R2R_SAMPLE;
    est.max_models = SFM_R2R_MAX_SOLUTIONS;
    est.model_size = R2R_MODEL;
    est.solve = r2r_solve_sample;
    est.residual = r2r_residual;
    est.refine = r2r_refine_lo;
    est.ctx = &c;
    sfm_ransac_options eo = o.ransac;
    eo.wide_mult = 1.0;
    eo.polish_rounds = 0;
    double model[R2R_MODEL];
    sfm_ransac_stats es;
    int ni = sfm_ransac_run(&est, nm, &eo, model, NULL, &es, L.eng, L.eng_size);
    if (ni < 0) {
        /* no sample gave a hypothesis: say why, when every answer agreed */
        if (ni == SFM_E_NO_CONVERGENCE && c.solved == 0 && c.degenerate > 0 && c.unsupported == 0)
            return SFM_E_DEGENERATE;
        if (ni == SFM_E_NO_CONVERGENCE && c.solved == 0 && c.unsupported > 0)
            return SFM_E_UNSUPPORTED;
        return ni;
    }

    /* final refit: squared loss on the inliers, re-collected until the set
     * stops changing */
    sfm_r2r_transform T;
    double cv[36];
    int n_in = collect(&c, model, L.list);
    for (int round = 0; round < R2R_FINAL_REFITS; round++) {
        if (mask_steps(&c, L.list, n_in) < 7)
            return SFM_E_NO_MODEL;
        const int ns = compact(&c);
        sfm_r2r_transform T0;
        model_to(model, &T0);
        st = sfm_r2r_refine(c.masked, ns, &T0, &c.ropt, &T, cv, NULL);
        if (st != SFM_OK)
            return st == SFM_E_SINGULAR ? SFM_E_DEGENERATE : st;
        model_from(&T, model);
        memcpy(L.prev, L.list, sizeof(int) * (size_t)n_in);
        const int n_prev = n_in;
        n_in = collect(&c, model, L.list);
        if (n_in == n_prev && memcmp(L.prev, L.list, sizeof(int) * (size_t)n_in) == 0)
            break;
    }
    if (mask_steps(&c, L.list, n_in) < 7)
        return SFM_E_NO_MODEL;

    model_to(model, out);
    if (inliers != NULL)
        for (int k = 0; k < n_steps; k++)
            inliers[k] = c.masked[k].has;
    if (cov != NULL)
        memcpy(cov, cv, sizeof cv);
    if (stats != NULL) {
        *stats = es;
        stats->num_inliers = n_in;
        stats->cov_dim = 6;
        memcpy(stats->covariance, cv, sizeof cv);
    }
    return n_in;
}
