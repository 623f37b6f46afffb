/*
 * Golden outputs: fixed-seed estimators on fixed synthetic inputs, one line
 * per output with its status and the FNV-1a hash of its bytes (doubles as
 * IEEE 754 binary64, little-endian on every target built here; inlier masks;
 * counters). The same program runs natively, under qemu-aarch64 and on a
 * Cortex-M7 under qemu-system-arm; mk/golden.mk compares each run with the
 * one committed file tests/golden/golden.txt, so "the same seed gives the
 * same answer, bit for bit, on every target" is tested, not assumed.
 *
 * Inputs are made by the library's own seeded generator and rotations, which
 * are themselves bit-identical across targets (core/dmath.h), and hashed as
 * well ("input ..." lines), so a changed input is told apart from a changed
 * estimator. No heap, no files: one static workspace.
 */
#include <stdint.h>
#include <stdio.h>
#include <string.h>

#include "sfm/sfm.h"

#define NPTS 160
#define WS_BYTES (3u << 20)

static unsigned char g_ws[WS_BYTES];
static int g_failures;

static uint64_t fnv1a(uint64_t h, const void *p, size_t n)
{
    const unsigned char *b = (const unsigned char *)p;
    for (size_t i = 0; i < n; i++) {
        h ^= b[i];
        h *= 1099511628211ull;
    }
    return h;
}
#define FNV_INIT 1469598103934665603ull

static void emit(const char *name, int status, uint64_t h)
{
    printf("%-26s %4d %016llx\n", name, status, (unsigned long long)h);
}

static void emit_bytes(const char *name, int status, const void *p, size_t n)
{
    emit(name, status, status < 0 ? FNV_INIT : fnv1a(FNV_INIT, p, n));
}

static uint64_t hash_stats(uint64_t h, const sfm_ransac_stats *s)
{
    h = fnv1a(h, &s->iterations, sizeof s->iterations);
    h = fnv1a(h, &s->num_inliers, sizeof s->num_inliers);
    h = fnv1a(h, &s->score, sizeof s->score);
    int stop = (int)s->stop_reason; /* enums need not be int-sized */
    h = fnv1a(h, &stop, sizeof stop);
    h = fnv1a(h, &s->flags, sizeof s->flags);
    return h;
}

/* The inlier mask and the run statistics of an estimator, as two lines. */
static void emit_ransac(const char *mask_name, const char *stats_name, int r, const uint8_t *mask,
                        const sfm_ransac_stats *st)
{
    emit_bytes(mask_name, r, mask, NPTS);
    emit(stats_name, r, r < 0 ? FNV_INIT : hash_stats(FNV_INIT, st));
}

static int ws_ok(const char *name, size_t need)
{
    if (need == 0 || need > WS_BYTES) {
        printf("%s: workspace %lu bytes over the program's %lu\n", name, (unsigned long)need,
               (unsigned long)WS_BYTES);
        g_failures++;
        return 0;
    }
    return 1;
}

/* ------------------------------------------------------------------ scene */

typedef struct scene {
    sfm_camera cam[3];
    sfm_pose pose[3];         /* x_cam = R X + t, pose[0] = identity */
    double X[NPTS * 3];       /* world points */
    double px[3][NPTS * 2];   /* pixels, noisy, outliers in views 2 and 3 */
} scene;

static void matvec(const double *R, const double *x, double *y)
{
    for (int r = 0; r < 3; r++)
        y[r] = R[3 * r] * x[0] + R[3 * r + 1] * x[1] + R[3 * r + 2] * x[2];
}

