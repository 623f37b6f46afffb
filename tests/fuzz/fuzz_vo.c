/* Fuzz target: the sequence pipeline (sfm_vo.h) used as a caller uses it.
 * The input gives, in order:
 *   dims (width 33..96, height 33..72, max_features and window, each
 *   sometimes out of range), the workspace (exact, one byte short, larger,
 *   NULL), the camera (model 0..3, calibrated 1 / 0 / 2, intrinsics and
 *   distortion either sane or raw doubles: NaN, zero, 1e300), up to 15
 *   parameter records (field byte + 8 raw bytes; hostile values included,
 *   iteration counts bounded so a run stays short), a fake monotonic clock
 *   or none, a texture seed, then up to 6 frames. A frame is a tiled patch
 *   of input bytes, a crop of a two-plane textured scene (the success path:
 *   the lower half moves a quarter as far as the upper, as a plane four
 *   times as deep would), the previous frame again, or a flat gray; each may come
 *   with a NULL image, NULL data, NULL result, a wrong size, a short stride,
 *   a timestamp going back, a gravity (raw or near-vertical), a reset first;
 *   after each push the map and the first-seen points are read out with
 *   capacities 0, -1, small or full and NULL outputs.
 * Checked: every status is the one the header names for the case (push:
 * exact; init: within its listed set, never SFM_OK with an argument the
 * header rules out); on failure the outputs keep their canary and the
 * workspace is byte-identical (the state is unchanged); on success every
 * number is finite, rotations are orthonormal with det +1, R_wc / c_w are
 * the inverse of R_cw / t_cw, counts lie in their ranges, the read-outs
 * agree with each other and with the frame result and write nothing past
 * what they return. The whole run is done twice on two workspaces and must
 * give the same results bit for bit. Buffers are exact-size heap blocks,
 * so a read past one is an ASan report. */
#include <math.h>
#include <stdlib.h>
#include <string.h>

#include "sfm/sfm_vo.h"

#include "fuzz_reader.h"

/* -DFUZZ_VO_TRACE prints each frame's status and counts (for writing seeds). */
#ifdef FUZZ_VO_TRACE
#include <stdio.h>
#define TRACE(...) fprintf(stderr, __VA_ARGS__)
#else
#define TRACE(...) ((void)0)
#endif

int LLVMFuzzerTestOneInput(const uint8_t *data, size_t size);

#define MAX_W 96
#define MAX_H 72
#define MAX_FRAMES 6
#define TEX_PAD 48 /* texture columns beyond the frame on each side */
#define CANARY 0x5a

#define CHECK(c)       \
    do {               \
        if (!(c))      \
            abort();   \
    } while (0)

/* What one run records, compared between the two runs. */
typedef struct summary {
    int init_status;
    int status[MAX_FRAMES];
    int state[MAX_FRAMES], n_map[MAX_FRAMES], n_inl[MAX_FRAMES];
    double pose[MAX_FRAMES][12];
    int n_read[MAX_FRAMES];
    double first_xyz[MAX_FRAMES][3];
} summary;

typedef struct fake_clock {
    double now, step;
} fake_clock;

static double clock_read(void *ctx)
{
    fake_clock *c = ctx;
    c->now += c->step;
    return c->now;
}

static uint64_t splitmix(uint64_t *s)
{
    uint64_t z = (*s += 0x9e3779b97f4a7c15ull);
    z = (z ^ (z >> 30)) * 0xbf58476d1ce4e5b9ull;
    z = (z ^ (z >> 27)) * 0x94d049bb133111ebull;
    return z ^ (z >> 31);
}

static int all_finite(const double *v, int n)
{
    for (int i = 0; i < n; i++)
        if (!isfinite(v[i]))
            return 0;
    return 1;
}

static int filled(const void *p, size_t n, unsigned char b)
{
    const unsigned char *q = p;
    for (size_t i = 0; i < n; i++)
        if (q[i] != b)
            return 0;
    return 1;
}

