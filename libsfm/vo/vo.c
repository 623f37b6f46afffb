/* The visual-odometry pipeline: public entry points, workspace layout and
 * the per-frame state machine (initialisation, tracking, keyframes). The
 * stages are described in sfm/sfm_vo.h. */
#include <math.h>
#include <string.h>

#include "core/dmath.h"
#include "core/linalg_util.h"
#include "sfm/sfm_ransac_trifocal.h"
#include "sfm/sfm_rotation.h"
#include "sfm/sfm_triangulate.h"
#include "sfm/sfm_uncalibrated.h"
#include "vo/vo_internal.h"

#define VO_PI 3.14159265358979323846
#define VO_LOST_RESET 3 /* consecutive lost frames before the map is dropped */

static int dims_ok(const sfm_vo_dims *d)
{
    return d != NULL && d->width >= 2 * SFM_FEATURES_BORDER + 1 &&
           d->height >= 2 * SFM_FEATURES_BORDER + 1 && d->width <= 16384 && d->height <= 16384 &&
           d->max_features >= 8 && d->max_features <= SFM_VO_MAX_FEATURES &&
           d->window >= SFM_VO_MIN_WINDOW && d->window <= SFM_VO_MAX_WINDOW;
}

/* Feature workspace reserved for any detector parameters up to the largest
 * pyramid (SFM_FEATURES_MAX_LEVELS levels, finest scale step, finest grid). */
static size_t feat_reserve(const sfm_vo_dims *d)
{
    sfm_features_params fp;
    sfm_features_default_params(&fp);
    fp.max_features = d->max_features;
    size_t a = sfm_features_workspace_size(&fp, d->width, d->height);
    fp.n_levels = SFM_FEATURES_MAX_LEVELS;
    fp.scale_factor = 1.05;
    fp.cell_size = 8;
    size_t b = sfm_features_workspace_size(&fp, d->width, d->height);
    return a > b ? a : b;
}

static size_t ransac_reserve(int n)
{
    size_t s = sfm_ransac_abspose_workspace_size(n), r;
    r = sfm_ransac_relpose_workspace_size(n);
    s = r > s ? r : s;
    r = sfm_ransac_relpose_upright_workspace_size(n);
    s = r > s ? r : s;
    r = sfm_ransac_trifocal_workspace_size(n);
    return r > s ? r : s;
}

/* Triplets handed to the self-calibration (evenly spread over the matches
 * when there are more: its cost and workspace grow with them). */
#define VO_CAL_MAX_TRIPLETS 256

static int cal_triplets(int nf)
{
    return nf < VO_CAL_MAX_TRIPLETS ? nf : VO_CAL_MAX_TRIPLETS;
}

static size_t ba_reserve(int window, int max_points, int max_obs, int nf)
{
    sfm_ba_dims a = {window, max_points, max_obs, SFM_BA_INTRINSICS_FIXED, 0};
    sfm_ba_dims b = {1, nf, nf, SFM_BA_INTRINSICS_FIXED, 0};
    /* self-calibrated runs refine one shared focal length */
    sfm_ba_dims c = {window, max_points, max_obs, SFM_BA_INTRINSICS_SHARED, SFM_BA_REFINE_FOCAL};
    size_t x = sfm_ba_workspace_size(&a), y = sfm_ba_workspace_size(&b);
    size_t z = sfm_ba_workspace_size(&c);
    /* the self-calibration runs before any map exists: it borrows the BA
     * scratch */
    size_t u = nf >= 7 ? sfm_recon_three_view_uncalibrated_workspace_size_radial(cal_triplets(nf), 0) : 1;
    if (x == 0 || y == 0 || z == 0 || u == 0)
        return 0;
    x = x > y ? x : y;
    x = x > z ? x : z;
    return x > u ? x : u;
}

/* One carving for both measuring and laying out. */
static sfm_vo *layout(sfmi_arena *a, const sfm_vo_dims *d)
{
    int nf = d->max_features, w = d->window;
    int cap = w * nf;
    sfm_vo *vo = SFM_ARENA_ARRAY(a, sfm_vo, 1);
    sfm_vo tmp;
    sfm_vo *v = vo != NULL ? vo : &tmp;
    memset(v, 0, sizeof *v);
    for (int k = 0; k < w; k++) {
        v->kf[k].px = SFM_ARENA_ARRAY(a, double, 2 * nf);
        v->kf[k].desc = SFM_ARENA_ARRAY(a, uint8_t, SFM_FEATURES_DESC_BYTES * nf);
        v->kf[k].pid = SFM_ARENA_ARRAY(a, int, nf);
    }
    v->cap_points = cap;
    v->X = SFM_ARENA_ARRAY(a, double, 3 * (size_t)cap);
    v->pdesc = SFM_ARENA_ARRAY(a, uint8_t, (size_t)SFM_FEATURES_DESC_BYTES * cap);
    v->pobs = SFM_ARENA_ARRAY(a, int, cap);
    v->pname = SFM_ARENA_ARRAY(a, uint32_t, cap);
    v->pfirst_px = SFM_ARENA_ARRAY(a, double, 2 * (size_t)cap);
    v->pfirst_frame = SFM_ARENA_ARRAY(a, int, cap);
    v->free_list = SFM_ARENA_ARRAY(a, int, cap);
    v->kps = SFM_ARENA_ARRAY(a, sfm_keypoint, nf);
    v->desc = SFM_ARENA_ARRAY(a, uint8_t, SFM_FEATURES_DESC_BYTES * nf);
    v->px = SFM_ARENA_ARRAY(a, double, 2 * nf);
    v->valid = SFM_ARENA_ARRAY(a, uint8_t, nf);
    v->cur_pid = SFM_ARENA_ARRAY(a, int, nf);
    v->best_d = SFM_ARENA_ARRAY(a, int, cap > nf ? cap : nf);
    v->best_q = SFM_ARENA_ARRAY(a, int, cap > nf ? cap : nf);
    v->grid.gw = (d->width + VO_GRID_CELL - 1) / VO_GRID_CELL;
    v->grid.gh = (d->height + VO_GRID_CELL - 1) / VO_GRID_CELL;
    v->grid.start = SFM_ARENA_ARRAY(a, int, v->grid.gw * v->grid.gh + 1);
    v->grid.items = SFM_ARENA_ARRAY(a, int, nf);
    v->grid.cell = SFM_ARENA_ARRAY(a, int, nf);
    v->m_a = SFM_ARENA_ARRAY(a, double, 3 * nf);
    v->m_b = SFM_ARENA_ARRAY(a, double, 2 * nf);
    v->m_c = SFM_ARENA_ARRAY(a, double, 2 * nf);
    v->m_i = SFM_ARENA_ARRAY(a, int, nf);
    v->m_j = SFM_ARENA_ARRAY(a, int, nf);
    v->mask = SFM_ARENA_ARRAY(a, uint8_t, nf);
    v->cal_mid = SFM_ARENA_ARRAY(a, int, nf);
    v->feat_ws_size = feat_reserve(d);
    v->feat_ws = sfmi_arena_alloc(a, v->feat_ws_size);
    v->ransac_ws_size = ransac_reserve(nf);
    v->ransac_ws = sfmi_arena_alloc(a, v->ransac_ws_size);
    v->ba_max_obs = cap;
    v->ba_max_points = cap / 2 > nf ? cap / 2 : nf;
    v->ba_R = SFM_ARENA_ARRAY(a, double, 9 * w);
    v->ba_t = SFM_ARENA_ARRAY(a, double, 3 * w);
    v->ba_cam = SFM_ARENA_ARRAY(a, sfm_camera, w);
    v->ba_cf = SFM_ARENA_ARRAY(a, unsigned char, w);
    v->ba_X = SFM_ARENA_ARRAY(a, double, 3 * (size_t)v->ba_max_points);
    v->ba_of_point = SFM_ARENA_ARRAY(a, int, v->ba_max_points);
    v->ba_xy = SFM_ARENA_ARRAY(a, double, 2 * (size_t)v->ba_max_obs);
    v->ba_oc = SFM_ARENA_ARRAY(a, int, v->ba_max_obs);
    v->ba_op = SFM_ARENA_ARRAY(a, int, v->ba_max_obs);
    v->ba_of = SFM_ARENA_ARRAY(a, int, v->ba_max_obs);
    v->pt_ba = SFM_ARENA_ARRAY(a, int, cap);
    v->pt_tmp = SFM_ARENA_ARRAY(a, int, cap);
    v->ba_ws_size = ba_reserve(w, v->ba_max_points, v->ba_max_obs, nf);
    v->ba_ws = sfmi_arena_alloc(a, v->ba_ws_size);
    if (v->feat_ws_size == 0 || v->ransac_ws_size == 0 || v->ba_ws_size == 0)
        a->failed = 1;
    return vo;
}

