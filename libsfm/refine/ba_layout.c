/*
 * Bundle adjustment: the workspace, the parameter layout and the gauge.
 *
 * Each observation of camera c touches cam_q[c] camera-side parameters; the
 * a-th sits at local column cam_col[c][a] of the observation's Jacobian (see
 * ba_internal.h) and at index cam_gi[c][a] of the reduced camera system.
 * Held coordinates (held poses, camera 0 under SFM_BA_GAUGE_FIRST_CAMERA,
 * the scale gauge's translation coordinate, held intrinsics) have no index.
 * Shared intrinsics sit once, after every pose.
 */
#include <math.h>
#include <string.h>

#include "refine/ba_internal.h"
#include "sfm/sfm_linalg.h"

/* Distortion coefficients of a model (sfm_camera.dist entries it uses). */
static int model_ndist(int model)
{
    return model == SFM_CAMERA_BROWN ? 5 : model == SFM_CAMERA_FISHEYE ? 4 : 0;
}

/* Upper bound of the intrinsics a camera refines under the mask. */
int sfmi_ba_n_intrinsics(const sfm_ba_dims *d)
{
    if (d->intrinsics == SFM_BA_INTRINSICS_FIXED)
        return 0;
    const int mask = d->refine_intrinsics;
    int nd = (mask & SFM_BA_REFINE_DISTORTION) ? SFMI_BA_NDIST
             : (mask & SFM_BA_REFINE_RADIAL)   ? 2
             : (mask & SFM_BA_REFINE_K1)       ? 1
                                               : 0;
    return ((mask & SFM_BA_REFINE_FOCAL) ? 1 : 0) + ((mask & SFM_BA_REFINE_PRINCIPAL) ? 2 : 0) + nd;
}

int sfmi_ba_dims_valid(const sfm_ba_dims *d)
{
    if (d == NULL || d->n_cameras < 1 || d->n_points < 0 || d->n_observations < 1)
        return 0;
    if ((unsigned)d->intrinsics > (unsigned)SFM_BA_INTRINSICS_PER_CAMERA)
        return 0;
    if (d->refine_intrinsics < 0 || d->refine_intrinsics > (SFM_BA_REFINE_ALL | SFM_BA_REFINE_K1))
        return 0;
    /* the reduced system must fit the dense solver and int indexing */
    long long ni = sfmi_ba_n_intrinsics(d);
    long long nc = 6LL * d->n_cameras + (d->intrinsics == SFM_BA_INTRINSICS_PER_CAMERA ? ni * d->n_cameras : ni);
    if (nc > SFM_LINALG_MAX_DIM || d->n_points > (1 << 26) || d->n_observations > (1 << 26))
        return 0;
    return 1;
}

