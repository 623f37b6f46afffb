/*
 * Calibrated three-view relative pose from the trifocal tensor (see
 * sfm_three_view.h for the method). The tensor's fundamental matrices are
 * mutually consistent, unlike three independently estimated pairwise ones,
 * so the two essential matrices share one set of inliers.
 */
#include <math.h>
#include <string.h>

#include "core/arena.h"
#include "core/linalg_util.h"
#include "recon/projective.h"
#include "sfm/sfm_ba.h"
#include "sfm/sfm_pose.h"
#include "sfm/sfm_ransac.h"
#include "robust/support_check.h"
#include "robust/trifocal_ransac.h"
#include "sfm/sfm_ransac_trifocal.h"
#include "sfm/sfm_three_view.h"
#include "sfm/sfm_triangulate.h"
#include "sfm/sfm_trifocal.h"

typedef struct tv_ws {
    double *ideal[3]; /* n x 2 ideal pinhole pixels per view */
    double *bear;     /* 3 views x n x 3 bearings of the inliers, view-major */
    double *X;        /* n x 3 */
    int *flags;       /* n */
    uint8_t *mask;    /* n */
    void *ransac_ws;
    size_t ransac_size;
    int *obs_cam, *obs_pt; /* 3n */
    double *obs_xy;        /* 3n x 2 */
    uint8_t *m12, *m13;    /* n: 5-point inliers of pairs (1, 2), (1, 3) */
    void *rel_ws;
    size_t rel_size;
    void *ba_ws;
    size_t ba_size;
} tv_ws;

static void layout(sfmi_arena *a, int n, tv_ws *w)
{
    for (int v = 0; v < 3; v++)
        w->ideal[v] = SFM_ARENA_ARRAY(a, double, 2 * (size_t)n);
    w->bear = SFM_ARENA_ARRAY(a, double, 9 * (size_t)n);
    w->X = SFM_ARENA_ARRAY(a, double, 3 * (size_t)n);
    w->flags = SFM_ARENA_ARRAY(a, int, n);
    w->mask = SFM_ARENA_ARRAY(a, uint8_t, n);
    w->ransac_size = sfm_ransac_trifocal_workspace_size(n);
    w->ransac_ws = sfmi_arena_alloc(a, w->ransac_size);
    w->obs_cam = SFM_ARENA_ARRAY(a, int, 3 * (size_t)n);
    w->obs_pt = SFM_ARENA_ARRAY(a, int, 3 * (size_t)n);
    w->obs_xy = SFM_ARENA_ARRAY(a, double, 6 * (size_t)n);
    sfm_ba_dims d = {3, n, 3 * n, SFM_BA_INTRINSICS_FIXED, 0};
    w->ba_size = sfm_ba_workspace_size(&d);
    w->ba_ws = sfmi_arena_alloc(a, w->ba_size);
    w->m12 = SFM_ARENA_ARRAY(a, uint8_t, n);
    w->m13 = SFM_ARENA_ARRAY(a, uint8_t, n);
    w->rel_size = sfm_ransac_relpose_workspace_size(n);
    w->rel_ws = sfmi_arena_alloc(a, w->rel_size);
}

size_t sfm_recon_three_view_pose_workspace_size(int n)
{
    if (n < SFM_TRIFOCAL_MIN_POINTS || n > SFM_RANSAC_MAX_POINTS)
        return 0;
    sfmi_arena a;
    tv_ws w;
    sfmi_arena_measure(&a);
    layout(&a, n, &w);
    return sfmi_arena_required(&a);
}

static void K_of(const sfm_camera *c, double K[9])
{
    const double k[9] = {c->fx, 0, c->cx, 0, c->fy, c->cy, 0, 0, 1};
    memcpy(K, k, sizeof k);
}