size_t sfm_vo_workspace_size(const sfm_vo_dims *dims)
{
    if (!dims_ok(dims))
        return 0;
    sfmi_arena a;
    sfmi_arena_measure(&a);
    layout(&a, dims);
    if (a.failed)
        return 0;
    return sfmi_arena_required(&a);
}

int sfm_vo_default_params(const sfm_vo_dims *dims, sfm_vo_params *p)
{
    if (p == NULL || !dims_ok(dims))
        return SFM_E_ARGUMENT;
    memset(p, 0, sizeof *p);
    p->camera.model = SFM_CAMERA_PINHOLE;
    p->camera.fx = p->camera.fy = dims->width;
    p->camera.cx = (dims->width - 1) / 2.0;
    p->camera.cy = (dims->height - 1) / 2.0;
    p->calibrated = 1;
    p->max_features = dims->max_features;
    p->window = dims->window;
    sfm_features_default_params(&p->features);
    p->features.max_features = dims->max_features;
    p->features.n_levels = 4;
    p->features.cell_size = 32;
    p->track_radius = 20.0;
    p->init_radius = 120.0;
    p->max_hamming = 64;
    p->ratio = 0.9;
    p->threshold = 1.5;
    p->min_iterations = 100;
    p->max_iterations = 1000;
    p->min_inliers = 25;
    p->min_inlier_ratio = 0.25;
    p->min_parallax_deg = 1.0;
    p->keyframe_ratio = 0.7;
    p->keyframe_max_gap = 10;
    p->keyframe_min_parallax_deg = 0.5;
    p->point_min_parallax_deg = 0.5;
    p->ba_iterations = 8;
    p->use_trifocal = 1;
    p->seed = SFM_RNG_DEFAULT_SEED;
    return SFM_OK;
}

static int params_check(const sfm_vo_dims *d, const sfm_vo_params *p, size_t feat_reserved)
{
    double f[] = {p->track_radius, p->init_radius, p->ratio, p->threshold, p->min_inlier_ratio,
                  p->min_parallax_deg, p->keyframe_ratio, p->keyframe_min_parallax_deg,
                  p->point_min_parallax_deg,
                  p->frame_budget};
    if (!sfmi_la_all_finite(f, sizeof f / sizeof f[0]))
        return SFM_E_NONFINITE;
    int st = sfm_camera_validate(&p->camera);
    if (st < 0)
        return st;
    if (p->max_features < 8 || p->max_features > d->max_features || p->window < SFM_VO_MIN_WINDOW ||
        p->window > d->window || !(p->track_radius > 0) || !(p->init_radius > 0) ||
        p->max_hamming < 0 || p->max_hamming > 256 || !(p->ratio > 0 && p->ratio <= 1) ||
        !(p->threshold > 0) || p->min_iterations < 0 || p->max_iterations < 1 ||
        p->min_iterations > p->max_iterations || p->min_inliers < 6 ||
        !(p->min_inlier_ratio >= 0 && p->min_inlier_ratio <= 1) || !(p->min_parallax_deg >= 0) ||
        !(p->keyframe_ratio >= 0 && p->keyframe_ratio <= 1) || p->keyframe_max_gap < 1 ||
        !(p->keyframe_min_parallax_deg >= 0) || !(p->point_min_parallax_deg >= 0) ||
        p->ba_iterations < 0 || (p->calibrated != 0 && p->calibrated != 1))
        return SFM_E_ARGUMENT;
    sfm_features_params fp = p->features;
    fp.max_features = p->max_features;
    size_t need = sfm_features_workspace_size(&fp, d->width, d->height);
    if (need == 0 || need > feat_reserved)
        return SFM_E_ARGUMENT;
    /* Self-calibration models a pinhole camera (the uncalibrated
     * reconstruction's priors): a distortion model cannot be found. */
    if (!p->calibrated && p->camera.model != SFM_CAMERA_PINHOLE)
        return SFM_E_UNSUPPORTED;
    return SFM_OK;
}

int sfm_vo_init(const sfm_vo_dims *dims, const sfm_vo_params *params, sfm_vo **out, void *ws,
                size_t ws_size)
{
    if (params == NULL || ws == NULL || out == NULL || !dims_ok(dims))
        return SFM_E_ARGUMENT;
    int st = params_check(dims, params, feat_reserve(dims));
    if (st < 0)
        return st;
    if (ws_size < sfm_vo_workspace_size(dims))
        return SFM_E_WORKSPACE;
    sfmi_arena a;
    sfmi_arena_init(&a, ws, ws_size);
    sfm_vo *vo = layout(&a, dims);
    if (!sfmi_arena_ok(&a) || vo == NULL)
        return SFM_E_WORKSPACE;
    vo->dims = *dims;
    vo->p = *params;
    vo->K_guess[0] = params->camera.fx;
    vo->K_guess[1] = params->camera.fy;
    vo->K_guess[2] = params->camera.cx;
    vo->K_guess[3] = params->camera.cy;
    if (!params->calibrated) {
        /* unit aspect ratio, principal point at the centre: the priors of
         * sfm_recon_three_view_uncalibrated */
        vo->K_guess[1] = params->camera.fx;
        vo->K_guess[2] = (dims->width - 1) / 2.0;
        vo->K_guess[3] = (dims->height - 1) / 2.0;
    }
    for (int i = 0; i < vo->cap_points; i++)
        vo->pt_ba[i] = vo->pt_tmp[i] = -1;
    sfm_vo_reset(vo);
    *out = vo;
    return SFM_OK;
}

