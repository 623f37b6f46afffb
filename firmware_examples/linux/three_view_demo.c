/* three_view_demo: libsfm's main job on three frames, as a robot program
 * would run it.
 *
 *   frames (a replay directory, or a camera through the same interface)
 *   -> corners and descriptors per frame (sfm_features_detect)
 *   -> matches 1-2, 2-3, 3-1 (sfm_features_match)
 *   -> triplets that survive the cycle 1->2->3->1 (sfm_features_associate_three_views)
 *   -> trifocal RANSAC and calibrated poses of views 2 and 3 relative to view 1
 *      with one consistent scale, |t2| = 1 (sfm_recon_three_view_pose)
 *   -> the inliers triangulated in all three views (sfm_triangulate_dlt):
 *      a sparse 3D point cloud in view 1's frame
 *
 * Poses are world-to-camera, x_cam = R X + t, R row-major; the world frame is
 * view 1's camera frame.
 *
 * All work memory of the library comes from one buffer sized up front by the
 * library's *_workspace_size functions; the library itself never allocates.
 *
 * Exit status: 0 poses found (and, with --gt, printed against the truth);
 * 1 the pipeline failed (the negative status is printed); 2 bad usage or an
 * unreadable ground-truth file.
 */
#define _POSIX_C_SOURCE 200809L
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <time.h>

#include "calib_file.h"
#include "sfm/sfm.h"
#include "sfm/sfm_capture.h"

#define PI 3.14159265358979323846

static void usage(FILE *f)
{
    fprintf(f,
            "usage: three_view_demo DIR [options]\n"
            "Runs the three-view pipeline on the first three frames of the replay\n"
            "directory DIR (manifest.csv + PGM/PNG/JPEG frames): features, matches,\n"
            "three-view association, trifocal RANSAC, calibrated poses of views 2\n"
            "and 3 relative to view 1, and the triangulated inliers.\n"
            "\n"
            "Options:\n"
            "  --camera fx,fy,cx,cy[,k1,k2,p1,p2,k3]\n"
            "                  intrinsics of all three views (pixels; Brown-Conrady\n"
            "                  distortion as OpenCV's when given); default: the\n"
            "                  cameras of the --gt file; with neither, the camera is\n"
            "                  self-calibrated (sfm_recon_three_view_uncalibrated: one\n"
            "                  focal length, principal point at the image centre, no\n"
            "                  distortion) and the run fails with a named status when\n"
            "                  the three frames do not determine it\n"
            "  --self-calibrate  self-calibrate even when the --gt file has cameras\n"
            "                  (they are then only compared with the estimate)\n"
            "  --calib FILE    intrinsics of all three views from a calibration file:\n"
            "                  OpenCV FileStorage YAML/XML, ROS camera_info, Kalibr\n"
            "                  camchain, EuRoC sensor.yaml or KITTI calib.txt; a file\n"
            "                  holding an image size must match the frames'\n"
            "  --calib-camera NAME\n"
            "                  which camera of the file (Kalibr cam0, cam1...; KITTI\n"
            "                  P0..P3); default the first\n"
            "  --gt FILE       ground truth: lines 'camera V fx fy cx cy' and\n"
            "                  'pose V r00 .. r22 t0 t1 t2' (x_cam = R X + t), V = 1..3;\n"
            "                  prints the errors of the estimate against it\n"
            "  --features N    features per frame (default 2000)\n"
            "  --threshold PX  RANSAC inlier threshold in pixels (default 1)\n"
            "  --seed S        RANSAC seed (default 1)\n"
            "  --min-parallax DEG\n"
            "                  refuse the poses when the median triangulation angle of\n"
            "                  the inliers is below DEG (default 0.1): without parallax\n"
            "                  the translation is not observable\n"
            "  --ply FILE      write the triangulated inliers as an ASCII PLY file\n"
            "  --help          this text\n");
}

static double now_ms(void)
{
    struct timespec ts;
    clock_gettime(CLOCK_MONOTONIC, &ts);
    return (double)ts.tv_sec * 1e3 + (double)ts.tv_nsec * 1e-6;
}

/* ---- ground truth ------------------------------------------------------ */

typedef struct ground_truth {
    int have_cam[3], have_pose[3];
    sfm_camera cam[3];
    sfm_pose pose[3];
} ground_truth;

