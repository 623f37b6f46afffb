/*
 * The metric stage of the uncalibrated pipelines (see sfm_uncalibrated.h
 * for the method and metric_upgrade.h for the interface).
 *
 * Candidate focal lengths are compared by the final cost of a metric bundle
 * adjustment with the focal length held, so the comparison is between
 * maximum-likelihood fits of the same observations (Huber loss; a point
 * that cannot be triangulated under a candidate counts as an outlier at
 * three thresholds).
 */
#include <math.h>
#include <string.h>

#include "core/dmath.h"
#include "core/linalg_util.h"
#include "recon/focal_search.h"
#include "recon/metric_upgrade.h"
#include "recon/projective.h"
#include "sfm/sfm_ba.h"
#include "sfm/sfm_camera.h"
#include "sfm/sfm_pose.h"
#include "sfm/sfm_solvers.h"
#include "sfm/sfm_triangulate.h"
#include "sfm/sfm_trifocal.h"

#define FINAL_ITERS 50
#define GOLDEN_STEPS 4
#define FAR_FACTOR 1.5  /* "far" focal lengths of the observability test */
#define NOISE_FLOOR 0.05 /* px: noise standard deviation assumed at least */
#define FOCAL_NOISE_FLOOR 0.2 /* px: per-observation error the sigma of f assumes
                                 at least. The residuals measure the white part of
                                 the localisation error only; its systematic part
                                 (a sub-pixel alignment's translation-only patch on
                                 slanted, turning surfaces) is spatially smooth, so
                                 the fit absorbs it into f, the poses and the radial
                                 terms and it does not average out. On the rendered
                                 loop (f known, the model exact, aligned points at
                                 0.07-0.14 px RMS) the spread of f is that of
                                 0.2 px of white noise. */
#define SEARCH_POINTS 150 /* inliers the focal search runs on */
#define RADIAL_MIN_RISE 9.0 /* a radial term is kept when holding it at 0
                               raises the cost by more than this many noise
                               variances (a likelihood ratio test, 1 degree
                               of freedom, 3 sigma) */

void sfmi_mu_layout(sfmi_arena *a, int nv, int nmax, int radial, sfmi_mu *c)
{
    c->nv = nv;
    c->nmax = nmax;
    for (int v = 0; v < 3; v++)
        c->x[v] = v < nv ? SFM_ARENA_ARRAY(a, double, 2 * (size_t)nmax) : NULL;
    c->idx = SFM_ARENA_ARRAY(a, int, nmax);
    c->bear = SFM_ARENA_ARRAY(a, double, 3 * (size_t)nv * nmax);
    c->X = SFM_ARENA_ARRAY(a, double, 3 * (size_t)nmax);
    c->Xkeep = SFM_ARENA_ARRAY(a, double, 3 * (size_t)nmax);
    c->flags = SFM_ARENA_ARRAY(a, int, nmax);
    c->pidx = SFM_ARENA_ARRAY(a, int, nmax);
    c->obs_cam = SFM_ARENA_ARRAY(a, int, (size_t)nv * nmax);
    c->obs_pt = SFM_ARENA_ARRAY(a, int, (size_t)nv * nmax);
    c->obs_xy = SFM_ARENA_ARRAY(a, double, 2 * (size_t)nv * nmax);
    for (int v = 0; v < 3; v++)
        c->xu[v] = v < nv && radial > 0 ? SFM_ARENA_ARRAY(a, double, 2 * (size_t)nmax) : NULL;
    c->idx0 = radial > 0 ? SFM_ARENA_ARRAY(a, int, nmax) : NULL;
    /* the largest of the adjustments run: shared focal and the radial
     * terms, one focal length per view */
    const int kmask = radial >= 2 ? SFM_BA_REFINE_RADIAL : radial == 1 ? SFM_BA_REFINE_K1 : 0;
    sfm_ba_dims d = {nv, nmax, nv * nmax, SFM_BA_INTRINSICS_SHARED, SFM_BA_REFINE_FOCAL | kmask};
    sfm_ba_dims dp = {nv, nmax, nv * nmax, SFM_BA_INTRINSICS_PER_CAMERA, SFM_BA_REFINE_FOCAL};
    size_t s1 = sfm_ba_workspace_size(&d), s2 = sfm_ba_workspace_size(&dp);
    c->ba_size = s1 > s2 ? s1 : s2;
    c->ba_ws = sfmi_arena_alloc(a, c->ba_size);
    c->radial_max = radial;
    c->radial = 0;
    c->kr[0] = c->kr[1] = 0;
}

static int has_radial(const double kr[2])
{
    return kr[0] != 0 || kr[1] != 0;
}

/* The camera of focal length f and radial terms kr = (k1, k2) about the
 * centre (pixels centred): pinhole when both are 0. */
static void centred_camera(double f, const double kr[2], sfm_camera *cam)
{
    memset(cam, 0, sizeof *cam);
    cam->model = has_radial(kr) ? SFM_CAMERA_BROWN : SFM_CAMERA_PINHOLE;
    cam->fx = cam->fy = f;
    cam->dist[0] = kr[0];
    cam->dist[1] = kr[1];
}

/* Undistorted centred pixel (and unit-depth ray b, may be NULL) of px under
 * focal f and radial terms kr. 0 when the distortion map cannot be inverted
 * there (the pixel is then returned as it is). */
static int undistort(double f, const double kr[2], const double px[2], double u[2], double b[3])
{
    double r[3] = {px[0] / f, px[1] / f, 1};
    int ok = 1;
    if (has_radial(kr)) {
        sfm_camera cam;
        centred_camera(f, kr, &cam);
        double d[3];
        ok = sfm_camera_unproject(&cam, px, d) == SFM_OK && d[2] > 0;
        if (ok) {
            r[0] = d[0] / d[2];
            r[1] = d[1] / d[2];
        }
    }
    u[0] = f * r[0];
    u[1] = f * r[1];
    if (b != NULL)
        memcpy(b, r, sizeof r);
    return ok;
}

static void identity_pose(sfm_pose *p)
{
    memset(p, 0, sizeof *p);
    p->R[0] = p->R[4] = p->R[8] = 1;
}