static void check_rotation(const double R[9])
{
    CHECK(all_finite(R, 9));
    for (int a = 0; a < 3; a++)
        for (int b = 0; b < 3; b++) {
            double d = R[3 * a] * R[3 * b] + R[3 * a + 1] * R[3 * b + 1] + R[3 * a + 2] * R[3 * b + 2];
            CHECK(fabs(d - (a == b)) < 1e-6);
        }
    double det = R[0] * (R[4] * R[8] - R[5] * R[7]) - R[1] * (R[3] * R[8] - R[5] * R[6]) +
                 R[2] * (R[3] * R[7] - R[4] * R[6]);
    CHECK(fabs(det - 1.0) < 1e-6);
}

/* Parameter record: field byte, then 8 bytes read as a double, an int32
 * (first 4 bytes), a bounded iteration count or a uint64. */
static void param_record(reader *r, sfm_vo_params *p)
{
    unsigned field = take_u8(r) % 25;
    uint8_t b[8] = {0};
    for (int i = 0; i < 8; i++)
        b[i] = (uint8_t)take_u8(r);
    double d;
    int32_t v;
    uint64_t u;
    memcpy(&d, b, 8);
    memcpy(&v, b, 4);
    memcpy(&u, b, 8);
    int iters = (int)(int16_t)v % 1500; /* -1499..1499: hostile sign, bounded time */
    switch (field) {
    case 0: p->track_radius = d; break;
    case 1: p->init_radius = d; break;
    case 2: p->max_hamming = v; break;
    case 3: p->ratio = d; break;
    case 4: p->threshold = d; break;
    case 5: p->min_iterations = iters; break;
    case 6: p->max_iterations = iters; break;
    case 7: p->min_inliers = v; break;
    case 8: p->min_inlier_ratio = d; break;
    case 9: p->min_parallax_deg = d; break;
    case 10: p->keyframe_ratio = d; break;
    case 11: p->keyframe_max_gap = v; break;
    case 12: p->keyframe_min_parallax_deg = d; break;
    case 13: p->point_min_parallax_deg = d; break;
    case 14: p->ba_iterations = iters % 20; break;
    case 15: p->use_trifocal = v; break;
    case 16: p->seed = u; break;
    case 17: p->frame_budget = d; break;
    case 18: p->max_features = v; break;
    case 19: p->window = v; break;
    case 20: p->features.n_levels = v; break;
    case 21: p->features.scale_factor = d; break;
    case 22: p->features.fast_threshold = v; break;
    case 23: p->features.cell_size = v; break;
    default: p->calibrated = v; break;
    }
}

/* What the header lets sfm_vo_init accept: checked only when it said OK. */
static void check_accepted(const sfm_vo_dims *d, const sfm_vo_params *p)
{
    const sfm_camera *c = &p->camera;
    double f[] = {p->track_radius, p->init_radius, p->ratio, p->threshold, p->min_inlier_ratio,
                  p->min_parallax_deg, p->keyframe_ratio, p->keyframe_min_parallax_deg,
                  p->point_min_parallax_deg, p->frame_budget, c->fx, c->fy, c->cx, c->cy};
    CHECK(all_finite(f, (int)(sizeof f / sizeof f[0])));
    CHECK(c->model >= SFM_CAMERA_PINHOLE && c->model <= SFM_CAMERA_FISHEYE);
    CHECK(c->fx != 0 && c->fy != 0);
    CHECK(p->calibrated == 0 || p->calibrated == 1);
    CHECK(p->calibrated == 1 || c->model == SFM_CAMERA_PINHOLE);
    CHECK(p->max_features >= 8 && p->max_features <= d->max_features);
    CHECK(p->window >= SFM_VO_MIN_WINDOW && p->window <= d->window);
}

