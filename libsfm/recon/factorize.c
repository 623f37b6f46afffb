/*
 * Sturm-Triggs projective factorization with missing data (see
 * sfm_factorize.h for the method and the measured convergence).
 */
#include <math.h>
#include <string.h>

#include "core/arena.h"
#include "recon/projective.h"
#include "recon/projective_ba.h"
#include "sfm/sfm_factorize.h"
#include "sfm/sfm_linalg.h"

typedef struct fz_ws {
    double *xn;      /* m x n x 2 normalized observations, NaN missing */
    double *D;       /* 3m x n block measurement matrix, row-major */
    double *z;       /* m x n depths of the block (view-major) */
    double *G;       /* 3m x 3m Gram matrix */
    double *V;       /* 3m x 3m eigenvectors */
    double *ev;      /* 3m eigenvalues */
    double *A;       /* m x m per-track matrix */
    double *Av;      /* m x m eigenvectors */
    double *U;       /* 3m x 4 */
    double *X;       /* n x 4 normalized-frame points */
    double *Pn;      /* m x 12 normalized-frame cameras */
    int *pt_ok;      /* n */
    int *view_ok;    /* m */
    int *bpts;       /* n block tracks */
    int *seen;       /* n scratch counts */
    void *eig_ws;
    size_t eig_size;
    int *obs_cam, *obs_pt, *first; /* observations grouped by track */
    double *obs_xy;
    void *ba_ws;
    size_t ba_size;
} fz_ws;

static void layout(sfmi_arena *a, int m, int n, fz_ws *w)
{
    size_t mn = (size_t)m * (size_t)n;
    w->xn = SFM_ARENA_ARRAY(a, double, 2 * mn);
    w->D = SFM_ARENA_ARRAY(a, double, 3 * mn);
    w->z = SFM_ARENA_ARRAY(a, double, mn);
    w->G = SFM_ARENA_ARRAY(a, double, 9 * (size_t)m * m);
    w->V = SFM_ARENA_ARRAY(a, double, 9 * (size_t)m * m);
    w->ev = SFM_ARENA_ARRAY(a, double, 3 * (size_t)m);
    w->A = SFM_ARENA_ARRAY(a, double, (size_t)m * m);
    w->Av = SFM_ARENA_ARRAY(a, double, (size_t)m * m);
    w->U = SFM_ARENA_ARRAY(a, double, 12 * (size_t)m);
    w->X = SFM_ARENA_ARRAY(a, double, 4 * (size_t)n);
    w->Pn = SFM_ARENA_ARRAY(a, double, 12 * (size_t)m);
    w->pt_ok = SFM_ARENA_ARRAY(a, int, n);
    w->view_ok = SFM_ARENA_ARRAY(a, int, m);
    w->bpts = SFM_ARENA_ARRAY(a, int, n);
    w->seen = SFM_ARENA_ARRAY(a, int, n);
    int big = 3 * m > 12 ? 3 * m : 12;
    w->eig_size = sfm_sym_eig_workspace_size(big);
    w->eig_ws = sfmi_arena_alloc(a, w->eig_size);
    w->obs_cam = SFM_ARENA_ARRAY(a, int, mn);
    w->obs_pt = SFM_ARENA_ARRAY(a, int, mn);
    w->first = SFM_ARENA_ARRAY(a, int, (size_t)n + 1);
    w->obs_xy = SFM_ARENA_ARRAY(a, double, 2 * mn);
    w->ba_size = sfmi_projective_ba_workspace_size(m, n, (int)mn);
    w->ba_ws = sfmi_arena_alloc(a, w->ba_size);
}

int sfm_factorize_default_options(sfm_factorize_options *opt)
{
    if (opt == NULL)
        return SFM_E_ARGUMENT;
    opt->max_iterations = 200;
    opt->tolerance = 1e-7;
    opt->ba_iterations = 100;
    return SFM_OK;
}

size_t sfm_factorize_workspace_size(int m, int n)
{
    if (m < 2 || m > SFM_FACTORIZE_MAX_VIEWS || n < SFM_FACTORIZE_MIN_BLOCK_POINTS ||
        n > SFM_FACTORIZE_MAX_POINTS)
        return 0;
    sfmi_arena a;
    fz_ws w;
    sfmi_arena_measure(&a);
    layout(&a, m, n, &w);
    return sfmi_arena_required(&a);
}

