/* The VO map: keyframes in a ring, points with a count of the keyframes that
 * observe them (a point is freed when the last one leaves the window),
 * triangulation of new points between the two newest keyframes, the
 * trifocal consistency check over the three newest, and the windowed bundle
 * adjustment. */
#include <math.h>
#include <string.h>

#include "sfm/sfm_ransac_trifocal.h"
#include "sfm/sfm_triangulate.h"
#include "sfm/sfm_trifocal.h"
#include "vo/vo_internal.h"
#include "core/dmath.h"

/* Tracks the trifocal tensor is fitted on. */
#define VO_TRIFOCAL_FIT 160

vo_keyframe *sfmi_vo_kf_at(sfm_vo *vo, int i)
{
    return &vo->kf[(vo->kf_head + i) % vo->p.window];
}

int sfmi_vo_point_new(sfm_vo *vo, const double X[3], const uint8_t *desc, const double px[2],
                      int frame)
{
    if (vo->n_free == 0)
        return -1;
    int pid = vo->free_list[--vo->n_free];
    memcpy(vo->X + 3 * (size_t)pid, X, 3 * sizeof(double));
    memcpy(vo->pdesc + (size_t)SFM_FEATURES_DESC_BYTES * pid, desc, SFM_FEATURES_DESC_BYTES);
    vo->pobs[pid] = 0;
    vo->pname[pid] = vo->next_name++;
    vo->pfirst_px[2 * pid] = px[0];
    vo->pfirst_px[2 * pid + 1] = px[1];
    vo->pfirst_frame[pid] = frame;
    return pid;
}

void sfmi_vo_point_unref(sfm_vo *vo, int pid)
{
    if (--vo->pobs[pid] == 0)
        vo->free_list[vo->n_free++] = pid;
}

void sfmi_vo_map_clear(sfm_vo *vo)
{
    vo->kf_head = 0;
    vo->kf_count = 0;
    vo->n_free = 0;
    for (int i = vo->cap_points - 1; i >= 0; i--) {
        vo->pobs[i] = 0;
        vo->free_list[vo->n_free++] = i;
    }
}

static void kf_drop_obs(sfm_vo *vo, vo_keyframe *k, int i)
{
    int pid = k->pid[i];
    if (pid >= 0) {
        k->pid[i] = -1;
        sfmi_vo_point_unref(vo, pid);
    }
}

vo_keyframe *sfmi_vo_kf_push(sfm_vo *vo, const double R[9], const double t[3], int64_t ts,
                             const double *gravity)
{
    if (vo->kf_count == vo->p.window) {
        vo_keyframe *old = sfmi_vo_kf_at(vo, 0);
        for (int i = 0; i < old->n; i++)
            kf_drop_obs(vo, old, i);
        vo->kf_head = (vo->kf_head + 1) % vo->p.window;
        vo->kf_count--;
    }
    vo_keyframe *k = sfmi_vo_kf_at(vo, vo->kf_count);
    vo->kf_count++;
    k->frame_index = vo->frame_index;
    k->timestamp_ns = ts;
    memcpy(k->R, R, sizeof k->R);
    memcpy(k->t, t, sizeof k->t);
    k->n = vo->n;
    memcpy(k->px, vo->px, 2 * sizeof(double) * (size_t)vo->n);
    memcpy(k->desc, vo->desc, (size_t)SFM_FEATURES_DESC_BYTES * vo->n);
    k->has_gravity = gravity != NULL;
    if (gravity != NULL)
        memcpy(k->gravity, gravity, sizeof k->gravity);
    for (int i = 0; i < vo->n; i++) {
        int pid = vo->valid[i] ? vo->cur_pid[i] : -1;
        k->pid[i] = pid;
        if (pid >= 0) {
            vo->pobs[pid]++;
            memcpy(vo->pdesc + (size_t)SFM_FEATURES_DESC_BYTES * pid,
                   vo->desc + (size_t)SFM_FEATURES_DESC_BYTES * i, SFM_FEATURES_DESC_BYTES);
        }
    }
    return k;
}