void sfmi_ba_carve(sfmi_arena *a, const sfm_ba_dims *d, sfmi_ba_ws *w, int *qmax_out, int *ncmax_out)
{
    int m = d->n_cameras, n = d->n_points, no = d->n_observations;
    int ni = sfmi_ba_n_intrinsics(d);
    int qmax = 6 + ni;
    int ncmax = 6 * m + (d->intrinsics == SFM_BA_INTRINSICS_PER_CAMERA ? ni * m : ni);
    size_t nc = (size_t)ncmax;
    w->cam_q = SFM_ARENA_ARRAY(a, int, m);
    w->cam_col = SFM_ARENA_ARRAY(a, int, (size_t)m * qmax);
    w->cam_gi = SFM_ARENA_ARRAY(a, int, (size_t)m * qmax);
    w->cam_base = SFM_ARENA_ARRAY(a, int, m);
    w->pt_start = SFM_ARENA_ARRAY(a, int, (size_t)n + 1);
    w->pt_obs = SFM_ARENA_ARRAY(a, int, no);
    w->pt_free = SFM_ARENA_ARRAY(a, int, (size_t)n + 1);
    w->R = SFM_ARENA_ARRAY(a, double, 9 * (size_t)m);
    w->t = SFM_ARENA_ARRAY(a, double, 3 * (size_t)m);
    w->K = SFM_ARENA_ARRAY(a, sfm_camera, m);
    w->X = SFM_ARENA_ARRAY(a, double, 3 * (size_t)n + 1);
    w->R2 = SFM_ARENA_ARRAY(a, double, 9 * (size_t)m);
    w->t2 = SFM_ARENA_ARRAY(a, double, 3 * (size_t)m);
    w->K2 = SFM_ARENA_ARRAY(a, sfm_camera, m);
    w->X2 = SFM_ARENA_ARRAY(a, double, 3 * (size_t)n + 1);
    w->res = SFM_ARENA_ARRAY(a, double, 2 * (size_t)no);
    w->Jc = SFM_ARENA_ARRAY(a, double, (size_t)no * 2 * qmax);
    w->Jp = SFM_ARENA_ARRAY(a, double, (size_t)no * 6);
    w->F = SFM_ARENA_ARRAY(a, double, (size_t)no * 3 * qmax);
    w->U = SFM_ARENA_ARRAY(a, double, nc * nc);
    w->S = SFM_ARENA_ARRAY(a, double, nc * nc);
    w->gc = SFM_ARENA_ARRAY(a, double, nc);
    w->dc = SFM_ARENA_ARRAY(a, double, nc);
    w->Dc = SFM_ARENA_ARRAY(a, double, nc);
    w->V = SFM_ARENA_ARRAY(a, double, 9 * (size_t)n + 1);
    w->gp = SFM_ARENA_ARRAY(a, double, 3 * (size_t)n + 1);
    w->L = SFM_ARENA_ARRAY(a, double, 9 * (size_t)n + 1);
    w->zp = SFM_ARENA_ARRAY(a, double, 3 * (size_t)n + 1);
    w->dp = SFM_ARENA_ARRAY(a, double, 3 * (size_t)n + 1);
    w->Dp = SFM_ARENA_ARRAY(a, double, 3 * (size_t)n + 1);
    w->aspect = SFM_ARENA_ARRAY(a, double, m);
    *qmax_out = qmax;
    *ncmax_out = ncmax;
}

/* Local intrinsics columns camera `cam` refines under the mask; returns
 * their count. */
static int intrinsics_columns(const sfm_camera *cam, int mask, int *cols)
{
    int k = 0;
    if (mask & SFM_BA_REFINE_FOCAL)
        cols[k++] = 6;
    if (mask & SFM_BA_REFINE_PRINCIPAL) {
        cols[k++] = 7;
        cols[k++] = 8;
    }
    int nd = model_ndist(cam->model);
    if (!(mask & SFM_BA_REFINE_DISTORTION) && (mask & SFM_BA_REFINE_RADIAL) && nd > 2)
        nd = 2;
    if (!(mask & (SFM_BA_REFINE_DISTORTION | SFM_BA_REFINE_RADIAL)))
        nd = (mask & SFM_BA_REFINE_K1) && nd > 0 ? 1 : 0;
    for (int e = 0; e < nd; e++)
        cols[k++] = 9 + e;
    return k;
}

/* The scale gauge by distance: the coordinate of t_c whose change best
 * measures scale, t_c(s) = s t_c - (1 - s) R_c C0 moving by t_c + R_c C0
 * per unit s; -1 when the centres coincide. */
static int distance_coordinate(const sfm_ba_problem *p, int cam)
{
    const double *R0 = p->rotations, *t0 = p->translations;
    const double *Rc = p->rotations + 9 * cam, *tc = p->translations + 3 * cam;
    double C0[3], best = 0.0;
    int coord = -1;
    for (int r = 0; r < 3; r++)
        C0[r] = -(R0[r] * t0[0] + R0[3 + r] * t0[1] + R0[6 + r] * t0[2]);
    for (int r = 0; r < 3; r++) {
        double v = tc[r] + Rc[3 * r] * C0[0] + Rc[3 * r + 1] * C0[1] + Rc[3 * r + 2] * C0[2];
        if (fabs(v) > best) {
            best = fabs(v);
            coord = r;
        }
    }
    return coord;
}

