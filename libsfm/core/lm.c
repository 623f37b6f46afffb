/*
 * The Levenberg-Marquardt driver (see lm.h for the contract): the loop that
 * owns damping, acceptance and stopping, and the dense normal-equation system
 * for small problems.
 */
#include "core/lm.h"

#include <math.h>
#include <string.h>

#include "core/arena.h"
#include "sfm/sfm_common.h"
#include "sfm/sfm_linalg.h"
#include "sfm/sfm_rotation.h"
#include "core/dmath.h"

#define MIN_DIAG 1e-6
#define MAX_DIAG 1e32
#define MAX_RADIUS 1e16
#define MIN_RADIUS 1e-32
#define MIN_RELATIVE_DECREASE 1e-3

void sfmi_lm_default_options(sfmi_lm_options *o)
{
    o->max_iterations = 50;
    o->function_tolerance = 1e-6;
    o->gradient_tolerance = 1e-10;
    o->step_tolerance = 1e-8;
    o->initial_radius = 1e4;
    o->want_covariance = 0;
}

int sfmi_lm_factor_full_rank(const double *L, const double *diag, int n)
{
    for (int i = 0; i < n; i++) {
        const double l = L[(size_t)i * n + i];
        if (!(l * l > SFMI_LM_COV_RANK_TOL * diag[i]))
            return 0;
    }
    return 1;
}

double sfmi_lm_clamp_diag(double d)
{
    return d < MIN_DIAG ? MIN_DIAG : (d > MAX_DIAG ? MAX_DIAG : d);
}

/* rho(s) and rho'(s) apart: the trial needs the cost alone, a
 * linearisation at an accepted trial's point only the weights. */
static double loss_rho(sfmi_lm_loss loss, double a2, double s)
{
    switch (loss) {
    case SFMI_LM_LOSS_HUBER:
        return s <= a2 ? s : 2.0 * sqrt(a2) * sqrt(s) - a2;
    case SFMI_LM_LOSS_CAUCHY:
        return a2 * sfmi_log1p(s / a2);
    case SFMI_LM_LOSS_TRUNCATED:
        return s <= a2 ? s : a2;
    default:
        return s;
    }
}

static double loss_rho1(sfmi_lm_loss loss, double a2, double s)
{
    switch (loss) {
    case SFMI_LM_LOSS_HUBER:
        return s <= a2 ? 1.0 : sqrt(a2) / sqrt(s);
    case SFMI_LM_LOSS_CAUCHY:
        return 1.0 / (1.0 + s / a2);
    case SFMI_LM_LOSS_TRUNCATED:
        return s <= a2 ? 1.0 : 0.0;
    default:
        return 1.0;
    }
}

void sfmi_lm_loss_eval(sfmi_lm_loss loss, double a2, double s, double *rho, double *rho1)
{
    *rho = loss_rho(loss, a2, s);
    *rho1 = loss_rho1(loss, a2, s);
}

static int options_valid(const sfmi_lm_options *o)
{
    return o->max_iterations >= 0 && o->function_tolerance >= 0.0 &&
           o->gradient_tolerance >= 0.0 && o->step_tolerance >= 0.0 &&
           isfinite(o->initial_radius) && o->initial_radius > 0.0;
}

/* ---- the loop ------------------------------------------------------------- */