static void projection(const double K[4], const double R[9], const double t[3], double P[12])
{
    for (int r = 0; r < 3; r++) {
        double kr[3] = {r == 0 ? K[0] : 0.0, r == 1 ? K[1] : 0.0, 0.0};
        double off = r == 0 ? K[2] : (r == 1 ? K[3] : 1.0);
        for (int c = 0; c < 3; c++)
            P[4 * r + c] = kr[0] * R[c] + kr[1] * R[3 + c] + off * R[6 + c];
        P[4 * r + 3] = kr[0] * t[0] + kr[1] * t[1] + off * t[2];
    }
}

/* Pixel epipolar line in b of pixel uv of a: K^-T [t]x R K^-1 (u, v, 1),
 * scaled so that (l0, l1) has unit length (the value is then a distance). */
static void epiline(const double K[4], const double Rab[9], const double tab[3],
                    const double uv[2], double l[3])
{
    double xn[3] = {(uv[0] - K[2]) / K[0], (uv[1] - K[3]) / K[1], 1.0}, y[3], ln[3];
    for (int r = 0; r < 3; r++)
        y[r] = Rab[3 * r] * xn[0] + Rab[3 * r + 1] * xn[1] + Rab[3 * r + 2] * xn[2];
    ln[0] = tab[1] * y[2] - tab[2] * y[1];
    ln[1] = tab[2] * y[0] - tab[0] * y[2];
    ln[2] = tab[0] * y[1] - tab[1] * y[0];
    l[0] = ln[0] / K[0];
    l[1] = ln[1] / K[1];
    l[2] = ln[2] - K[2] * l[0] - K[3] * l[1];
    double s = sqrt(l[0] * l[0] + l[1] * l[1]);
    if (s > 0)
        for (int k = 0; k < 3; k++)
            l[k] /= s;
}

int sfmi_vo_triangulate_new(sfm_vo *vo)
{
    if (vo->kf_count < 2)
        return 0;
    vo_keyframe *a = sfmi_vo_kf_at(vo, vo->kf_count - 2);
    vo_keyframe *b = sfmi_vo_kf_at(vo, vo->kf_count - 1);
    double Ria[9], tia[3], Rab[9], tab[3];
    sfmi_vo_inverse(a->R, a->t, Ria, tia);
    sfmi_vo_compose(b->R, b->t, Ria, tia, Rab, tab);
    double ca[3], cb[3];
    sfmi_vo_centre(a->R, a->t, ca);
    sfmi_vo_centre(b->R, b->t, cb);
    /* b's keypoints are the current frame's: the grid indexes them. */
    int *best_d = vo->best_d, *best_q = vo->best_q;
    sfmi_vo_best_reset(best_d, best_q, b->n);
    double tol = 2.0 * vo->p.threshold;
    for (int i = 0; i < a->n; i++) {
        if (a->pid[i] >= 0)
            continue;
        double l[3];
        epiline(vo->K, Rab, tab, a->px + 2 * i, l);
        int d;
        int j = sfmi_vo_grid_search(&vo->grid, b->px, b->desc, a->px + 2 * i, vo->p.init_radius,
                                    a->desc + (size_t)SFM_FEATURES_DESC_BYTES * i,
                                    vo->p.max_hamming, vo->p.ratio, b->pid, l, tol, &d);
        sfmi_vo_best_offer(best_d, best_q, j, d, i);
    }
    double Pa[12], Pb[12], P[24];
    projection(vo->K, a->R, a->t, Pa);
    projection(vo->K, b->R, b->t, Pb);
    memcpy(P, Pa, sizeof Pa);
    memcpy(P + 12, Pb, sizeof Pb);
    double min_par = vo->p.point_min_parallax_deg * 3.14159265358979323846 / 180.0;
    int created = 0;
    for (int j = 0; j < b->n; j++) {
        int i = best_q[j];
        if (i < 0)
            continue;
        double x[4] = {a->px[2 * i], a->px[2 * i + 1], b->px[2 * j], b->px[2 * j + 1]}, X[3];
        int fl = 0;
        if (sfm_triangulate_dlt(2, P, 1, x, X, &fl) != 1 || fl != 0)
            continue;
        double ua[2], ub[2];
        if (!sfmi_vo_project(vo->K, a->R, a->t, X, ua) || !sfmi_vo_project(vo->K, b->R, b->t, X, ub))
            continue;
        double ea = sfmi_hypot(ua[0] - x[0], ua[1] - x[1]), eb = sfmi_hypot(ub[0] - x[2], ub[1] - x[3]);
        if (ea > tol || eb > tol)
            continue;
        if (sfmi_vo_ray_angle(ca, cb, X) < min_par)
            continue;
        int pid = sfmi_vo_point_new(vo, X, b->desc + (size_t)SFM_FEATURES_DESC_BYTES * j,
                                    a->px + 2 * i, a->frame_index);
        if (pid < 0)
            break;
        a->pid[i] = pid;
        b->pid[j] = pid;
        vo->pobs[pid] = 2;
        created++;
    }
    return created;
}