/* E = K2^T F K1 */
static void essential(const double F[9], const double K1[9], const double K2[9], double E[9])
{
    double M[9];
    for (int r = 0; r < 3; r++)
        for (int c = 0; c < 3; c++)
            M[r * 3 + c] = F[r * 3] * K1[c] + F[r * 3 + 1] * K1[3 + c] + F[r * 3 + 2] * K1[6 + c];
    for (int r = 0; r < 3; r++)
        for (int c = 0; c < 3; c++)
            E[r * 3 + c] = K2[r] * M[c] + K2[3 + r] * M[3 + c] + K2[6 + r] * M[6 + c];
}

/* Ideal pinhole pixels and unit bearings of every point of one view. */
static int undistort(const sfm_camera *cam, const double *px, int n, double *ideal)
{
    for (int i = 0; i < n; i++) {
        double b[3];
        int st = sfm_camera_unproject(cam, &px[2 * i], b);
        if (st < 0)
            return st;
        if (!(b[2] > 1e-12))
            return SFM_E_NO_CONVERGENCE; /* no pinhole image: outside the field of view */
        ideal[2 * i] = cam->fx * b[0] / b[2] + cam->cx;
        ideal[2 * i + 1] = cam->fy * b[1] / b[2] + cam->cy;
    }
    return SFM_OK;
}

/* Metric bundle adjustment of the three poses and the inlier points, view 1
 * fixed and |t2| = 1, on the ideal pixels (intrinsics held). The projective
 * tensor has 18 degrees of freedom against the calibrated problem's 11, so
 * its essential matrices fit the noise; this step brings the estimate to the
 * calibrated maximum-likelihood answer. A Huber loss at 2 px guards against
 * inliers that are outliers of the calibrated model. */
static int polish(tv_ws *w, const sfm_camera *const cams[3], int m, sfm_pose est[3], double *cost)
{
    int st = sfm_triangulate_midpoint(3, est, m, w->bear, w->X, w->flags);
    if (st < 0)
        return st;
    int np = 0, no = 0;
    for (int j = 0; j < m; j++) {
        if (w->flags[j] != 0)
            continue;
        memmove(&w->X[3 * np], &w->X[3 * j], 3 * sizeof(double));
        for (int v = 0; v < 3; v++) {
            const double *b = &w->bear[((size_t)v * m + j) * 3];
            w->obs_cam[no] = v;
            w->obs_pt[no] = np;
            w->obs_xy[2 * no] = cams[v]->fx * b[0] / b[2] + cams[v]->cx;
            w->obs_xy[2 * no + 1] = cams[v]->fy * b[1] / b[2] + cams[v]->cy;
            no++;
        }
        np++;
    }
    if (np < SFM_TRIFOCAL_MIN_POINTS)
        return SFM_E_SINGULAR;
    double Rs[27], ts[9];
    sfm_camera K[3]; /* the ideal pinhole cameras of the undistorted pixels */
    for (int v = 0; v < 3; v++) {
        memcpy(&Rs[9 * v], est[v].R, 9 * sizeof(double));
        memcpy(&ts[3 * v], est[v].t, 3 * sizeof(double));
        memset(&K[v], 0, sizeof K[v]);
        K[v].model = SFM_CAMERA_PINHOLE;
        K[v].fx = cams[v]->fx;
        K[v].fy = cams[v]->fy;
        K[v].cx = cams[v]->cx;
        K[v].cy = cams[v]->cy;
    }
    sfm_ba_problem p = {3, np, no, Rs, ts, K, w->X, w->obs_cam, w->obs_pt, w->obs_xy, NULL, NULL, NULL};
    sfm_ba_options o;
    sfm_ba_default_options(&o);
    o.loss = SFM_BA_LOSS_HUBER;
    o.loss_scale = 2.0;
    o.scale_gauge = SFM_BA_SCALE_DISTANCE;
    o.scale_camera = 1;
    o.scale_distance = 1.0;
    o.max_iterations = 30;
    sfm_ba_result res;
    st = sfm_ba_solve(&p, &o, &res, NULL, 0, w->ba_ws, w->ba_size);
    if (st < 0)
        return st;
    for (int v = 0; v < 3; v++) {
        memcpy(est[v].R, &Rs[9 * v], 9 * sizeof(double));
        memcpy(est[v].t, &ts[3 * v], 3 * sizeof(double));
    }
    *cost = res.final_cost;
    return SFM_OK;
}