int sfmi_lm_run(const sfmi_lm_system *sys, const sfmi_lm_options *opt, sfmi_lm_summary *summary)
{
    if (sys == NULL || opt == NULL || summary == NULL || !options_valid(opt))
        return SFM_E_ARGUMENT;
    double gmax = 0.0;
    double cost = sys->linearize(sys->self, &gmax);
    if (!isfinite(cost))
        return SFM_E_NONFINITE;
    sfmi_lm_summary s;
    memset(&s, 0, sizeof s);
    s.initial_cost = cost;
    s.covariance_status = 1;
    double radius = opt->initial_radius, decrease = 2.0;
    sfmi_lm_stop stop = sys->n_free > 0 ? SFMI_LM_STOP_NONE : SFMI_LM_STOP_NO_PARAMETERS;
    int iter = 0;
    while (stop == SFMI_LM_STOP_NONE) {
        if (gmax <= opt->gradient_tolerance) {
            stop = SFMI_LM_STOP_GRADIENT;
            break;
        }
        if (iter >= opt->max_iterations) {
            stop = SFMI_LM_STOP_MAX_ITERATIONS;
            break;
        }
        iter++;
        double step2 = 0.0, x2 = 0.0, pred = 0.0;
        if (!sys->solve(sys->self, 1.0 / radius, &step2, &x2, &pred)) {
            radius /= decrease;
            decrease *= 2.0;
            if (radius < MIN_RADIUS)
                stop = SFMI_LM_STOP_TRUST_REGION;
            continue;
        }
        if (sqrt(step2) <= opt->step_tolerance * (sqrt(x2) + opt->step_tolerance)) {
            stop = SFMI_LM_STOP_STEP;
            break;
        }
        double cost2 = sys->trial(sys->self);
        double rho = (isfinite(cost2) && pred > 0.0) ? (cost - cost2) / pred : -1.0;
        if (rho > MIN_RELATIVE_DECREASE) {
            double change = cost - cost2, prev = cost;
            sys->accept(sys->self);
            cost = sys->linearize(sys->self, &gmax);
            s.successful_steps++;
            if (!isfinite(cost)) {
                /* the trial's cost was finite, so the callbacks disagree
                 * with themselves: keep the point, report the collapse */
                cost = cost2;
                stop = SFMI_LM_STOP_TRUST_REGION;
                break;
            }
            double f = 2.0 * rho - 1.0;
            radius = radius / fmax(1.0 / 3.0, 1.0 - f * f * f);
            if (radius > MAX_RADIUS)
                radius = MAX_RADIUS;
            decrease = 2.0;
            if (fabs(change) <= opt->function_tolerance * prev)
                stop = SFMI_LM_STOP_FUNCTION;
        } else {
            radius /= decrease;
            decrease *= 2.0;
            if (radius < MIN_RADIUS)
                stop = SFMI_LM_STOP_TRUST_REGION;
            else if (isfinite(cost2) && fabs(cost - cost2) <= opt->function_tolerance * cost)
                stop = SFMI_LM_STOP_FUNCTION;
        }
    }
    s.iterations = iter;
    s.stop = stop;
    s.final_cost = cost;
    *summary = s;
    return SFM_OK;
}

/* ---- manifolds ------------------------------------------------------------ */

void sfmi_lm_sphere_basis(const double *x, int n, double *B)
{
    /* v = x + sign(x_k) |x| e_k, k the largest entry; the reflection
     * I - 2 v v^T / v.v maps x onto -sign(x_k) |x| e_k, so its other
     * columns are orthonormal and orthogonal to x. */
    int k = 0;
    double nn = 0.0;
    for (int i = 0; i < n; i++) {
        nn += x[i] * x[i];
        if (fabs(x[i]) > fabs(x[k]))
            k = i;
    }
    double v[SFMI_LM_SPHERE_MAX];
    for (int i = 0; i < n; i++)
        v[i] = x[i];
    v[k] += (x[k] >= 0.0 ? 1.0 : -1.0) * sqrt(nn);
    double vv = 0.0;
    for (int i = 0; i < n; i++)
        vv += v[i] * v[i];
    double s = vv > 0.0 ? 2.0 / vv : 0.0;
    for (int r = 0; r < n; r++) {
        for (int j = 0, c = 0; j < n; j++) {
            if (j == k)
                continue;
            B[r * (n - 1) + c] = (r == j ? 1.0 : 0.0) - s * v[r] * v[j];
            c++;
        }
    }
}

static int block_tangent(const sfmi_lm_block *b)
{
    switch (b->manifold) {
    case SFMI_LM_EUCLIDEAN:
        return b->size >= 1 ? b->size : -1;
    case SFMI_LM_SO3:
    case SFMI_LM_SO3_RIGHT:
        return b->size == 9 ? 3 : -1;
    case SFMI_LM_SPHERE:
        return b->size >= 2 && b->size <= SFMI_LM_SPHERE_MAX ? b->size - 1 : -1;
    case SFMI_LM_CONSTANT:
        return b->size >= 1 ? 0 : -1;
    case SFMI_LM_CUSTOM:
        return b->size >= 1 && b->tangent >= 0 && b->plus != NULL ? b->tangent : -1;
    }
    return -1;
}