/* Observations grouped by point (counting sort) and the free flags. */
static int group_points(sfmi_ba_ctx *c)
{
    const sfm_ba_problem *p = c->p;
    sfmi_ba_ws *w = &c->w;
    const int n = c->n;
    for (int j = 0; j < n; j++)
        w->pt_free[j] = (c->o->mode != SFM_BA_MODE_POSE_ONLY) && !(p->point_fixed && p->point_fixed[j]);
    memset(w->pt_start, 0, sizeof(int) * ((size_t)n + 1));
    for (int k = 0; k < c->nobs; k++)
        w->pt_start[p->obs_point[k] + 1]++;
    for (int j = 0; j < n; j++) {
        if (w->pt_free[j] && w->pt_start[j + 1] == 0)
            return SFM_E_ARGUMENT; /* a free point nobody sees */
        w->pt_start[j + 1] += w->pt_start[j];
    }
    int *cursor = (int *)w->Dp; /* 3n + 1 doubles: room for n ints */
    for (int j = 0; j < n; j++)
        cursor[j] = w->pt_start[j];
    for (int k = 0; k < c->nobs; k++)
        w->pt_obs[cursor[p->obs_point[k]]++] = k;
    return SFM_OK;
}

/* The gauge: which translation coordinate the scale gauge holds. */
static int choose_gauge(sfmi_ba_ctx *c, int *gauge)
{
    const sfm_ba_problem *p = c->p;
    const sfm_ba_options *o = c->o;
    /* The gauge options act in FULL mode only: held points fix the gauge of a
     * pose-only solve, and a points-only solve holds every camera. */
    const int full = o->mode == SFM_BA_MODE_FULL;
    *gauge = full ? o->gauge : SFM_BA_GAUGE_NONE;
    c->scale_gauge = full ? o->scale_gauge : SFM_BA_SCALE_NONE;
    c->scale_cam = -1;
    c->scale_coord = -1;
    if (c->scale_gauge == SFM_BA_SCALE_COORDINATE) {
        c->scale_cam = o->scale_camera;
        c->scale_coord = o->scale_coordinate;
    } else if (c->scale_gauge == SFM_BA_SCALE_DISTANCE) {
        /* other held cameras or points would fix the scale themselves */
        for (int i = 1; i < c->m; i++)
            if (p->camera_flags && (p->camera_flags[i] & SFM_BA_FIX_POSE))
                return SFM_E_ARGUMENT;
        for (int j = 0; j < c->n; j++)
            if (!c->w.pt_free[j])
                return SFM_E_ARGUMENT;
        c->scale_coord = distance_coordinate(p, o->scale_camera);
        if (c->scale_coord < 0)
            return SFM_E_ARGUMENT; /* camera centres coincide: no scale to fix */
        c->scale_cam = o->scale_camera;
    }
    return SFM_OK;
}