/* P = K [R | t] */
static void metric_camera(const sfm_camera *c, const sfm_pose *p, double P[12])
{
    const double K[9] = {c->fx, 0, c->cx, 0, c->fy, c->cy, 0, 0, 1};
    for (int r = 0; r < 3; r++)
        for (int col = 0; col < 4; col++) {
            double s = 0;
            for (int k = 0; k < 3; k++)
                s += K[r * 3 + k] * (col < 3 ? p->R[k * 3 + col] : p->t[k]);
            P[r * 4 + col] = s;
        }
}

/* Scale of t3 relative to |t2| = 1 from the gathered points triangulated in
 * views 1 and 2 (midpoint): least squares on b3 x (R3 X + s t3) = 0; then
 * polish. Writes the candidate and its cost; 0 when it fails. */
static int try_start(tv_ws *w, const sfm_camera *const cams[3], int m, const sfm_pose *p2,
                     const sfm_pose *p3, sfm_pose est[3], double *cost)
{
    memset(&est[0], 0, sizeof est[0]);
    est[0].R[0] = est[0].R[4] = est[0].R[8] = 1.0;
    est[1] = *p2;
    est[2] = *p3;
    if (sfm_triangulate_midpoint(2, est, m, w->bear, w->X, w->flags) <= 0)
        return 0;
    double s = sfmi_third_view_scale(p3, m, w->X, w->flags, &w->bear[(size_t)2 * m * 3]);
    if (!isfinite(s))
        return 0;
    const double *t3 = p3->t;
    for (int r = 0; r < 3; r++)
        est[2].t[r] = s * t3[r];
    return polish(w, cams, m, est, cost) == SFM_OK;
}

/* Triplets whose three-view error after optimal triangulation under the
 * metric cameras K [R | t] is below tau per view; written to w->mask when
 * write_mask. */
static int metric_inliers(tv_ws *w, const sfm_camera *const cams[3], int n, double tau,
                          const sfm_pose est[3], int write_mask)
{
    double Pm[3][12];
    for (int v = 0; v < 3; v++)
        metric_camera(cams[v], &est[v], Pm[v]);
    int cnt = 0;
    for (int i = 0; i < n; i++) {
        double e;
        int in = sfm_trifocal_point_error(Pm[0], Pm[1], Pm[2], &w->ideal[0][2 * i], &w->ideal[1][2 * i],
                                          &w->ideal[2][2 * i], &e, NULL) == SFM_OK &&
                 e / 3.0 < tau * tau;
        if (write_mask)
            w->mask[i] = (uint8_t)in;
        cnt += in;
    }
    return cnt;
}

static void keep_better(tv_ws *w, const sfm_camera *const cams[3], int n, double tau,
                        const sfm_pose cand[3], double cost, sfm_pose best[3], int *best_in,
                        double *best_cost)
{
    int in = metric_inliers(w, cams, n, tau, cand, 0);
    if (in > *best_in || (in == *best_in && cost < *best_cost)) {
        *best_in = in;
        *best_cost = cost;
        memcpy(best, cand, 3 * sizeof(sfm_pose));
    }
}

/* Bearings (z = 1) of the masked points, view-major with stride cnt. */
static int gather(tv_ws *w, const sfm_camera *const cams[3], int n, int cnt)
{
    int m = 0;
    for (int i = 0; i < n; i++) {
        if (!w->mask[i])
            continue;
        for (int v = 0; v < 3; v++) {
            double *b = &w->bear[((size_t)v * cnt + m) * 3];
            b[0] = (w->ideal[v][2 * i] - cams[v]->cx) / cams[v]->fx;
            b[1] = (w->ideal[v][2 * i + 1] - cams[v]->cy) / cams[v]->fy;
            b[2] = 1.0;
        }
        m++;
    }
    return m;
}

