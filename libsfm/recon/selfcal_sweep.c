/*
 * m-view self-calibration with points: the linear dual quadric, a search
 * over one shared focal length scored by metric bundle adjustment, then the
 * focal length free (see sfm_selfcal.h).
 *
 * With K fixed, the dual image of the absolute conic in the coordinates
 * K_i^{-1} x is w*_i ~ I (Hartley & Zisserman 2nd ed., 19.3; Pollefeys et
 * al., IJCV 1999): w_01 = w_02 = w_12 = 0 and w_00 = w_11 = w_22, linear in
 * Q*, so each candidate f has its own plane at infinity without the
 * ambiguity of the unknown-f system. A candidate is then judged by what the
 * data say of it, the reprojection cost of the metric reconstruction
 * refined with f held (the profile of the cost over f), as the focal sweeps
 * of the uncalibrated pipelines do from fundamental matrices.
 */
#include <math.h>
#include <stdint.h>
#include <string.h>

#include "core/arena.h"
#include "core/dmath.h"
#include "core/linalg_util.h"
#include "recon/focal_search.h"
#include "recon/selfcal_internal.h"
#include "sfm/sfm_ba.h"
#include "sfm/sfm_camera.h"
#include "sfm/sfm_linalg.h"
#include "sfm/sfm_rotation.h"
#include "sfm/sfm_selfcal.h"

_Static_assert(SFM_SELFCAL_MAX_VIEWS <= 32, "a view mask per point is one uint32_t");

#define SWEEP_ITERS 30
#define GOLDEN_STEPS 14
#define PROFILE_STEP 0.05 /* log f */
#define FAR_FACTOR 1.5

typedef struct ctx {
    int m, n, nobs;
    const double *P, *wh, *X;
    const int *oc, *op;
    const double *oxy;
    const sfm_selfcal_options *o;
    /* carved */
    int *bo_cam, *bo_pt; /* BA observations (compacted) */
    double *bo_xy;
    int *pmap;           /* n: BA point of input point j, -1 dropped */
    int *pidx;           /* n: input point of BA point k */
    int *nseen;          /* n: observations of input point j */
    uint32_t *flag;      /* n: scratch (a mask of the views seeing point j
                            while the observations are checked) */
    double *Xw, *Xb;     /* n x 3: BA points, a copy */
    double *R, *t, *Rb, *tb; /* m x 9, m x 3 and copies */
    sfm_camera *cams;    /* m */
    double *Ps;          /* m x 12: the cameras, scaled (sfmi_selfcal_scale_cameras) */
    void *ba_ws;
    size_t ba_size;
    /* state of the last start */
    int np, no, dropped, scale_cam;
    double H[16];
    double pp[2 * SFM_SELFCAL_MAX_VIEWS]; /* principal points of the adjustments */
    int evaluations;
} ctx;

int sfm_selfcal_default_options(sfm_selfcal_options *o)
{
    if (o == NULL)
        return SFM_E_ARGUMENT;
    o->sweep = SFM_SELFCAL_SWEEP_ALWAYS;
    o->sweep_steps = 17;
    o->focal_min = 0.25;
    o->focal_max = 4;
    o->per_view_focal = 0;
    o->principal = SFM_SELFCAL_PRINCIPAL_CENTRE;
    o->loss_scale = 2;
    o->max_rms = 1;
    o->min_front = 0.95;
    o->min_profile = 100;
    o->max_focal_sigma = 0.05 / 3;
    o->max_iterations = 100;
    return SFM_OK;
}

static int options_ok(const sfm_selfcal_options *o)
{
    return (o->per_view_focal == 0 || o->per_view_focal == 1) && o->principal >= 0 && o->principal <= 2 &&
           (o->sweep == SFM_SELFCAL_SWEEP_ALWAYS || o->sweep == SFM_SELFCAL_SWEEP_WHEN_NEEDED) &&
           o->sweep_steps >= 3 && o->sweep_steps <= SFM_SELFCAL_MAX_SWEEP && o->focal_min > 0 &&
           o->focal_max > o->focal_min && isfinite(o->focal_max) && o->loss_scale > 0 &&
           isfinite(o->loss_scale) && o->max_rms > 0 && o->min_front >= 0 && o->min_front <= 1 &&
           o->min_profile >= 0 && isfinite(o->min_profile) && o->max_focal_sigma > 0 &&
           o->max_iterations >= 1;
}