static void make_scene(scene *s, sfm_rng *rng)
{
    memset(s, 0, sizeof *s);
    for (int v = 0; v < 3; v++) {
        s->cam[v].model = SFM_CAMERA_PINHOLE;
        s->cam[v].fx = s->cam[v].fy = 500.0;
        s->cam[v].cx = 320.0;
        s->cam[v].cy = 240.0;
    }
    /* view 3 has Brown-Conrady distortion */
    s->cam[2].model = SFM_CAMERA_BROWN;
    s->cam[2].dist[0] = -0.12;
    s->cam[2].dist[1] = 0.03;
    s->cam[2].dist[2] = 0.001;
    s->cam[2].dist[3] = -0.0005;
    const double aa[3][3] = {{0, 0, 0}, {0.02, -0.09, 0.015}, {-0.03, -0.17, 0.02}};
    const double c[3][3] = {{0, 0, 0}, {0.9, -0.1, 0.3}, {1.7, 0.25, 0.9}}; /* centres */
    for (int v = 0; v < 3; v++) {
        sfm_rot_from_axis_angle(aa[v], s->pose[v].R);
        double Rc[3];
        matvec(s->pose[v].R, c[v], Rc);
        for (int k = 0; k < 3; k++)
            s->pose[v].t[k] = -Rc[k];
    }
    for (int i = 0; i < NPTS; i++) {
        double *X = s->X + 3 * i;
        for (;;) {
            X[0] = 8.0 * (sfm_rng_uniform(rng) - 0.5);
            X[1] = 6.0 * (sfm_rng_uniform(rng) - 0.5);
            X[2] = 5.0 + 6.0 * sfm_rng_uniform(rng);
            int ok = 1;
            for (int v = 0; v < 3 && ok; v++) {
                double Xc[3];
                matvec(s->pose[v].R, X, Xc);
                for (int k = 0; k < 3; k++)
                    Xc[k] += s->pose[v].t[k];
                double *p = s->px[v] + 2 * i;
                ok = sfm_camera_project(&s->cam[v], Xc, p, NULL) == SFM_OK && p[0] > 0.0 &&
                     p[0] < 640.0 && p[1] > 0.0 && p[1] < 480.0;
            }
            if (ok)
                break;
        }
        for (int v = 0; v < 3; v++) {
            double *p = s->px[v] + 2 * i;
            p[0] += 0.4 * sfm_rng_normal(rng);
            p[1] += 0.4 * sfm_rng_normal(rng);
        }
        /* 15 % outliers: a random pixel in view 2 or view 3 */
        if (sfm_rng_uniform(rng) < 0.15) {
            int v = 1 + (sfm_rng_uniform(rng) < 0.5);
            s->px[v][2 * i] = 640.0 * sfm_rng_uniform(rng);
            s->px[v][2 * i + 1] = 480.0 * sfm_rng_uniform(rng);
        }
    }
}

static void bearing(const sfm_camera *cam, const double *px, double b[3])
{
    (void)sfm_camera_unproject(cam, px, b);
}

/* ------------------------------------------------------------- estimators */

static void run_relpose(const scene *s, const sfm_ransac_options *opt)
{
    if (!ws_ok("relpose", sfm_ransac_relpose_workspace_size(NPTS)))
        return;
    sfm_pose pose;
    sfm_mat3 E;
    uint8_t mask[NPTS];
    sfm_ransac_stats st;
    int r = sfm_ransac_relpose(s->px[0], s->px[1], NPTS, &s->cam[0], &s->cam[1], opt, &pose, &E,
                               mask, &st, g_ws, WS_BYTES);
    emit_bytes("ransac_relpose.pose", r, &pose, sizeof pose);
    emit_bytes("ransac_relpose.E", r, E.m, sizeof E.m);
    emit_ransac("ransac_relpose.mask", "ransac_relpose.stats", r, mask, &st);
}

static void run_abspose(const scene *s, const sfm_ransac_options *opt)
{
    if (!ws_ok("abspose", sfm_ransac_abspose_workspace_size(NPTS)))
        return;
    sfm_pose pose;
    uint8_t mask[NPTS];
    sfm_ransac_stats st;
    int r = sfm_ransac_abspose(s->px[1], s->X, NPTS, &s->cam[1], opt, &pose, mask, &st, g_ws,
                               WS_BYTES);
    emit_bytes("ransac_abspose.pose", r, &pose, sizeof pose);
    emit_ransac("ransac_abspose.mask", "ransac_abspose.stats", r, mask, &st);
}

static void run_fundamental_homography(const scene *s, const sfm_ransac_options *opt)
{
    sfm_mat3 F;
    uint8_t mask[NPTS];
    sfm_ransac_stats st;
    if (ws_ok("fundamental", sfm_ransac_fundamental_workspace_size(NPTS))) {
        int r = sfm_ransac_fundamental(s->px[0], s->px[1], NPTS, NULL, NULL, opt, &F, mask, &st,
                                       g_ws, WS_BYTES);
        emit_bytes("ransac_fundamental.F", r, F.m, sizeof F.m);
        emit("ransac_fundamental.mask+st", r,
             r < 0 ? FNV_INIT : hash_stats(fnv1a(FNV_INIT, mask, sizeof mask), &st));
    }
    if (ws_ok("homography", sfm_ransac_homography_workspace_size(NPTS))) {
        int r = sfm_ransac_homography(s->px[0], s->px[1], NPTS, NULL, NULL, opt, &F, mask, &st,
                                      g_ws, WS_BYTES);
        emit_bytes("ransac_homography.H", r, F.m, sizeof F.m);
        emit("ransac_homography.mask+st", r,
             r < 0 ? FNV_INIT : hash_stats(fnv1a(FNV_INIT, mask, sizeof mask), &st));
    }
}