static void bearings(sfmi_mu *c, double f)
{
    for (int v = 0; v < c->nv; v++)
        for (int j = 0; j < c->m; j++) {
            double *b = &c->bear[((size_t)v * c->m + j) * 3];
            if (!has_radial(c->kr)) {
                b[0] = c->x[v][2 * j] / f;
                b[1] = c->x[v][2 * j + 1] / f;
                b[2] = 1;
            } else {
                double u[2];
                undistort(f, c->kr, &c->x[v][2 * j], u, b);
            }
        }
}

/* Metric cameras of focal length f from the fundamental matrices:
 * E = K^T F K, the cheirality choice of its four decompositions, the third
 * translation scaled. 1 on success. */
static int start_from_focal(sfmi_mu *c, double f, sfm_pose poses[3])
{
    bearings(c, f);
    const double kd[3] = {f, f, 1};
    sfm_mat3 E[2];
    for (int e = 0; e < c->nv - 1; e++)
        for (int r = 0; r < 3; r++)
            for (int k = 0; k < 3; k++)
                E[e].m[3 * r + k] = kd[r] * c->F[e].m[3 * r + k] * kd[k];
    sfm_pose cand[4];
    identity_pose(&poses[0]);
    const double *b1 = c->bear;
    if (sfm_essential_to_poses(&E[0], b1, &c->bear[(size_t)c->m * 3], c->m, cand, NULL) != 4)
        return 0;
    poses[1] = cand[0];
    if (c->nv == 3) {
        if (sfm_essential_to_poses(&E[1], b1, &c->bear[(size_t)2 * c->m * 3], c->m, cand, NULL) != 4)
            return 0;
        if (sfm_triangulate_midpoint(2, poses, c->m, c->bear, c->X, c->flags) <= 0)
            return 0;
        double s = sfmi_third_view_scale(&cand[0], c->m, c->X, c->flags, &c->bear[(size_t)2 * c->m * 3]);
        if (!isfinite(s))
            return 0;
        poses[2] = cand[0];
        for (int r = 0; r < 3; r++)
            poses[2].t[r] *= s;
    }
    return 1;
}

/* Triangulate (midpoint) the current inliers under poses and f and build
 * the observations of the points that triangulate: c->X / c->pidx / c->np
 * and the obs arrays. */
static int build(sfmi_mu *c, const sfm_pose poses[3], double f)
{
    const int nv = c->nv;
    bearings(c, f);
    if (sfm_triangulate_midpoint(nv, poses, c->m, c->bear, c->X, c->flags) < 0)
        return SFM_E_SINGULAR;
    int np = 0, no = 0;
    for (int j = 0; j < c->m; j++) {
        if (c->flags[j] != 0)
            continue;
        memmove(&c->X[3 * np], &c->X[3 * j], 3 * sizeof(double));
        c->pidx[np] = j;
        for (int v = 0; v < nv; v++) {
            c->obs_cam[no] = v;
            c->obs_pt[no] = np;
            c->obs_xy[2 * no] = c->x[v][2 * j];
            c->obs_xy[2 * no + 1] = c->x[v][2 * j + 1];
            no++;
        }
        np++;
    }
    c->np = np;
    return np < SFM_TRIFOCAL_MIN_POINTS + 1 ? SFM_E_SINGULAR : SFM_OK;
}

/* Metric bundle adjustment of poses, c->X and f (free or held) over the
 * observations of build(); *cost with the penalty of the inliers that did
 * not triangulate. free_focal: 0 held, 1 one free focal length for all
 * views, 2 one per view; f holds nv focal lengths for mode 2, f[0]
 * otherwise. The first c->radial radial terms c->kr are free in modes 0
 * and 1 (the fixed-focal costs are then profiles over them), the others
 * held; all are held in mode 2. */
static int adjust(sfmi_mu *c, sfm_pose poses[3], double *f, int free_focal, int max_it, double *cost)
{
    const int nv = c->nv, np = c->np, no = np * nv;
    c->evaluations++;
    double Rs[27], ts[9];
    sfm_camera cams[3];
    memset(cams, 0, sizeof cams);
    for (int v = 0; v < nv; v++) {
        memcpy(&Rs[9 * v], poses[v].R, 9 * sizeof(double));
        memcpy(&ts[3 * v], poses[v].t, 3 * sizeof(double));
        centred_camera(free_focal == 2 ? f[v] : f[0], c->kr, &cams[v]);
        if (c->radial)
            cams[v].model = SFM_CAMERA_BROWN;
    }
    sfm_ba_problem p = {nv, np, no, Rs, ts, cams, c->X, c->obs_cam, c->obs_pt, c->obs_xy, NULL, NULL, NULL};
    sfm_ba_options o;
    sfm_ba_default_options(&o);
    o.loss = SFM_BA_LOSS_HUBER;
    o.loss_scale = 2.0 * c->thr;
    o.scale_gauge = SFM_BA_SCALE_DISTANCE;
    o.scale_camera = 1;
    o.scale_distance = 1.0;
    o.max_iterations = max_it;
    const int k_free = free_focal != 2 ? c->radial : 0;
    const int k_mask = k_free == 2 ? SFM_BA_REFINE_RADIAL : k_free == 1 ? SFM_BA_REFINE_K1 : 0;
    if (free_focal) {
        o.intrinsics = free_focal == 2 ? SFM_BA_INTRINSICS_PER_CAMERA : SFM_BA_INTRINSICS_SHARED;
        o.refine_intrinsics = SFM_BA_REFINE_FOCAL | k_mask;
    } else if (k_free) {
        o.intrinsics = SFM_BA_INTRINSICS_SHARED;
        o.refine_intrinsics = k_mask;
    }
    sfm_ba_result res;
    int st = sfm_ba_solve(&p, &o, &res, NULL, 0, c->ba_ws, c->ba_size);
    if (st < 0)
        return st;
    for (int v = 0; v < nv; v++) {
        memcpy(poses[v].R, &Rs[9 * v], 9 * sizeof(double));
        memcpy(poses[v].t, &ts[3 * v], 3 * sizeof(double));
    }
    for (int v = 0; v < (free_focal == 2 ? nv : 1); v++)
        f[v] = cams[v].fx;
    for (int e = 0; e < k_free; e++)
        c->kr[e] = cams[0].dist[e];
    *cost = res.final_cost + (double)(c->m - np) * nv * 4.0 * c->thr * c->thr;
    return SFM_OK;
}