static void layout(sfmi_arena *a, int m, int n, int nobs, ctx *c)
{
    c->bo_cam = SFM_ARENA_ARRAY(a, int, nobs);
    c->bo_pt = SFM_ARENA_ARRAY(a, int, nobs);
    c->bo_xy = SFM_ARENA_ARRAY(a, double, 2 * (size_t)nobs);
    c->pmap = SFM_ARENA_ARRAY(a, int, n);
    c->pidx = SFM_ARENA_ARRAY(a, int, n);
    c->nseen = SFM_ARENA_ARRAY(a, int, n);
    c->flag = SFM_ARENA_ARRAY(a, uint32_t, n);
    c->Xw = SFM_ARENA_ARRAY(a, double, 3 * (size_t)n);
    c->Xb = SFM_ARENA_ARRAY(a, double, 3 * (size_t)n);
    c->R = SFM_ARENA_ARRAY(a, double, 9 * (size_t)m);
    c->t = SFM_ARENA_ARRAY(a, double, 3 * (size_t)m);
    c->Rb = SFM_ARENA_ARRAY(a, double, 9 * (size_t)m);
    c->tb = SFM_ARENA_ARRAY(a, double, 3 * (size_t)m);
    c->cams = SFM_ARENA_ARRAY(a, sfm_camera, m);
    c->Ps = SFM_ARENA_ARRAY(a, double, 12 * (size_t)m);
    size_t ba = 0;
    const sfm_ba_intrinsics modes[3] = {SFM_BA_INTRINSICS_FIXED, SFM_BA_INTRINSICS_SHARED,
                                        SFM_BA_INTRINSICS_PER_CAMERA};
    for (int k = 0; k < 3; k++) {
        sfm_ba_dims d = {m, n, nobs, modes[k], k ? SFM_BA_REFINE_FOCAL | SFM_BA_REFINE_PRINCIPAL : 0};
        size_t s = sfm_ba_workspace_size(&d);
        if (s == 0)
            a->failed = 1;
        ba = s > ba ? s : ba;
    }
    c->ba_size = ba;
    c->ba_ws = sfmi_arena_alloc(a, ba);
}

size_t sfm_selfcal_workspace_size(int m, int n, int n_obs)
{
    if (m < 3 || m > SFM_SELFCAL_MAX_VIEWS || n < 1 || n_obs < 1)
        return 0;
    sfmi_arena a;
    ctx c;
    sfmi_arena_measure(&a);
    layout(&a, m, n, n_obs, &c);
    return a.failed ? 0 : sfmi_arena_required(&a);
}

static void centre(const ctx *c, int i, double *cx, double *cy)
{
    *cx = 0.5 * (c->wh[2 * i] - 1);
    *cy = 0.5 * (c->wh[2 * i + 1] - 1);
}

/* The rectifying H of the shared focal length f: the dual quadric with K
 * known (see the file comment). SFM_E_SINGULAR when Q* is not
 * semi-definite, w*_1 not definite or the plane at infinity cuts the scene. */
static int known_k_upgrade(const ctx *c, double f, double H[16])
{
    const int m = c->m;
    unsigned char ews[2048]; /* sfm_sym_eig for n <= 10 (as selfcal.c) */
    double Pc[SFM_SELFCAL_MAX_VIEWS][12], H0[16];
    for (int i = 0; i < m; i++) {
        double cx, cy;
        centre(c, i, &cx, &cy);
        sfmi_selfcal_condition(&c->P[12 * i], cx, cy, f, Pc[i]);
    }
    int st = sfmi_selfcal_frame(m, Pc, H0, ews, sizeof ews);
    if (st < 0)
        return st;
    double nu[SFM_SELFCAL_MAX_VIEWS], Q[16];
    for (int i = 0; i < m; i++)
        nu[i] = 1;
    for (int pass = 0; pass < 2; pass++) {
        double A[100] = {0};
        for (int i = 0; i < m; i++) {
            /* the rows of solve_adq (selfcal.c), all at one weight: K is known */
            double r[6][10];
            sfmi_selfcal_adq_rows(Pc[i], r);
            const double iw = 1.0 / nu[i];
            for (int k = 0; k < 6; k++)
                sfmi_selfcal_add_row(A, r[k], iw);
        }
        double w10[10], V10[100];
        st = sfm_sym_eig(A, 10, w10, V10, ews, sizeof ews);
        if (st < 0)
            return st;
        double q[10];
        for (int k = 0; k < 10; k++)
            q[k] = V10[k * 10];
        sfmi_selfcal_set_q(q, m, (const double(*)[12])Pc, Q, nu);
    }
    int flags = 0;
    st = sfmi_selfcal_rank3(Q, &flags, ews, sizeof ews);
    if (st < 0)
        return st;
    if (flags)
        return SFM_E_SINGULAR;
    double W[9], K1[9];
    sfmi_selfcal_omega(Pc[0], Q, W);
    if (!sfmi_selfcal_upper_cholesky(W, K1))
        return SFM_E_SINGULAR;
    sfm_selfcal_result res;
    memset(&res, 0, sizeof res);
    return sfmi_selfcal_rectify(m, c->P, Q, K1, H0, c->n, c->X, H, &res);
}