int sfmi_lm_tangent_size(const sfmi_lm_block *blocks, int n_blocks)
{
    if (blocks == NULL || n_blocks < 1 || n_blocks > SFMI_LM_DENSE_MAX_BLOCKS)
        return -1;
    int nt = 0;
    for (int b = 0; b < n_blocks; b++) {
        int t = block_tangent(&blocks[b]);
        if (t < 0 || blocks[b].x == NULL)
            return -1;
        nt += t;
    }
    return nt;
}

/* out = x (+) d on b's manifold; 0 when the result is not finite. */
int sfmi_lm_block_plus(const sfmi_lm_block *b, const double *x, const double *d, double *out)
{
    switch (b->manifold) {
    case SFMI_LM_EUCLIDEAN:
        for (int i = 0; i < b->size; i++)
            out[i] = x[i] + d[i];
        break;
    case SFMI_LM_SO3:
    case SFMI_LM_SO3_RIGHT: {
        double dR[9];
        if (sfm_rot_from_axis_angle(d, dR) != SFM_OK)
            return 0;
        const double *A = b->manifold == SFMI_LM_SO3 ? dR : x;
        const double *C = b->manifold == SFMI_LM_SO3 ? x : dR;
        for (int r = 0; r < 3; r++)
            for (int c = 0; c < 3; c++)
                out[3 * r + c] = A[3 * r] * C[c] + A[3 * r + 1] * C[3 + c] + A[3 * r + 2] * C[6 + c];
        break;
    }
    case SFMI_LM_SPHERE: {
        const int n = b->size;
        double B[SFMI_LM_SPHERE_MAX * (SFMI_LM_SPHERE_MAX - 1)], nn = 0.0;
        sfmi_lm_sphere_basis(x, n, B);
        for (int r = 0; r < n; r++) {
            double v = x[r];
            for (int c = 0; c < n - 1; c++)
                v += B[r * (n - 1) + c] * d[c];
            out[r] = v;
            nn += v * v;
        }
        nn = sqrt(nn);
        if (!(nn > 0.0))
            return 0;
        for (int r = 0; r < n; r++)
            out[r] /= nn;
        break;
    }
    case SFMI_LM_CONSTANT:
        memcpy(out, x, sizeof(double) * (size_t)b->size);
        break;
    case SFMI_LM_CUSTOM:
        b->plus(x, d, out, b->plus_user);
        break;
    }
    for (int i = 0; i < b->size; i++)
        if (!isfinite(out[i]))
            return 0;
    return 1;
}

/* ---- the dense system ----------------------------------------------------- */

typedef struct dense_ws {
    double *cur, *trial; /* n_values each */
    double *H, *A;       /* nt x nt: normal matrix (lower), damped factor */
    double *g, *h, *D;   /* nt: gradient J^T W r, step, damping */
    double *r, *J;       /* residual_size, residual_size x nt */
} dense_ws;

typedef struct dense_ctx {
    const sfmi_lm_problem *p;
    dense_ws w;
    int nv, nt;
    double a2;
    /* the trial's cost, the current point's once accepted (known: the
     * linearisation there needs only the weights) */
    double trial_cost;
    int cost_known;
    /* lazy: H and g at an accepted point are formed by the next solve, so
     * a run that stops right after the step forms none (sfmi_lm_refine:
     * no gradient test, no covariance) */
    int lazy, stale;
    int voff[SFMI_LM_DENSE_MAX_BLOCKS], toff[SFMI_LM_DENSE_MAX_BLOCKS];
} dense_ctx;

static void dense_layout(sfmi_arena *a, int nv, int nt, int rs, dense_ws *w)
{
    w->cur = SFM_ARENA_ARRAY(a, double, nv);
    w->trial = SFM_ARENA_ARRAY(a, double, nv);
    w->H = SFM_ARENA_ARRAY(a, double, (size_t)nt * nt + 1);
    w->A = SFM_ARENA_ARRAY(a, double, (size_t)nt * nt + 1);
    w->g = SFM_ARENA_ARRAY(a, double, nt + 1);
    w->h = SFM_ARENA_ARRAY(a, double, nt + 1);
    w->D = SFM_ARENA_ARRAY(a, double, nt + 1);
    w->r = SFM_ARENA_ARRAY(a, double, rs);
    w->J = SFM_ARENA_ARRAY(a, double, (size_t)rs * nt + 1);
}