static int refine(sfmi_mu *c, sfm_pose poses[3], double *f, int free_focal, int max_it, double *cost)
{
    int st = build(c, poses, *f);
    return st < 0 ? st : adjust(c, poses, f, free_focal, max_it, cost);
}

/* Fixed-focal score of f (INFINITY when no metric cameras follow); the
 * free radial terms start at 0. */
static double score(void *ctx, double f)
{
    sfmi_mu *c = ctx;
    sfm_pose poses[3];
    double cost, ff = f;
    c->kr[0] = c->kr[1] = 0;
    if (!start_from_focal(c, f, poses) || refine(c, poses, &ff, 0, c->sweep_iters, &cost) != SFM_OK)
        return HUGE_VAL;
    return cost;
}

/* RMS reprojection error per view and share of points in front of every
 * camera, over the BA points of the current inliers (projected through the
 * radial terms c->kr). */
static void quality(const sfmi_mu *c, const sfm_pose poses[3], const double *fv, double *rms, double *front)
{
    double se = 0;
    int nf = 0;
    for (int k = 0; k < c->np; k++) {
        const double *X = &c->X[3 * k];
        int j = c->pidx[k], ok = 1;
        for (int v = 0; v < c->nv; v++) {
            const double *R = poses[v].R, *t = poses[v].t;
            double y[3];
            for (int r = 0; r < 3; r++)
                y[r] = R[3 * r] * X[0] + R[3 * r + 1] * X[1] + R[3 * r + 2] * X[2] + t[r];
            if (!(y[2] > 0)) {
                ok = 0;
                continue;
            }
            double du, dv;
            if (!has_radial(c->kr)) {
                du = fv[v] * y[0] / y[2] - c->x[v][2 * j];
                dv = fv[v] * y[1] / y[2] - c->x[v][2 * j + 1];
            } else {
                sfm_camera cam;
                double px[2];
                centred_camera(fv[v], c->kr, &cam);
                if (sfm_camera_project(&cam, y, px, NULL) != SFM_OK) {
                    ok = 0;
                    continue;
                }
                du = px[0] - c->x[v][2 * j];
                dv = px[1] - c->x[v][2 * j + 1];
            }
            se += du * du + dv * dv;
        }
        nf += ok;
    }
    *rms = c->np > 0 ? sqrt(se / (c->np * c->nv)) : (double)INFINITY;
    *front = c->m > 0 ? (double)nf / c->m : 0.0;
}

/* 1 when, for every view v > 1, the homography fitted to the inliers x
 * (undistorted; view 1 -> v, normalized DLT) transfers them with an RMS
 * error of at most three times the metric model's per-observation RMS. With a translation
 * the scene's depth makes the transfer error grow with the parallax; without
 * one it stays at the noise: 1.9 and 2.1 in the two views of a pure rotation
 * at 0.3 px (both images noisy, no point to adjust). */
static int homographies_explain(const sfmi_mu *c, double rms_metric, const double *const x[3])
{
    if (c->m < 8 || !(rms_metric >= 0))
        return 0;
    for (int v = 1; v < c->nv; v++) {
        sfm_mat3 H;
        if (sfm_homography_dlt(x[0], x[v], c->m, &H) != 1)
            return 0;
        double se = 0;
        for (int j = 0; j < c->m; j++) {
            const double *p = &x[0][2 * j], *q = &x[v][2 * j];
            double w = H.m[6] * p[0] + H.m[7] * p[1] + H.m[8];
            if (!(fabs(w) > 0))
                return 0;
            double du = (H.m[0] * p[0] + H.m[1] * p[1] + H.m[2]) / w - q[0];
            double dv = (H.m[3] * p[0] + H.m[4] * p[1] + H.m[5]) / w - q[1];
            se += du * du + dv * dv;
        }
        if (!(sqrt(se / c->m) <= 3.0 * rms_metric))
            return 0;
    }
    return 1;
}

/* Median over the BA points of the largest angle (degrees) between the
 * rays from two camera centres. */
static double median_parallax(const sfmi_mu *c, const sfm_pose poses[3], double *scratch)
{
    double C[3][3];
    for (int v = 0; v < c->nv; v++)
        for (int k = 0; k < 3; k++)
            C[v][k] = -(poses[v].R[k] * poses[v].t[0] + poses[v].R[3 + k] * poses[v].t[1] +
                        poses[v].R[6 + k] * poses[v].t[2]);
    for (int p = 0; p < c->np; p++) {
        const double *X = &c->X[3 * p];
        double best = 0;
        for (int a = 0; a < c->nv; a++)
            for (int b = a + 1; b < c->nv; b++) {
                double u[3], w[3];
                for (int k = 0; k < 3; k++) {
                    u[k] = X[k] - C[a][k];
                    w[k] = X[k] - C[b][k];
                }
                double cr[3] = {u[1] * w[2] - u[2] * w[1], u[2] * w[0] - u[0] * w[2], u[0] * w[1] - u[1] * w[0]};
                double ang = sfmi_atan2(sqrt(cr[0] * cr[0] + cr[1] * cr[1] + cr[2] * cr[2]),
                                        u[0] * w[0] + u[1] * w[1] + u[2] * w[2]);
                if (ang > best)
                    best = ang;
            }
        scratch[p] = best * (180.0 / 3.14159265358979323846);
    }
    /* median by selection (insertion sort on a small array is enough) */
    for (int i = 1; i < c->np; i++) {
        double v = scratch[i];
        int j = i - 1;
        while (j >= 0 && scratch[j] > v) {
            scratch[j + 1] = scratch[j];
            j--;
        }
        scratch[j + 1] = v;
    }
    return c->np > 0 ? scratch[c->np / 2] : 0.0;
}