static void run_trifocal(const scene *s, const sfm_ransac_options *opt)
{
    if (!ws_ok("trifocal", sfm_ransac_trifocal_workspace_size(NPTS)))
        return;
    double T[27], P[36];
    uint8_t mask[NPTS];
    sfm_ransac_stats st;
    /* the projective solver works on pinhole pixels: use views 1 and 2 and
     * view 3 undistorted */
    static double und[NPTS * 2];
    sfm_camera pin = s->cam[2];
    pin.model = SFM_CAMERA_PINHOLE;
    for (int i = 0; i < NPTS; i++) {
        double b[3];
        bearing(&s->cam[2], s->px[2] + 2 * i, b);
        (void)sfm_camera_project(&pin, b, und + 2 * i, NULL);
    }
    int r = sfm_ransac_trifocal(s->px[0], s->px[1], und, NPTS, opt, T, P, mask, &st, g_ws,
                                WS_BYTES);
    emit_bytes("ransac_trifocal.T", r, T, sizeof T);
    emit_bytes("ransac_trifocal.P", r, P, sizeof P);
    emit_ransac("ransac_trifocal.mask", "ransac_trifocal.stats", r, mask, &st);
}

static void run_three_view(const scene *s, const sfm_ransac_options *opt)
{
    if (!ws_ok("three_view", sfm_recon_three_view_pose_workspace_size(NPTS)))
        return;
    sfm_pose poses[3];
    uint8_t mask[NPTS];
    sfm_ransac_stats st;
    int r = sfm_recon_three_view_pose(s->px[0], s->px[1], s->px[2], NPTS, &s->cam[0], &s->cam[1],
                                      &s->cam[2], opt, poses, mask, &st, g_ws, WS_BYTES);
    emit_bytes("recon_three_view.poses", r, poses, sizeof poses);
    emit_ransac("recon_three_view.mask", "recon_three_view.stats", r, mask, &st);
}

/* Minimal solvers on the first samples of the clean points. */
static void run_minimal(const scene *s)
{
    uint64_t h5 = FNV_INIT, h3 = FNV_INIT;
    int n5 = 0, n3 = 0;
    for (int k = 0; k < 8; k++) {
        double b1[15], b2[15];
        for (int j = 0; j < 5; j++) {
            int i = (k * 5 + j) % NPTS;
            bearing(&s->cam[0], s->px[0] + 2 * i, b1 + 3 * j);
            bearing(&s->cam[1], s->px[1] + 2 * i, b2 + 3 * j);
        }
        sfm_mat3 E[SFM_RELPOSE_5PT_MAX_SOLUTIONS];
        int r = sfm_relpose_5pt(b1, b2, E);
        if (r > 0)
            h5 = fnv1a(h5, E, (size_t)r * sizeof E[0]);
        n5 += r;
        /* P3P: bearings of view 2 against the world points */
        double x[9], X[9];
        for (int j = 0; j < 3; j++) {
            int i = (k * 3 + j + 50) % NPTS;
            bearing(&s->cam[1], s->px[1] + 2 * i, x + 3 * j);
            memcpy(X + 3 * j, s->X + 3 * i, sizeof(double) * 3);
        }
        sfm_pose P[SFM_P3P_MAX_SOLUTIONS];
        r = sfm_p3p(x, X, P);
        if (r > 0)
            h3 = fnv1a(h3, P, (size_t)r * sizeof P[0]);
        n3 += r;
    }
    emit("relpose_5pt.E", n5, h5);
    emit("p3p.poses", n3, h3);
}

/* Bundle adjustment of the three cameras and the first 60 points, started
 * from perturbed poses and points. */