static void set_intrinsics(sfm_vo *vo, const double K[4])
{
    vo->pinhole.model = SFM_CAMERA_PINHOLE;
    vo->pinhole.fx = K[0];
    vo->pinhole.fy = K[1];
    vo->pinhole.cx = K[2];
    vo->pinhole.cy = K[3];
    memcpy(vo->K, K, sizeof vo->K);
}

int sfm_vo_reset(sfm_vo *vo)
{
    if (vo == NULL)
        return SFM_E_ARGUMENT;
    sfmi_vo_map_clear(vo);
    vo->frame_index = 0;
    vo->started = 0;
    vo->mapped = 0;
    vo->ever_mapped = 0;
    vo->have_last = vo->have_prev = 0;
    vo->frames_since_kf = 0;
    vo->kf_tracked = 0;
    vo->base_len = 1.0;
    vo->segment = 0;
    vo->origin_given = 0;
    vo->seg_speed = 0.0;
    vo->feat_count = vo->p.max_features;
    vo->lost_frames = 0;
    vo->next_name = 0;
    /* a self-calibrated focal length is forgotten with the map */
    set_intrinsics(vo, vo->K_guess);
    vo->cal_done = vo->p.calibrated;
    vo->cal_attempts = 0;
    vo->cal_mid_parallax = 0.0;
    vo->cal_next_parallax = 0.0;
    vo->cal_retry = 0;
    vo->cal_peak_parallax = 0.0;
    vo->cal_refinements = 0;
    return SFM_OK;
}

const char *sfm_vo_state_str(int state)
{
    switch (state) {
    case SFM_VO_INITIALISING: return "initialising";
    case SFM_VO_TRACKING: return "tracking";
    case SFM_VO_LOST: return "lost";
    case SFM_VO_INSUFFICIENT_PARALLAX: return "insufficient_parallax";
    case SFM_VO_PURE_ROTATION: return "pure_rotation";
    default: return "unknown";
    }
}

int sfm_vo_map_points(const sfm_vo *vo, double *xyz, uint32_t *ids, int capacity)
{
    if (vo == NULL || xyz == NULL || capacity < 0)
        return SFM_E_ARGUMENT;
    int n = 0;
    for (int i = 0; i < vo->cap_points && n < capacity; i++) {
        if (vo->pobs[i] <= 0)
            continue;
        memcpy(xyz + 3 * (size_t)n, vo->X + 3 * (size_t)i, 3 * sizeof(double));
        if (ids != NULL)
            ids[n] = vo->pname[i];
        n++;
    }
    return n;
}

int sfm_vo_map_points_first_seen(const sfm_vo *vo, uint32_t *ids, double *px, int *frame,
                                 int capacity)
{
    if (vo == NULL || px == NULL || frame == NULL || capacity < 0)
        return SFM_E_ARGUMENT;
    const sfm_camera *cam = &vo->p.camera;
    int n = 0;
    for (int i = 0; i < vo->cap_points && n < capacity; i++) {
        if (vo->pobs[i] <= 0)
            continue;
        /* ideal pinhole pixel back to the image through the camera model
         * (the identity for a pinhole or a self-calibrated camera) */
        double u = vo->pfirst_px[2 * i], v = vo->pfirst_px[2 * i + 1], uv[2] = {u, v};
        if (vo->p.calibrated && cam->model != SFM_CAMERA_PINHOLE) {
            double f[3] = {(u - cam->cx) / cam->fx, (v - cam->cy) / cam->fy, 1.0};
            if (sfm_camera_project(cam, f, uv, NULL) != SFM_OK)
                uv[0] = uv[1] = (double)NAN;
        }
        px[2 * n] = uv[0];
        px[2 * n + 1] = uv[1];
        frame[n] = vo->pfirst_frame[i];
        if (ids != NULL)
            ids[n] = vo->pname[i];
        n++;
    }
    return n;
}

/* ---------------------------------------------------------------------- */

static double now(const sfm_vo *vo)
{
    return vo->p.clock != NULL ? vo->p.clock(vo->p.clock_ctx) : 0.0;
}

static void set_pose(sfm_vo_frame_result *r, const double R[9], const double t[3])
{
    memcpy(r->R_cw, R, sizeof r->R_cw);
    memcpy(r->t_cw, t, sizeof r->t_cw);
    sfmi_vo_inverse(R, t, r->R_wc, r->c_w);
    r->has_pose = 1;
}

static void ransac_opts(const sfm_vo *vo, double t0, sfm_ransac_options *o)
{
    sfm_ransac_default_options(o);
    o->threshold = vo->p.threshold;
    o->min_iterations = vo->p.min_iterations;
    o->max_iterations = vo->p.max_iterations;
    o->seed = vo->p.seed ^ (0x9e3779b97f4a7c15ull * (uint64_t)(vo->frame_index + 1));
    if (vo->p.clock != NULL && vo->p.frame_budget > 0) {
        double left = vo->p.frame_budget - (now(vo) - t0);
        o->clock = vo->p.clock;
        o->clock_ctx = vo->p.clock_ctx;
        o->time_budget = left > 1e-4 ? left : 1e-4;
    }
}

/* The pose expected at this frame: the last motion per frame, continued
 * (rotation by its axis-angle scaled, translation scaled). */
static void predict(const sfm_vo *vo, double R[9], double t[3])
{
    memcpy(R, vo->R_last, sizeof vo->R_last);
    memcpy(t, vo->t_last, sizeof vo->t_last);
    if (!vo->have_prev)
        return;
    int span = vo->last_frame_index - vo->prev_frame_index;
    int ahead = vo->frame_index - vo->last_frame_index;
    if (span <= 0 || ahead <= 0)
        return;
    double Rpi[9], tpi[3], Rd[9], td[3], aa[3];
    sfmi_vo_inverse(vo->R_prev, vo->t_prev, Rpi, tpi);
    sfmi_vo_compose(vo->R_last, vo->t_last, Rpi, tpi, Rd, td);
    if (sfm_rot_to_axis_angle(Rd, aa) < 0)
        return;
    double f = (double)ahead / (double)span;
    for (int k = 0; k < 3; k++) {
        aa[k] *= f;
        td[k] *= f;
    }
    if (sfm_rot_from_axis_angle(aa, Rd) < 0)
        return;
    sfmi_vo_compose(Rd, td, vo->R_last, vo->t_last, R, t);
}

