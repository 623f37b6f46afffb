/* vo-camera: visual odometry on a Linux board. Frames come from a V4L2
 * camera (/dev/videoN), from libcamera (libcamera[:ID], where the capture
 * library was built with it), or from a replay directory (manifest.csv plus
 * images): the same loop for all three. Every frame's state goes to stdout,
 * with its pose when it has one; --tum writes the trajectory.
 *
 * Poses printed and written are camera-to-world (the camera centre and
 * orientation in the world frame, which is the first frame's camera):
 * TUM rows "timestamp tx ty tz qx qy qz qw", timestamp in seconds.
 *
 * All library memory is one buffer of sfm_vo_workspace_size() bytes,
 * allocated once before the first frame; nothing is allocated per frame.
 * Exit status: 0 done, 1 a library call failed (its status is named), 2 bad
 * usage. */
#define _POSIX_C_SOURCE 200809L
#include <inttypes.h>
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <time.h>

#include "sfm/sfm_capture.h"
#include "sfm/sfm_vo.h"

#ifndef VO_DEFAULT_SOURCE
#define VO_DEFAULT_SOURCE NULL
#endif

static double mono_seconds(void *ctx)
{
    (void)ctx;
    struct timespec ts;
    clock_gettime(CLOCK_MONOTONIC, &ts);
    return (double)ts.tv_sec + 1e-9 * (double)ts.tv_nsec;
}

static void usage(FILE *f)
{
    fprintf(f,
            "usage: vo-camera SOURCE [options]\n"
            "SOURCE: /dev/videoN (V4L2), libcamera[:ID], or a replay directory.\n"
            "Options:\n"
            "  --camera fx,fy,cx,cy[,k1,k2,p1,p2,k3]  intrinsics at the frame size (Brown\n"
            "                 distortion as OpenCV's); a replay directory's\n"
            "                 ground_truth.txt 'camera' line is used when absent\n"
            "  --fisheye      the four numbers after cx,cy are Kannala-Brandt k1..k4\n"
            "  --tum FILE     write the trajectory (camera-to-world, TUM format)\n"
            "  --features N   features per frame (default 500)\n"
            "  --window W     keyframes in the bundle adjustment (default 5)\n"
            "  --frames N     stop after N frames\n"
            "  --budget-ms B  time budget per frame (degrades under load)\n"
            "  --width W --height H   V4L2 / libcamera size to ask for\n"
            "  --quiet        no line per frame\n");
}

static int fail(const char *what, int st)
{
    fprintf(stderr, "vo-camera: %s: %s (%d)\n", what, sfm_status_str(st), st);
    return 1;
}

/* (qx, qy, qz, qw) of a row-major rotation, qw >= 0. */
static void rot_to_quat(const double R[9], double q[4])
{
    double tr = R[0] + R[4] + R[8], s;
    if (tr > 0) {
        s = sqrt(tr + 1.0) * 2;
        q[3] = 0.25 * s;
        q[0] = (R[7] - R[5]) / s;
        q[1] = (R[2] - R[6]) / s;
        q[2] = (R[3] - R[1]) / s;
    } else if (R[0] > R[4] && R[0] > R[8]) {
        s = sqrt(1.0 + R[0] - R[4] - R[8]) * 2;
        q[3] = (R[7] - R[5]) / s;
        q[0] = 0.25 * s;
        q[1] = (R[1] + R[3]) / s;
        q[2] = (R[2] + R[6]) / s;
    } else if (R[4] > R[8]) {
        s = sqrt(1.0 + R[4] - R[0] - R[8]) * 2;
        q[3] = (R[2] - R[6]) / s;
        q[0] = (R[1] + R[3]) / s;
        q[1] = 0.25 * s;
        q[2] = (R[5] + R[7]) / s;
    } else {
        s = sqrt(1.0 + R[8] - R[0] - R[4]) * 2;
        q[3] = (R[3] - R[1]) / s;
        q[0] = (R[2] + R[6]) / s;
        q[1] = (R[5] + R[7]) / s;
        q[2] = 0.25 * s;
    }
    if (q[3] < 0)
        for (int k = 0; k < 4; k++)
            q[k] = -q[k];
}