size_t sfmi_lm_dense_workspace_size(int n_values, int n_tangent, int residual_size)
{
    if (n_values < 1 || n_tangent < 0 || n_tangent > SFMI_LM_DENSE_MAX_TANGENT ||
        residual_size < 1 || residual_size > SFMI_LM_DENSE_MAX_RESIDUAL || n_values > (1 << 20))
        return 0;
    sfmi_arena a;
    dense_ws w;
    sfmi_arena_measure(&a);
    dense_layout(&a, n_values, n_tangent, residual_size, &w);
    return sfmi_arena_required(&a);
}

/* H += rho1 J^T J (lower triangle) and g += rho1 J^T r for one residual row
 * J (nt entries), which is left zero: rows of H from the last, row a the
 * last reader of J_a (each entry of H and g takes one term per row, so the
 * order of a leaves the sums as they are). Called with nt a constant for
 * the common sizes, so the loops unroll fully. */
static inline void accumulate_row(double *H, double *g, double *J, double r, double rho1, int nt)
{
#pragma GCC unroll 8
    for (int a = nt - 1; a >= 0; a--) {
        const double wj = rho1 * J[a];
        g[a] += wj * r;
        double *Hrow = H + (size_t)a * nt;
#pragma GCC unroll 8
        for (int b = 0; b <= a; b++)
            Hrow[b] += wj * J[b];
        J[a] = 0.0;
    }
}

/* accumulate_row for the row J[0], J[stride], ... of a batch (core/lm.h),
 * the same terms in the same order; J is left as it is. */
static inline void accumulate_col(double *H, double *g, const double *J, int stride, double r,
                                  double rho1, int nt)
{
#pragma GCC unroll 8
    for (int a = nt - 1; a >= 0; a--) {
        const double wj = rho1 * J[a * stride];
        g[a] += wj * r;
        double *Hrow = H + (size_t)a * nt;
#pragma GCC unroll 8
        for (int b = 0; b <= a; b++)
            Hrow[b] += wj * J[b * stride];
    }
}

/* 2^CAUCHY_SPLIT: the bound of the running product of Cauchy factors
 * (each below it too, so the product stays below 2^(2 CAUCHY_SPLIT)). */
#define CAUCHY_SPLIT 256
#define CAUCHY_SPLIT_POW 0x1p256
#define LM_LN2 0.69314718055994530942

/* Cost at the values v (+Inf when undefined); with lin, also H and g.
 * known: the cost at v is c->trial_cost (v the accepted trial, evaluated
 * by the same callbacks), so only the loss weights are computed. */