int sfmi_vo_trifocal_check(sfm_vo *vo)
{
    if (vo->kf_count < 3)
        return 0;
    vo_keyframe *k1 = sfmi_vo_kf_at(vo, vo->kf_count - 3);
    vo_keyframe *k2 = sfmi_vo_kf_at(vo, vo->kf_count - 2);
    vo_keyframe *k3 = sfmi_vo_kf_at(vo, vo->kf_count - 1);
    int *in1 = vo->pt_ba, *in2 = vo->pt_tmp;
    for (int i = 0; i < k1->n; i++)
        if (k1->pid[i] >= 0)
            in1[k1->pid[i]] = i;
    for (int i = 0; i < k2->n; i++)
        if (k2->pid[i] >= 0)
            in2[k2->pid[i]] = i;
    int n = 0;
    for (int i = 0; i < k3->n; i++) {
        int pid = k3->pid[i];
        if (pid < 0 || in1[pid] < 0 || in2[pid] < 0)
            continue;
        /* m_a rows are 3 wide: view 1 pixels there, views 2 and 3 in m_b, m_c */
        vo->m_a[2 * n] = k1->px[2 * in1[pid]];
        vo->m_a[2 * n + 1] = k1->px[2 * in1[pid] + 1];
        vo->m_b[2 * n] = k2->px[2 * in2[pid]];
        vo->m_b[2 * n + 1] = k2->px[2 * in2[pid] + 1];
        vo->m_c[2 * n] = k3->px[2 * i];
        vo->m_c[2 * n + 1] = k3->px[2 * i + 1];
        vo->m_i[n++] = i;
    }
    for (int i = 0; i < k1->n; i++)
        if (k1->pid[i] >= 0)
            in1[k1->pid[i]] = -1;
    for (int i = 0; i < k2->n; i++)
        if (k2->pid[i] >= 0)
            in2[k2->pid[i]] = -1;
    if (n < 20)
        return 0;
    /* The tensor is fitted on at most VO_TRIFOCAL_FIT evenly spread tracks
     * (its cost grows with the refinement set), then every track is judged
     * by its three-view reprojection error under the fitted cameras. */
    int sub = n < VO_TRIFOCAL_FIT ? n : VO_TRIFOCAL_FIT;
    if (3 * sub > vo->ba_max_obs)
        sub = vo->ba_max_obs / 3;
    double *s1 = vo->ba_xy, *s2 = s1 + 2 * sub, *s3 = s2 + 2 * sub;
    for (int q = 0; q < sub; q++) {
        int r = (int)((long)q * n / sub);
        for (int d = 0; d < 2; d++) {
            s1[2 * q + d] = vo->m_a[2 * r + d];
            s2[2 * q + d] = vo->m_b[2 * r + d];
            s3[2 * q + d] = vo->m_c[2 * r + d];
        }
    }
    sfm_ransac_options opt;
    sfm_ransac_default_options(&opt);
    opt.threshold = 2.0 * vo->p.threshold;
    opt.seed = vo->p.seed ^ (0x9e3779b97f4a7c15ull * (uint64_t)(vo->frame_index + 1));
    opt.max_iterations = 100;
    opt.min_iterations = 20;
    opt.lo_rounds = 1;
    opt.polish_rounds = 0;
    double T[27], P[36];
    int st = sfm_ransac_trifocal(s1, s2, s3, sub, &opt, T, P, vo->mask, NULL, vo->ransac_ws,
                                 vo->ransac_ws_size);
    if (st < 0)
        return st;
    /* A tensor that explains few of the tracks says nothing about the rest. */
    if (st < sub / 2)
        return 0;
    double lim = 3.0 * opt.threshold * opt.threshold; /* sum over three views */
    int removed = 0;
    for (int r = 0; r < n; r++) {
        double e2;
        int es = sfm_trifocal_point_error(P, P + 12, P + 24, vo->m_a + 2 * r, vo->m_b + 2 * r,
                                          vo->m_c + 2 * r, &e2, NULL);
        if (es == SFM_OK && e2 <= lim)
            continue;
        kf_drop_obs(vo, k3, vo->m_i[r]);
        removed++;
    }
    return removed;
}