/* A start from H (P_i H ~ K(fv_i) [R_i | t_i]): poses (camera 1 at the
 * identity, the farthest centre at distance 1), H moved to that frame, the
 * points H^{-1} X kept where they are finite and in front of every camera
 * that sees them, the BA observations. SFM_E_SINGULAR when no metric
 * cameras follow. */
static int start_from_h(ctx *c, const double Hin[16], const double *fv)
{
    const int m = c->m;
    double Rr[SFM_SELFCAL_MAX_VIEWS][9], tr[SFM_SELFCAL_MAX_VIEWS][3];
    for (int i = 0; i < m; i++) {
        double Pm[12], cx, cy, M[9];
        sfmi_selfcal_mul34_44(&c->P[12 * i], Hin, Pm);
        centre(c, i, &cx, &cy);
        sfmi_selfcal_condition(Pm, cx, cy, fv[i], Pm); /* K^{-1} Pm */
        for (int r = 0; r < 3; r++)
            for (int k = 0; k < 3; k++)
                M[3 * r + k] = Pm[4 * r + k];
        double d = sfmi_selfcal_det3(M);
        if (!(fabs(d) > 0) || !isfinite(d))
            return SFM_E_SINGULAR;
        double s = sfmi_cbrt(d); /* sign included: -P is the same camera */
        for (int k = 0; k < 9; k++)
            M[k] /= s;
        if (sfm_rot_nearest(M, Rr[i]) < 0)
            return SFM_E_SINGULAR;
        for (int r = 0; r < 3; r++)
            tr[i][r] = Pm[4 * r + 3] / s;
    }
    /* centres c_i = -R_i^T t_i; frame of camera 1, farthest centre at 1 */
    double C0[3], dmax = 0;
    int far = 1;
    for (int r = 0; r < 3; r++)
        C0[r] = -(Rr[0][r] * tr[0][0] + Rr[0][3 + r] * tr[0][1] + Rr[0][6 + r] * tr[0][2]);
    for (int i = 1; i < m; i++) {
        double d2 = 0;
        for (int r = 0; r < 3; r++) {
            double ci = -(Rr[i][r] * tr[i][0] + Rr[i][3 + r] * tr[i][1] + Rr[i][6 + r] * tr[i][2]);
            d2 += (ci - C0[r]) * (ci - C0[r]);
        }
        if (d2 > dmax)
            dmax = d2, far = i;
    }
    if (!(dmax > 0) || !isfinite(dmax))
        return SFM_E_SINGULAR;
    const double sig = 1 / sqrt(dmax);
    const double *R0 = Rr[0], *t0 = tr[0];
    /* X_old = R0^T (X_new / sig - t0): T = [R0^T, -sig R0^T t0; 0, sig] */
    double T[16] = {0}, Ht[16];
    for (int r = 0; r < 3; r++) {
        for (int k = 0; k < 3; k++)
            T[4 * r + k] = R0[3 * k + r];
        T[4 * r + 3] = -sig * (R0[r] * t0[0] + R0[3 + r] * t0[1] + R0[6 + r] * t0[2]);
    }
    T[15] = sig;
    sfmi_selfcal_mul44(Hin, T, Ht);
    for (int i = 0; i < m; i++) {
        /* R_i' = R_i R0^T, t_i' = sig (t_i - R_i' t0) */
        double *Ri = &c->R[9 * i], *ti = &c->t[3 * i];
        for (int r = 0; r < 3; r++)
            for (int k = 0; k < 3; k++)
                Ri[3 * r + k] = Rr[i][3 * r] * R0[3 * k] + Rr[i][3 * r + 1] * R0[3 * k + 1] +
                                Rr[i][3 * r + 2] * R0[3 * k + 2];
        for (int r = 0; r < 3; r++)
            ti[r] = sig * (tr[i][r] - (Ri[3 * r] * t0[0] + Ri[3 * r + 1] * t0[1] + Ri[3 * r + 2] * t0[2]));
    }
    memset(c->R, 0, 9 * sizeof(double));
    c->R[0] = c->R[4] = c->R[8] = 1;
    c->t[0] = c->t[1] = c->t[2] = 0;
    double Hi[16];
    if (!sfmi_selfcal_inv44(Ht, Hi))
        return SFM_E_SINGULAR;
    memcpy(c->H, Ht, sizeof Ht);
    c->scale_cam = far;
    /* points */
    int np = 0;
    for (int j = 0; j < c->n; j++) {
        c->pmap[j] = -1;
        const double *Xj = &c->X[4 * (size_t)j];
        if (c->nseen[j] < 2)
            continue;
        double Y[4];
        for (int r = 0; r < 4; r++)
            Y[r] = Hi[4 * r] * Xj[0] + Hi[4 * r + 1] * Xj[1] + Hi[4 * r + 2] * Xj[2] + Hi[4 * r + 3] * Xj[3];
        double nrm = fabs(Y[0]) + fabs(Y[1]) + fabs(Y[2]);
        if (!(fabs(Y[3]) > 1e-9 * nrm))
            continue;
        double *Xo = &c->Xw[3 * (size_t)np];
        for (int r = 0; r < 3; r++)
            Xo[r] = Y[r] / Y[3];
        if (!sfmi_la_all_finite(Xo, 3))
            continue;
        c->pmap[j] = np;
        c->pidx[np++] = j;
    }
    /* observations; a point behind a camera that sees it is dropped */
    for (int k = 0; k < np; k++)
        c->flag[k] = 0;
    for (int k = 0; k < c->nobs; k++) {
        int pk = c->pmap[c->op[k]];
        if (pk < 0)
            continue;
        const double *Ri = &c->R[9 * c->oc[k]], *ti = &c->t[3 * c->oc[k]], *Xo = &c->Xw[3 * (size_t)pk];
        if (!(Ri[6] * Xo[0] + Ri[7] * Xo[1] + Ri[8] * Xo[2] + ti[2] > 1e-9))
            c->flag[pk] = 1;
    }
    int kept = 0;
    for (int k = 0; k < np; k++) {
        int j = c->pidx[k];
        if (c->flag[k]) {
            c->pmap[j] = -1;
            continue;
        }
        memmove(&c->Xw[3 * (size_t)kept], &c->Xw[3 * (size_t)k], 3 * sizeof(double));
        c->pidx[kept] = j;
        c->pmap[j] = kept++;
    }
    np = kept;
    int no = 0, dropped = 0;
    for (int k = 0; k < c->nobs; k++) {
        int j = c->op[k];
        if (c->nseen[j] < 2)
            continue;
        if (c->pmap[j] < 0) {
            dropped++;
            continue;
        }
        c->bo_cam[no] = c->oc[k];
        c->bo_pt[no] = c->pmap[j];
        c->bo_xy[2 * no] = c->oxy[2 * k];
        c->bo_xy[2 * no + 1] = c->oxy[2 * k + 1];
        no++;
    }
    c->np = np;
    c->no = no;
    c->dropped = dropped;
    if (np < 8 || no < 2 * np)
        return SFM_E_SINGULAR;
    /* every camera must see a point */
    for (int i = 0; i < m; i++) {
        int seen = 0;
        for (int k = 0; k < no && !seen; k++)
            seen = c->bo_cam[k] == i;
        if (!seen)
            return SFM_E_SINGULAR;
    }
    return SFM_OK;
}