static int observed(const double *x, int m, int n, int i, int j)
{
    (void)m;
    const double *p = &x[((size_t)i * n + j) * 2];
    return !isnan(p[0]) && !isnan(p[1]);
}

/* Greedy complete block: starting from every view, drop the view whose
 * removal leaves the most observations k * p, while that grows. */
static int choose_block(const double *x, int m, int n, int *in_block, int *bpts, int *cnt_scratch,
                        int *k_out)
{
    for (int i = 0; i < m; i++)
        in_block[i] = 1;
    int k = m;
    for (;;) {
        /* complete tracks of the current set, and for each view v the
         * tracks complete once v is dropped */
        long best_area = -1;
        int best_drop = -1;
        int p = 0;
        for (int j = 0; j < n; j++) {
            int miss = 0, last = -1;
            for (int i = 0; i < m; i++)
                if (in_block[i] && !observed(x, m, n, i, j)) {
                    miss++;
                    last = i;
                }
            cnt_scratch[j] = miss == 0 ? -1 : (miss == 1 ? last : -2);
            p += miss == 0;
        }
        long area_now = (long)k * p;
        if (k > 2) {
            for (int v = 0; v < m; v++) {
                if (!in_block[v])
                    continue;
                long pv = 0;
                for (int j = 0; j < n; j++)
                    pv += cnt_scratch[j] == -1 || cnt_scratch[j] == v;
                long area = (long)(k - 1) * pv;
                if (area > best_area) {
                    best_area = area;
                    best_drop = v;
                }
            }
        }
        if (best_drop < 0 || (best_area <= area_now && p >= SFM_FACTORIZE_MIN_BLOCK_POINTS))
            break;
        in_block[best_drop] = 0;
        k--;
    }
    int p = 0;
    for (int j = 0; j < n; j++) {
        int all = 1;
        for (int i = 0; i < m && all; i++)
            if (in_block[i] && !observed(x, m, n, i, j))
                all = 0;
        if (all)
            bpts[p++] = j;
    }
    *k_out = k;
    return p;
}

/* D (3k x p) from the depths z and the block's observations, its Gram
 * matrix D D^T, its eigenvalues (w->ev, ascending) and the dominant rank-4
 * subspace U (3k x 4, largest first); *tr = trace(D D^T). */
static int dominant_subspace(fz_ws *w, const int *views, int k, int p, int n, double *tr)
{
    const int r3 = 3 * k;
    for (int a = 0; a < k; a++)
        for (int b = 0; b < p; b++) {
            const double *q = &w->xn[((size_t)views[a] * n + w->bpts[b]) * 2];
            double zz = w->z[(size_t)a * p + b];
            w->D[(size_t)(3 * a) * p + b] = zz * q[0];
            w->D[(size_t)(3 * a + 1) * p + b] = zz * q[1];
            w->D[(size_t)(3 * a + 2) * p + b] = zz;
        }
    *tr = 0;
    for (int r = 0; r < r3; r++)
        for (int c = 0; c <= r; c++) {
            const double *dr = &w->D[(size_t)r * p], *dc = &w->D[(size_t)c * p];
            double s = 0;
            for (int b = 0; b < p; b++)
                s += dr[b] * dc[b];
            w->G[r * r3 + c] = w->G[c * r3 + r] = s;
            if (r == c)
                *tr += s;
        }
    int st = sfm_sym_eig(w->G, r3, w->ev, w->V, w->eig_ws, w->eig_size);
    if (st < 0)
        return st;
    for (int c = 0; c < 4; c++)
        for (int r = 0; r < r3; r++)
            w->U[r * 4 + c] = w->V[r * r3 + (r3 - 1 - c)];
    return SFM_OK;
}

/* Sturm-Triggs iteration on the block; fills U (3k x 4, the block's
 * cameras in normalized coordinates) and the block points in w->X. */