static double dense_eval(dense_ctx *c, const double *v, int lin, int known, double *gmax)
{
    const sfmi_lm_problem *p = c->p;
    dense_ws *w = &c->w;
    const int nt = c->nt, rs = p->residual_size;
    const double *xp[SFMI_LM_DENSE_MAX_BLOCKS];
    for (int b = 0; b < p->n_blocks; b++)
        xp[b] = v + c->voff[b];
    /* J is zero before every callback: zeroed here, and again by the
     * accumulation below as it reads each entry for the last time */
    const size_t jn = (size_t)rs * nt;
    if (lin) {
        memset(w->H, 0, sizeof(double) * (size_t)nt * nt);
        memset(w->g, 0, sizeof(double) * (size_t)nt);
        memset(w->J, 0, sizeof(double) * jn);
    }
    double cost = 0.0;
    /* Cauchy: the sum of a2 log(1 + s/a2) as a2 log of the product of the
     * factors, kept below 2^CAUCHY_SPLIT by counting the powers taken out
     * (one log per evaluation instead of one per residual: the logs were
     * 6 % of a relative-pose RANSAC call). Each product rounds once, so the
     * log is off by at most about n units of 2^-53, the order of the
     * rounding of a sum of n log1p terms. A factor that could overflow the
     * product, or NaN, takes its own log1p. */
    const int cauchy = !known && p->loss == SFMI_LM_LOSS_CAUCHY;
    double prod = 1.0;
    int split = 0;
#if SFMI_LM_HAVE_BATCH
    const int batch = p->batch != NULL && rs == 1 && nt <= SFMI_LM_BATCH_TANGENT;
    int okb[SFMI_LM_BATCH];
    double rb[SFMI_LM_BATCH], Jb[SFMI_LM_BATCH * SFMI_LM_BATCH_TANGENT];
#else
    const int batch = 0;
    int okb[1];
    double *rb = w->r, *Jb = w->J;
#endif
    /* blocks i0 .. i0 + cnt - 1 from one batch call, or one block through
     * residual; then each in order, as if one by one */
    for (int i0 = 0, cnt = 1; i0 < p->n_residuals; i0 += cnt) {
        const double *rv = w->r;
        if (batch) {
            cnt = p->n_residuals - i0 < SFMI_LM_BATCH ? p->n_residuals - i0 : SFMI_LM_BATCH;
            p->batch(p->user, xp, i0, cnt, okb, rb, lin ? Jb : NULL);
            rv = rb;
        } else {
            okb[0] = p->residual(p->user, xp, i0, w->r, lin ? w->J : NULL);
        }
        for (int q = 0; q < cnt; q++) {
            const int ok = okb[q];
            const double *r = rv + q;
            double *J = w->J; /* per block only; a batch's rows are in Jb */
            if (ok < 0)
                return HUGE_VAL;
            if (ok == 0) {
                if (lin && !batch)
                    memset(J, 0, sizeof(double) * jn);
                continue;
            }
            double s = 0.0;
            for (int k = 0; k < rs; k++)
                s += r[k] * r[k];
            if (cauchy) {
                const double f = 1.0 + s / c->a2;
                if (f < CAUCHY_SPLIT_POW) {
                    prod *= f;
                    if (prod >= CAUCHY_SPLIT_POW) {
                        prod *= 1.0 / CAUCHY_SPLIT_POW;
                        split++;
                    }
                } else {
                    cost += loss_rho(p->loss, c->a2, s);
                }
            } else if (!known) {
                cost += loss_rho(p->loss, c->a2, s);
            }
            if (!lin)
                continue;
            const double rho1 = loss_rho1(p->loss, c->a2, s);
            if (rho1 == 0.0) {
                if (!batch)
                    memset(J, 0, sizeof(double) * jn);
                continue;
            }
            if (batch && nt == 5) /* the Sampson refits: free, upright */
                accumulate_col(w->H, w->g, Jb + q, SFMI_LM_BATCH, r[0], rho1, 5);
            else if (batch && nt == 3)
                accumulate_col(w->H, w->g, Jb + q, SFMI_LM_BATCH, r[0], rho1, 3);
            else if (batch)
                accumulate_col(w->H, w->g, Jb + q, SFMI_LM_BATCH, r[0], rho1, nt);
            else if (rs == 1 && nt == 5)
                accumulate_row(w->H, w->g, J, r[0], rho1, 5);
            else if (rs == 1 && nt == 3)
                accumulate_row(w->H, w->g, J, r[0], rho1, 3);
            else
                for (int k = 0; k < rs; k++)
                    accumulate_row(w->H, w->g, J + (size_t)k * nt, r[k], rho1, nt);
        }
    }
    if (lin) {
        double m = 0.0;
        for (int a = 0; a < nt; a++)
            m = fmax(m, fabs(w->g[a]));
        *gmax = m;
    }
    if (known)
        return c->trial_cost;
    if (cauchy)
        cost += c->a2 * (sfmi_log(prod) + (double)split * (CAUCHY_SPLIT * LM_LN2));
    cost *= 0.5;
    return isfinite(cost) ? cost : HUGE_VAL;
}

static double dense_linearize(void *self, double *gmax)
{
    dense_ctx *c = self;
    const int known = c->cost_known;
    c->cost_known = 0;
    if (known && c->lazy) {
        /* no gradient test: any value above 0 lets the loop go on */
        c->stale = 1;
        *gmax = HUGE_VAL;
        return c->trial_cost;
    }
    return dense_eval(c, c->w.cur, 1, known, gmax);
}