/* Metric BA of the current state with focal lengths fv (mode 0 held, 1 one
 * shared free, 2 one per view free, 3 one per view and the principal
 * points free, 4 one shared focal length and principal point free); fv
 * (and c->pp in modes 3 and 4) updated; *cost with the penalty of the
 * dropped observations. */
static int adjust(ctx *c, double *fv, int mode, int max_it, double *cost)
{
    const int m = c->m;
    c->evaluations++;
    for (int i = 0; i < m; i++) {
        memset(&c->cams[i], 0, sizeof(sfm_camera));
        c->cams[i].model = SFM_CAMERA_PINHOLE;
        c->cams[i].fx = c->cams[i].fy = fv[mode == 1 ? 0 : i];
        c->cams[i].cx = c->pp[2 * i];
        c->cams[i].cy = c->pp[2 * i + 1];
    }
    sfm_ba_problem p = {m, c->np, c->no, c->R, c->t, c->cams, c->Xw, c->bo_cam, c->bo_pt, c->bo_xy,
                        NULL, NULL, NULL};
    sfm_ba_options o;
    sfm_ba_default_options(&o);
    o.loss = SFM_BA_LOSS_HUBER;
    o.loss_scale = c->o->loss_scale;
    o.scale_gauge = SFM_BA_SCALE_DISTANCE;
    o.scale_camera = c->scale_cam;
    o.scale_distance = 1.0;
    o.max_iterations = max_it;
    if (mode) {
        o.intrinsics = mode == 1 || mode == 4 ? SFM_BA_INTRINSICS_SHARED : SFM_BA_INTRINSICS_PER_CAMERA;
        o.refine_intrinsics = SFM_BA_REFINE_FOCAL | (mode >= 3 ? SFM_BA_REFINE_PRINCIPAL : 0);
    }
    sfm_ba_result res;
    int st = sfm_ba_solve(&p, &o, &res, NULL, 0, c->ba_ws, c->ba_size);
    if (st < 0)
        return st == SFM_E_ARGUMENT || st == SFM_E_NONFINITE ? SFM_E_SINGULAR : st;
    if (mode == 1)
        for (int i = 0; i < m; i++)
            fv[i] = c->cams[0].fx;
    else if (mode == 4)
        for (int i = 0; i < m; i++) {
            fv[i] = c->cams[0].fx;
            c->pp[2 * i] = c->cams[0].cx;
            c->pp[2 * i + 1] = c->cams[0].cy;
        }
    else if (mode >= 2)
        for (int i = 0; i < m; i++) {
            fv[i] = c->cams[i].fx;
            c->pp[2 * i] = c->cams[i].cx;
            c->pp[2 * i + 1] = c->cams[i].cy;
        }
    *cost = res.final_cost + (double)c->dropped * c->o->loss_scale * c->o->loss_scale;
    return SFM_OK;
}