static void run_ba(const scene *s)
{
    enum { M = 3, N = 60, NOBS = M * N };
    static double R[M * 9], t[M * 3], X[N * 3], xy[NOBS * 2];
    static sfm_camera cams[M];
    static int oc[NOBS], op[NOBS];
    sfm_rng rng;
    sfm_rng_seed(&rng, 7);
    for (int v = 0; v < M; v++) {
        double d[3] = {0.01 * sfm_rng_normal(&rng), 0.01 * sfm_rng_normal(&rng),
                       0.01 * sfm_rng_normal(&rng)}, dR[9];
        sfm_rot_from_axis_angle(d, dR);
        for (int r = 0; r < 3; r++)
            for (int c = 0; c < 3; c++) {
                double a = 0.0;
                for (int k = 0; k < 3; k++)
                    a += dR[3 * r + k] * s->pose[v].R[3 * k + c];
                R[9 * v + 3 * r + c] = v == 0 ? s->pose[v].R[3 * r + c] : a;
            }
        for (int k = 0; k < 3; k++)
            t[3 * v + k] = s->pose[v].t[k] + (v == 0 ? 0.0 : 0.02 * sfm_rng_normal(&rng));
        memset(&cams[v], 0, sizeof cams[v]);
        cams[v].model = SFM_CAMERA_PINHOLE;
        cams[v].fx = cams[v].fy = 500.0;
        cams[v].cx = 320.0;
        cams[v].cy = 240.0;
    }
    for (int i = 0; i < N; i++)
        for (int k = 0; k < 3; k++)
            X[3 * i + k] = s->X[3 * i + k] + 0.05 * sfm_rng_normal(&rng);
    /* observations: views 1 and 2 as given (pinhole), view 3 undistorted;
     * outliers replaced by the true projection plus noise */
    int o = 0;
    for (int v = 0; v < M; v++)
        for (int i = 0; i < N; i++, o++) {
            double Xc[3], p[2];
            matvec(s->pose[v].R, s->X + 3 * i, Xc);
            for (int k = 0; k < 3; k++)
                Xc[k] += s->pose[v].t[k];
            sfm_camera pin = s->cam[v];
            pin.model = SFM_CAMERA_PINHOLE;
            (void)sfm_camera_project(&pin, Xc, p, NULL);
            xy[2 * o] = p[0] + 0.3 * sfm_rng_normal(&rng);
            xy[2 * o + 1] = p[1] + 0.3 * sfm_rng_normal(&rng);
            oc[o] = v;
            op[o] = i;
        }
    sfm_ba_problem pb;
    memset(&pb, 0, sizeof pb);
    pb.n_cameras = M;
    pb.n_points = N;
    pb.n_observations = NOBS;
    pb.rotations = R;
    pb.translations = t;
    pb.cameras = cams;
    pb.points = X;
    pb.obs_camera = oc;
    pb.obs_point = op;
    pb.obs_xy = xy;
    sfm_ba_options bo;
    sfm_ba_default_options(&bo);
    bo.loss = SFM_BA_LOSS_HUBER;
    bo.loss_scale = 1.0;
    bo.gauge = SFM_BA_GAUGE_FIRST_CAMERA;
    bo.scale_gauge = SFM_BA_SCALE_DISTANCE;
    bo.scale_camera = 1;
    bo.scale_distance = 1.0;
    sfm_ba_dims dims;
    memset(&dims, 0, sizeof dims);
    dims.n_cameras = M;
    dims.n_points = N;
    dims.n_observations = NOBS;
    dims.intrinsics = bo.intrinsics;
    dims.refine_intrinsics = bo.refine_intrinsics;
    if (!ws_ok("ba", sfm_ba_workspace_size(&dims)))
        return;
    sfm_ba_result res;
    int r = sfm_ba_solve(&pb, &bo, &res, NULL, 0, g_ws, WS_BYTES);
    uint64_t h = fnv1a(FNV_INIT, R, sizeof R);
    h = fnv1a(h, t, sizeof t);
    emit("ba.poses", r, r < 0 ? FNV_INIT : h);
    emit_bytes("ba.points", r, X, sizeof X);
    h = fnv1a(FNV_INIT, &res.final_cost, sizeof res.final_cost);
    h = fnv1a(h, &res.iterations, sizeof res.iterations);
    h = fnv1a(h, &res.successful_steps, sizeof res.successful_steps);
    int stop = (int)res.stop_reason;
    h = fnv1a(h, &stop, sizeof stop);
    emit("ba.result", r, r < 0 ? FNV_INIT : h);
}