static void remember(sfm_vo *vo, const double R[9], const double t[3])
{
    if (vo->have_last) {
        memcpy(vo->R_prev, vo->R_last, sizeof vo->R_prev);
        memcpy(vo->t_prev, vo->t_last, sizeof vo->t_prev);
        vo->prev_frame_index = vo->last_frame_index;
        vo->have_prev = 1;
    }
    memcpy(vo->R_last, R, sizeof vo->R_last);
    memcpy(vo->t_last, t, sizeof vo->t_last);
    vo->last_frame_index = vo->frame_index;
    vo->have_last = 1;
}

static int count_pids(const vo_keyframe *k)
{
    int c = 0;
    for (int i = 0; i < k->n; i++)
        c += k->pid[i] >= 0;
    return c;
}

/* The reference frame of an initialisation: identity on a fresh run, else
 * the pose the last motion predicts for this frame. */
static void start_reference(sfm_vo *vo, const double *gravity, sfm_vo_frame_result *r)
{
    double R[9] = {1, 0, 0, 0, 1, 0, 0, 0, 1}, t[3] = {0, 0, 0};
    sfmi_vo_map_clear(vo);
    if (vo->ever_mapped && vo->mapped && vo->have_prev) {
        /* The map is lost: the speed of the last tracked motion (units per
         * frame) carries the scale over to the next segment's first pair. */
        double c0[3], c1[3];
        sfmi_vo_centre(vo->R_prev, vo->t_prev, c0);
        sfmi_vo_centre(vo->R_last, vo->t_last, c1);
        int span = vo->last_frame_index - vo->prev_frame_index;
        vo->seg_speed = span > 0 ? sfmi_hypot(sfmi_hypot(c1[0] - c0[0], c1[1] - c0[1]), c1[2] - c0[2]) / span
                                 : 0.0;
    }
    if (vo->ever_mapped && vo->have_last)
        predict(vo, R, t);
    for (int i = 0; i < vo->n; i++)
        vo->cur_pid[i] = -1;
    sfmi_vo_kf_push(vo, R, t, r->timestamp_ns, gravity);
    vo->mapped = 0;
    vo->have_prev = 0;
    r->state = SFM_VO_INITIALISING;
    r->is_keyframe = 1;
    if (!vo->ever_mapped) {
        /* A reference that starts over before the first map (no overlap
         * left, too few points triangulated, a self-calibration triple
         * starting over) is not tied to the one that reported the origin
         * before it: it reports the origin of a new segment, as after a
         * loss, rather than the same origin for another place. */
        if (vo->origin_given)
            vo->segment++;
        vo->origin_given = 1;
        set_pose(r, R, t); /* the origin, by definition */
        vo->have_last = 0;
        remember(vo, R, t);
        r->quality = SFM_VO_QUALITY_GOOD;
    }
}

static int self_calibrate(sfm_vo *vo, const double *gravity, int want_cov, double t0,
                          sfm_vo_frame_result *r, int nm, int inl, double med);