/* Fixed-focal score of a shared f from its own upgrade; HUGE_VAL when no
 * metric cameras follow. */
static double score(void *ctxp, double f)
{
    ctx *c = ctxp;
    double H[16], fv[SFM_SELFCAL_MAX_VIEWS], cost;
    for (int i = 0; i < c->m; i++)
        fv[i] = f;
    if (known_k_upgrade(c, f, H) != SFM_OK || start_from_h(c, H, fv) != SFM_OK ||
        adjust(c, fv, 0, SWEEP_ITERS, &cost) != SFM_OK)
        return HUGE_VAL;
    return cost;
}

static void save(ctx *c)
{
    memcpy(c->Rb, c->R, 9 * sizeof(double) * (size_t)c->m);
    memcpy(c->tb, c->t, 3 * sizeof(double) * (size_t)c->m);
    memcpy(c->Xb, c->Xw, 3 * sizeof(double) * (size_t)c->np);
}

static void restore(ctx *c)
{
    memcpy(c->R, c->Rb, 9 * sizeof(double) * (size_t)c->m);
    memcpy(c->t, c->tb, 3 * sizeof(double) * (size_t)c->m);
    memcpy(c->Xw, c->Xb, 3 * sizeof(double) * (size_t)c->np);
}

/* Fixed-focal cost at shared f warm-started from the current state (which
 * is kept). */
static double warm_score(ctx *c, double f)
{
    double fv[SFM_SELFCAL_MAX_VIEWS], cost;
    for (int i = 0; i < c->m; i++)
        fv[i] = f;
    save(c);
    int st = adjust(c, fv, 0, SWEEP_ITERS, &cost);
    restore(c);
    return st == SFM_OK ? cost : HUGE_VAL;
}

/* RMS per observation and the share of points in front of every camera
 * that sees them (of those seen twice or more) under the current state. */
static void quality(ctx *c, const double *fv, double *rms, double *front)
{
    double se = 0;
    for (int k = 0; k < c->no; k++) {
        const int i = c->bo_cam[k];
        const double *Ri = &c->R[9 * i], *ti = &c->t[3 * i], *Xo = &c->Xw[3 * (size_t)c->bo_pt[k]];
        double y[3], cx = c->pp[2 * i], cy = c->pp[2 * i + 1];
        for (int r = 0; r < 3; r++)
            y[r] = Ri[3 * r] * Xo[0] + Ri[3 * r + 1] * Xo[1] + Ri[3 * r + 2] * Xo[2] + ti[r];
        double u = fv[i] * y[0] / y[2] + cx - c->bo_xy[2 * k];
        double v = fv[i] * y[1] / y[2] + cy - c->bo_xy[2 * k + 1];
        se += u * u + v * v;
    }
    *rms = c->no > 0 ? sqrt(se / c->no) : HUGE_VAL;
    int seen2 = 0;
    for (int j = 0; j < c->n; j++)
        seen2 += c->nseen[j] >= 2;
    /* the adjustment keeps observed points in front (a step that would
     * cross is rejected); checked again, the dropped ones count as behind */
    for (int k = 0; k < c->np; k++)
        c->flag[k] = 0;
    for (int q = 0; q < c->no; q++) {
        const double *Ri = &c->R[9 * c->bo_cam[q]], *ti = &c->t[3 * c->bo_cam[q]];
        const double *Xo = &c->Xw[3 * (size_t)c->bo_pt[q]];
        if (!(Ri[6] * Xo[0] + Ri[7] * Xo[1] + Ri[8] * Xo[2] + ti[2] > 0))
            c->flag[c->bo_pt[q]] = 1;
    }
    int infront = 0;
    for (int k = 0; k < c->np; k++)
        infront += !c->flag[k];
    *front = seen2 > 0 ? (double)infront / seen2 : 0.0;
}