/* Features on a generated 256 x 192 image: smooth blobs and bars, integer
 * arithmetic plus the seeded generator's noise. */
static void run_features(void)
{
    enum { W = 256, H = 192, CAP = 400 };
    static uint8_t img[W * H];
    static sfm_keypoint kps[CAP];
    static uint8_t desc[CAP * SFM_FEATURES_DESC_BYTES];
    sfm_rng rng;
    sfm_rng_seed(&rng, 11);
    for (int y = 0; y < H; y++)
        for (int x = 0; x < W; x++) {
            int v = 60 + ((x / 16 + y / 16) % 2) * 90;
            int dx = x % 37 - 18, dy = y % 29 - 14;
            if (dx * dx + dy * dy < 60)
                v = 230 - v / 2;
            v += (int)(8.0 * sfm_rng_uniform(&rng));
            img[y * W + x] = (uint8_t)(v > 255 ? 255 : v);
        }
    sfm_image_u8 im = {img, W, H, W};
    sfm_features_params fp;
    sfm_features_default_params(&fp);
    fp.max_features = CAP;
    fp.n_levels = 3;
    if (!ws_ok("features", sfm_features_workspace_size(&fp, W, H)))
        return;
    int r = sfm_features_detect(&im, &fp, kps, desc, CAP, g_ws, WS_BYTES);
    emit_bytes("features.keypoints", r, kps, r > 0 ? (size_t)r * sizeof kps[0] : 0);
    emit_bytes("features.descriptors", r, desc, r > 0 ? (size_t)r * SFM_FEATURES_DESC_BYTES : 0);
    /* matched against itself shifted by one feature: a fixed call */
    uint64_t hd = FNV_INIT;
    for (int i = 0; i + 1 < r; i++) {
        int d = sfm_features_hamming(desc + i * SFM_FEATURES_DESC_BYTES,
                                     desc + (i + 1) * SFM_FEATURES_DESC_BYTES);
        hd = fnv1a(hd, &d, sizeof d);
    }
    emit("features.hamming", r, hd);
    /* the keypoints aligned back onto themselves from a sub-pixel offset */
    static double xr[2 * CAP], xs[2 * CAP];
    static uint8_t ok[CAP];
    const int n = r > 0 ? r : 0;
    for (int i = 0; i < n; i++) {
        xr[2 * i] = kps[i].x;
        xr[2 * i + 1] = kps[i].y;
        xs[2 * i] = kps[i].x + 0.3 + 0.1 * sfm_rng_uniform(&rng);
        xs[2 * i + 1] = kps[i].y - 0.4 + 0.1 * sfm_rng_uniform(&rng);
    }
    sfm_align_params ap;
    sfm_features_default_align_params(&ap);
    int ra = sfm_features_align_points(&im, xr, &im, xs, n, &ap, xs, ok);
    emit("features.align", ra, ra < 0 ? FNV_INIT : fnv1a(fnv1a(FNV_INIT, xs, (size_t)n * 2 * sizeof(double)), ok, (size_t)n));
}

/* Decompositions of fixed random matrices. */
static void run_linalg(void)
{
    sfm_rng rng;
    sfm_rng_seed(&rng, 3);
    static double A[10 * 10], S[10], U[10 * 10], V[10 * 10], w[10], wi[10];
    for (int i = 0; i < 100; i++)
        A[i] = sfm_rng_normal(&rng);
    if (ws_ok("svd", sfm_svd_workspace_size(9, 9))) {
        int r = sfm_svd(A, 9, 9, U, S, V, g_ws, WS_BYTES);
        uint64_t h = fnv1a(fnv1a(fnv1a(FNV_INIT, U, 81 * sizeof(double)), S, 9 * sizeof(double)),
                           V, 81 * sizeof(double));
        emit("svd_9x9", r, r < 0 ? FNV_INIT : h);
    }
    static double Sy[6 * 6];
    for (int r = 0; r < 6; r++)
        for (int c = 0; c < 6; c++)
            Sy[6 * r + c] = A[10 * r + c] + A[10 * c + r];
    if (ws_ok("sym_eig", sfm_sym_eig_workspace_size(6))) {
        int r = sfm_sym_eig(Sy, 6, w, V, g_ws, WS_BYTES);
        emit("sym_eig_6x6", r,
             r < 0 ? FNV_INIT : fnv1a(fnv1a(FNV_INIT, w, 6 * sizeof(double)), V, 36 * sizeof(double)));
    }
    if (ws_ok("eig", sfm_eig_workspace_size(10))) {
        int r = sfm_eig(A, 10, w, wi, V, g_ws, WS_BYTES);
        uint64_t h = fnv1a(fnv1a(fnv1a(FNV_INIT, w, sizeof w), wi, sizeof wi), V, sizeof V);
        emit("eig_10x10", r, r < 0 ? FNV_INIT : h);
    }
}