/* Inliers of all n input points under metric cameras K [R | t] and the
 * radial terms c->kr: the mean squared error per view after triangulation
 * (in undistorted pixels) below thr^2. */
static int recollect(sfmi_mu *c, const double *const xin[3], int n, const sfm_pose poses[3], double f)
{
    const double *xall[3] = {xin[0], xin[1], xin[2]};
    if (has_radial(c->kr)) {
        for (int v = 0; v < c->nv; v++) {
            for (int i = 0; i < n; i++)
                undistort(f, c->kr, &xin[v][2 * i], &c->xu[v][2 * i], NULL);
            xall[v] = c->xu[v];
        }
    }
    double P[3][12];
    for (int v = 0; v < c->nv; v++)
        for (int r = 0; r < 3; r++) {
            double kr = r < 2 ? f : 1.0;
            for (int k = 0; k < 3; k++)
                P[v][4 * r + k] = kr * poses[v].R[3 * r + k];
            P[v][4 * r + 3] = kr * poses[v].t[r];
        }
    int m = 0;
    for (int i = 0; i < n; i++) {
        double e2 = HUGE_VAL;
        if (c->nv == 3) {
            if (sfm_trifocal_point_error(P[0], P[1], P[2], &xall[0][2 * i], &xall[1][2 * i],
                                         &xall[2][2 * i], &e2, NULL) != SFM_OK)
                e2 = HUGE_VAL;
        } else {
            double Xh[3];
            int fl;
            if (sfm_triangulate_optimal2(P[0], P[1], 1, &xall[0][2 * i], &xall[1][2 * i], Xh, &fl) == 1) {
                e2 = 0;
                for (int v = 0; v < 2; v++) {
                    double y[3];
                    for (int r = 0; r < 3; r++)
                        y[r] = P[v][4 * r] * Xh[0] + P[v][4 * r + 1] * Xh[1] + P[v][4 * r + 2] * Xh[2] + P[v][4 * r + 3];
                    double du = y[0] / y[2] - xall[v][2 * i], dv = y[1] / y[2] - xall[v][2 * i + 1];
                    e2 += du * du + dv * dv;
                }
            }
        }
        if (!(e2 / c->nv < c->thr * c->thr))
            continue;
        for (int v = 0; v < c->nv; v++) {
            c->x[v][2 * m] = xin[v][2 * i];
            c->x[v][2 * m + 1] = xin[v][2 * i + 1];
        }
        c->idx[m] = i;
        m++;
    }
    c->m = m;
    return m;
}

/* Noise variance of a fit of cost over the current BA points. */
static double noise_variance(const sfmi_mu *c, double cost)
{
    int nobs = c->np * c->nv * 2, dof = c->np * 3 + 6 * (c->nv - 1);
    double s2 = nobs > dof ? 2 * cost / (nobs - dof) : 0;
    return s2 < NOISE_FLOOR * NOISE_FLOOR ? NOISE_FLOOR * NOISE_FLOOR : s2;
}

/* The part of the standard deviation of log f that the noise does not
 * explain: the model holds the principal point at the image centre and the
 * aspect ratio at 1, and a real camera misses both. Each assumption moved
 * by one standard deviation of its prior (the principal point by
 * c->pp_sigma pixels along x, then y; the aspect ratio by c->aspect_sigma),
 * the free-focal optimum is refitted from the answer (cand, c->X, focal ff,
 * radial terms k_ans) on the same inliers, and the changes of log f add in
 * quadrature (the first-order propagation of the prior). A refit that
 * fails, or leaves f <= 0, is INFINITY: f is then not determined under a
 * plausible principal point. Leaves c->X, c->kr and the observations as
 * they were. */
static double prior_variance(sfmi_mu *c, const sfm_pose cand[3], double ff, const double k_ans[2])
{
    const int nv = c->nv, no = c->np * nv;
    double var = 0;
    memcpy(c->Xkeep, c->X, sizeof(double) * 3 * (size_t)c->np);
    for (int q = 0; q < 3 && var < (double)INFINITY; q++) {
        const double s = q < 2 ? c->pp_sigma : c->aspect_sigma;
        if (!(s > 0))
            continue;
        for (int i = 0; i < no; i++) {
            if (q < 2)
                c->obs_xy[2 * i + q] += s;
            else
                c->obs_xy[2 * i + 1] *= 1 + s;
        }
        sfm_pose pp[3];
        double f1 = ff, cost1;
        memcpy(pp, cand, (size_t)nv * sizeof(sfm_pose));
        c->kr[0] = k_ans[0];
        c->kr[1] = k_ans[1];
        if (adjust(c, pp, &f1, 1, FINAL_ITERS, &cost1) == SFM_OK && f1 > 0) {
            const double dl = sfmi_log(f1 / ff);
            var += dl * dl;
        } else {
            var = (double)INFINITY;
        }
        /* the observations again from the pixels (bit for bit) */
        for (int k = 0; k < c->np; k++)
            for (int v = 0; v < nv; v++) {
                c->obs_xy[2 * (k * nv + v)] = c->x[v][2 * c->pidx[k]];
                c->obs_xy[2 * (k * nv + v) + 1] = c->x[v][2 * c->pidx[k] + 1];
            }
        memcpy(c->X, c->Xkeep, sizeof(double) * 3 * (size_t)c->np);
    }
    c->kr[0] = k_ans[0];
    c->kr[1] = k_ans[1];
    return var;
}

/* The final stage from one candidate: inliers re-collected under its
 * metric cameras, a free-focal adjustment on them, the radial terms tested,
 * the standard deviation of f from the profile's curvature and the
 * physical checks. */