static int iterate_block(fz_ws *w, int m, int n, const int *views, int k, int p,
                         const sfm_factorize_options *o, sfm_factorize_result *res)
{
    const int r3 = 3 * k;
    for (int a = 0; a < k; a++)
        for (int b = 0; b < p; b++)
            w->z[(size_t)a * p + b] = 1.0;
    double prev = HUGE_VAL, prev_step = -1;
    res->monotone = 1;
    res->converged = 0;
    res->iterations = 0;
    for (int it = 0; it < o->max_iterations; it++) {
        /* balance: column norms 1, then each view's rows to sqrt(p/k) */
        for (int pass = 0; pass < 3; pass++) {
            for (int b = 0; b < p; b++) {
                double s = 0;
                for (int a = 0; a < k; a++) {
                    const double *q = &w->xn[((size_t)views[a] * n + w->bpts[b]) * 2];
                    double zz = w->z[(size_t)a * p + b];
                    s += zz * zz * (q[0] * q[0] + q[1] * q[1] + 1.0);
                }
                s = 1.0 / sqrt(s);
                for (int a = 0; a < k; a++)
                    w->z[(size_t)a * p + b] *= s;
            }
            for (int a = 0; a < k; a++) {
                double s = 0;
                for (int b = 0; b < p; b++) {
                    const double *q = &w->xn[((size_t)views[a] * n + w->bpts[b]) * 2];
                    double zz = w->z[(size_t)a * p + b];
                    s += zz * zz * (q[0] * q[0] + q[1] * q[1] + 1.0);
                }
                s = sqrt((double)p / (double)k / s);
                for (int b = 0; b < p; b++)
                    w->z[(size_t)a * p + b] *= s;
            }
        }
        double tr;
        int st = dominant_subspace(w, views, k, p, n, &tr);
        if (st < 0)
            return st;
        double top = w->ev[r3 - 1] + w->ev[r3 - 2] + w->ev[r3 - 3] + w->ev[r3 - 4];
        if (!(w->ev[r3 - 4] > 1e-12 * tr))
            return SFM_E_SINGULAR;
        double resid = 1.0 - top / tr;
        if (resid < 0)
            resid = 0;
        if (it == 0)
            res->first_residual = resid;
        if (resid > prev * (1 + 1e-9) + 1e-15)
            res->monotone = 0;
        prev = resid;
        res->last_residual = resid;
        res->iterations = it + 1;
        /* depth update, track by track */
        double change = 0;
        for (int b = 0; b < p; b++) {
            double B[4 * SFM_FACTORIZE_MAX_VIEWS], qn[SFM_FACTORIZE_MAX_VIEWS];
            for (int a = 0; a < k; a++) {
                const double *q = &w->xn[((size_t)views[a] * n + w->bpts[b]) * 2];
                qn[a] = sqrt(q[0] * q[0] + q[1] * q[1] + 1.0);
                double u[3] = {q[0] / qn[a], q[1] / qn[a], 1.0 / qn[a]};
                for (int c = 0; c < 4; c++)
                    B[c * k + a] = w->U[(3 * a) * 4 + c] * u[0] + w->U[(3 * a + 1) * 4 + c] * u[1] +
                                   w->U[(3 * a + 2) * 4 + c] * u[2];
            }
            for (int a1 = 0; a1 < k; a1++)
                for (int a2 = 0; a2 <= a1; a2++) {
                    double s = 0;
                    for (int c = 0; c < 4; c++)
                        s += B[c * k + a1] * B[c * k + a2];
                    w->A[a1 * k + a2] = w->A[a2 * k + a1] = s;
                }
            st = sfm_sym_eig(w->A, k, w->ev, w->Av, w->eig_ws, w->eig_size); /* w->ev reused */
            if (st < 0)
                return st;
            double sum = 0, old = 0;
            for (int a = 0; a < k; a++) {
                sum += w->Av[a * k + (k - 1)];
                double zz = w->z[(size_t)a * p + b];
                old += zz * zz * qn[a] * qn[a];
            }
            double sg = sum < 0 ? -1.0 : 1.0;
            old = 1.0 / sqrt(old);
            for (int a = 0; a < k; a++) {
                double wn = sg * w->Av[a * k + (k - 1)];
                double wo = w->z[(size_t)a * p + b] * qn[a] * old;
                double d = fabs(wn - wo);
                if (d > change)
                    change = d;
                w->z[(size_t)a * p + b] = wn / qn[a];
            }
        }
        /* settled: the depths, or the residual they minimize, stopped moving */
        if (change < o->tolerance || (it > 0 && fabs(res->first_residual) > 0 &&
                                      prev_step >= 0 && prev_step - resid <= o->tolerance * resid)) {
            res->converged = 1;
            break;
        }
        prev_step = resid;
    }
    /* final factorization with the settled depths: D = U (U^T D) */
    double tr;
    int st = dominant_subspace(w, views, k, p, n, &tr);
    if (st < 0)
        return st;
    for (int b = 0; b < p; b++) {
        double *Xj = &w->X[4 * (size_t)w->bpts[b]];
        for (int c = 0; c < 4; c++) {
            double s = 0;
            for (int r = 0; r < r3; r++)
                s += w->U[r * 4 + c] * w->D[(size_t)r * p + b];
            Xj[c] = s;
        }
        sfmi_normalize4(Xj);
        w->pt_ok[w->bpts[b]] = 1;
    }
    for (int a = 0; a < k; a++) {
        double *Pa = &w->Pn[12 * views[a]];
        for (int r = 0; r < 3; r++)
            for (int c = 0; c < 4; c++)
                Pa[r * 4 + c] = w->U[(3 * a + r) * 4 + c];
        w->view_ok[views[a]] = 1;
    }
    (void)m;
    return SFM_OK;
}