static int initialise(sfm_vo *vo, const double *gravity, int want_cov, double t0,
                      sfm_vo_frame_result *r)
{
    vo_keyframe *ref = sfmi_vo_kf_at(vo, 0);
    int *best_d = vo->best_d, *best_q = vo->best_q;
    sfmi_vo_best_reset(best_d, best_q, vo->n);
    for (int i = 0; i < ref->n; i++) {
        int d;
        int j = sfmi_vo_grid_search(&vo->grid, vo->px, vo->desc, ref->px + 2 * i,
                                    vo->p.init_radius,
                                    ref->desc + (size_t)SFM_FEATURES_DESC_BYTES * i,
                                    vo->p.max_hamming, vo->p.ratio, NULL, NULL, 0, &d);
        sfmi_vo_best_offer(best_d, best_q, j, d, i);
    }
    int nm = 0;
    for (int j = 0; j < vo->n; j++) {
        if (best_q[j] < 0)
            continue;
        int i = best_q[j];
        vo->m_c[2 * nm] = ref->px[2 * i];
        vo->m_c[2 * nm + 1] = ref->px[2 * i + 1];
        vo->m_b[2 * nm] = vo->px[2 * j];
        vo->m_b[2 * nm + 1] = vo->px[2 * j + 1];
        vo->m_i[nm] = i;
        vo->m_j[nm] = j;
        nm++;
    }
    r->n_matches = nm;
    r->state = SFM_VO_INITIALISING;
    if (nm < 2 * vo->p.min_inliers) {
        /* The reference no longer overlaps: start again from this frame. */
        if (nm < vo->p.min_inliers || vo->frame_index - ref->frame_index > vo->p.keyframe_max_gap)
            start_reference(vo, gravity, r);
        return SFM_OK;
    }
    /* A frame whose every match sits exactly where it was in the reference
     * (the same image again: a stalled capture) carries no baseline. It
     * does not reach the relative-pose RANSAC: on correspondences with
     * x2 = x1 the 5-point solver's root isolation need not end. */
    double moved = 0.0;
    for (int k = 0; k < 2 * nm; k++) {
        double dv = fabs(vo->m_b[k] - vo->m_c[k]);
        moved = dv > moved ? dv : moved;
    }
    if (!(moved > 1e-9)) {
        r->state = SFM_VO_INSUFFICIENT_PARALLAX;
        return SFM_OK;
    }
    sfm_ransac_options o;
    ransac_opts(vo, t0, &o);
    sfm_pose rel;
    sfm_mat3 E;
    sfm_ransac_stats rs;
    int inl;
    if (gravity != NULL && ref->has_gravity)
        inl = sfm_ransac_relpose_upright(vo->m_c, vo->m_b, nm, &vo->pinhole, &vo->pinhole,
                                         ref->gravity, gravity, &o, &rel, &E, vo->mask, &rs,
                                         vo->ransac_ws, vo->ransac_ws_size);
    else
        inl = sfm_ransac_relpose(vo->m_c, vo->m_b, nm, &vo->pinhole, &vo->pinhole, &o, &rel, &E,
                                 vo->mask, &rs, vo->ransac_ws, vo->ransac_ws_size);
    if (inl < 0) {
        /* The estimator's refusals are states of this frame, not errors:
         * too little of a baseline yet (degenerate support), or matches no
         * better than chance. */
        if (inl == SFM_E_DEGENERATE)
            r->state = SFM_VO_INSUFFICIENT_PARALLAX;
        if (inl == SFM_E_NO_CONVERGENCE || inl == SFM_E_SINGULAR || inl == SFM_E_DEGENERATE ||
            inl == SFM_E_NO_MODEL)
            return SFM_OK;
        return inl;
    }
    r->n_inliers = inl;
    if (rs.flags & SFM_RANSAC_FLAG_PURE_ROTATION) {
        r->state = SFM_VO_PURE_ROTATION;
        return SFM_OK;
    }
    /* SFM_RANSAC_FLAG_LOW_PARALLAX is left to the parallax test below,
     * which holds the first baseline to the pipeline's own bound. */
    /* Parallax of each inlier: angle between its two rays once the rotation
     * is taken out. */
    double *par = vo->m_a;
    int np = 0;
    for (int k = 0; k < nm; k++) {
        if (!vo->mask[k])
            continue;
        double f1[3] = {(vo->m_c[2 * k] - vo->K[2]) / vo->K[0], (vo->m_c[2 * k + 1] - vo->K[3]) / vo->K[1], 1};
        double f2[3] = {(vo->m_b[2 * k] - vo->K[2]) / vo->K[0], (vo->m_b[2 * k + 1] - vo->K[3]) / vo->K[1], 1};
        double g[3], z[3] = {0, 0, 0};
        sfmi_vo_transform(rel.R, z, f1, g);
        /* the angle between g and f2: rays from -g and -f2 meeting at 0 */
        double mg[3] = {-g[0], -g[1], -g[2]}, mf[3] = {-f2[0], -f2[1], -f2[2]};
        par[np++] = sfmi_vo_ray_angle(mg, mf, z);
    }
    double med = np > 0 ? sfmi_vo_median(par, np) * 180.0 / VO_PI : 0.0;
    r->median_parallax_deg = med;
    if (!vo->cal_done)
        return self_calibrate(vo, gravity, want_cov, t0, r, nm, inl, med);
    if (med < vo->p.min_parallax_deg) {
        r->state = SFM_VO_INSUFFICIENT_PARALLAX;
        return SFM_OK;
    }
    if (inl < 2 * vo->p.min_inliers)
        return SFM_OK;
    /* World poses of the pair: the reference's, and the relative pose on it
     * with the run's unit baseline. */
    double s = vo->base_len;
    if (vo->ever_mapped && vo->seg_speed > 0 && vo->frame_index > ref->frame_index)
        s = vo->seg_speed * (vo->frame_index - ref->frame_index);
    double R1[9], t1[3], ts[3] = {s * rel.t[0], s * rel.t[1], s * rel.t[2]};
    sfmi_vo_compose(rel.R, ts, ref->R, ref->t, R1, t1);
    double P[24];
    {
        const double *Rs[2] = {ref->R, R1}, *tv[2] = {ref->t, t1};
        for (int v = 0; v < 2; v++)
            for (int row = 0; row < 3; row++) {
                double kr0 = row == 0 ? vo->K[0] : 0, kr1 = row == 1 ? vo->K[1] : 0;
                double off = row == 0 ? vo->K[2] : (row == 1 ? vo->K[3] : 1);
                for (int c = 0; c < 3; c++)
                    P[12 * v + 4 * row + c] = kr0 * Rs[v][c] + kr1 * Rs[v][3 + c] + off * Rs[v][6 + c];
                P[12 * v + 4 * row + 3] = kr0 * tv[v][0] + kr1 * tv[v][1] + off * tv[v][2];
            }
    }
    double c0[3], c1[3];
    sfmi_vo_centre(ref->R, ref->t, c0);
    sfmi_vo_centre(R1, t1, c1);
    double tol = 2.0 * vo->p.threshold, min_par = 0.5 * vo->p.min_parallax_deg * VO_PI / 180.0;
    for (int j = 0; j < vo->n; j++)
        vo->cur_pid[j] = -1;
    int created = 0;
    for (int k = 0; k < nm; k++) {
        if (!vo->mask[k])
            continue;
        double x[4] = {vo->m_c[2 * k], vo->m_c[2 * k + 1], vo->m_b[2 * k], vo->m_b[2 * k + 1]};
        double X[3], u0[2], u1[2];
        int fl = 0;
        if (sfm_triangulate_dlt(2, P, 1, x, X, &fl) != 1 || fl != 0)
            continue;
        if (!sfmi_vo_project(vo->K, ref->R, ref->t, X, u0) || !sfmi_vo_project(vo->K, R1, t1, X, u1))
            continue;
        if (sfmi_hypot(u0[0] - x[0], u0[1] - x[1]) > tol || sfmi_hypot(u1[0] - x[2], u1[1] - x[3]) > tol)
            continue;
        if (sfmi_vo_ray_angle(c0, c1, X) < min_par)
            continue;
        int pid = sfmi_vo_point_new(vo, X, vo->desc + (size_t)SFM_FEATURES_DESC_BYTES * vo->m_j[k],
                                    vo->m_c + 2 * k, ref->frame_index);
        if (pid < 0)
            break;
        ref->pid[vo->m_i[k]] = pid;
        vo->pobs[pid] = 1;
        vo->cur_pid[vo->m_j[k]] = pid;
        created++;
    }
    if (created < vo->p.min_inliers * 2) {
        /* Not enough well-triangulated points: keep waiting on this reference. */
        for (int i = 0; i < ref->n; i++)
            if (ref->pid[i] >= 0) {
                sfmi_vo_point_unref(vo, ref->pid[i]);
                ref->pid[i] = -1;
            }
        r->state = SFM_VO_INSUFFICIENT_PARALLAX;
        return SFM_OK;
    }
    vo_keyframe *k1 = sfmi_vo_kf_push(vo, R1, t1, r->timestamp_ns, gravity);
    if (vo->p.ba_iterations > 0) {
        int st = sfmi_vo_window_ba(vo, 1, 1);
        if (st < 0 && st != SFM_E_NONFINITE)
            return st;
    }
    vo->kf_tracked = count_pids(k1);
    if (vo->kf_tracked < vo->p.min_inliers) {
        start_reference(vo, gravity, r);
        return SFM_OK;
    }
    if (vo->ever_mapped)
        vo->segment++;
    vo->mapped = 1;
    vo->ever_mapped = 1;
    vo->frames_since_kf = 0;
    vo->lost_frames = 0;
    vo->have_prev = 0;
    /* velocity from the pair: the reference is the previous pose */
    {
        memcpy(vo->R_last, ref->R, sizeof vo->R_last);
        memcpy(vo->t_last, ref->t, sizeof vo->t_last);
        vo->last_frame_index = ref->frame_index;
        vo->have_last = 1;
        remember(vo, k1->R, k1->t);
    }
    r->state = SFM_VO_TRACKING;
    r->is_keyframe = 1;
    r->quality = SFM_VO_QUALITY_GOOD;
    r->n_inliers = vo->kf_tracked;
    set_pose(r, k1->R, k1->t);
    if (want_cov) {
        int nc = 0;
        for (int j = 0; j < k1->n; j++) {
            int pid = k1->pid[j];
            if (pid < 0)
                continue;
            memcpy(vo->m_a + 3 * nc, vo->X + 3 * (size_t)pid, 3 * sizeof(double));
            vo->m_b[2 * nc] = k1->px[2 * j];
            vo->m_b[2 * nc + 1] = k1->px[2 * j + 1];
            vo->mask[nc++] = 1;
        }
        if (sfmi_vo_pose_covariance(vo, nc, k1->R, k1->t, r->covariance) == SFM_OK)
            r->has_covariance = 1;
    }
    return SFM_OK;
}