/* One adjustment in a larger model (mode of adjust) from the current
 * state, kept (state, fv, c->pp, report figures) when every f > 0 and the
 * front and RMS checks pass; 1 when kept. */
static int larger_model(ctx *c, const sfm_selfcal_options *o, int mode, double *fv, sfm_selfcal_report *rep)
{
    const int m = c->m;
    double fp[SFM_SELFCAL_MAX_VIEWS], ppk[2 * SFM_SELFCAL_MAX_VIEWS], cost, rms, front;
    memcpy(fp, fv, sizeof(double) * (size_t)m);
    memcpy(ppk, c->pp, sizeof ppk);
    save(c);
    int ok = adjust(c, fp, mode, o->max_iterations, &cost) == SFM_OK;
    for (int i = 0; i < m && ok; i++)
        ok = fp[i] > 0;
    if (ok) {
        quality(c, fp, &rms, &front);
        ok = front >= o->min_front && rms <= o->max_rms;
    }
    if (!ok) {
        restore(c);
        memcpy(c->pp, ppk, sizeof ppk);
        return 0;
    }
    memcpy(fv, fp, sizeof(double) * (size_t)m);
    rep->rms = rms, rep->front_fraction = front;
    for (int i = 0; i < m; i++)
        rep->focal_view[i] = fv[i];
    if (mode == 4)
        rep->focal = fv[0];
    return 1;
}

/* Free parameters of the adjusted model (poses less the 7 of the gauge,
 * points, nf focal lengths). */
static double noise_variance(const ctx *c, double cost, int nf)
{
    double dof = 2.0 * c->no - (6.0 * c->m - 7 + 3.0 * c->np + nf);
    return dof > 0 ? 2 * cost / dof : HUGE_VAL;
}