void sfmi_vo_ba_problem(sfm_vo *vo, int m, int np, int no, sfm_ba_problem *pr)
{
    memset(pr, 0, sizeof *pr);
    pr->n_cameras = m;
    pr->n_points = np;
    pr->n_observations = no;
    pr->rotations = vo->ba_R;
    pr->translations = vo->ba_t;
    pr->cameras = vo->ba_cam;
    pr->points = vo->ba_X;
    pr->obs_camera = vo->ba_oc;
    pr->obs_point = vo->ba_op;
    pr->obs_xy = vo->ba_xy;
}

int sfmi_vo_window_ba(sfm_vo *vo, int fixed, int scale_gauge)
{
    int m = vo->kf_count;
    int np = 0, no = 0;
    for (int c = 0; c < m; c++) {
        vo_keyframe *k = sfmi_vo_kf_at(vo, c);
        for (int i = 0; i < k->n; i++) {
            int pid = k->pid[i];
            if (pid < 0 || vo->pobs[pid] < 2)
                continue;
            if (vo->pt_ba[pid] < 0) {
                if (np == vo->ba_max_points)
                    continue;
                vo->pt_ba[pid] = np;
                vo->ba_of_point[np] = pid;
                memcpy(vo->ba_X + 3 * np, vo->X + 3 * (size_t)pid, 3 * sizeof(double));
                np++;
            }
            if (no == vo->ba_max_obs)
                continue;
            vo->ba_oc[no] = c;
            vo->ba_op[no] = vo->pt_ba[pid];
            vo->ba_of[no] = i;
            vo->ba_xy[2 * no] = k->px[2 * i];
            vo->ba_xy[2 * no + 1] = k->px[2 * i + 1];
            no++;
        }
        memcpy(vo->ba_R + 9 * c, k->R, sizeof k->R);
        memcpy(vo->ba_t + 3 * c, k->t, sizeof k->t);
        vo->ba_cam[c] = vo->pinhole;
        vo->ba_cf[c] = c < fixed ? SFM_BA_FIX_POSE : 0;
    }
    for (int q = 0; q < np; q++)
        vo->pt_ba[vo->ba_of_point[q]] = -1;
    if (np == 0 || no == 0)
        return SFM_OK;
    sfm_ba_problem pr;
    sfmi_vo_ba_problem(vo, m, np, no, &pr);
    pr.camera_flags = vo->ba_cf;
    sfm_ba_options o;
    sfm_ba_default_options(&o);
    o.loss = SFM_BA_LOSS_HUBER;
    o.loss_scale = vo->p.threshold;
    o.max_iterations = vo->p.ba_iterations;
    o.gauge = SFM_BA_GAUGE_FIRST_CAMERA;
    /* A self-calibrated focal length is refined with the window (one shared
     * pinhole camera) over the first `window` adjustments of three keyframes
     * or more (a pair alone determines it poorly), then held: one window's
     * estimate wanders by a few percent and, refined in every window, the
     * errors accumulate (the demo sequence: 492 px self-calibrated, true
     * 500, drifting to 596 px by the end of the loop). */
    int refine_f = !vo->p.calibrated && vo->cal_done && m >= 3 &&
                   vo->cal_refinements < vo->p.window;
    if (refine_f) {
        o.intrinsics = SFM_BA_INTRINSICS_SHARED;
        o.refine_intrinsics = SFM_BA_REFINE_FOCAL;
    }
    if (scale_gauge) {
        double c0[3], c1[3];
        sfmi_vo_centre(vo->ba_R, vo->ba_t, c0);
        sfmi_vo_centre(vo->ba_R + 9, vo->ba_t + 3, c1);
        o.scale_gauge = SFM_BA_SCALE_DISTANCE;
        o.scale_camera = 1;
        o.scale_distance = sfmi_hypot(sfmi_hypot(c1[0] - c0[0], c1[1] - c0[1]), c1[2] - c0[2]);
    }
    sfm_ba_result res;
    int st = sfm_ba_solve(&pr, &o, &res, NULL, 0, vo->ba_ws, vo->ba_ws_size);
    if (st < 0)
        return st;
    for (int c = 0; c < m; c++) {
        vo_keyframe *k = sfmi_vo_kf_at(vo, c);
        memcpy(k->R, vo->ba_R + 9 * c, sizeof k->R);
        memcpy(k->t, vo->ba_t + 3 * c, sizeof k->t);
    }
    for (int q = 0; q < np; q++)
        memcpy(vo->X + 3 * (size_t)vo->ba_of_point[q], vo->ba_X + 3 * q, 3 * sizeof(double));
    if (refine_f) {
        vo->cal_refinements++;
        vo->pinhole = vo->ba_cam[0];
        vo->K[0] = vo->pinhole.fx;
        vo->K[1] = vo->pinhole.fy;
    }
    /* Observations the refined geometry does not explain leave the map. */
    double lim = 3.0 * vo->p.threshold;
    for (int o2 = 0; o2 < no; o2++) {
        vo_keyframe *k = sfmi_vo_kf_at(vo, vo->ba_oc[o2]);
        int i = vo->ba_of[o2];
        int pid = k->pid[i];
        if (pid < 0)
            continue;
        double uv[2];
        int ok = sfmi_vo_project(vo->K, k->R, k->t, vo->X + 3 * (size_t)pid, uv);
        if (!ok || sfmi_hypot(uv[0] - k->px[2 * i], uv[1] - k->px[2 * i + 1]) > lim)
            kf_drop_obs(vo, k, i);
    }
    return SFM_OK;
}