static int validate_once(sfmi_mu *c, const double *const xall[3], int n, const sfm_uncal_options *o,
                         const sfm_pose best[3], double best_f, const double best_k[2], sfm_pose poses[3],
                         double *f_out, sfm_uncal_report *rep)
{
    const int nv = c->nv;
    c->undetermined = 0;
    /* inliers under the metric cameras, one more adjustment, checks */
    rep->stage = SFM_UNCAL_STAGE_VALIDATE;
    c->kr[0] = best_k[0];
    c->kr[1] = best_k[1];
    if (recollect(c, xall, n, best, best_f) < SFM_TRIFOCAL_MIN_POINTS + 1)
        return SFM_E_NO_CONVERGENCE;
    double ff = best_f, cost;
    sfm_pose cand[3];
    memcpy(cand, best, sizeof cand);
    int st = refine(c, cand, &ff, 1, FINAL_ITERS, &cost);
    if (st < 0)
        return st == SFM_E_SINGULAR ? SFM_E_NO_CONVERGENCE : st;
    double sigma2f = noise_variance(c, cost);
    /* nested models: the last free radial term held at 0 (k2, then k1),
     * refitted from the same answer; the term stays when the data reject
     * it being 0, else the smaller model is the answer (and its profile
     * gives sigma f) */
    rep->radial_rise[0] = rep->radial_rise[1] = 0;
    while (c->radial > 0) {
        const int e = c->radial - 1;
        sfm_pose pp[3];
        double f0 = ff, cost0 = HUGE_VAL;
        const double k_fit[2] = {c->kr[0], c->kr[1]}; /* the smaller fit moves the others */
        memcpy(pp, cand, sizeof pp);
        memcpy(c->Xkeep, c->X, sizeof(double) * 3 * (size_t)c->np);
        c->radial = e;
        c->kr[e] = 0;
        int ast = adjust(c, pp, &f0, 1, FINAL_ITERS, &cost0);
        rep->radial_rise[e] = ast == SFM_OK ? 2 * (cost0 - cost) / sigma2f : (double)INFINITY;
        if (!(ast == SFM_OK && f0 > 0 && rep->radial_rise[e] < RADIAL_MIN_RISE)) {
            c->radial = e + 1;
            c->kr[0] = k_fit[0];
            c->kr[1] = k_fit[1];
            memcpy(c->X, c->Xkeep, sizeof(double) * 3 * (size_t)c->np);
            break;
        }
        memcpy(cand, pp, sizeof pp);
        ff = f0;
        cost = cost0;
        sigma2f = noise_variance(c, cost);
    }
    const double k_ans[2] = {c->kr[0], c->kr[1]};
    c->cost = cost;
    /* local curvature of the profile likelihood: the fixed-focal optimum at
     * f e^{+-d}, started from the answer (its cameras and points), against
     * the free optimum, on the final inliers; the chi-square rise
     * on the flatter side gives the standard deviation of log f,
     * d / sqrt(rise) */
    {
        const double d = 0.05;
        double c0 = cost, cpm[2];
        memcpy(c->Xkeep, c->X, sizeof(double) * 3 * (size_t)c->np);
        for (int sgn = 0; sgn < 2; sgn++) {
            sfm_pose pp[3];
            memcpy(pp, cand, sizeof pp);
            memcpy(c->X, c->Xkeep, sizeof(double) * 3 * (size_t)c->np);
            double fd = ff * sfmi_exp(sgn ? -d : d);
            c->kr[0] = k_ans[0]; /* free again in the profile */
            c->kr[1] = k_ans[1];
            int ast = adjust(c, pp, &fd, 0, FINAL_ITERS, &cpm[sgn]);
            if (ast != SFM_OK)
                cpm[sgn] = c0;
        }
        c->kr[0] = k_ans[0];
        c->kr[1] = k_ans[1];
        memcpy(c->X, c->Xkeep, sizeof(double) * 3 * (size_t)c->np);
        /* the flatter side: a profile steep on one side only does not pin f */
        const double s2p = fmax(sigma2f, FOCAL_NOISE_FLOOR * FOCAL_NOISE_FLOOR);
        double rise = 2 * (fmin(cpm[0], cpm[1]) - c0) / s2p;
        rep->focal_sigma_noise = rise > 0 ? d / sqrt(rise) : (double)INFINITY;
    }
    rep->focal_sigma = rep->focal_sigma_noise;
    if (rep->focal_sigma < (double)INFINITY) {
        const double pv = prior_variance(c, cand, ff, k_ans);
        rep->focal_sigma = sqrt(rep->focal_sigma * rep->focal_sigma + pv);
    }
    /* the candidate's figures, reported also when it is refused */
    double rms, front, fv[3] = {ff, ff, ff};
    quality(c, cand, fv, &rms, &front);
    rep->focal = ff;
    rep->k1 = c->kr[0];
    rep->k2 = c->kr[1];
    rep->inliers = c->m;
    rep->rms = rms;
    rep->front_fraction = front;
    if (!(rep->focal_sigma <= o->max_focal_sigma)) {
        c->undetermined = 1;
        return SFM_E_SINGULAR;
    }
    /* rotation alone: |t2| = 1 is then fitted to noise and the points go to
     * infinity, their rays parallel */
    rep->parallax_deg = median_parallax(c, cand, c->bear);
    if (!(rep->parallax_deg >= o->min_parallax_deg))
        return SFM_E_SINGULAR;
    /* ...but the fit can also give the noise a baseline and the points a
     * finite depth, with a parallax above the bound. The test that cannot be
     * fooled so: when a homography maps view 1 to every other view about as
     * well as the metric model explains them (a rotation about the centre,
     * or a plane: both critical for self-calibration), the translation is
     * not determined by the data. */
    const double *xh[3] = {c->x[0], c->x[1], c->x[2]};
    int invertible = 1;
    if (has_radial(c->kr) && ff > 0) {
        /* every inlier inside the region where the distortion map is
         * invertible (a distortion folding the image is not a lens) */
        for (int v = 0; v < nv; v++) {
            for (int j = 0; j < c->m; j++)
                invertible &= undistort(ff, c->kr, &c->x[v][2 * j], &c->xu[v][2 * j], NULL);
            xh[v] = c->xu[v];
        }
    }
    if (!invertible)
        return SFM_E_NO_CONVERGENCE;
    if (homographies_explain(c, rms, xh))
        return SFM_E_SINGULAR;
    double max_rms = o->max_rms > 0 ? o->max_rms : c->thr;
    if (!(ff > 0) || !(front >= o->min_front) || !(rms <= max_rms))
        return SFM_E_NO_CONVERGENCE;
    /* one focal length per view when asked: a last adjustment from the
     * shared answer, kept when it passes the same checks */
    if (o->per_view_focal) {
        sfm_pose pp[3];
        double fp[3] = {ff, ff, ff}, cp, rp, frp;
        memcpy(pp, cand, sizeof pp);
        memcpy(c->Xkeep, c->X, sizeof(double) * 3 * (size_t)c->np);
        int ok = adjust(c, pp, fp, 2, FINAL_ITERS, &cp) == SFM_OK;
        for (int v = 0; v < nv && ok; v++)
            ok = fp[v] > 0;
        if (ok) {
            quality(c, pp, fp, &rp, &frp);
            ok = frp >= o->min_front && rp <= max_rms;
        }
        if (ok) {
            memcpy(cand, pp, sizeof pp);
            memcpy(fv, fp, sizeof fp);
            rep->rms = rp;
            rep->front_fraction = frp;
        } else {
            memcpy(c->X, c->Xkeep, sizeof(double) * 3 * (size_t)c->np);
        }
    }
    memcpy(poses, cand, (size_t)nv * sizeof(sfm_pose));
    for (int v = 0; v < nv; v++) {
        f_out[v] = fv[v];
        rep->focal_view[v] = fv[v];
    }
    rep->stage = SFM_UNCAL_STAGE_DONE;
    return SFM_OK;
}