static void check_result(const sfm_vo_frame_result *r, const sfm_vo_params *p, const sfm_vo_dims *d,
                         int64_t ts, int index, int want_cov, int have_clock, int last_segment)
{
    CHECK(r->timestamp_ns == ts);
    CHECK(r->frame_index == index);
    CHECK(r->state >= SFM_VO_INITIALISING && r->state <= SFM_VO_PURE_ROTATION);
    CHECK(sfm_vo_state_str(r->state) != NULL && strcmp(sfm_vo_state_str(r->state), "unknown") != 0);
    CHECK(r->quality >= SFM_VO_QUALITY_NONE && r->quality <= SFM_VO_QUALITY_DEGRADED);
    CHECK(r->has_pose == 0 || r->has_pose == 1);
    CHECK(r->is_keyframe == 0 || r->is_keyframe == 1);
    CHECK(r->has_covariance == 0 || r->has_covariance == 1);
    CHECK((r->quality == SFM_VO_QUALITY_NONE) == !r->has_pose);
    if (r->state == SFM_VO_TRACKING)
        CHECK(r->has_pose);
    if (r->state == SFM_VO_LOST)
        CHECK(!r->has_pose);
    /* every number finite, pose or not */
    CHECK(all_finite(r->R_cw, 9) && all_finite(r->t_cw, 3) && all_finite(r->R_wc, 9) &&
          all_finite(r->c_w, 3) && all_finite(r->stage_seconds, SFM_VO_STAGES));
    CHECK(isfinite(r->median_parallax_deg) && r->median_parallax_deg >= 0);
    /* a calibrated camera's fx (any sign but zero: sfm_camera_validate), or
     * 0 / the self-calibrated focal length */
    CHECK(isfinite(r->focal));
    if (p->calibrated)
        CHECK(r->focal == p->camera.fx);
    else
        CHECK(r->focal >= 0);
    if (r->has_pose) {
        check_rotation(r->R_cw);
        double tn = fabs(r->t_cw[0]) + fabs(r->t_cw[1]) + fabs(r->t_cw[2]);
        for (int a = 0; a < 3; a++) {
            double c = 0;
            for (int b = 0; b < 3; b++) {
                CHECK(r->R_wc[3 * a + b] == r->R_cw[3 * b + a]);
                c -= r->R_cw[3 * b + a] * r->t_cw[b];
            }
            CHECK(fabs(c - r->c_w[a]) <= 1e-9 * (tn + 1.0));
        }
    }
    if (r->has_covariance) {
        CHECK(r->has_pose && want_cov);
        CHECK(all_finite(r->covariance, 36));
        for (int i = 0; i < 6; i++)
            CHECK(r->covariance[7 * i] >= 0);
    }
    CHECK(r->n_features >= 0 && r->n_features <= p->max_features);
    CHECK(r->n_matches >= 0 && r->n_inliers >= 0);
    CHECK(r->n_map_points >= 0 && r->n_map_points <= d->window * d->max_features);
    CHECK(r->n_keyframes >= 0 && r->n_keyframes <= d->window);
    CHECK((r->degraded & ~(SFM_VO_DEGRADED_FEATURES | SFM_VO_DEGRADED_BA_SKIPPED |
                           SFM_VO_DEGRADED_TRIFOCAL_SKIPPED)) == 0);
    for (int s = 0; s < SFM_VO_STAGES; s++)
        CHECK(have_clock ? r->stage_seconds[s] >= 0 : r->stage_seconds[s] == 0);
    CHECK(r->segment >= last_segment);
}

/* The read-outs after a frame: statuses, canaries past what is returned,
 * agreement of the two calls and with the frame result. */