int sfmi_vo_pose_covariance(sfm_vo *vo, int nm, const double R[9], const double t[3],
                            double cov[36])
{
    int np = 0;
    for (int r = 0; r < nm && np < vo->ba_max_points; r++) {
        if (!vo->mask[r])
            continue;
        memcpy(vo->ba_X + 3 * np, vo->m_a + 3 * r, 3 * sizeof(double));
        vo->ba_xy[2 * np] = vo->m_b[2 * r];
        vo->ba_xy[2 * np + 1] = vo->m_b[2 * r + 1];
        vo->ba_oc[np] = 0;
        vo->ba_op[np] = np;
        np++;
    }
    if (np < 3)
        return SFM_E_SINGULAR;
    memcpy(vo->ba_R, R, 9 * sizeof(double));
    memcpy(vo->ba_t, t, 3 * sizeof(double));
    vo->ba_cam[0] = vo->pinhole;
    sfm_ba_problem pr;
    sfmi_vo_ba_problem(vo, 1, np, np, &pr);
    sfm_ba_options o;
    sfm_ba_default_options(&o);
    o.mode = SFM_BA_MODE_POSE_ONLY;
    o.max_iterations = 1;
    o.want_covariance = 1;
    sfm_ba_result res;
    int st = sfm_ba_solve(&pr, &o, &res, cov, 36, vo->ba_ws, vo->ba_ws_size);
    if (st < 0)
        return st;
    return res.covariance_status == SFM_OK ? SFM_OK : SFM_E_SINGULAR;
}