/* validate_once() with c->radial restored (the pinhole choice is per
 * candidate). */
static int validate(sfmi_mu *c, const double *const xall[3], int n, const sfm_uncal_options *o,
                    const sfm_pose best[3], double best_f, const double best_k[2], sfm_pose poses[3], double *f_out,
                    sfm_uncal_report *rep)
{
    const int radial = c->radial;
    int st = validate_once(c, xall, n, o, best, best_f, best_k, poses, f_out, rep);
    c->radial = radial;
    return st;
}

/* Sweep, starts and checks with the first `radial` radial terms free. */
static int solve_once(sfmi_mu *c, const double *const xall[3], int n, double f_linear, double diag,
                      const sfm_uncal_options *o, int radial, sfm_pose poses[3], double *f_out,
                      sfm_uncal_report *rep)
{
    const int nv = c->nv;
    double fk[SFM_UNCAL_MAX_SWEEP], ck[SFM_UNCAL_MAX_SWEEP];
    c->radial = radial;
    c->kr[0] = c->kr[1] = 0;
    const int K = o->sweep_steps;
    const double u0 = sfmi_log(o->focal_min * diag), u1 = sfmi_log(o->focal_max * diag);
    rep->stage = SFM_UNCAL_STAGE_SWEEP;
    /* the search runs on an evenly strided subset of the inliers: costs of
     * candidates are compared, not reported, and the final adjustment and
     * the curvature run on every inlier */
    const int m_all = c->m;
    if (c->m > SEARCH_POINTS) {
        int keep = 0;
        for (int j = 0; j < c->m; j++) {
            if ((long)j * SEARCH_POINTS / c->m == (long)keep) {
                for (int v = 0; v < nv; v++) {
                    c->x[v][2 * keep] = c->x[v][2 * j];
                    c->x[v][2 * keep + 1] = c->x[v][2 * j + 1];
                }
                c->idx[keep] = c->idx[j];
                keep++;
            }
        }
        c->m = keep;
    }

    /* coarse sweep */
    for (int k = 0; k < K; k++)
        fk[k] = sfmi_exp(u0 + (u1 - u0) * k / (K - 1));
    const int kb = sfmi_focal_sweep(score, c, fk, K, ck);
    if (kb < 0)
        return SFM_E_SINGULAR;
    /* golden-section search on log f between the neighbours of the best */
    double ug[2], sg[2];
    sfmi_focal_golden(score, c, sfmi_log(fk[kb > 0 ? kb - 1 : kb]), sfmi_log(fk[kb < K - 1 ? kb + 1 : kb]),
                      GOLDEN_STEPS, 0, ug, sg);
    const double s1 = sg[0], s2 = sg[1];
    double f_sweep = s1 < s2 ? sfmi_exp(ug[0]) : sfmi_exp(ug[1]);
    double c_sweep_fixed = fmin(s1, s2);
    if (ck[kb] < c_sweep_fixed) {
        f_sweep = fk[kb];
        c_sweep_fixed = ck[kb];
    }
    rep->focal_sweep = f_sweep;

    /* free-focal bundle adjustment from the linear start and from the
     * sweep's best; the sweep's fixed-focal answer as a third candidate */
    rep->stage = SFM_UNCAL_STAGE_BA;
    double cost, fs[3] = {0, 0, 0}, cs[3] = {HUGE_VAL, HUGE_VAL, HUGE_VAL}, ks[3][2] = {{0, 0}, {0, 0}, {0, 0}};
    sfm_pose sol[3][3];
    int started[3] = {0, 0, 0};
    for (int s = 0; s < 2; s++) {
        double f0 = s == 0 ? f_linear : f_sweep;
        c->kr[0] = c->kr[1] = 0;
        if (!(f0 > 0) || !start_from_focal(c, f0, sol[s]))
            continue;
        started[s] = 1;
        if (s == 1) {
            /* candidate 2 starts from the same cameras */
            memcpy(sol[2], sol[1], sizeof sol[2]);
            started[2] = 1;
        }
        double ff = f0;
        if (refine(c, sol[s], &ff, s < 2, FINAL_ITERS, &cost) != SFM_OK || !(ff > 0))
            continue;
        fs[s] = ff;
        cs[s] = cost;
        ks[s][0] = c->kr[0];
        ks[s][1] = c->kr[1];
    }
    /* candidates in order of cost (the fixed-focal one last), each checked
     * in full; the first that passes is the answer. The fixed-focal
     * candidate is adjusted only when its turn comes: it is validated only
     * after both free-focal ones failed, which is rare, and its adjustment
     * starts from the same cameras (those of f_sweep) and runs on the same
     * search subset as if it had been run here, so the answer is the same
     * bit for bit. validate() replaces the subset: its indices are kept to
     * restore it. */
    const int np_search = c->np; /* the same after candidate 2's build, which triangulates
                                    candidate 1's start */
    const int m_search = c->m;
    int idx_search[SEARCH_POINTS];
    memcpy(idx_search, c->idx, sizeof(int) * (size_t)m_search);
    int order[3] = {0, 1, 2};
    if (cs[1] < cs[0]) {
        order[0] = 1;
        order[1] = 0;
    }
    int st = SFM_E_SINGULAR;
    for (int k = 0; k < 3; k++) {
        int s = order[k];
        if (s == 2 && started[2]) {
            /* the search subset again (copies of the input pixels) */
            c->m = m_search;
            for (int j = 0; j < m_search; j++) {
                const int i = idx_search[j];
                c->idx[j] = i;
                for (int v = 0; v < nv; v++) {
                    c->x[v][2 * j] = xall[v][2 * i];
                    c->x[v][2 * j + 1] = xall[v][2 * i + 1];
                }
            }
            c->kr[0] = c->kr[1] = 0;
            double ff = f_sweep;
            if (refine(c, sol[2], &ff, 0, FINAL_ITERS, &cost) == SFM_OK && ff > 0) {
                fs[2] = ff;
                cs[2] = cost;
                ks[2][0] = c->kr[0];
                ks[2][1] = c->kr[1];
            }
        }
        if (!(cs[s] < (double)INFINITY))
            continue;
        double best_f = fs[s];
        /* observability of f: the fixed-focal cost far from the answer */
        rep->stage = SFM_UNCAL_STAGE_BA;
        double c_far = HUGE_VAL;
        for (int q = 0; q < K; q++)
            if (fabs(sfmi_log(fk[q] / best_f)) > sfmi_log(FAR_FACTOR) && ck[q] < c_far)
                c_far = ck[q];
        int nobs = np_search * nv * 2, dof = np_search * 3 + 6 * (nv - 1);
        double sigma2 = nobs > dof ? 2 * c_sweep_fixed / (nobs - dof) : 0;
        if (sigma2 < NOISE_FLOOR * NOISE_FLOOR)
            sigma2 = NOISE_FLOOR * NOISE_FLOOR;
        /* a chi-square rise grows with the number of points: measured on
         * the subset, it is scaled to every inlier */
        rep->profile_rise = 2 * (c_far - fmin(c_sweep_fixed, cs[s])) / sigma2 * (double)m_all /
                            (double)(np_search > 0 ? np_search : 1);
        if (!(rep->profile_rise >= o->min_profile)) {
            st = SFM_E_SINGULAR;
            continue;
        }
        st = validate(c, xall, n, o, sol[s], best_f, ks[s], poses, f_out, rep);
        if (st == SFM_OK) {
            int lin = s == 0 || (s == 1 && fs[0] > 0 && fabs(fs[1] / fs[0] - 1) < 0.01);
            rep->path = lin ? SFM_UNCAL_PATH_LINEAR : SFM_UNCAL_PATH_SWEEP;
            return SFM_OK;
        }
        rep->path = s == 0 ? SFM_UNCAL_PATH_LINEAR : SFM_UNCAL_PATH_SWEEP;
        if (st != SFM_E_SINGULAR && st != SFM_E_NO_CONVERGENCE)
            return st;
        /* The candidates run in order of cost: the one refused here is the
         * best fit found, and its profile says the data do not pin f. A
         * costlier candidate is a local optimum of the same likelihood,
         * whose curvature may pass the bound only because it does not see
         * the better basin (Herz-Jesu 0000-0005-0006 with 5 steps per sweep
         * candidate: the sweep's fixed-focal answer, cost 37.8 against
         * 34.3, then f +7.3 % at sigma 1.67 % after the best fit's 2.35 %
         * was refused). Any other failure (cheirality, RMS, the
         * distortion, parallax, a homography) hands the turn to the next
         * candidate. */
        if (c->undetermined)
            break;
    }
    return st;
}