/* Camera-side columns and reduced-system indices. */
static int index_cameras(sfmi_ba_ctx *c, int gauge, int ncmax)
{
    const sfm_ba_problem *p = c->p;
    const sfm_ba_options *o = c->o;
    sfmi_ba_ws *w = &c->w;
    const int m = c->m, qmax = c->qmax;
    int mask = o->intrinsics == SFM_BA_INTRINSICS_FIXED || o->mode == SFM_BA_MODE_POINTS_ONLY
                   ? 0
                   : o->refine_intrinsics;
    /* cam_q first counts observations per camera */
    memset(w->cam_q, 0, sizeof(int) * (size_t)m);
    for (int k = 0; k < c->nobs; k++)
        w->cam_q[p->obs_camera[k]]++;
    int nc = 0, icols[4 + SFMI_BA_NDIST];
    for (int ci = 0; ci < m; ci++) {
        int q = 0;
        int pose_free = o->mode != SFM_BA_MODE_POINTS_ONLY &&
                        !(p->camera_flags && (p->camera_flags[ci] & SFM_BA_FIX_POSE)) &&
                        !(ci == 0 && gauge == SFM_BA_GAUGE_FIRST_CAMERA);
        if (pose_free) {
            for (int l = 0; l < 6; l++) {
                if (ci == c->scale_cam && l == 3 + c->scale_coord)
                    continue;
                w->cam_col[(size_t)ci * qmax + q] = l;
                w->cam_gi[(size_t)ci * qmax + q] = nc++;
                q++;
            }
        }
        if (o->intrinsics == SFM_BA_INTRINSICS_PER_CAMERA &&
            !(p->camera_flags && (p->camera_flags[ci] & SFM_BA_FIX_INTRINSICS))) {
            int ni = intrinsics_columns(&p->cameras[ci], mask, icols);
            for (int e = 0; e < ni; e++) {
                w->cam_col[(size_t)ci * qmax + q] = icols[e];
                w->cam_gi[(size_t)ci * qmax + q] = nc++;
                q++;
            }
        }
        /* a camera with free parameters must be observed */
        if (q > 0 && w->cam_q[ci] == 0)
            return SFM_E_ARGUMENT;
        w->cam_q[ci] = q;
    }
    c->nic = 0;
    if (o->intrinsics == SFM_BA_INTRINSICS_SHARED) {
        /* one block: every camera of the same model */
        int ni = intrinsics_columns(&p->cameras[0], mask, icols);
        for (int ci = 0; ci < m; ci++) {
            for (int e = 0; e < ni; e++) {
                w->cam_col[(size_t)ci * qmax + w->cam_q[ci] + e] = icols[e];
                w->cam_gi[(size_t)ci * qmax + w->cam_q[ci] + e] = nc + e;
            }
            w->cam_q[ci] += ni;
        }
        nc += ni;
        c->nic = ni;
    } else if (o->intrinsics == SFM_BA_INTRINSICS_PER_CAMERA) {
        c->nic = mask ? 1 : 0;
    }
    for (int ci = 0; ci < m; ci++) {
        const int *gi = w->cam_gi + (size_t)ci * qmax;
        int contig = w->cam_q[ci] > 0;
        for (int e = 1; e < w->cam_q[ci]; e++)
            contig = contig && gi[e] == gi[0] + e;
        w->cam_base[ci] = contig ? gi[0] : -1;
    }
    c->nc = nc;
    return nc > ncmax ? SFM_E_ARGUMENT : SFM_OK; /* cannot happen: ncmax bounds every layout */
}

/* Working copies; a shared block starts from camera 0's refined entries. */
static void working_copies(sfmi_ba_ctx *c)
{
    const sfm_ba_problem *p = c->p;
    sfmi_ba_ws *w = &c->w;
    const int m = c->m, n = c->n;
    memcpy(w->R, p->rotations, sizeof(double) * 9 * (size_t)m);
    memcpy(w->t, p->translations, sizeof(double) * 3 * (size_t)m);
    memcpy(w->K, p->cameras, sizeof(sfm_camera) * (size_t)m);
    if (n > 0)
        memcpy(w->X, p->points, sizeof(double) * 3 * (size_t)n);
    for (int ci = 0; ci < m; ci++)
        w->aspect[ci] = w->K[ci].fy / w->K[ci].fx;
    if (c->o->intrinsics != SFM_BA_INTRINSICS_SHARED || c->nic == 0)
        return;
    const int *col = w->cam_col, q = w->cam_q[0];
    for (int ci = 1; ci < m; ci++) {
        sfm_camera *K = &w->K[ci];
        for (int a = q - c->nic; a < q; a++) {
            const int l = col[a];
            if (l == 6) {
                K->fx = w->K[0].fx;
                K->fy = K->fx * w->aspect[ci];
            } else if (l == 7) {
                K->cx = w->K[0].cx;
            } else if (l == 8) {
                K->cy = w->K[0].cy;
            } else {
                K->dist[l - 9] = w->K[0].dist[l - 9];
            }
        }
    }
}

int sfmi_ba_setup(sfmi_ba_ctx *c, int ncmax)
{
    int gauge, st = group_points(c);
    if (st == SFM_OK)
        st = choose_gauge(c, &gauge);
    if (st == SFM_OK)
        st = index_cameras(c, gauge, ncmax);
    if (st != SFM_OK)
        return st;
    working_copies(c);
    return SFM_OK;
}