/* Share of its peak to which the parallax of a calibration triple's third
 * frame falls before the triple starts over (frame-to-frame changes of the
 * median parallax are a few per cent). */
#define CAL_FALLING 0.8

/* Largest relative standard deviation of a self-calibrated focal length
 * the pipeline starts tracking with (see sfm_vo.h). */
#define CAL_FOCAL_SIGMA 0.025

/* Unknown intrinsics. The relative-pose test of initialise() runs with the
 * focal guess (its parallax is then only approximate); the first frame that
 * passes it becomes the middle keyframe of the calibration triple (its
 * matches to the reference remembered), and the first later frame with
 * twice that parallax the third. Their triplets (every match of the third
 * frame to the reference that the middle also matched: the uncalibrated
 * reconstruction runs its own trifocal RANSAC) give the focal length by
 * sfm_recon_three_view_uncalibrated; on success the middle keyframe is
 * dropped and the ordinary initialisation runs on this frame with the found
 * focal length. A refusal (focal length not determined: translation only,
 * motion along the axis, too few triplets) moves the middle keyframe on
 * (below); a parallax that falls instead starts the triple over from this
 * frame; until an answer no frame is tracked. */
static int self_calibrate(sfm_vo *vo, const double *gravity, int want_cov, double t0,
                          sfm_vo_frame_result *r, int nm, int inl, double med)
{
    vo_keyframe *ref = sfmi_vo_kf_at(vo, 0);
    /* The next attempt waits for more parallax to the reference, which need
     * not come: a camera circling back towards its start (the demo
     * sequence: the parallax peaks near 19 deg, then falls while the
     * reference stays in view for all 240 frames). Once the parallax has
     * fallen to CAL_FALLING of its peak since the middle keyframe (or the
     * last failure), the triple starts over from this frame as the
     * reference, so that the attempts go on with other points and other
     * baselines. */
    if (vo->kf_count > 1 && med < CAL_FALLING * vo->cal_peak_parallax) {
        vo->cal_retry = 0;
        vo->cal_peak_parallax = 0.0;
        start_reference(vo, gravity, r);
        return SFM_OK;
    }
    vo->cal_peak_parallax = fmax(vo->cal_peak_parallax, med);
    if (med < vo->p.min_parallax_deg || inl < 2 * vo->p.min_inliers) {
        r->state = SFM_VO_INSUFFICIENT_PARALLAX;
        return SFM_OK;
    }
    if (vo->kf_count == 1 || (vo->cal_retry && med >= vo->cal_next_parallax)) {
        vo->kf_count = 1;
        vo->cal_retry = 0;
        for (int i = 0; i < ref->n; i++)
            vo->cal_mid[i] = -1;
        for (int k = 0; k < nm; k++)
            vo->cal_mid[vo->m_i[k]] = vo->m_j[k];
        for (int j = 0; j < vo->n; j++)
            vo->cur_pid[j] = -1;
        sfmi_vo_kf_push(vo, ref->R, ref->t, r->timestamp_ns, gravity); /* pose unused */
        vo->cal_mid_parallax = med;
        vo->cal_next_parallax = 2.0 * med;
        vo->cal_peak_parallax = med;
        r->state = SFM_VO_INITIALISING;
        return SFM_OK;
    }
    if (med < vo->cal_next_parallax) {
        r->state = SFM_VO_INSUFFICIENT_PARALLAX;
        return SFM_OK;
    }
    vo_keyframe *mid = sfmi_vo_kf_at(vo, 1);
    int nf = vo->dims.max_features, n3 = 0;
    double *p1 = vo->ba_xy, *p2 = p1 + 2 * (size_t)nf, *p3 = p2 + 2 * (size_t)nf;
    for (int k = 0; k < nm; k++) {
        int i = vo->m_i[k], jm = vo->cal_mid[i];
        if (jm < 0)
            continue;
        p1[2 * n3] = ref->px[2 * i];
        p1[2 * n3 + 1] = ref->px[2 * i + 1];
        p2[2 * n3] = mid->px[2 * jm];
        p2[2 * n3 + 1] = mid->px[2 * jm + 1];
        p3[2 * n3] = vo->m_b[2 * k];
        p3[2 * n3 + 1] = vo->m_b[2 * k + 1];
        n3++;
    }
    int cap = cal_triplets(nf);
    if (n3 > cap) {
        for (int q = 0; q < cap; q++) {
            int src = (int)((long)q * n3 / cap);
            for (int d = 0; d < 2; d++) {
                p1[2 * q + d] = p1[2 * src + d];
                p2[2 * q + d] = p2[2 * src + d];
                p3[2 * q + d] = p3[2 * src + d];
            }
        }
        n3 = cap;
    }
    int st = SFM_E_NO_CONVERGENCE;
    sfm_uncal_report rep;
    double Kc[27];
    sfm_pose poses[3];
    if (n3 >= 2 * vo->p.min_inliers) {
        sfm_uncal_options uo;
        sfm_uncal_default_options(&uo);
        uo.ransac.threshold = vo->p.threshold;
        uo.radial = 0; /* the map's camera is a pinhole */
        /* The windowed BA refines the answer over its first window
         * adjustments, so tracking may start from a focal length known to
         * 5 % at two sigma rather than three (the demo room, frame 23: 500.7
         * px, relative sigma 1.9 %, refused at the default 1.7 %). */
        uo.max_focal_sigma = CAL_FOCAL_SIGMA;
        uo.ransac.seed = vo->p.seed ^ (0x9e3779b97f4a7c15ull * (uint64_t)(vo->frame_index + 1));
        st = sfm_recon_three_view_uncalibrated(p1, p2, p3, n3, vo->dims.width, vo->dims.height, &uo,
                                               Kc, poses, NULL, NULL, &rep, vo->ba_ws,
                                               vo->ba_ws_size);
        vo->cal_attempts++;
    }
    if (st < 0) {
        if (st != SFM_E_NO_CONVERGENCE && st != SFM_E_SINGULAR && st != SFM_E_DEGENERATE &&
            st != SFM_E_NO_MODEL)
            return st;
        /* Too little baseline for three views (a degenerate trifocal
         * support: the middle keyframe too near the reference) or a focal
         * length the motion does not determine so far: this frame becomes
         * the middle keyframe at the next frame with a quarter more
         * parallax (so both baselines grow); the triple starts over when
         * the parallax falls instead (above) or initialise() when the
         * reference no longer overlaps. */
        vo->cal_next_parallax = 1.25 * med;
        vo->cal_retry = 1;
        vo->cal_peak_parallax = med;
        r->state = SFM_VO_INSUFFICIENT_PARALLAX;
        return SFM_OK;
    }
    double K[4] = {Kc[0], Kc[4], Kc[2], Kc[5]};
    set_intrinsics(vo, K);
    vo->cal_done = 1;
    vo->kf_count = 1; /* the middle keyframe holds no map point */
    return initialise(vo, gravity, want_cov, t0, r);
}