static void read_map(reader *r, const sfm_vo *vo, int n_live, int n_frames, int *n_read,
                     double first[3])
{
    unsigned sel = take_u8(r);
    int full = n_live + 4;
    int cap = sel % 4 == 0 ? full : sel % 4 == 1 ? 0 : sel % 4 == 2 ? -1 - (int)(sel >> 5) : (int)(sel >> 2);
    int nbuf = cap > 0 ? cap : 1;
    double *xyz = malloc(3 * sizeof(double) * (size_t)nbuf), *px = malloc(2 * sizeof(double) * (size_t)nbuf);
    uint32_t *ids = malloc(sizeof(uint32_t) * (size_t)nbuf), *ids2 = malloc(sizeof(uint32_t) * (size_t)nbuf);
    int *frame = malloc(sizeof(int) * (size_t)nbuf);
    if (!xyz || !px || !ids || !ids2 || !frame)
        goto done;
    memset(xyz, CANARY, 3 * sizeof(double) * (size_t)nbuf);
    memset(px, CANARY, 2 * sizeof(double) * (size_t)nbuf);
    memset(ids, CANARY, sizeof(uint32_t) * (size_t)nbuf);
    memset(ids2, CANARY, sizeof(uint32_t) * (size_t)nbuf);
    memset(frame, CANARY, sizeof(int) * (size_t)nbuf);
    int null_xyz = (sel >> 7) & 1 && sel % 4 == 3, no_ids = (sel >> 6) & 1;
    int n = sfm_vo_map_points(vo, null_xyz ? NULL : xyz, no_ids ? NULL : ids, cap);
    if (null_xyz || cap < 0) {
        CHECK(n == SFM_E_ARGUMENT);
        CHECK(filled(xyz, 3 * sizeof(double) * (size_t)nbuf, CANARY) &&
              filled(ids, sizeof(uint32_t) * (size_t)nbuf, CANARY));
    } else {
        CHECK(n == (cap < n_live ? cap : n_live));
        CHECK(all_finite(xyz, 3 * n));
        CHECK(filled(xyz + 3 * n, 3 * sizeof(double) * (size_t)(nbuf - n), CANARY));
        CHECK(filled(ids + (no_ids ? 0 : n), sizeof(uint32_t) * (size_t)(nbuf - (no_ids ? 0 : n)), CANARY));
        for (int i = 0; i < n && !no_ids; i++)
            for (int j = 0; j < i; j++)
                CHECK(ids[i] != ids[j]);
        *n_read = n;
        if (n > 0)
            memcpy(first, xyz, 3 * sizeof(double));
    }
    int m = sfm_vo_map_points_first_seen(vo, ids2, null_xyz ? NULL : px, frame, cap);
    if (null_xyz || cap < 0) {
        CHECK(m == SFM_E_ARGUMENT);
        CHECK(filled(px, 2 * sizeof(double) * (size_t)nbuf, CANARY) &&
              filled(frame, sizeof(int) * (size_t)nbuf, CANARY) &&
              filled(ids2, sizeof(uint32_t) * (size_t)nbuf, CANARY));
    } else {
        CHECK(m == n);
        for (int i = 0; i < m; i++) {
            if (!no_ids)
                CHECK(ids2[i] == ids[i]);
            /* NaN (both) where the model cannot map a point back */
            CHECK((isfinite(px[2 * i]) && isfinite(px[2 * i + 1])) ||
                  (isnan(px[2 * i]) && isnan(px[2 * i + 1])));
            CHECK(frame[i] >= 0 && frame[i] < n_frames);
        }
        CHECK(filled(px + 2 * m, 2 * sizeof(double) * (size_t)(nbuf - m), CANARY));
        CHECK(filled(frame + m, sizeof(int) * (size_t)(nbuf - m), CANARY));
        CHECK(filled(ids2 + m, sizeof(uint32_t) * (size_t)(nbuf - m), CANARY));
    }
done:
    free(xyz);
    free(px);
    free(ids);
    free(ids2);
    free(frame);
}

/* A two-plane scene: texture rows shifted by off (upper half) and off / 4
 * (lower half, four times as deep) into the frame. A camera sliding along x
 * past fronto-parallel planes sees exactly these shifts, so the true centres
 * lie on the x axis in proportion to off. */