static int dense_solve(void *self, double mu, double *step2, double *x2, double *pred)
{
    dense_ctx *c = self;
    dense_ws *w = &c->w;
    const int nt = c->nt;
    if (c->stale) {
        double gmax;
        if (!isfinite(dense_eval(c, w->cur, 1, 1, &gmax)))
            return 0;
        c->stale = 0;
    }
    for (int a = 0; a < nt; a++) {
        for (int b = 0; b <= a; b++)
            w->A[(size_t)a * nt + b] = w->H[(size_t)a * nt + b];
        w->D[a] = mu * sfmi_lm_clamp_diag(w->H[(size_t)a * nt + a]);
        w->A[(size_t)a * nt + a] += w->D[a];
        w->h[a] = -w->g[a];
    }
    if (sfm_cholesky_factor(w->A, nt) != SFM_OK || sfm_cholesky_solve(w->A, nt, w->h, 1) != SFM_OK)
        return 0;
    double s2 = 0.0, pr = 0.0;
    for (int a = 0; a < nt; a++) {
        s2 += w->h[a] * w->h[a];
        pr += w->h[a] * (w->D[a] * w->h[a] - w->g[a]);
    }
    double xx = 0.0;
    const sfmi_lm_problem *p = c->p;
    for (int b = 0; b < p->n_blocks; b++) {
        const sfmi_lm_block *B = &p->blocks[b];
        if (B->manifold == SFMI_LM_SO3 || B->manifold == SFMI_LM_SO3_RIGHT ||
            B->manifold == SFMI_LM_CONSTANT)
            continue;
        for (int i = 0; i < B->size; i++)
            xx += w->cur[c->voff[b] + i] * w->cur[c->voff[b] + i];
    }
    *step2 = s2;
    *x2 = xx;
    *pred = 0.5 * pr;
    return isfinite(s2) && isfinite(pr);
}

static double dense_trial(void *self)
{
    dense_ctx *c = self;
    dense_ws *w = &c->w;
    const sfmi_lm_problem *p = c->p;
    for (int b = 0; b < p->n_blocks; b++) {
        if (!sfmi_lm_block_plus(&p->blocks[b], w->cur + c->voff[b], w->h + c->toff[b], w->trial + c->voff[b]))
            return HUGE_VAL;
    }
    c->trial_cost = dense_eval(c, w->trial, 0, 0, NULL);
    return c->trial_cost;
}

static void dense_accept(void *self)
{
    dense_ctx *c = self;
    memcpy(c->w.cur, c->w.trial, sizeof(double) * (size_t)c->nv);
    c->cost_known = 1;
}