static int camera_from_gt(const char *dir, sfm_camera *cam)
{
    char path[SFM_CAPTURE_PATH_MAX + 32];
    snprintf(path, sizeof path, "%s/ground_truth.txt", dir);
    FILE *f = fopen(path, "r");
    if (f == NULL)
        return 0;
    char line[512];
    int ok = 0;
    while (!ok && fgets(line, sizeof line, f) != NULL) {
        int v;
        if (sscanf(line, "camera %d %lf %lf %lf %lf", &v, &cam->fx, &cam->fy, &cam->cx, &cam->cy) == 5)
            ok = 1;
    }
    fclose(f);
    return ok;
}

int main(int argc, char **argv)
{
    const char *src = VO_DEFAULT_SOURCE, *tum_path = NULL;
    sfm_camera cam;
    memset(&cam, 0, sizeof cam);
    int have_cam = 0, fisheye = 0, nfeat = 500, window = 5, max_frames = -1, quiet = 0;
    int req_w = 0, req_h = 0, src_given = 0;
    double budget_ms = 0;
    for (int i = 1; i < argc; i++) {
        const char *a = argv[i], *v = i + 1 < argc ? argv[i + 1] : NULL;
        if (strcmp(a, "--help") == 0) {
            usage(stdout);
            return 0;
        } else if (strcmp(a, "--camera") == 0 && v) {
            double x[9] = {0};
            int n = sscanf(v, "%lf,%lf,%lf,%lf,%lf,%lf,%lf,%lf,%lf", &x[0], &x[1], &x[2], &x[3],
                           &x[4], &x[5], &x[6], &x[7], &x[8]);
            if (n < 4) {
                usage(stderr);
                return 2;
            }
            cam.fx = x[0];
            cam.fy = x[1];
            cam.cx = x[2];
            cam.cy = x[3];
            for (int k = 0; k < 5; k++)
                cam.dist[k] = x[4 + k];
            cam.model = n > 4 ? SFM_CAMERA_BROWN : SFM_CAMERA_PINHOLE;
            have_cam = 1;
            i++;
        } else if (strcmp(a, "--fisheye") == 0) {
            fisheye = 1;
        } else if (strcmp(a, "--tum") == 0 && v) {
            tum_path = v;
            i++;
        } else if (strcmp(a, "--features") == 0 && v) {
            nfeat = atoi(v);
            i++;
        } else if (strcmp(a, "--window") == 0 && v) {
            window = atoi(v);
            i++;
        } else if (strcmp(a, "--frames") == 0 && v) {
            max_frames = atoi(v);
            i++;
        } else if (strcmp(a, "--budget-ms") == 0 && v) {
            budget_ms = atof(v);
            i++;
        } else if (strcmp(a, "--width") == 0 && v) {
            req_w = atoi(v);
            i++;
        } else if (strcmp(a, "--height") == 0 && v) {
            req_h = atoi(v);
            i++;
        } else if (strcmp(a, "--quiet") == 0) {
            quiet = 1;
        } else if (a[0] != '-' && !src_given) {
            src = a;
            src_given = 1;
        } else {
            usage(stderr);
            return 2;
        }
    }
    if (src == NULL) {
        usage(stderr);
        return 2;
    }
    if (fisheye)
        cam.model = SFM_CAMERA_FISHEYE;

    sfm_capture *cap = NULL;
    int st;
    if (strncmp(src, "/dev/", 5) == 0) {
        sfm_v4l2_options o = {req_w, req_h, 0, 0, 0};
        st = sfm_capture_open_v4l2(src, &o, &cap);
    } else if (strncmp(src, "libcamera", 9) == 0) {
#ifdef VO_NO_LIBCAMERA
        /* a build whose capture library has no libcamera side at all */
        st = SFM_E_UNSUPPORTED;
#else
        sfm_libcamera_options o = {req_w, req_h, 0};
        st = sfm_capture_open_libcamera(src[9] == ':' ? src + 10 : NULL, &o, &cap);
#endif
    } else {
        if (!have_cam && camera_from_gt(src, &cam)) {
            cam.model = SFM_CAMERA_PINHOLE;
            have_cam = 1;
        }
        st = sfm_capture_open_replay(src, NULL, &cap);
    }
    if (st < 0)
        return fail(src, st);
    if (!have_cam) {
        sfm_capture_close(cap);
        fprintf(stderr, "vo-camera: no intrinsics: give --camera fx,fy,cx,cy "
                        "(self-calibration is not in this build: %s)\n",
                sfm_status_str(SFM_E_UNSUPPORTED));
        return 1;
    }
    sfm_capture_info info;
    sfm_capture_get_info(cap, &info);

    sfm_vo_dims dims = {info.width, info.height, nfeat, window};
    sfm_vo_params p;
    st = sfm_vo_default_params(&dims, &p);
    if (st < 0) {
        sfm_capture_close(cap);
        return fail("sfm_vo_default_params", st);
    }
    p.camera = cam;
    p.clock = mono_seconds;
    p.frame_budget = budget_ms / 1e3;
    size_t ws_size = sfm_vo_workspace_size(&dims);
    void *ws = ws_size ? malloc(ws_size) : NULL;
    sfm_vo *vo = NULL;
    st = ws ? sfm_vo_init(&dims, &p, &vo, ws, ws_size) : SFM_E_WORKSPACE;
    if (st < 0) {
        free(ws);
        sfm_capture_close(cap);
        return fail("sfm_vo_init", st);
    }
    FILE *tum = NULL;
    if (tum_path != NULL) {
        tum = fopen(tum_path, "w");
        if (tum == NULL) {
            free(ws);
            sfm_capture_close(cap);
            return fail(tum_path, SFM_E_IO);
        }
        fprintf(tum, "# timestamp tx ty tz qx qy qz qw (camera-to-world)\n");
    }
    fprintf(stderr, "vo-camera: %s (%s) %dx%d, %d features, window %d, workspace %zu bytes\n",
            info.card, info.driver, info.width, info.height, nfeat, window, ws_size);
    int rc = 0, frames = 0, tracked = 0, with_pose = 0;
    double t_total = 0;
    sfm_frame fr;
    while (max_frames < 0 || frames < max_frames) {
        st = sfm_capture_acquire(cap, 2000, &fr);
        if (st == 0)
            break;
        if (st < 0) {
            rc = fail("sfm_capture_acquire", st);
            break;
        }
        sfm_image_u8 img = {fr.data, fr.width, fr.height, fr.stride};
        sfm_vo_frame_result r;
        double t0 = mono_seconds(NULL);
        st = sfm_vo_push_frame(vo, &img, fr.timestamp_ns, NULL, 0, &r);
        t_total += mono_seconds(NULL) - t0;
        sfm_capture_release(cap, &fr);
        if (st < 0) {
            rc = fail("sfm_vo_push_frame", st);
            break;
        }
        frames++;
        tracked += r.state == SFM_VO_TRACKING;
        if (r.has_pose) {
            double q[4];
            rot_to_quat(r.R_wc, q);
            with_pose++;
            if (!quiet)
                printf("%6d %.9f %-21s %-8s %.6f %.6f %.6f %.6f %.6f %.6f %.6f\n", r.frame_index,
                       r.timestamp_ns / 1e9, sfm_vo_state_str(r.state),
                       r.quality == SFM_VO_QUALITY_GOOD ? "good" : "degraded", r.c_w[0], r.c_w[1],
                       r.c_w[2], q[0], q[1], q[2], q[3]);
            if (tum)
                fprintf(tum, "%.9f %.9f %.9f %.9f %.9f %.9f %.9f %.9f\n", r.timestamp_ns / 1e9,
                        r.c_w[0], r.c_w[1], r.c_w[2], q[0], q[1], q[2], q[3]);
        } else if (!quiet) {
            printf("%6d %.9f %-21s none\n", r.frame_index, r.timestamp_ns / 1e9,
                   sfm_vo_state_str(r.state));
        }
    }
    if (tum)
        fclose(tum);
    fprintf(stderr, "vo-camera: %d frames, %d tracking, %d with a pose, %.2f ms/frame mean\n", frames,
            tracked, with_pose, frames ? 1e3 * t_total / frames : 0.0);
    free(ws);
    sfm_capture_close(cap);
    return rc;
}