static void scene_frame(uint8_t *img, int w, int h, int stride, const uint8_t *tex, int tw, int off, int dy)
{
    for (int y = 0; y < h; y++) {
        int o = TEX_PAD + (y < h / 2 ? off : off / 4);
        int ty = y + (y < h / 2 ? dy : dy / 4);
        ty = ty < 0 ? 0 : ty >= MAX_H + 8 ? MAX_H + 7 : ty;
        memcpy(img + (size_t)y * stride, tex + (size_t)ty * tw + o, (size_t)w);
    }
}

static void run(const uint8_t *data, size_t size, summary *s)
{
    reader rd = {data, size}, *r = &rd;
    memset(s, 0, sizeof *s);
    sfm_vo_dims d;
    d.width = 33 + (int)(take_u8(r) % 64);
    d.height = 33 + (int)(take_u8(r) % 40);
    unsigned bf = take_u8(r), bw = take_u8(r);
    d.max_features = bf < 248 ? 8 + (int)(bf % 193) : bf == 248 ? 7 : bf == 249 ? SFM_VO_MAX_FEATURES + 1 : 0;
    d.window = bw < 250 ? SFM_VO_MIN_WINDOW + (int)(bw % 3) : bw == 250 ? SFM_VO_MIN_WINDOW - 1 : SFM_VO_MAX_WINDOW + 1;
    int dims_ok = bf < 248 && bw < 250;
    size_t need = sfm_vo_workspace_size(&d);
    CHECK(dims_ok ? need > 0 : need == 0);
    unsigned wsmode = take_u8(r) % 4;

    sfm_vo_params p;
    int st = sfm_vo_default_params(&d, &p);
    CHECK(st == (dims_ok ? SFM_OK : SFM_E_ARGUMENT));
    if (st != SFM_OK) {
        memset(&p, 0, sizeof p);
        p.calibrated = 1;
        p.camera.fx = p.camera.fy = 100;
    }
    /* settings that can track on frames this small */
    p.features.n_levels = 1;
    p.features.cell_size = 16;
    p.features.fast_threshold = 12;
    p.min_inliers = 8;
    p.init_radius = 24.0;
    p.track_radius = 8.0;
    p.min_iterations = 20;
    p.max_iterations = 300;
    p.ba_iterations = 3;
    p.min_parallax_deg = 0.5;

    unsigned cm = take_u8(r), cf = take_u8(r);
    p.camera.model = (int)(cm % 4);
    unsigned cal = (cm >> 2) & 3;
    p.calibrated = cal == 1 ? 0 : cal == 2 ? 2 : 1;
    p.camera.fx = p.camera.fy = (double)d.width;
    p.camera.cx = (d.width - 1) / 2.0;
    p.camera.cy = (d.height - 1) / 2.0;
    memset(p.camera.dist, 0, sizeof p.camera.dist);
    if (cf & 1)
        p.camera.fx = take_f64(r);
    p.camera.fy = cf & 2 ? take_f64(r) : p.camera.fx;
    if (cf & 4)
        p.camera.cx = take_f64(r);
    if (cf & 8)
        p.camera.cy = take_f64(r);
    if (cf & 16)
        for (int i = 0; i < 5; i++)
            p.camera.dist[i] = take_f64(r);
    else if (cf & 32)
        p.camera.dist[0] = (p.camera.model == SFM_CAMERA_FISHEYE ? 0.01 : -0.05) * (double)(cf >> 6);
    int nrec = (int)(take_u8(r) % 16);
    for (int i = 0; i < nrec; i++)
        param_record(r, &p);
    unsigned ck = take_u8(r);
    fake_clock clk = {0.0, 1e-4 * (double)ck};
    if (ck) {
        p.clock = clock_read;
        p.clock_ctx = &clk;
    } else {
        p.clock = NULL;
        p.clock_ctx = NULL;
    }
    uint64_t tseed = (uint32_t)take_i32(r);

    /* the workspace: an exact-size block filled with a sentinel */
    size_t ws_size = need + (wsmode == 2 ? 64 : 0);
    if (wsmode == 1 && ws_size > 0)
        ws_size--;
    unsigned char *ws = wsmode == 3 ? NULL : malloc(ws_size ? ws_size : 1);
    unsigned char *snap = malloc(ws_size ? ws_size : 1);
    int tw = MAX_W + 2 * TEX_PAD, th = MAX_H + 8;
    uint8_t *tex = malloc((size_t)tw * th);
    if ((wsmode != 3 && ws == NULL) || snap == NULL || tex == NULL)
        goto done;
    if (ws)
        memset(ws, 0xa5, ws_size ? ws_size : 1);
    for (int by = 0; by < th; by += 4)
        for (int bx = 0; bx < tw; bx += 4) {
            uint8_t g = (uint8_t)(20 + splitmix(&tseed) % 216);
            for (int y = by; y < by + 4 && y < th; y++)
                for (int x = bx; x < bx + 4 && x < tw; x++)
                    tex[(size_t)y * tw + x] = g;
        }

    sfm_vo *vo, *vo_canary;
    memset(&vo_canary, CANARY, sizeof vo_canary);
    vo = vo_canary;
    st = sfm_vo_init(&d, &p, &vo, ws, ws_size);
    s->init_status = st;
    TRACE("init %d (%dx%d, %d features, window %d)\n", st, d.width, d.height, d.max_features, d.window);
    if (!dims_ok || ws == NULL)
        CHECK(st == SFM_E_ARGUMENT);
    CHECK(st == SFM_OK || st == SFM_E_ARGUMENT || st == SFM_E_NONFINITE || st == SFM_E_WORKSPACE ||
          st == SFM_E_UNSUPPORTED);
    if (st != SFM_OK) {
        CHECK(vo == vo_canary);
        if (ws)
            CHECK(filled(ws, ws_size ? ws_size : 1, 0xa5));
        goto done;
    }
    CHECK(ws_size >= need);
    check_accepted(&d, &p);
    CHECK(vo != NULL && (unsigned char *)vo >= ws && (unsigned char *)vo < ws + ws_size);
    CHECK(sfm_vo_reset(NULL) == SFM_E_ARGUMENT);

    int nframes = (int)(take_u8(r) % (MAX_FRAMES + 1));
    uint8_t *prev = NULL;
    int prev_w = 0, prev_h = 0;
    int started = 0, index = 0, live = 0, segment = 0;
    int64_t ts = 1000, last_ts = 0;
    for (int f = 0; f < nframes; f++) {
        unsigned mode = take_u8(r), fl = take_u8(r), pad = take_u8(r) % 4;
        int dts = (int)(int8_t)take_u8(r);
        if (fl & 64) {
            CHECK(sfm_vo_reset(vo) == SFM_OK);
            started = 0;
            index = 0;
            live = 0;
            segment = 0;
        }
        int w = d.width, h = d.height;
        if (fl & 8) {
            /* another size: one pixel off either way */
            if (mode & 128)
                w += (mode & 64) ? 1 : -1;
            else
                h += (mode & 64) ? 1 : -1;
        }
        int stride = w + (int)pad;
        if (fl & 16)
            stride = w - 1 - (int)pad;
        int rows_stride = stride > w ? stride : w;
        size_t n = (size_t)rows_stride * (size_t)(h - 1) + (size_t)w;
        uint8_t *img = malloc(n);
        if (img == NULL)
            break;
        memset(img, 0, n);
        switch (mode % 4) {
        case 0: { /* a patch of input bytes, tiled */
            int pw = 1 + (int)(take_u8(r) % 16), ph = 1 + (int)(take_u8(r) % 16);
            uint8_t patch[256];
            for (int i = 0; i < pw * ph; i++)
                patch[i] = (uint8_t)take_u8(r);
            for (int y = 0; y < h; y++)
                for (int x = 0; x < w; x++)
                    img[(size_t)y * rows_stride + x] = patch[(y % ph) * pw + x % pw];
            break;
        }
        case 1: { /* the textured scene, moved */
            int off = (int)(int8_t)take_u8(r) % (TEX_PAD + 1), dy = (int)(int8_t)take_u8(r) % 5;
            if (w <= MAX_W + 1)
                scene_frame(img, w > MAX_W ? MAX_W : w, h, rows_stride, tex, tw, off, dy);
            break;
        }
        case 2: /* the previous frame again (when of this size) */
            if (prev != NULL && prev_w == w && prev_h == h)
                for (int y = 0; y < h; y++)
                    memcpy(img + (size_t)y * rows_stride, prev + (size_t)y * w, (size_t)w);
            break;
        default:
            memset(img, (int)take_u8(r), n);
            break;
        }
        double g[3] = {0, 0, 0};
        int have_g = (fl >> 7) & 1;
        if (have_g) {
            unsigned gm = take_u8(r);
            if (gm % 2) {
                for (int i = 0; i < 3; i++)
                    g[i] = take_f64(r);
            } else {
                /* down the image's y axis, tilted by up to 0.07 / 9.81 */
                g[0] = 0.01 * (double)((gm >> 1) & 7);
                g[1] = 9.81;
                g[2] = 0.01 * (double)((gm >> 4) & 7);
            }
        }
        int want_cov = (fl >> 5) & 1;
        ts += dts * 1000;
        /* the status the header names for this call */
        int expect = SFM_OK;
        if ((fl & 1) || (fl & 2) || (fl & 4) || w != d.width || h != d.height || stride < w ||
            (started && ts < last_ts))
            expect = SFM_E_ARGUMENT;
        else if (have_g && !all_finite(g, 3))
            expect = SFM_E_NONFINITE;
        else if (have_g && g[0] == 0 && g[1] == 0 && g[2] == 0)
            expect = SFM_E_ARGUMENT;
        sfm_image_u8 im = {(fl & 2) ? NULL : img, w, h, stride};
        sfm_vo_frame_result res, canary;
        memset(&canary, CANARY, sizeof canary);
        res = canary;
        memcpy(snap, ws, ws_size);
        st = sfm_vo_push_frame(vo, (fl & 1) ? NULL : &im, ts, have_g ? g : NULL, want_cov,
                               (fl & 4) ? NULL : &res);
        s->status[f] = st;
        TRACE("frame %d: status %d (expected %d) state %d pose %d kf %d features %d matches %d "
              "inliers %d map %d keyframes %d focal %g c_w %g %g %g\n",
              f, st, expect, res.state, res.has_pose, res.is_keyframe, res.n_features, res.n_matches,
              res.n_inliers, res.n_map_points, res.n_keyframes, res.focal, res.c_w[0], res.c_w[1],
              res.c_w[2]);
        CHECK(st == expect);
        if (st != SFM_OK) {
            CHECK(memcmp(&res, &canary, sizeof res) == 0);
            CHECK(memcmp(snap, ws, ws_size) == 0);
        } else {
            check_result(&res, &p, &d, ts, index, want_cov, p.clock != NULL, segment);
            started = 1;
            index++;
            last_ts = ts;
            live = res.n_map_points;
            segment = res.segment;
            s->state[f] = res.state;
            s->n_map[f] = res.n_map_points;
            s->n_inl[f] = res.n_inliers;
            memcpy(s->pose[f], res.R_cw, sizeof res.R_cw);
            memcpy(s->pose[f] + 9, res.t_cw, sizeof res.t_cw);
        }
        read_map(r, vo, live, index, &s->n_read[f], s->first_xyz[f]);
        free(prev);
        prev = img;
        prev_w = w;
        prev_h = h;
    }
    free(prev);
done:
    free(ws);
    free(snap);
    free(tex);
}

int LLVMFuzzerTestOneInput(const uint8_t *data, size_t size)
{
    summary a, b;
    run(data, size, &a);
    run(data, size, &b);
    /* deterministic: the same input, the same answers bit for bit */
    CHECK(memcmp(&a, &b, sizeof a) == 0);
    return 0;
}