static int dense_run(const sfmi_lm_problem *prob, const sfmi_lm_options *opt, void *ws,
                     size_t ws_size, sfmi_lm_summary *summary, double *cov, int lazy)
{
    if (prob == NULL || opt == NULL || summary == NULL || prob->residual == NULL ||
        prob->n_residuals < 0 || prob->residual_size < 1 ||
        prob->residual_size > SFMI_LM_DENSE_MAX_RESIDUAL || !options_valid(opt) ||
        (opt->want_covariance && cov == NULL))
        return SFM_E_ARGUMENT;
    if ((unsigned)prob->loss > (unsigned)SFMI_LM_LOSS_TRUNCATED)
        return SFM_E_ARGUMENT;
    if (isnan(prob->loss_scale))
        return SFM_E_NONFINITE;
    if (prob->loss != SFMI_LM_LOSS_SQUARED && !(prob->loss_scale > 0.0 && isfinite(prob->loss_scale)))
        return SFM_E_ARGUMENT;
    const int nt = sfmi_lm_tangent_size(prob->blocks, prob->n_blocks);
    if (nt < 0 || nt > SFMI_LM_DENSE_MAX_TANGENT)
        return SFM_E_ARGUMENT;
    dense_ctx c;
    memset(&c, 0, sizeof c);
    c.p = prob;
    c.nt = nt;
    c.lazy = lazy && !opt->want_covariance && opt->gradient_tolerance == 0.0;
    for (int b = 0, vo = 0, to = 0; b < prob->n_blocks; b++) {
        c.voff[b] = vo;
        c.toff[b] = to;
        vo += prob->blocks[b].size;
        to += block_tangent(&prob->blocks[b]);
        c.nv = vo;
    }
    size_t need = sfmi_lm_dense_workspace_size(c.nv, nt, prob->residual_size);
    if (need == 0)
        return SFM_E_ARGUMENT;
    if (ws == NULL || ws_size < need)
        return SFM_E_WORKSPACE;
    sfmi_arena ar;
    sfmi_arena_init(&ar, ws, ws_size);
    dense_layout(&ar, c.nv, nt, prob->residual_size, &c.w);
    if (!sfmi_arena_ok(&ar))
        return SFM_E_WORKSPACE;
    for (int b = 0; b < prob->n_blocks; b++) {
        const sfmi_lm_block *B = &prob->blocks[b];
        for (int i = 0; i < B->size; i++)
            if (!isfinite(B->x[i]))
                return SFM_E_NONFINITE;
        memcpy(c.w.cur + c.voff[b], B->x, sizeof(double) * (size_t)B->size);
    }
    c.a2 = prob->loss == SFMI_LM_LOSS_SQUARED ? 1.0 : prob->loss_scale * prob->loss_scale;

    sfmi_lm_system sys = {&c, dense_linearize, dense_solve, dense_trial, dense_accept, nt};
    sfmi_lm_summary s;
    int st = sfmi_lm_run(&sys, opt, &s);
    if (st != SFM_OK)
        return st;
    if (opt->want_covariance) {
        /* H is the undamped matrix at the final point: the loop linearises
         * after every accepted step */
        s.covariance_status = SFM_OK;
        if (nt > 0) {
            memcpy(c.w.A, c.w.H, sizeof(double) * (size_t)nt * nt);
            for (int a = 0; a < nt; a++)
                c.w.D[a] = c.w.H[(size_t)a * nt + a];
            if (sfm_cholesky_factor(c.w.A, nt) != SFM_OK || !sfmi_lm_factor_full_rank(c.w.A, c.w.D, nt)) {
                s.covariance_status = SFM_E_SINGULAR;
            } else {
                /* the inverse column by column into cov, then checked */
                double *C = cov;
                for (int a = 0; a < nt * nt; a++)
                    C[a] = 0.0;
                for (int a = 0; a < nt; a++)
                    C[(size_t)a * nt + a] = 1.0;
                if (sfm_cholesky_solve(c.w.A, nt, C, nt) != SFM_OK)
                    s.covariance_status = SFM_E_SINGULAR;
                for (int a = 0; a < nt * nt && s.covariance_status == SFM_OK; a++)
                    if (!isfinite(C[a]))
                        s.covariance_status = SFM_E_SINGULAR;
            }
        }
    }
    for (int b = 0; b < prob->n_blocks; b++)
        memcpy(prob->blocks[b].x, c.w.cur + c.voff[b], sizeof(double) * (size_t)prob->blocks[b].size);
    *summary = s;
    return SFM_OK;
}

int sfmi_lm_dense_solve(const sfmi_lm_problem *prob, const sfmi_lm_options *opt, void *ws,
                        size_t ws_size, sfmi_lm_summary *summary, double *cov)
{
    return dense_run(prob, opt, ws, ws_size, summary, cov, 0);
}

int sfmi_lm_refine(const sfmi_lm_problem *prob, int max_iterations, double function_tolerance,
                   void *ws, size_t ws_size)
{
    sfmi_lm_options opt;
    sfmi_lm_default_options(&opt);
    opt.max_iterations = max_iterations;
    opt.function_tolerance = function_tolerance;
    opt.gradient_tolerance = 0.0;
    sfmi_lm_summary sum;
    /* only whether a step was taken is reported: no linearisation after
     * the last one (the summary's stop may say MAX_ITERATIONS where the
     * gradient was exactly 0, no result differs) */
    if (dense_run(prob, &opt, ws, ws_size, &sum, NULL, 1) != SFM_OK)
        return -1;
    return sum.successful_steps > 0 ? 0 : 1;
}