/* The radial terms tested forward from an accepted pinhole answer (poses,
 * focal f, c->X and c->cost of validate_once()): k1 free, then k1 and k2,
 * each fit from the previous one. The same likelihood-ratio rule as the
 * backward test of validate_once(): the pinhole model is the answer there
 * only when neither rise reaches RADIAL_MIN_RISE, so 1 here (a term
 * significant, or a fit failing) sends the solve to the radial model.
 * pp, *ff_fit, k_fit: the last fit (its start). Leaves c pinhole with the
 * answer's points. */
static int radial_needed(sfmi_mu *c, const sfm_pose poses[3], double f, int radial, sfm_pose pp[3],
                         double *ff_fit, double k_fit[2], sfm_uncal_report *rep)
{
    double ff = f, cost_prev = c->cost;
    int need = 0;
    memcpy(pp, poses, (size_t)c->nv * sizeof(sfm_pose));
    memcpy(c->Xkeep, c->X, sizeof(double) * 3 * (size_t)c->np);
    for (int e = 1; e <= radial && !need; e++) {
        double cost = HUGE_VAL;
        c->radial = e;
        int ast = adjust(c, pp, &ff, 1, FINAL_ITERS, &cost);
        double rise = ast == SFM_OK ? 2 * (cost_prev - cost) / noise_variance(c, cost) : (double)INFINITY;
        rep->radial_rise[e - 1] = rise;
        need = !(ast == SFM_OK && ff > 0 && rise < RADIAL_MIN_RISE);
        cost_prev = cost;
    }
    *ff_fit = ff;
    k_fit[0] = c->kr[0];
    k_fit[1] = c->kr[1];
    c->radial = 0;
    c->kr[0] = c->kr[1] = 0;
    memcpy(c->X, c->Xkeep, sizeof(double) * 3 * (size_t)c->np);
    return need;
}

/* A cascade: the pinhole stage first (the model chosen on undistorted
 * lenses), the radial terms tested from its answer, and the stage with the
 * terms free in the sweep (as the focal sigma on a distorted lens must
 * account for them) only when one is significant or the pinhole answer is
 * refused. per_view_focal answers take the radial stage directly. */