int sfm_recon_three_view_pose(const double *px1, const double *px2, const double *px3, int n,
                              const sfm_camera *cam1, const sfm_camera *cam2, const sfm_camera *cam3,
                              const sfm_ransac_options *opt, sfm_pose poses[3], uint8_t *inlier_mask,
                              sfm_ransac_stats *stats, void *ws, size_t ws_size)
{
    if (px1 == NULL || px2 == NULL || px3 == NULL || cam1 == NULL || cam2 == NULL || cam3 == NULL ||
        poses == NULL || ws == NULL || n < SFM_TRIFOCAL_MIN_POINTS || n > SFM_RANSAC_MAX_POINTS)
        return SFM_E_ARGUMENT;
    const sfm_camera *cams[3] = {cam1, cam2, cam3};
    const double *px[3] = {px1, px2, px3};
    for (int v = 0; v < 3; v++) {
        int st = sfm_camera_validate(cams[v]);
        if (st < 0)
            return st;
        if (!sfmi_la_all_finite(px[v], 2 * n))
            return SFM_E_NONFINITE;
    }
    sfmi_arena a;
    tv_ws w;
    sfmi_arena_init(&a, ws, ws_size);
    layout(&a, n, &w);
    if (!sfmi_arena_ok(&a))
        return SFM_E_WORKSPACE;
    for (int v = 0; v < 3; v++) {
        int st = undistort(cams[v], px[v], n, w.ideal[v]);
        if (st < 0)
            return st;
    }
    double T[27], P[36];
    sfm_ransac_stats rs;
    /* spread checks only: a dominant plane can make RANSAC's tensor a
     * plane-induced one, which the calibrated start (b) below recovers
     * from; the support of the metric result is judged at the end */
    int cnt = sfmi_ransac_trifocal(w.ideal[0], w.ideal[1], w.ideal[2], n, opt, T, P, w.mask, &rs,
                                   w.ransac_ws, w.ransac_size, 0);
    if (cnt == SFM_E_NO_CONVERGENCE || cnt == SFM_E_DEGENERATE) {
        /* no tensor, or none determined: when a rotation alone explains
         * views 1 and 2 the cause is the missing baseline, reported as such
         * (the minimal samples of views related by one homography are all
         * degenerate) */
        sfm_camera pc1 = *cams[0], pc2 = *cams[1];
        pc1.model = pc2.model = SFM_CAMERA_PINHOLE;
        sfm_pose p;
        sfm_ransac_stats s;
        if (sfm_ransac_relpose(w.ideal[0], w.ideal[1], n, &pc1, &pc2, opt, &p, NULL, NULL, &s,
                               w.rel_ws, w.rel_size) > 0 &&
            (s.flags & SFM_RANSAC_FLAG_PURE_ROTATION))
            return SFM_E_SINGULAR;
    }
    if (cnt < 0)
        return cnt;

    /* Candidate starts, each scaled and polished, then judged by how many of
     * all n triplets the metric cameras explain (ties: lower cost):
     * (a) the essential matrices of the tensor's fundamental matrices, on
     *     the trifocal inliers;
     * (b) calibrated 5-point RANSAC over all n pairs (1, 2) and (1, 3), on
     *     the triplets inlier to both. The calibrated model has no planar
     *     ambiguity of the projective kind, so (b) is right where a
     *     dominant plane made trifocal RANSAC settle on a plane-induced
     *     tensor, or made its fundamental matrices poorly determined. */
    double tau = opt != NULL ? opt->threshold : 1.0;
    sfm_ransac_options ro;
    if (opt != NULL)
        ro = *opt;
    else
        sfm_ransac_default_options(&ro);
    sfm_pose best[3], cand[3];
    int best_in = -1;
    double best_cost = HUGE_VAL, cost;

    int m = gather(&w, cams, n, cnt);
    sfm_mat3 F21, F31, E21, E31;
    double K1[9], K2[9], K3[9];
    int st = sfm_trifocal_fundamentals(T, &F21, &F31, NULL);
    if (st < 0)
        return st;
    K_of(cam1, K1);
    K_of(cam2, K2);
    K_of(cam3, K3);
    essential(F21.m, K1, K2, E21.m);
    essential(F31.m, K1, K3, E31.m);
    const double *b1 = w.bear, *b2 = &w.bear[(size_t)m * 3], *b3 = &w.bear[(size_t)2 * m * 3];
    sfm_pose c2[4], c3[4];
    if (sfm_essential_to_poses(&E21, b1, b2, m, c2, NULL) == 4 &&
        sfm_essential_to_poses(&E31, b1, b3, m, c3, NULL) == 4 &&
        try_start(&w, cams, m, &c2[0], &c3[0], cand, &cost))
        keep_better(&w, cams, n, tau, cand, cost, best, &best_in, &best_cost);

    sfm_camera pin[3];
    for (int v = 0; v < 3; v++) {
        pin[v] = *cams[v];
        pin[v].model = SFM_CAMERA_PINHOLE;
    }
    sfm_pose p12, p13;
    sfm_ransac_stats s12;
    int n12 = sfm_ransac_relpose(w.ideal[0], w.ideal[1], n, &pin[0], &pin[1], &ro, &p12, NULL, w.m12,
                                 &s12, w.rel_ws, w.rel_size);
    /* Rotation alone explains views 1 and 2: |t2|, the scale gauge, and with
     * it every translation are unobservable. */
    if (n12 > 0 && (s12.flags & SFM_RANSAC_FLAG_PURE_ROTATION))
        return SFM_E_SINGULAR;
    /* the pair that fixes the scale gauge has a support that determines no
     * pose (one cluster, a line): nor do the three views */
    if (n12 == SFM_E_DEGENERATE)
        return SFM_E_DEGENERATE;
    /* the (1, 2) pair's support checks: translation direction undetermined
     * (low parallax), or a dominant plane (the pose may be its twin) */
    const int pair_flags = n12 > 0 ? s12.flags & (SFM_RANSAC_FLAG_LOW_PARALLAX |
                                                  SFM_RANSAC_FLAG_PLANAR) : 0;
    if (n12 > 0 && sfm_ransac_relpose(w.ideal[0], w.ideal[2], n, &pin[0], &pin[2], &ro, &p13, NULL,
                                      w.m13, NULL, w.rel_ws, w.rel_size) > 0) {
        int mb = 0;
        for (int i = 0; i < n; i++) {
            w.mask[i] = (uint8_t)(w.m12[i] && w.m13[i]);
            mb += w.mask[i];
        }
        if (mb >= SFM_TRIFOCAL_MIN_POINTS) {
            m = gather(&w, cams, n, mb);
            if (try_start(&w, cams, m, &p12, &p13, cand, &cost))
                keep_better(&w, cams, n, tau, cand, cost, best, &best_in, &best_cost);
        }
    }
    if (best_in < SFM_TRIFOCAL_MIN_POINTS)
        return SFM_E_SINGULAR;

    /* Final inliers under the chosen metric cameras, and one more polish. */
    int cnt2 = metric_inliers(&w, cams, n, tau, best, 1);
    if (!sfmi_above_chance(n, SFM_TRIFOCAL_MIN_POINTS, cnt2,
                           sfmi_trifocal_chance(w.ideal[1], w.ideal[2], n, tau)))
        return SFM_E_NO_MODEL;
    m = gather(&w, cams, n, cnt2);
    memcpy(cand, best, sizeof cand);
    if (polish(&w, cams, m, cand, &cost) == SFM_OK)
        memcpy(best, cand, sizeof cand);
    cnt = cnt2;
    memcpy(poses, best, 3 * sizeof(sfm_pose));
    if (inlier_mask != NULL)
        memcpy(inlier_mask, w.mask, (size_t)n);
    if (stats != NULL) {
        /* The counters are the trifocal search's; the inliers are those of
         * the metric cameras returned, as in the mask and the return value. */
        *stats = rs;
        stats->num_inliers = cnt;
        stats->flags |= pair_flags;
    }
    return cnt;
}