int sfm_selfcal_solve(int m, const double *P, const double *wh, int n, const double *X, int n_obs,
                      const int *obs_camera, const int *obs_point, const double *obs_xy,
                      const sfm_selfcal_options *options, double *K, double H[16], sfm_pose *poses,
                      double *Xm, sfm_selfcal_report *report, void *ws, size_t ws_size)
{
    if (P == NULL || wh == NULL || X == NULL || obs_camera == NULL || obs_point == NULL ||
        obs_xy == NULL || K == NULL || H == NULL || report == NULL || m < 3 ||
        m > SFM_SELFCAL_MAX_VIEWS || n < 1 || n_obs < 1)
        return SFM_E_ARGUMENT;
    sfm_selfcal_options o;
    if (options != NULL)
        o = *options;
    else
        sfm_selfcal_default_options(&o);
    if (!options_ok(&o))
        return SFM_E_ARGUMENT;
    for (int i = 0; i < m; i++)
        if (!(wh[2 * i] > 0) || !(wh[2 * i + 1] > 0) ||
            (o.principal == SFM_SELFCAL_PRINCIPAL_SHARED && (wh[2 * i] != wh[0] || wh[2 * i + 1] != wh[1])))
            return SFM_E_ARGUMENT;
    for (int k = 0; k < n_obs; k++)
        if (obs_camera[k] < 0 || obs_camera[k] >= m || obs_point[k] < 0 || obs_point[k] >= n)
            return SFM_E_ARGUMENT;
    if (!sfmi_la_all_finite(P, 12 * (size_t)m) || !sfmi_la_all_finite(wh, 2 * (size_t)m) ||
        !sfmi_la_all_finite(X, 4 * (size_t)n) || !sfmi_la_all_finite(obs_xy, 2 * (size_t)n_obs))
        return SFM_E_NONFINITE;
    size_t need = sfm_selfcal_workspace_size(m, n, n_obs);
    if (ws == NULL || need == 0 || ws_size < need)
        return SFM_E_WORKSPACE;
    ctx c;
    memset(&c, 0, sizeof c);
    sfmi_arena a;
    sfmi_arena_init(&a, ws, ws_size);
    layout(&a, m, n, n_obs, &c);
    if (!sfmi_arena_ok(&a))
        return SFM_E_WORKSPACE;
    sfmi_selfcal_scale_cameras(m, P, c.Ps);
    P = c.Ps;
    c.m = m, c.n = n, c.nobs = n_obs, c.P = P, c.wh = wh, c.X = X;
    c.oc = obs_camera, c.op = obs_point, c.oxy = obs_xy, c.o = &o;
    for (int i = 0; i < m; i++)
        centre(&c, i, &c.pp[2 * i], &c.pp[2 * i + 1]);
    /* a view sees a point once: a repeated (view, point) pair would count
     * one measurement twice (the noise variance and focal_sigma with it) */
    for (int j = 0; j < n; j++)
        c.flag[j] = 0;
    for (int k = 0; k < n_obs; k++) {
        const uint32_t bit = (uint32_t)1 << obs_camera[k];
        if (c.flag[obs_point[k]] & bit)
            return SFM_E_ARGUMENT;
        c.flag[obs_point[k]] |= bit;
    }
    for (int j = 0; j < n; j++)
        c.nseen[j] = 0;
    for (int k = 0; k < n_obs; k++)
        c.nseen[obs_point[k]]++;
    for (int j = 0; j < n; j++) {
        const double *Xj = &X[4 * (size_t)j];
        if (Xj[0] == 0 && Xj[1] == 0 && Xj[2] == 0 && Xj[3] == 0)
            c.nseen[j] = 0;
    }

    sfm_selfcal_report rep;
    memset(&rep, 0, sizeof rep);
    const double s0 = 0.5 * (wh[0] + wh[1]);

    /* 1. linear */
    double Klin[9 * SFM_SELFCAL_MAX_VIEWS], Hlin[16];
    sfm_selfcal_result lr;
    memset(&lr, 0, sizeof lr);
    rep.linear_status = sfm_selfcal_linear(m, P, wh, n, X, Klin, Hlin, &lr);
    rep.linear_flags = lr.flags;
    double best_cost = HUGE_VAL, best_H[16];
    int path = SFM_SELFCAL_PATH_NONE;
    if (rep.linear_status == SFM_OK) {
        double fv[SFM_SELFCAL_MAX_VIEWS], fm = 0, cost;
        for (int i = 0; i < m; i++)
            fv[i] = lr.focal[i], fm += lr.focal[i] / m;
        rep.focal_linear = fm;
        if (start_from_h(&c, Hlin, fv) == SFM_OK) {
            memcpy(best_H, c.H, sizeof best_H);
            for (int i = 0; i < m; i++)
                fv[i] = fm;
            if (adjust(&c, fv, 1, o.max_iterations, &cost) == SFM_OK && fv[0] > 0) {
                best_cost = cost, path = SFM_SELFCAL_PATH_LINEAR;
            }
        }
    }

    /* 2. the focal search */
    const int steps = o.sweep_steps;
    double u_best = 0;
    int swept = o.sweep == SFM_SELFCAL_SWEEP_ALWAYS || path == SFM_SELFCAL_PATH_NONE;
    if (swept) {
        const double u0 = sfmi_log(o.focal_min * s0), du = (sfmi_log(o.focal_max * s0) - u0) / (steps - 1);
        for (int k = 0; k < steps; k++)
            rep.sweep_focal[k] = sfmi_exp(u0 + du * k);
        const int kb = sfmi_focal_sweep(score, &c, rep.sweep_focal, steps, rep.sweep_cost);
        rep.sweep_count = steps;
        if (kb >= 0) {
            /* golden section on log f between the neighbours; a tie keeps
             * the sweep's point, then the lower one */
            double ug[2], sg[2];
            sfmi_focal_golden(score, &c, u0 + du * (kb > 0 ? kb - 1 : kb), u0 + du * (kb < steps - 1 ? kb + 1 : kb),
                              GOLDEN_STEPS, 1, ug, sg);
            u_best = u0 + du * kb;
            double cb = rep.sweep_cost[kb];
            if (sg[0] < cb)
                u_best = ug[0], cb = sg[0];
            if (sg[1] < cb)
                u_best = ug[1];
            rep.focal_sweep = sfmi_exp(u_best);
            /* the free-focal adjustment from the best candidate */
            double Hs[16], fv[SFM_SELFCAL_MAX_VIEWS], cost;
            for (int i = 0; i < m; i++)
                fv[i] = rep.focal_sweep;
            if (known_k_upgrade(&c, rep.focal_sweep, Hs) == SFM_OK && start_from_h(&c, Hs, fv) == SFM_OK) {
                double Hkeep[16];
                memcpy(Hkeep, c.H, sizeof Hkeep);
                if (adjust(&c, fv, 1, o.max_iterations, &cost) == SFM_OK && fv[0] > 0 &&
                    !(path == SFM_SELFCAL_PATH_LINEAR && best_cost <= cost * (1 + 1e-9))) {
                    best_cost = cost, path = SFM_SELFCAL_PATH_SWEEP;
                    memcpy(best_H, Hkeep, sizeof best_H);
                }
            }
        }
    }
    rep.path = path;
    if (path == SFM_SELFCAL_PATH_NONE) {
        *report = rep;
        return SFM_E_SINGULAR;
    }
    /* the winner's start again (the last one run may be the other): best_H
     * is in the frame of start_from_h, P_i H ~ K(f_i) [R_i | t_i] with the
     * start's focal lengths f_i */
    double fv[SFM_SELFCAL_MAX_VIEWS], cost;
    for (int i = 0; i < m; i++)
        fv[i] = path == SFM_SELFCAL_PATH_LINEAR ? lr.focal[i] : rep.focal_sweep;
    int st = start_from_h(&c, best_H, fv);
    if (st != SFM_OK) {
        *report = rep;
        return SFM_E_SINGULAR;
    }
    memcpy(best_H, c.H, sizeof best_H);
    for (int i = 0; i < m; i++)
        fv[i] = path == SFM_SELFCAL_PATH_LINEAR ? rep.focal_linear : rep.focal_sweep;
    st = adjust(&c, fv, 1, o.max_iterations, &cost);
    if (st != SFM_OK) {
        *report = rep;
        return st == SFM_E_WORKSPACE ? st : SFM_E_SINGULAR;
    }
    rep.focal = fv[0];
    for (int i = 0; i < m; i++)
        rep.focal_view[i] = fv[i];
    rep.points = c.np;
    rep.observations = c.no;

    /* 4. the profile */
    const double var = noise_variance(&c, cost, 1);
    rep.noise_sigma = sqrt(var / 2);
    const double cp = warm_score(&c, fv[0] * sfmi_exp(PROFILE_STEP));
    const double cm = warm_score(&c, fv[0] * sfmi_exp(-PROFILE_STEP));
    const double curv = (cp + cm - 2 * cost) / (PROFILE_STEP * PROFILE_STEP);
    rep.focal_sigma = curv > 0 && var < HUGE_VAL ? sqrt(var / curv) : HUGE_VAL;
    double far = fmin(warm_score(&c, fv[0] * FAR_FACTOR), warm_score(&c, fv[0] / FAR_FACTOR));
    for (int k = 0; k < rep.sweep_count; k++)
        if (fabs(sfmi_log(rep.sweep_focal[k] / fv[0])) > sfmi_log(FAR_FACTOR))
            far = fmin(far, rep.sweep_cost[k]);
    rep.profile_rise = var > 0 && var < HUGE_VAL ? (far - cost) / var : 0.0;
    quality(&c, fv, &rep.rms, &rep.front_fraction);
    rep.evaluations = c.evaluations;
    if (!(rep.profile_rise >= o.min_profile) || !(rep.focal_sigma <= o.max_focal_sigma)) {
        *report = rep;
        return SFM_E_SINGULAR;
    }
    for (int i = 0; i < m; i++)
        if (!(fv[i] > 0)) {
            *report = rep;
            return SFM_E_NO_CONVERGENCE;
        }
    if (!(rep.front_fraction >= o.min_front) || !(rep.rms <= o.max_rms)) {
        *report = rep;
        return SFM_E_NO_CONVERGENCE;
    }

    /* 5. the larger models, each kept when it passes the same checks */
    if (o.principal == SFM_SELFCAL_PRINCIPAL_SHARED && larger_model(&c, &o, 4, fv, &rep))
        rep.principal = SFM_SELFCAL_PRINCIPAL_SHARED;
    if (o.per_view_focal || o.principal == SFM_SELFCAL_PRINCIPAL_PER_VIEW) {
        int per_pp = o.principal == SFM_SELFCAL_PRINCIPAL_PER_VIEW;
        if (larger_model(&c, &o, per_pp ? 3 : 2, fv, &rep)) {
            rep.per_view = 1;
            if (per_pp)
                rep.principal = SFM_SELFCAL_PRINCIPAL_PER_VIEW;
        }
    }

    /* outputs */
    for (int i = 0; i < m; i++) {
        const double k[9] = {fv[i], 0, c.pp[2 * i], 0, fv[i], c.pp[2 * i + 1], 0, 0, 1};
        memcpy(&K[9 * i], k, sizeof k);
        if (poses != NULL) {
            memcpy(poses[i].R, &c.R[9 * i], 9 * sizeof(double));
            memcpy(poses[i].t, &c.t[3 * i], 3 * sizeof(double));
        }
    }
    memcpy(H, best_H, sizeof best_H);
    rep.evaluations = c.evaluations;
    if (Xm != NULL) {
        memset(Xm, 0, 3 * sizeof(double) * (size_t)n);
        for (int k = 0; k < c.np; k++)
            memcpy(&Xm[3 * (size_t)c.pidx[k]], &c.Xw[3 * (size_t)k], 3 * sizeof(double));
    }
    *report = rep;
    return SFM_OK;
}