static int read_gt(const char *path, ground_truth *gt)
{
    FILE *f = fopen(path, "r");
    if (f == NULL) {
        fprintf(stderr, "three_view_demo: cannot open %s\n", path);
        return -1;
    }
    memset(gt, 0, sizeof *gt);
    char line[1024];
    int lineno = 0, ok = 1;
    while (ok && fgets(line, sizeof line, f)) {
        lineno++;
        char key[16];
        int v, used = 0;
        if (line[0] == '#' || sscanf(line, "%15s%n", key, &used) != 1)
            continue;
        const char *p = line + used;
        if (sscanf(p, "%d%n", &v, &used) != 1 || v < 1 || v > 3) {
            ok = 0;
            break;
        }
        p += used;
        int want = strcmp(key, "camera") == 0 ? 4 : strcmp(key, "pose") == 0 ? 12 : 0;
        double val[12];
        for (int k = 0; k < want && ok; k++) {
            if (sscanf(p, "%lf%n", &val[k], &used) != 1)
                ok = 0;
            p += used;
        }
        if (!ok || want == 0) {
            ok = 0;
            break;
        }
        if (want == 4) {
            sfm_camera c = {SFM_CAMERA_PINHOLE, val[0], val[1], val[2], val[3], {0, 0, 0, 0, 0}};
            gt->cam[v - 1] = c;
            gt->have_cam[v - 1] = 1;
        } else {
            memcpy(gt->pose[v - 1].R, val, 9 * sizeof(double));
            memcpy(gt->pose[v - 1].t, val + 9, 3 * sizeof(double));
            gt->have_pose[v - 1] = 1;
        }
    }
    fclose(f);
    if (!ok) {
        fprintf(stderr, "three_view_demo: %s line %d: expected 'camera V fx fy cx cy' or "
                        "'pose V r00 .. r22 t0 t1 t2'\n", path, lineno);
        return -1;
    }
    return 0;
}

static int parse_camera(const char *s, sfm_camera *cam)
{
    double v[9];
    int n = 0;
    char *end = NULL;
    while (n < 9) {
        v[n++] = strtod(s, &end);
        if (end == s)
            return -1;
        if (*end == '\0')
            break;
        if (*end != ',')
            return -1;
        s = end + 1;
    }
    if (*end != '\0' || (n != 4 && n != 6 && n != 9))
        return -1;
    memset(cam, 0, sizeof *cam);
    cam->model = n == 4 ? SFM_CAMERA_PINHOLE : SFM_CAMERA_BROWN;
    cam->fx = v[0];
    cam->fy = v[1];
    cam->cx = v[2];
    cam->cy = v[3];
    for (int k = 4; k < n; k++)
        cam->dist[k - 4] = v[k];
    return sfm_camera_validate(cam) == SFM_OK ? 0 : -1;
}

/* ---- small geometry helpers (application side) ------------------------- */

static double norm3(const double *v) { return sqrt(v[0] * v[0] + v[1] * v[1] + v[2] * v[2]); }

static double angle_deg(const double *a, const double *b)
{
    double c[3] = {a[1] * b[2] - a[2] * b[1], a[2] * b[0] - a[0] * b[2], a[0] * b[1] - a[1] * b[0]};
    double d = a[0] * b[0] + a[1] * b[1] + a[2] * b[2];
    return atan2(norm3(c), d) * 180.0 / PI;
}

/* Pose of view v relative to view 1: R = Rv R1^T, t = tv - R t1. */
static void relative_pose(const sfm_pose *p1, const sfm_pose *pv, sfm_pose *out)
{
    for (int r = 0; r < 3; r++)
        for (int c = 0; c < 3; c++) {
            double s = 0.0;
            for (int k = 0; k < 3; k++)
                s += pv->R[r * 3 + k] * p1->R[c * 3 + k];
            out->R[r * 3 + c] = s;
        }
    for (int r = 0; r < 3; r++)
        out->t[r] = pv->t[r] - (out->R[r * 3] * p1->t[0] + out->R[r * 3 + 1] * p1->t[1] +
                                out->R[r * 3 + 2] * p1->t[2]);
}

static int cmp_double(const void *a, const void *b)
{
    double x = *(const double *)a, y = *(const double *)b;
    return (x > y) - (x < y);
}

static void print_pose(const char *name, const sfm_pose *p)
{
    double aa[3] = {0, 0, 0};
    sfm_rot_to_axis_angle(p->R, aa);
    printf("  %s  R = [% .6f % .6f % .6f; % .6f % .6f % .6f; % .6f % .6f % .6f]\n", name, p->R[0],
           p->R[1], p->R[2], p->R[3], p->R[4], p->R[5], p->R[6], p->R[7], p->R[8]);
    printf("      t = [% .6f % .6f % .6f]  (rotation %.3f deg)\n", p->t[0], p->t[1], p->t[2],
           norm3(aa) * 180.0 / PI);
}