/* Dense stereo on a generated 128 x 64 pair (textured blobs, a step in
 * disparity): rectification and its remap table through a Brown camera, SGM
 * (5 and 8 paths) and the correlation matcher; the disparities are floats
 * from integer costs, so they must agree to the bit. */
static void run_stereo(void)
{
    enum { W = 128, H = 64, WT = W + 48 };
    static uint8_t tex[H * WT], L[W * H], R[W * H];
    static float disp[W * H];
    static int32_t map[2 * W * H];
    sfm_rng rng;
    sfm_rng_seed(&rng, 11);
    for (int i = 0; i < H * WT; i++)
        tex[i] = (uint8_t)(sfm_rng_next(&rng) >> 56);
    for (int y = 0; y < H; y++)
        for (int x = 0; x < W; x++) {
            int d = x < W / 2 ? 5 : 12;
            L[y * W + x] = tex[y * WT + x + 16];
            R[y * W + x] = tex[y * WT + x + 16 + d];
        }
    sfm_camera cam;
    memset(&cam, 0, sizeof cam);
    cam.model = SFM_CAMERA_BROWN;
    cam.fx = cam.fy = 110.0;
    cam.cx = 63.5;
    cam.cy = 31.5;
    cam.dist[0] = -0.12;
    cam.dist[1] = 0.03;
    double aa[3] = {0.01, -0.03, 0.005}, Rr[9], t[3] = {-0.3, 0.01, 0.02};
    sfm_rot_from_axis_angle(aa, Rr);
    sfm_stereo_rectification rect;
    int r = sfm_stereo_rectify(&cam, &cam, W, H, Rr, t, 0.0, 0, 0, &rect);
    emit_bytes("stereo.rectification", r, &rect, sizeof rect);
    r = r < 0 ? r : sfm_stereo_rectify_map(&cam, W, H, &rect, 2, map, 2 * W * H);
    emit_bytes("stereo.map", r, map, sizeof map);
    sfm_stereo_sgm_options so;
    sfm_stereo_sgm_default_options(&so);
    so.num_disparities = 24;
    for (int k = 0; k < 2; k++) {
        so.paths = k ? SFM_STEREO_PATHS_8 : SFM_STEREO_PATHS_5;
        if (!ws_ok("stereo_sgm", sfm_stereo_sgm_workspace_size(W, H, &so)))
            return;
        r = sfm_stereo_sgm(L, R, W, H, W, &so, disp, g_ws, WS_BYTES);
        emit_bytes(k ? "stereo.sgm8" : "stereo.sgm5", r, disp, sizeof disp);
    }
    sfm_stereo_block_options bo;
    sfm_stereo_block_default_options(&bo);
    bo.num_disparities = 24;
    if (!ws_ok("stereo_block", sfm_stereo_block_workspace_size(W, H, &bo)))
        return;
    r = sfm_stereo_block(L, R, W, H, W, &bo, disp, g_ws, WS_BYTES);
    emit_bytes("stereo.block", r, disp, sizeof disp);
}

int main(void)
{
    static scene s;
    sfm_rng rng;
    sfm_rng_seed(&rng, 2024);
    make_scene(&s, &rng);
    emit_bytes("input.world_points", 0, s.X, sizeof s.X);
    emit_bytes("input.pixels", 0, s.px, sizeof s.px);
    emit_bytes("input.poses", 0, s.pose, sizeof s.pose);

    sfm_ransac_options opt;
    sfm_ransac_default_options(&opt);
    opt.threshold = 1.5;
    opt.seed = 99;

    run_minimal(&s);
    run_relpose(&s, &opt);
    run_abspose(&s, &opt);
    run_fundamental_homography(&s, &opt);
    run_trifocal(&s, &opt);
    run_three_view(&s, &opt);
    run_ba(&s);
    run_features();
    run_linalg();
    run_stereo();
    printf("golden: %d workspace failures\n", g_failures);
    return g_failures ? 1 : 0;
}