int sfmi_mu_solve(sfmi_mu *c, const double *const xall[3], int n, double f_linear, double diag,
                  const sfm_uncal_options *o, sfm_pose poses[3], double *f_out, sfm_uncal_report *rep)
{
    const int nv = c->nv;
    const int radial = nv == 3 ? (o->radial < c->radial_max ? o->radial : c->radial_max) : 0;
    c->pp_sigma = o->principal_sigma * diag;
    c->sweep_iters = o->sweep_iterations;
    c->aspect_sigma = o->aspect_sigma;
    if (radial == 0 || o->per_view_focal)
        return solve_once(c, xall, n, f_linear, diag, o, radial, poses, f_out, rep);
    const sfm_uncal_report rep0 = *rep;
    const int m0 = c->m;
    memcpy(c->idx0, c->idx, sizeof(int) * (size_t)m0);
    int st = solve_once(c, xall, n, f_linear, diag, o, 0, poses, f_out, rep);
    if (st == SFM_OK) {
        sfm_pose p0[3];
        double f0, k_fit[2];
        if (!radial_needed(c, poses, f_out[0], radial, p0, &f0, k_fit, rep))
            return SFM_OK;
        /* a term significant: the checked answer with the terms free from
         * the last fit of the test (the pinhole answer's basin of f), the
         * radial sweep when refused */
        c->radial = radial;
        st = validate(c, xall, n, o, p0, f0, k_fit, poses, f_out, rep);
        if (st == SFM_OK || (st != SFM_E_SINGULAR && st != SFM_E_NO_CONVERGENCE))
            return st;
    } else if (st != SFM_E_SINGULAR && st != SFM_E_NO_CONVERGENCE) {
        return st;
    }
    /* the inliers the stage started from, the report as it was */
    *rep = rep0;
    c->m = m0;
    for (int j = 0; j < m0; j++) {
        const int i = c->idx0[j];
        c->idx[j] = i;
        for (int v = 0; v < nv; v++) {
            c->x[v][2 * j] = xall[v][2 * i];
            c->x[v][2 * j + 1] = xall[v][2 * i + 1];
        }
    }
    return solve_once(c, xall, n, f_linear, diag, o, radial, poses, f_out, rep);
}

void sfmi_mu_outputs(const sfmi_mu *c, int n, const double *f, double cx, double cy, double *K, double *X,
                     uint8_t *mask)
{
    for (int v = 0; v < c->nv; v++) {
        const double Kout[9] = {f[v], 0, cx, 0, f[v], cy, 0, 0, 1};
        memcpy(&K[9 * v], Kout, sizeof Kout);
    }
    if (X != NULL) {
        memset(X, 0, sizeof(double) * 3 * (size_t)n);
        for (int k = 0; k < c->np; k++)
            memcpy(&X[3 * (size_t)c->idx[c->pidx[k]]], &c->X[3 * k], 3 * sizeof(double));
    }
    if (mask != NULL) {
        memset(mask, 0, (size_t)n);
        for (int j = 0; j < c->m; j++)
            mask[c->idx[j]] = 1;
    }
}

int sfmi_uncal_check_options(const sfm_uncal_options *o);

int sfmi_uncal_options(const sfm_uncal_options *opt, sfm_uncal_options *o)
{
    if (opt != NULL)
        *o = *opt;
    else
        sfm_uncal_default_options(o);
    return sfmi_uncal_check_options(o) < 0 ? SFM_E_ARGUMENT : SFM_OK;
}

int sfmi_uncal_centre(int nv, const double *const px[3], int n, int width, int height, double *const xc[3],
                      sfm_uncal_report *rep)
{
    for (int v = 0; v < nv; v++)
        if (!sfmi_la_all_finite(px[v], 2 * (size_t)n))
            return SFM_E_NONFINITE;
    memset(rep, 0, sizeof *rep);
    rep->n_input = n;
    rep->stage = SFM_UNCAL_STAGE_RANSAC;
    const double cx = 0.5 * (width - 1), cy = 0.5 * (height - 1);
    for (int v = 0; v < nv; v++)
        for (int i = 0; i < n; i++) {
            xc[v][2 * i] = px[v][2 * i] - cx;
            xc[v][2 * i + 1] = px[v][2 * i + 1] - cy;
        }
    return SFM_OK;
}

#define UNCAL_ATTEMPTS 3

int sfmi_uncal_attempts(sfmi_uncal_once_fn once, void *ctx, const sfm_uncal_options *o, int n,
                        sfm_pose est[3], double *f, sfm_uncal_report *rep)
{
    /* a tensor or F whose metric upgrade fails every check may be a RANSAC
     * answer on part of the scene (a plane, a wrong cluster): the pipeline
     * runs again from RANSAC with the next seeds */
    int st = SFM_E_SINGULAR;
    for (int attempt = 0; attempt < UNCAL_ATTEMPTS; attempt++) {
        sfm_uncal_options oa = *o;
        oa.ransac.seed = o->ransac.seed + (uint64_t)attempt;
        /* the last run with twice the threshold: on few matches with many
         * outliers RANSAC at the noise level can settle on a small subset */
        if (attempt == UNCAL_ATTEMPTS - 1) {
            oa.ransac.threshold = 2 * o->ransac.threshold;
            if (!(oa.max_rms > 0))
                oa.max_rms = o->ransac.threshold;
        }
        memset(rep, 0, sizeof *rep);
        rep->n_input = n;
        rep->attempts = attempt + 1;
        st = once(ctx, &oa, est, f, rep);
        /* RANSAC refusing its answer as degenerate (a tensor or F induced by
         * a dominant plane: the rest of the scene is outside its band) is
         * the case the next runs are for; any other RANSAC failure is the
         * data's */
        if (st >= 0 || (st != SFM_E_SINGULAR && st != SFM_E_NO_CONVERGENCE &&
                        st != SFM_E_DEGENERATE) ||
            (rep->stage == SFM_UNCAL_STAGE_RANSAC && st != SFM_E_DEGENERATE))
            break;
    }
    return st;
}