/* ---- the pipeline ------------------------------------------------------ */

int main(int argc, char **argv)
{
    const char *dir = NULL, *gt_path = NULL, *ply_path = NULL;
    const char *calib_path = NULL, *calib_camera = NULL;
    int max_features = 2000, have_cam = 0, calib_w = 0, calib_h = 0, force_uncal = 0;
    double threshold = 1.0, min_parallax = 0.1;
    unsigned long long seed = 1;
    sfm_camera cam_arg;
    memset(&cam_arg, 0, sizeof cam_arg);

    for (int i = 1; i < argc; i++) {
        const char *a = argv[i], *v = i + 1 < argc ? argv[i + 1] : NULL;
        char *end = NULL;
        if (strcmp(a, "--help") == 0 || strcmp(a, "-h") == 0) {
            usage(stdout);
            return 0;
        } else if (strcmp(a, "--camera") == 0 && v) {
            i++;
            if (parse_camera(v, &cam_arg) != 0) {
                fprintf(stderr, "three_view_demo: bad --camera %s (fx,fy,cx,cy[,k1,k2[,p1,p2,k3]])\n", v);
                return 2;
            }
            have_cam = 1;
        } else if (strcmp(a, "--calib") == 0 && v) {
            calib_path = argv[++i];
        } else if (strcmp(a, "--calib-camera") == 0 && v) {
            calib_camera = argv[++i];
        } else if (strcmp(a, "--self-calibrate") == 0) {
            force_uncal = 1;
        } else if (strcmp(a, "--gt") == 0 && v) {
            gt_path = argv[++i];
        } else if (strcmp(a, "--ply") == 0 && v) {
            ply_path = argv[++i];
        } else if (strcmp(a, "--features") == 0 && v) {
            i++;
            long n = strtol(v, &end, 10);
            if (*end != '\0' || n < 8 || n > SFM_FEATURES_MAX_FEATURES) {
                fprintf(stderr, "three_view_demo: bad --features %s (8..%d)\n", v, SFM_FEATURES_MAX_FEATURES);
                return 2;
            }
            max_features = (int)n;
        } else if (strcmp(a, "--threshold") == 0 && v) {
            i++;
            threshold = strtod(v, &end);
            if (*end != '\0' || !(threshold > 0.0 && threshold < 1e3)) {
                fprintf(stderr, "three_view_demo: bad --threshold %s\n", v);
                return 2;
            }
        } else if (strcmp(a, "--min-parallax") == 0 && v) {
            i++;
            min_parallax = strtod(v, &end);
            if (*end != '\0' || !(min_parallax >= 0.0 && min_parallax < 90.0)) {
                fprintf(stderr, "three_view_demo: bad --min-parallax %s\n", v);
                return 2;
            }
        } else if (strcmp(a, "--seed") == 0 && v) {
            i++;
            seed = strtoull(v, &end, 10);
            if (*end != '\0') {
                fprintf(stderr, "three_view_demo: bad --seed %s\n", v);
                return 2;
            }
        } else if (a[0] == '-') {
            fprintf(stderr, "three_view_demo: unknown option or missing value: %s (see --help)\n", a);
            return 2;
        } else if (dir == NULL) {
            dir = a;
        } else {
            fprintf(stderr, "three_view_demo: one directory only (got %s and %s)\n", dir, a);
            return 2;
        }
    }
    if (dir == NULL) {
        usage(stderr);
        return 2;
    }
    if (calib_path != NULL && have_cam) {
        fprintf(stderr, "three_view_demo: give --camera or --calib, not both\n");
        return 2;
    }
    if (calib_camera != NULL && calib_path == NULL) {
        fprintf(stderr, "three_view_demo: --calib-camera needs --calib\n");
        return 2;
    }
    if (calib_path != NULL) {
        char err[768];
        int st = calib_file_read(calib_path, calib_camera, &cam_arg, &calib_w, &calib_h, err, sizeof err);
        if (st != SFM_OK) {
            fprintf(stderr, "three_view_demo: --calib %s (%s)\n", err, sfm_status_str(st));
            return 2;
        }
        have_cam = 1;
    }

    ground_truth gt;
    memset(&gt, 0, sizeof gt);
    if (gt_path && read_gt(gt_path, &gt) != 0)
        return 2;
    sfm_camera cams[3];
    int uncalibrated = force_uncal && !have_cam;
    memset(cams, 0, sizeof cams);
    for (int v = 0; v < 3; v++) {
        if (have_cam)
            cams[v] = cam_arg;
        else if (gt.have_cam[v] && !force_uncal)
            cams[v] = gt.cam[v];
        else
            uncalibrated = 1;
    }

    /* Memory: keypoints and descriptors of the three views, the match lists,
     * the triplets and the library's workspace, all sized before the first
     * library call that needs them. */
    sfm_features_params fp;
    sfm_features_default_params(&fp);
    fp.max_features = max_features;
    sfm_match_params mp;
    sfm_features_default_match_params(&mp);
    const int cap = max_features;

    sfm_keypoint *kps[3] = {NULL, NULL, NULL};
    uint8_t *desc[3] = {NULL, NULL, NULL};
    int *matches[3] = {NULL, NULL, NULL}; /* pairs 1-2, 2-3, 3-1 */
    uint8_t *frames[3] = {NULL, NULL, NULL}; /* copies of the frames, uncalibrated path only */
    int *trip = malloc(sizeof(int) * 3 * (size_t)cap);
    double *px = malloc(sizeof(double) * 6 * (size_t)cap); /* px1 | px2 | px3, cap x 2 each */
    uint8_t *inl = malloc((size_t)cap);
    double *X = malloc(sizeof(double) * 3 * (size_t)cap);
    double *obs = malloc(sizeof(double) * 6 * (size_t)cap); /* view-major normalized coordinates */
    double *err = malloc(sizeof(double) * 3 * (size_t)cap);
    int *flags = malloc(sizeof(int) * (size_t)cap);
    double *hp = malloc(sizeof(double) * 4 * (size_t)cap); /* inlier pixels of views 1 and 2 */
    int ok = trip && px && inl && X && obs && err && flags && hp;
    for (int v = 0; v < 3 && ok; v++) {
        kps[v] = malloc(sizeof(sfm_keypoint) * (size_t)cap);
        desc[v] = malloc((size_t)SFM_FEATURES_DESC_BYTES * (size_t)cap);
        matches[v] = malloc(sizeof(int) * 2 * (size_t)cap);
        ok = kps[v] && desc[v] && matches[v];
    }
    void *ws = NULL;
    size_t ws_size = 0;
    sfm_capture *src = NULL;
    int status = SFM_OK, rc = 1;
    if (!ok) {
        fprintf(stderr, "three_view_demo: out of memory\n");
        goto done;
    }

    printf("three_view_demo: %s\n", dir);
    if (uncalibrated)
        printf("  camera: unknown, self-calibrated from the frames\n");
    else
        for (int v = 0; v < 3; v++)
            printf("  camera %d: fx %.3f fy %.3f cx %.3f cy %.3f%s\n", v + 1, cams[v].fx, cams[v].fy,
                   cams[v].cx, cams[v].cy,
                   cams[v].model == SFM_CAMERA_BROWN     ? " (Brown distortion)"
                   : cams[v].model == SFM_CAMERA_FISHEYE ? " (Kannala-Brandt fisheye)"
                                                         : "");

    /* 1. Frames and features. Each frame is a borrowed view: features are
     * computed while it is held, then it goes back to the source. */
    status = sfm_capture_open_replay(dir, NULL, &src);
    if (status != SFM_OK) {
        fprintf(stderr, "three_view_demo: cannot open replay %s: %s (%d)\n", dir, sfm_status_str(status), status);
        goto done;
    }
    int nf[3] = {0, 0, 0}, w = 0, h = 0;
    double t0 = now_ms();
    for (int v = 0; v < 3; v++) {
        sfm_frame fr;
        status = sfm_capture_acquire(src, 1000, &fr);
        if (status == 0) {
            fprintf(stderr, "three_view_demo: %s holds %d frame(s); three are needed\n", dir, v);
            status = SFM_E_FORMAT;
            goto done;
        }
        if (status < 0) {
            fprintf(stderr, "three_view_demo: frame %d: %s (%d)\n", v + 1, sfm_status_str(status), status);
            goto done;
        }
        if (v == 0) {
            w = fr.width;
            h = fr.height;
            /* Intrinsics hold for the image size they were calibrated at. */
            if (calib_w > 0 && (calib_w != w || calib_h != h)) {
                fprintf(stderr, "three_view_demo: --calib %s is for %dx%d images, the frames are %dx%d\n",
                        calib_path, calib_w, calib_h, w, h);
                sfm_capture_release(src, &fr);
                status = SFM_E_ARGUMENT;
                goto done;
            }
            /* The largest workspace any step needs, for this frame size. */
            size_t need[6] = {sfm_features_workspace_size(&fp, w, h),
                              sfm_features_match_workspace_size(cap, cap),
                              sfm_features_associate_workspace_size(cap, cap, cap),
                              sfm_recon_three_view_pose_workspace_size(cap),
                              sfm_ransac_homography_workspace_size(cap),
                              sfm_recon_three_view_uncalibrated_workspace_size(cap)};
            for (int k = 0; k < 6; k++)
                ws_size = need[k] > ws_size ? need[k] : ws_size;
            ws = malloc(ws_size);
            if (need[0] == 0 || ws == NULL) {
                fprintf(stderr, "three_view_demo: cannot size or allocate the workspace (%zu bytes)\n", ws_size);
                sfm_capture_release(src, &fr);
                status = SFM_E_WORKSPACE;
                goto done;
            }
            printf("  frames %dx%d, workspace %zu bytes\n", w, h, ws_size);
        }
        sfm_image_u8 img = {fr.data, fr.width, fr.height, fr.stride};
        status = fr.width == w && fr.height == h
                     ? sfm_features_detect(&img, &fp, kps[v], desc[v], cap, ws, ws_size)
                     : SFM_E_FORMAT;
        /* the uncalibrated path aligns the triplets on the pixels: keep a copy */
        if (status >= 0 && uncalibrated) {
            if (frames[v] == NULL)
                frames[v] = malloc((size_t)w * (size_t)h);
            if (frames[v] == NULL)
                status = SFM_E_WORKSPACE;
            else
                for (int y = 0; y < h; y++)
                    memcpy(frames[v] + (size_t)y * (size_t)w, fr.data + (size_t)y * (size_t)fr.stride, (size_t)w);
        }
        sfm_capture_release(src, &fr);
        if (status < 0) {
            fprintf(stderr, "three_view_demo: features of frame %d: %s (%d)\n", v + 1, sfm_status_str(status), status);
            goto done;
        }
        nf[v] = status;
    }
    double t1 = now_ms();
    printf("features per view: %d %d %d  (%.1f ms for three frames, read + detect)\n", nf[0], nf[1],
           nf[2], t1 - t0);

    /* 2. Matches 1-2, 2-3, 3-1 and the cyclic association. */
    int nm[3];
    for (int p = 0; p < 3; p++) {
        int a = p, b = (p + 1) % 3;
        status = sfm_features_match(desc[a], nf[a], desc[b], nf[b], &mp, matches[p], NULL, cap, ws, ws_size);
        if (status < 0) {
            fprintf(stderr, "three_view_demo: matching %d-%d: %s (%d)\n", a + 1, b + 1, sfm_status_str(status), status);
            goto done;
        }
        nm[p] = status;
    }
    status = sfm_features_associate_three_views(matches[0], nm[0], matches[1], nm[1], matches[2], nm[2],
                                                nf[0], nf[1], nf[2], trip, cap, ws, ws_size);
    if (status < 0) {
        fprintf(stderr, "three_view_demo: association: %s (%d)\n", sfm_status_str(status), status);
        goto done;
    }
    int nt = status;
    double t2 = now_ms();
    printf("matches per pair: 1-2 %d, 2-3 %d, 3-1 %d\n", nm[0], nm[1], nm[2]);
    printf("triplets after association: %d  (%.1f ms, matching + association)\n", nt, t2 - t1);

    /* 3. Trifocal RANSAC and the calibrated poses. */
    double *px1 = px, *px2 = px + 2 * (size_t)cap, *px3 = px + 4 * (size_t)cap;
    for (int k = 0; k < nt; k++) {
        const sfm_keypoint *a = &kps[0][trip[3 * k]], *b = &kps[1][trip[3 * k + 1]], *c = &kps[2][trip[3 * k + 2]];
        px1[2 * k] = a->x;
        px1[2 * k + 1] = a->y;
        px2[2 * k] = b->x;
        px2[2 * k + 1] = b->y;
        px3[2 * k] = c->x;
        px3[2 * k + 1] = c->y;
    }
    sfm_ransac_options ro;
    sfm_ransac_default_options(&ro);
    ro.threshold = threshold;
    ro.seed = seed;
    sfm_pose poses[3];
    sfm_ransac_stats st;
    memset(&st, 0, sizeof st);
    if (uncalibrated) {
        /* The detector's positions lie on their pyramid level's pixel grid:
         * align each triplet's view-2 and view-3 points onto its view-1
         * patch (Lucas-Kanade), which the focal length's precision needs.
         * Points that do not align keep the detector's position. */
        sfm_align_params ap;
        sfm_features_default_align_params(&ap);
        const sfm_image_u8 f1 = {frames[0], w, h, w}, f2 = {frames[1], w, h, w}, f3 = {frames[2], w, h, w};
        const int a2 = sfm_features_align_points(&f1, px1, &f2, px2, nt, &ap, px2, inl);
        const int a3 = sfm_features_align_points(&f1, px1, &f3, px3, nt, &ap, px3, inl);
        printf("aligned onto view 1: %d (view 2) and %d (view 3) of %d triplets\n", a2, a3, nt);
        /* No intrinsics: trifocal RANSAC, self-calibration, metric BA;
         * every stage reported. The cameras found feed the steps below. */
        sfm_uncal_options uo;
        sfm_uncal_default_options(&uo);
        uo.ransac = ro;
        sfm_uncal_report rep;
        memset(&rep, 0, sizeof rep);
        double K[27];
        status = nt >= SFM_TRIFOCAL_MIN_POINTS
                     ? sfm_recon_three_view_uncalibrated(px1, px2, px3, nt, w, h, &uo, K, poses, NULL, inl, &rep,
                                                         ws, ws_size)
                     : SFM_E_SINGULAR;
        static const char *const path[] = {"none", "linear (absolute dual quadric)", "focal sweep"};
        printf("self-calibration: %d run(s) from RANSAC, %d trifocal inliers (projective RMS %.3f px)\n",
               rep.attempts, rep.ransac_inliers, rep.projective_rms);
        printf("  linear estimate: %s (f %.1f px), sweep best f %.1f px, %d metric adjustments\n",
               rep.linear_status == SFM_OK ? "usable" : "unusable", rep.focal_linear, rep.focal_sweep,
               rep.evaluations);
        printf("  path: %s, far-profile rise %.3g, focal sigma %.2f %%\n",
               rep.path >= 0 && rep.path <= 2 ? path[rep.path] : "?", rep.profile_rise, 100 * rep.focal_sigma);
        if (status >= 0) {
            printf("  focal length %.2f px, principal point (%.1f, %.1f), radial k1 %.4f k2 %.4f, %d inliers, "
                   "RMS %.3f px, %.1f %% in front, median parallax %.2f deg\n",
                   K[0], K[2], K[5], rep.k1, rep.k2, status, rep.rms, 100 * rep.front_fraction, rep.parallax_deg);
            for (int v = 0; v < 3; v++) {
                memset(&cams[v], 0, sizeof cams[v]);
                cams[v].model = rep.k1 != 0 || rep.k2 != 0 ? SFM_CAMERA_BROWN : SFM_CAMERA_PINHOLE;
                cams[v].fx = cams[v].fy = K[9 * v];
                cams[v].cx = K[9 * v + 2];
                cams[v].cy = K[9 * v + 5];
                cams[v].dist[0] = rep.k1;
                cams[v].dist[1] = rep.k2;
            }
            if (gt.have_cam[0])
                printf("  against ground truth: fx %.2f, error %+.2f %%\n", gt.cam[0].fx,
                       100 * (K[0] / gt.cam[0].fx - 1));
        } else {
            fprintf(stderr, "three_view_demo: self-calibration from %d triplets failed at stage %d: %s (%d)\n",
                    nt, rep.stage, sfm_status_str(status), status);
            goto done;
        }
        st = rep.ransac;
    } else {
        status = sfm_recon_three_view_pose(px1, px2, px3, nt, &cams[0], &cams[1], &cams[2], &ro, poses,
                                           inl, &st, ws, ws_size);
    }
    double t3 = now_ms();
    if (status < 0) {
        fprintf(stderr, "three_view_demo: three-view pose from %d triplets failed: %s (%d)\n", nt,
                sfm_status_str(status), status);
        goto done;
    }
    int ni = status;
    static const char *const stop[] = {"confidence reached", "iteration cap", "time budget"};
    printf("trifocal inliers: %d of %d (%.1f%%), threshold %.2f px\n", ni, nt, 100.0 * ni / nt, threshold);
    printf("RANSAC iterations: %d (%s, seed %llu, %d local optimisations)  (%.1f ms)\n", st.iterations,
           st.stop_reason >= 0 && st.stop_reason <= 2 ? stop[st.stop_reason] : "?",
           (unsigned long long)st.seed, st.lo_runs, t3 - t2);
    printf("poses (x_cam = R X + t, X in view 1's frame, |t2| = 1):\n");
    print_pose("view 2", &poses[1]);
    print_pose("view 3", &poses[2]);
    printf("  |t3| / |t2| = %.4f\n", norm3(poses[2].t) / norm3(poses[1].t));

    /* 4. Sparse points: the inliers triangulated in the three views (DLT on
     * normalized coordinates, [R | t] per view) and reprojected through the
     * full camera models. */
    double P[36];
    for (int v = 0; v < 3; v++)
        for (int r = 0; r < 3; r++) {
            memcpy(&P[v * 12 + r * 4], &poses[v].R[r * 3], 3 * sizeof(double));
            P[v * 12 + r * 4 + 3] = poses[v].t[r];
        }
    int np = 0;
    for (int k = 0; k < nt; k++) {
        if (!inl[k])
            continue;
        const double *pv[3] = {px1 + 2 * k, px2 + 2 * k, px3 + 2 * k};
        int good = 1;
        double f[3][3];
        for (int v = 0; v < 3 && good; v++)
            good = sfm_camera_unproject(&cams[v], pv[v], f[v]) == SFM_OK && f[v][2] > 0.0;
        if (!good)
            continue;
        for (int v = 0; v < 3; v++) {
            obs[(v * (size_t)ni + np) * 2] = f[v][0] / f[v][2];
            obs[(v * (size_t)ni + np) * 2 + 1] = f[v][1] / f[v][2];
        }
        trip[np] = k; /* reuse: inlier index of point np */
        np++;
    }
    /* obs was laid out for ni points per view; compact it to np. */
    if (np < ni)
        for (int v = 1; v < 3; v++)
            memmove(obs + 2 * (size_t)v * np, obs + 2 * (size_t)v * ni, sizeof(double) * 2 * (size_t)np);
    status = sfm_triangulate_dlt(3, P, np, obs, X, flags);
    if (status < 0) {
        fprintf(stderr, "three_view_demo: triangulation: %s (%d)\n", sfm_status_str(status), status);
        goto done;
    }
    int ne = 0, nfront = 0;
    for (int j = 0; j < np; j++) {
        if (flags[j])
            continue;
        nfront++;
        int k = trip[j];
        const double *pv[3] = {px1 + 2 * k, px2 + 2 * k, px3 + 2 * k};
        for (int v = 0; v < 3; v++) {
            double Xc[3], q[2];
            for (int r = 0; r < 3; r++)
                Xc[r] = poses[v].R[r * 3] * X[3 * j] + poses[v].R[r * 3 + 1] * X[3 * j + 1] +
                        poses[v].R[r * 3 + 2] * X[3 * j + 2] + poses[v].t[r];
            if (sfm_camera_project(&cams[v], Xc, q, NULL) == SFM_OK)
                err[ne++] = hypot(q[0] - pv[v][0], q[1] - pv[v][1]);
        }
    }
    qsort(err, (size_t)ne, sizeof(double), cmp_double);
    double med = ne ? err[ne / 2] : (double)NAN;
    printf("sparse points: %d triangulated (%d in front of all three cameras)\n", np, nfront);
    printf("median reprojection error of the inliers: %.3f px (%d observations)\n", med, ne);

    /* Parallax: per point, the larger of the angles its rays from view 1
     * make with those from views 2 and 3. Points at (or near) infinity carry
     * rotation only; when most are, |t| = 1 is a direction fitted to noise,
     * and an application should not act on it. */
    double C[3][3];
    for (int v = 0; v < 3; v++)
        for (int r = 0; r < 3; r++)
            C[v][r] = -(poses[v].R[r] * poses[v].t[0] + poses[v].R[3 + r] * poses[v].t[1] +
                        poses[v].R[6 + r] * poses[v].t[2]);
    int na = 0;
    for (int j = 0; j < np; j++) {
        if (flags[j])
            continue;
        double best = 0.0;
        for (int v = 1; v < 3; v++) {
            double r1[3], rv[3];
            for (int r = 0; r < 3; r++) {
                r1[r] = X[3 * j + r] - C[0][r];
                rv[r] = X[3 * j + r] - C[v][r];
            }
            double a = angle_deg(r1, rv);
            best = a > best ? a : best;
        }
        err[na++] = best;
    }
    qsort(err, (size_t)na, sizeof(double), cmp_double);
    double parallax = na ? err[na / 2] : 0.0;
    printf("median triangulation angle: %.2f deg\n", parallax);
    if (!(parallax >= min_parallax)) {
        status = SFM_E_SINGULAR;
        fprintf(stderr, "three_view_demo: median triangulation angle %.3g deg is below %.3g deg: "
                        "too little parallax for a translation\n", parallax, min_parallax);
        goto done;
    }

    /* One plane: when a homography between views 1 and 2 explains most
     * inliers, the calibrated pose has a twin (the two decompositions of a
     * plane's homography) and the trifocal tensor is not determined by
     * those points; the answer may be the wrong twin. */
    int nh = 0;
    for (int k = 0; k < nt; k++)
        if (inl[k]) {
            memcpy(hp + 2 * (size_t)nh, px1 + 2 * k, 2 * sizeof(double));
            memcpy(hp + 2 * ((size_t)ni + nh), px2 + 2 * k, 2 * sizeof(double));
            nh++;
        }
    sfm_mat3 H;
    int on_plane = sfm_ransac_homography(hp, hp + 2 * (size_t)ni, nh, &cams[0], &cams[1], &ro, &H, NULL,
                                         NULL, ws, ws_size);
    if (on_plane >= 0) {
        printf("inliers on one plane (homography 1-2 within %.2f px): %d of %d (%.0f%%)\n", threshold,
               on_plane, ni, 100.0 * on_plane / ni);
        if (on_plane >= 0.75 * ni)
            printf("warning: one plane dominates the inliers; the poses may be the plane's twin "
                   "solution (views with more depth variation help)\n");
    }

    if (ply_path) {
        FILE *f = fopen(ply_path, "w");
        if (f == NULL) {
            fprintf(stderr, "three_view_demo: cannot write %s\n", ply_path);
        } else {
            fprintf(f, "ply\nformat ascii 1.0\nelement vertex %d\nproperty double x\nproperty double y\n"
                       "property double z\nend_header\n", nfront);
            for (int j = 0; j < np; j++)
                if (!flags[j])
                    fprintf(f, "%.9g %.9g %.9g\n", X[3 * j], X[3 * j + 1], X[3 * j + 2]);
            fclose(f);
            printf("points written to %s\n", ply_path);
        }
    }

    /* 5. Against the ground truth: poses of views 2 and 3 relative to view 1. */
    if (gt_path) {
        if (!(gt.have_pose[0] && gt.have_pose[1] && gt.have_pose[2])) {
            fprintf(stderr, "three_view_demo: %s lacks a 'pose' line for some view\n", gt_path);
            rc = 2;
            goto done;
        }
        sfm_pose rel[3];
        double rot_err[3], dir_err[3];
        for (int v = 1; v < 3; v++) {
            relative_pose(&gt.pose[0], &gt.pose[v], &rel[v]);
            double ang = 0.0;
            sfm_rot_angle_between(poses[v].R, rel[v].R, &ang);
            rot_err[v] = ang * 180.0 / PI;
            dir_err[v] = angle_deg(poses[v].t, rel[v].t);
        }
        double s_est = norm3(poses[2].t) / norm3(poses[1].t);
        double s_gt = norm3(rel[2].t) / norm3(rel[1].t);
        printf("against ground truth (%s):\n", gt_path);
        printf("  rotation error: view 2 %.4f deg, view 3 %.4f deg\n", rot_err[1], rot_err[2]);
        printf("  translation direction error: view 2 %.4f deg, view 3 %.4f deg\n", dir_err[1], dir_err[2]);
        printf("  scale |t3|/|t2|: estimated %.4f, true %.4f, error %.2f%%\n", s_est, s_gt,
               100.0 * (s_est / s_gt - 1.0));
    }
    rc = 0;
    status = SFM_OK;

done:
    sfm_capture_close(src);
    free(ws);
    for (int v = 0; v < 3; v++) {
        free(frames[v]);
        free(kps[v]);
        free(desc[v]);
        free(matches[v]);
    }
    free(trip);
    free(px);
    free(inl);
    free(X);
    free(obs);
    free(err);
    free(flags);
    free(hp);
    if (rc == 1 && status < 0)
        fprintf(stderr, "three_view_demo: failed: %s (%d)\n", sfm_status_str(status), status);
    return rc;
}