/* Guided 2D-3D matching: every live point projected with (R, t) and looked
 * for within radius. Fills m_a (X), m_b (px), m_i (keypoint), m_j (point). */
static int match_map(sfm_vo *vo, const double R[9], const double t[3], double radius)
{
    int *best_d = vo->best_d, *best_q = vo->best_q;
    sfmi_vo_best_reset(best_d, best_q, vo->n);
    double w = vo->dims.width, h = vo->dims.height;
    for (int pid = 0; pid < vo->cap_points; pid++) {
        if (vo->pobs[pid] <= 0)
            continue;
        double uv[2];
        if (!sfmi_vo_project(vo->K, R, t, vo->X + 3 * (size_t)pid, uv))
            continue;
        if (uv[0] < -radius || uv[1] < -radius || uv[0] > w + radius || uv[1] > h + radius)
            continue;
        int d;
        int j = sfmi_vo_grid_search(&vo->grid, vo->px, vo->desc, uv, radius,
                                    vo->pdesc + (size_t)SFM_FEATURES_DESC_BYTES * pid,
                                    vo->p.max_hamming, vo->p.ratio, NULL, NULL, 0, &d);
        sfmi_vo_best_offer(best_d, best_q, j, d, pid);
    }
    int nm = 0;
    for (int j = 0; j < vo->n; j++) {
        int pid = best_q[j];
        if (pid < 0)
            continue;
        memcpy(vo->m_a + 3 * nm, vo->X + 3 * (size_t)pid, 3 * sizeof(double));
        vo->m_b[2 * nm] = vo->px[2 * j];
        vo->m_b[2 * nm + 1] = vo->px[2 * j + 1];
        vo->m_i[nm] = j;
        vo->m_j[nm] = pid;
        nm++;
    }
    return nm;
}

static int track(sfm_vo *vo, const double *gravity, int want_cov, double t0,
                 sfm_vo_frame_result *r)
{
    double Rp[9], tp[3];
    predict(vo, Rp, tp);
    sfm_pose pose;
    int inl = -1, nm = 0;
    double radius[2] = {vo->lost_frames > 0 ? vo->p.init_radius : vo->p.track_radius,
                        vo->p.init_radius};
    for (int attempt = 0; attempt < 2; attempt++) {
        if (attempt == 1 && radius[0] == radius[1])
            break;
        nm = match_map(vo, Rp, tp, radius[attempt]);
        r->n_matches = nm;
        if (nm < vo->p.min_inliers)
            continue;
        sfm_ransac_options o;
        ransac_opts(vo, t0, &o);
        sfm_ransac_stats rs;
        inl = sfm_ransac_abspose(vo->m_b, vo->m_a, nm, &vo->pinhole, &o, &pose, vo->mask, &rs,
                                 vo->ransac_ws, vo->ransac_ws_size);
        if (inl < 0 && inl != SFM_E_NO_CONVERGENCE && inl != SFM_E_DEGENERATE &&
            inl != SFM_E_NO_MODEL)
            return inl;
        if (inl >= vo->p.min_inliers && inl >= vo->p.min_inlier_ratio * nm)
            break;
        inl = -1;
    }
    r->n_inliers = inl > 0 ? inl : 0;
    if (inl < 0) {
        r->state = SFM_VO_LOST;
        if (++vo->lost_frames >= VO_LOST_RESET)
            start_reference(vo, gravity, r), r->state = SFM_VO_LOST;
        return SFM_OK;
    }
    vo->lost_frames = 0;
    for (int j = 0; j < vo->n; j++)
        vo->cur_pid[j] = -1;
    for (int k = 0; k < nm; k++)
        if (vo->mask[k])
            vo->cur_pid[vo->m_i[k]] = vo->m_j[k];
    r->state = SFM_VO_TRACKING;
    r->quality = inl >= 2 * vo->p.min_inliers ? SFM_VO_QUALITY_GOOD : SFM_VO_QUALITY_DEGRADED;
    if (want_cov && sfmi_vo_pose_covariance(vo, nm, pose.R, pose.t, r->covariance) == SFM_OK)
        r->has_covariance = 1;
    set_pose(r, pose.R, pose.t);
    if (vo->p.clock != NULL)
        r->stage_seconds[SFM_VO_STAGE_TRACKING] = now(vo) - t0 - r->stage_seconds[SFM_VO_STAGE_FEATURES];

    /* Keyframe decision. */
    vo_keyframe *last = sfmi_vo_kf_at(vo, vo->kf_count - 1);
    for (int i = 0; i < last->n; i++)
        if (last->pid[i] >= 0)
            vo->pt_tmp[last->pid[i]] = 1;
    int common = 0, npar = 0;
    double c_now[3], c_kf[3];
    sfmi_vo_centre(pose.R, pose.t, c_now);
    sfmi_vo_centre(last->R, last->t, c_kf);
    for (int k = 0; k < nm; k++) {
        if (!vo->mask[k])
            continue;
        if (vo->pt_tmp[vo->m_j[k]] == 1) {
            common++;
            vo->m_c[npar++] = sfmi_vo_ray_angle(c_now, c_kf, vo->m_a + 3 * k);
        }
    }
    for (int i = 0; i < last->n; i++)
        if (last->pid[i] >= 0)
            vo->pt_tmp[last->pid[i]] = -1;
    double par = npar > 0 ? sfmi_vo_median(vo->m_c, npar) * 180.0 / VO_PI : 0.0;
    vo->frames_since_kf++;
    int need = common < vo->p.keyframe_ratio * vo->kf_tracked ||
               vo->frames_since_kf >= vo->p.keyframe_max_gap || inl < 3 * vo->p.min_inliers;
    int urgent = inl < 2 * vo->p.min_inliers;
    if (!((need && par >= vo->p.keyframe_min_parallax_deg) || urgent)) {
        remember(vo, pose.R, pose.t);
        return SFM_OK;
    }

    /* New keyframe. */
    double tm = now(vo);
    vo_keyframe *k = sfmi_vo_kf_push(vo, pose.R, pose.t, r->timestamp_ns, gravity);
    sfmi_vo_triangulate_new(vo);
    double tm2 = now(vo);
    r->stage_seconds[SFM_VO_STAGE_MAPPING] = tm2 - tm;
    int budget = vo->p.clock != NULL && vo->p.frame_budget > 0;
    if (vo->p.use_trifocal) {
        if (budget && tm2 - t0 > 0.6 * vo->p.frame_budget) {
            r->degraded |= SFM_VO_DEGRADED_TRIFOCAL_SKIPPED;
        } else {
            int st = sfmi_vo_trifocal_check(vo);
            if (st < 0 && st != SFM_E_NO_CONVERGENCE && st != SFM_E_DEGENERATE &&
                st != SFM_E_NO_MODEL && st != SFM_E_SINGULAR)
                return st;
        }
    }
    double tm3 = now(vo);
    r->stage_seconds[SFM_VO_STAGE_TRIFOCAL] = tm3 - tm2;
    if (vo->p.ba_iterations > 0) {
        if (budget && tm3 - t0 > 0.7 * vo->p.frame_budget) {
            r->degraded |= SFM_VO_DEGRADED_BA_SKIPPED;
        } else {
            int fixed = vo->kf_count >= 3 ? 2 : 1;
            int st = sfmi_vo_window_ba(vo, fixed, fixed == 1);
            if (st < 0 && st != SFM_E_NONFINITE)
                return st;
        }
    }
    r->stage_seconds[SFM_VO_STAGE_BA] = now(vo) - tm3;
    vo->kf_tracked = count_pids(k);
    vo->frames_since_kf = 0;
    r->is_keyframe = 1;
    set_pose(r, k->R, k->t);
    remember(vo, k->R, k->t);
    return SFM_OK;
}