/* RMS reprojection error (pixels) over the observations of the recovered
 * tracks under pixel cameras P. */
static double pixel_rms(const double *x, int m, int n, const double *P, const double *X, const int *pt_ok,
                        int *nobs_out, int *nrec_out)
{
    double se = 0;
    int nobs = 0, nrec = 0;
    for (int j = 0; j < n; j++) {
        if (!pt_ok[j])
            continue;
        nrec++;
        for (int i = 0; i < m; i++) {
            if (!observed(x, m, n, i, j))
                continue;
            double e2;
            if (sfmi_reproj_err2(&P[12 * i], &X[4 * (size_t)j], &x[((size_t)i * n + j) * 2], &e2))
                se += e2;
            else
                se += 1e12; /* a point on the camera's principal plane */
            nobs++;
        }
    }
    *nobs_out = nobs;
    *nrec_out = nrec;
    return nobs > 0 ? sqrt(se / nobs) : 0.0;
}

int sfm_factorize_projective(int m, int n, const double *x, const sfm_factorize_options *opt,
                             double *P, double *X, sfm_factorize_result *result, void *ws,
                             size_t ws_size)
{
    if (x == NULL || P == NULL || X == NULL || ws == NULL || m < 2 || m > SFM_FACTORIZE_MAX_VIEWS ||
        n < SFM_FACTORIZE_MIN_BLOCK_POINTS || n > SFM_FACTORIZE_MAX_POINTS)
        return SFM_E_ARGUMENT;
    sfm_factorize_options o;
    if (opt != NULL)
        o = *opt;
    else
        sfm_factorize_default_options(&o);
    if (o.max_iterations < 1 || !(o.tolerance > 0) || !isfinite(o.tolerance) || o.ba_iterations < 0)
        return SFM_E_ARGUMENT;
    for (size_t i = 0; i < 2 * (size_t)m * n; i++)
        if (isinf(x[i]))
            return SFM_E_NONFINITE;
    sfmi_arena a;
    fz_ws w;
    sfmi_arena_init(&a, ws, ws_size);
    layout(&a, m, n, &w);
    if (!sfmi_arena_ok(&a))
        return SFM_E_WORKSPACE;

    double Tn[9 * SFM_FACTORIZE_MAX_VIEWS];
    for (int i = 0; i < m; i++) {
        int st = sfmi_hartley_view(&x[(size_t)i * n * 2], n, &Tn[9 * i], &w.xn[(size_t)i * n * 2]);
        if (st < 0)
            return st;
    }
    int in_block[SFM_FACTORIZE_MAX_VIEWS], views[SFM_FACTORIZE_MAX_VIEWS], k;
    int p = choose_block(w.xn, m, n, in_block, w.bpts, w.seen, &k);
    if (p < SFM_FACTORIZE_MIN_BLOCK_POINTS || k < 2)
        return SFM_E_SINGULAR;
    for (int i = 0, c = 0; i < m; i++)
        if (in_block[i])
            views[c++] = i;
    memset(w.pt_ok, 0, sizeof(int) * (size_t)n);
    memset(w.view_ok, 0, sizeof(int) * (size_t)m);
    sfm_factorize_result res;
    memset(&res, 0, sizeof res);
    res.block_views = k;
    res.block_points = p;
    int st = iterate_block(&w, m, n, views, k, p, &o, &res);
    if (st < 0)
        return st;

    /* grow: triangulate tracks seen by >= 2 known views, resection views
     * seeing >= 6 known points, until nothing changes */
    for (int changed = 1; changed;) {
        changed = 0;
        for (int j = 0; j < n; j++) {
            if (w.pt_ok[j])
                continue;
            int c = 0;
            for (int i = 0; i < m; i++)
                c += w.view_ok[i] && observed(w.xn, m, n, i, j);
            if (c < 2)
                continue;
            if (sfmi_triangulate_homog(m, n, w.xn, w.Pn, w.view_ok, j, &w.X[4 * (size_t)j], w.eig_ws,
                                       w.eig_size) == SFM_OK) {
                w.pt_ok[j] = 1;
                changed = 1;
            }
        }
        for (int i = 0; i < m; i++) {
            if (w.view_ok[i])
                continue;
            int c = 0;
            for (int j = 0; j < n; j++)
                c += w.pt_ok[j] && observed(w.xn, m, n, i, j);
            if (c < 6)
                continue;
            st = sfmi_resection_dlt(&w.xn[(size_t)i * n * 2], n, w.X, w.pt_ok, &w.Pn[12 * i],
                                    w.eig_ws, w.eig_size);
            if (st == SFM_OK) {
                w.view_ok[i] = 1;
                changed = 1;
            } else if (st != SFM_E_SINGULAR) {
                return st;
            }
        }
    }
    for (int i = 0; i < m; i++)
        if (!w.view_ok[i])
            return SFM_E_SINGULAR;

    {
        double Pf[12 * SFM_FACTORIZE_MAX_VIEWS];
        for (int i = 0; i < m; i++)
            sfmi_denormalize_camera(&Tn[9 * i], &w.Pn[12 * i], &Pf[12 * i]);
        int no, nr;
        res.factorization_rms = pixel_rms(x, m, n, Pf, w.X, w.pt_ok, &no, &nr);
    }
    /* projective bundle adjustment over every observation of the
     * recovered tracks, in pixels */
    if (o.ba_iterations > 0) {
        int nobs = 0;
        double iscale[SFM_FACTORIZE_MAX_VIEWS];
        for (int i = 0; i < m; i++)
            iscale[i] = 1.0 / Tn[9 * i];
        for (int j = 0; j < n; j++) {
            w.first[j] = nobs;
            if (!w.pt_ok[j]) {
                double *Xj = &w.X[4 * (size_t)j];
                Xj[0] = Xj[1] = Xj[2] = 0;
                Xj[3] = 1; /* held: no observations */
                continue;
            }
            for (int i = 0; i < m; i++)
                if (observed(w.xn, m, n, i, j)) {
                    w.obs_cam[nobs] = i;
                    w.obs_pt[nobs] = j;
                    w.obs_xy[2 * nobs] = w.xn[((size_t)i * n + j) * 2];
                    w.obs_xy[2 * nobs + 1] = w.xn[((size_t)i * n + j) * 2 + 1];
                    nobs++;
                }
        }
        w.first[n] = nobs;
        sfmi_lm_summary sum;
        st = sfmi_projective_ba(m, n, nobs, w.obs_cam, w.obs_pt, w.first, w.obs_xy, iscale, w.Pn, w.X,
                                o.ba_iterations, &sum, w.ba_ws, w.ba_size);
        if (st < 0)
            return st == SFM_E_NONFINITE ? SFM_E_SINGULAR : st;
        res.ba_iterations = sum.iterations;
        res.ba_stop = (int)sum.stop;
    }

    /* back to pixels: P_i = T_i^{-1} Pn_i */
    double Pout[12 * SFM_FACTORIZE_MAX_VIEWS];
    for (int i = 0; i < m; i++)
        sfmi_denormalize_camera(&Tn[9 * i], &w.Pn[12 * i], &Pout[12 * i]);
    int nobs, nrec;
    res.reproj_rms = pixel_rms(x, m, n, Pout, w.X, w.pt_ok, &nobs, &nrec);
    res.points_recovered = nrec;
    res.n_observations = nobs;
    memcpy(P, Pout, sizeof(double) * 12 * (size_t)m);
    for (int j = 0; j < n; j++) {
        if (w.pt_ok[j])
            memcpy(&X[4 * (size_t)j], &w.X[4 * (size_t)j], 4 * sizeof(double));
        else
            memset(&X[4 * (size_t)j], 0, 4 * sizeof(double));
    }
    if (result != NULL)
        *result = res;
    return SFM_OK;
}