/* A stage failed after the frame's checks (a status the stages keep for
 * themselves, such as SFM_E_WORKSPACE, which a workspace carved by
 * sfm_vo_init does not give): the map may be half updated, so the pipeline
 * starts again from a known state instead of carrying it (sfm_vo.h). */
static int internal_failure(sfm_vo *vo, int status)
{
    sfm_vo_reset(vo);
    return status;
}

int sfm_vo_push_frame(sfm_vo *vo, const sfm_image_u8 *image, int64_t timestamp_ns,
                      const double *gravity, int want_covariance, sfm_vo_frame_result *out)
{
    if (vo == NULL || image == NULL || out == NULL || image->data == NULL)
        return SFM_E_ARGUMENT;
    if (image->width != vo->dims.width || image->height != vo->dims.height ||
        image->stride < image->width)
        return SFM_E_ARGUMENT;
    if (vo->started && timestamp_ns < vo->last_ts)
        return SFM_E_ARGUMENT;
    if (gravity != NULL) {
        if (!sfmi_la_all_finite(gravity, 3))
            return SFM_E_NONFINITE;
        if (gravity[0] == 0 && gravity[1] == 0 && gravity[2] == 0)
            return SFM_E_ARGUMENT;
    }
    sfm_vo_frame_result r;
    memset(&r, 0, sizeof r);
    r.timestamp_ns = timestamp_ns;
    r.frame_index = vo->frame_index;
    double t0 = now(vo);

    sfm_features_params fp = vo->p.features;
    fp.max_features = vo->feat_count;
    int n = sfm_features_detect(image, &fp, vo->kps, vo->desc, vo->dims.max_features, vo->feat_ws,
                                vo->feat_ws_size);
    if (n < 0)
        return internal_failure(vo, n);
    if (vo->feat_count < vo->p.max_features)
        r.degraded |= SFM_VO_DEGRADED_FEATURES;
    vo->n = n;
    r.n_features = n;
    const sfm_camera *cam = &vo->p.camera;
    for (int i = 0; i < n; i++) {
        double uv[2] = {vo->kps[i].x, vo->kps[i].y}, f[3];
        vo->valid[i] = 0;
        vo->cur_pid[i] = -1;
        if (cam->model == SFM_CAMERA_PINHOLE) {
            vo->px[2 * i] = uv[0];
            vo->px[2 * i + 1] = uv[1];
            vo->valid[i] = 1;
        } else if (sfm_camera_unproject(cam, uv, f) == SFM_OK && f[2] > 1e-3) {
            vo->px[2 * i] = cam->fx * f[0] / f[2] + cam->cx;
            vo->px[2 * i + 1] = cam->fy * f[1] / f[2] + cam->cy;
            vo->valid[i] = 1;
        } else {
            vo->px[2 * i] = vo->px[2 * i + 1] = 0.0;
        }
    }
    sfmi_vo_grid_build(&vo->grid, vo->px, vo->valid, n);
    double t1 = now(vo);
    r.stage_seconds[SFM_VO_STAGE_FEATURES] = t1 - t0;

    int st;
    if (!vo->started || vo->kf_count == 0) {
        start_reference(vo, gravity, &r);
        st = SFM_OK;
    } else if (!vo->mapped) {
        st = initialise(vo, gravity, want_covariance, t0, &r);
    } else {
        st = track(vo, gravity, want_covariance, t0, &r);
    }
    if (st < 0)
        return internal_failure(vo, st);
    if (vo->p.clock != NULL && r.stage_seconds[SFM_VO_STAGE_TRACKING] == 0.0 && !r.is_keyframe)
        r.stage_seconds[SFM_VO_STAGE_TRACKING] = now(vo) - t1;
    if (!vo->mapped && r.state == SFM_VO_TRACKING)
        r.state = SFM_VO_INITIALISING;
    if (r.has_pose && r.quality == SFM_VO_QUALITY_GOOD && r.degraded)
        r.quality = SFM_VO_QUALITY_DEGRADED;
    if (!r.has_pose)
        r.quality = SFM_VO_QUALITY_NONE;
    int live = 0;
    for (int i = 0; i < vo->cap_points; i++)
        live += vo->pobs[i] > 0;
    r.n_map_points = live;
    r.n_keyframes = vo->kf_count;

    if (vo->p.clock != NULL && vo->p.frame_budget > 0) {
        double total = now(vo) - t0;
        int lo = vo->p.max_features / 4 > 8 ? vo->p.max_features / 4 : 8;
        if (total > vo->p.frame_budget) {
            int c = (int)(vo->feat_count * 0.8);
            vo->feat_count = c > lo ? c : lo;
        } else if (total < 0.8 * vo->p.frame_budget && vo->feat_count < vo->p.max_features) {
            int c = (int)(vo->feat_count * 1.1) + 1;
            vo->feat_count = c < vo->p.max_features ? c : vo->p.max_features;
        }
    }
    vo->started = 1;
    vo->last_ts = timestamp_ns;
    vo->frame_index++;
    r.focal = vo->cal_done ? vo->K[0] : 0.0;
    r.segment = vo->segment;
    *out = r;
    return SFM_OK;
}
