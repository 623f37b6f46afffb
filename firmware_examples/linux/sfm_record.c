/* sfm-record: frames from a camera (V4L2 or libcamera) or from another
 * recording to a replay directory (images + manifest.csv).
 * Exit status: 0 done, 1 a capture or write error, 2 bad usage. */
#define _POSIX_C_SOURCE 200809L
#include <signal.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "sfm/sfm_capture.h"

static volatile sig_atomic_t stop;
static void on_signal(int s) { (void)s; stop = 1; }

static void usage(FILE *f)
{
    fprintf(f,
            "usage: sfm-record SOURCE --out DIR [options]\n"
            "Records gray frames and their timestamps to DIR (created; must not\n"
            "already hold a manifest.csv), for sfm-replay and the replay source.\n"
            "\n"
            "SOURCE (one of):\n"
            "  --v4l2 DEV          a V4L2 capture device, e.g. /dev/video0\n"
            "  --libcamera ID      a libcamera camera id, or 'first'\n"
            "  --list-libcamera    print the libcamera camera ids and exit\n"
            "  --replay DIR        another recording\n"
            "\n"
            "Options:\n"
            "  --frames N          frames to record (default 100; 0 = until Ctrl-C)\n"
            "  --width W --height H  requested size (default: the device's)\n"
            "  --format F          V4L2 format: grey, yuyv, nv12, mjpeg (default: first offered)\n"
            "  --fps N             requested frame rate (V4L2)\n"
            "  --buffers N         driver buffers (default 4)\n"
            "  --image F           pgm (default), png or jpg\n"
            "  --timeout-ms MS     give up when no frame comes for MS ms (default 3000)\n"
            "  --quiet             no progress line\n"
            "  --help              this text\n");
}

static int parse_int(const char *s, int lo, int hi, int *out)
{
    char *end;
    long v = strtol(s, &end, 10);
    if (*s == '\0' || *end != '\0' || v < lo || v > hi)
        return -1;
    *out = (int)v;
    return 0;
}

int main(int argc, char **argv)
{
    const char *v4l2 = NULL, *libcam = NULL, *replay = NULL, *out = NULL;
    int frames = 100, timeout_ms = 3000, quiet = 0, image = SFM_RECORD_PGM;
    sfm_v4l2_options vo = {0, 0, 0, 0, 0};
    sfm_libcamera_options lo = {0, 0, 0};
    for (int i = 1; i < argc; i++) {
        const char *a = argv[i];
        const char *v = i + 1 < argc ? argv[i + 1] : NULL;
        int bad = 0;
        if (strcmp(a, "--help") == 0 || strcmp(a, "-h") == 0) {
            usage(stdout);
            return 0;
        } else if (strcmp(a, "--list-libcamera") == 0) {
            static char ids[16][128];
            int n = sfm_libcamera_list(&ids[0][0], 16, 128);
            if (n < 0) {
                fprintf(stderr, "sfm-record: libcamera: %s\n", sfm_status_str(n));
                return 1;
            }
            printf("%d camera(s)\n", n);
            for (int k = 0; k < n && k < 16; k++)
                printf("%s\n", ids[k]);
            return 0;
        } else if (strcmp(a, "--quiet") == 0) {
            quiet = 1;
            continue;
        } else if (v == NULL) {
            fprintf(stderr, "sfm-record: %s needs a value (see --help)\n", a);
            return 2;
        } else if (strcmp(a, "--v4l2") == 0) {
            v4l2 = v;
        } else if (strcmp(a, "--libcamera") == 0) {
            libcam = v;
        } else if (strcmp(a, "--replay") == 0) {
            replay = v;
        } else if (strcmp(a, "--out") == 0) {
            out = v;
        } else if (strcmp(a, "--frames") == 0) {
            bad = parse_int(v, 0, 1 << 30, &frames);
        } else if (strcmp(a, "--width") == 0) {
            bad = parse_int(v, 1, SFM_CAPTURE_MAX_SIDE, &vo.width);
            lo.width = vo.width;
        } else if (strcmp(a, "--height") == 0) {
            bad = parse_int(v, 1, SFM_CAPTURE_MAX_SIDE, &vo.height);
            lo.height = vo.height;
        } else if (strcmp(a, "--fps") == 0) {
            bad = parse_int(v, 1, 1000, &vo.fps);
        } else if (strcmp(a, "--buffers") == 0) {
            bad = parse_int(v, 2, 32, &vo.buffers);
            lo.buffers = vo.buffers;
        } else if (strcmp(a, "--timeout-ms") == 0) {
            bad = parse_int(v, 1, 3600000, &timeout_ms);
        } else if (strcmp(a, "--format") == 0) {
            if (strcmp(v, "grey") == 0 || strcmp(v, "gray") == 0) vo.format = SFM_PIX_GRAY8;
            else if (strcmp(v, "yuyv") == 0) vo.format = SFM_PIX_YUYV;
            else if (strcmp(v, "nv12") == 0) vo.format = SFM_PIX_NV12;
            else if (strcmp(v, "mjpeg") == 0) vo.format = SFM_PIX_MJPEG;
            else bad = 1;
        } else if (strcmp(a, "--image") == 0) {
            if (strcmp(v, "pgm") == 0) image = SFM_RECORD_PGM;
            else if (strcmp(v, "png") == 0) image = SFM_RECORD_PNG;
            else if (strcmp(v, "jpg") == 0 || strcmp(v, "jpeg") == 0) image = SFM_RECORD_JPEG;
            else bad = 1;
        } else {
            fprintf(stderr, "sfm-record: unknown option %s (see --help)\n", a);
            return 2;
        }
        if (bad) {
            fprintf(stderr, "sfm-record: bad value for %s: %s\n", a, v);
            return 2;
        }
        i++;
    }
    if ((v4l2 != NULL) + (libcam != NULL) + (replay != NULL) != 1 || out == NULL) {
        fprintf(stderr, "sfm-record: give one source (--v4l2, --libcamera or --replay) and --out DIR\n");
        usage(stderr);
        return 2;
    }

    sfm_capture *c = NULL;
    int rc;
    const char *what = v4l2 ? v4l2 : libcam ? libcam : replay;
    if (v4l2)
        rc = sfm_capture_open_v4l2(v4l2, &vo, &c);
    else if (libcam)
        rc = sfm_capture_open_libcamera(strcmp(libcam, "first") == 0 ? NULL : libcam, &lo, &c);
    else
        rc = sfm_capture_open_replay(replay, NULL, &c);
    if (rc != SFM_OK) {
        fprintf(stderr, "sfm-record: cannot open %s: %s\n", what, sfm_status_str(rc));
        return 1;
    }
    sfm_capture_info info;
    sfm_capture_get_info(c, &info);
    fprintf(stderr, "sfm-record: %s (%s): %dx%d %s, %d buffers, granted %d/%d fps\n", info.card,
            info.driver, info.width, info.height, sfm_pixfmt_name(info.source_format),
            info.buffers, info.fps_num, info.fps_den);
    sfm_recorder *r = NULL;
    rc = sfm_recorder_open(out, image, &r);
    if (rc != SFM_OK) {
        fprintf(stderr, "sfm-record: cannot record to %s: %s%s\n", out, sfm_status_str(rc),
                rc == SFM_E_ARGUMENT ? " (it already holds a manifest.csv?)" : "");
        sfm_capture_close(c);
        return 1;
    }
    struct sigaction sa;
    memset(&sa, 0, sizeof sa);
    sa.sa_handler = on_signal;
    sigaction(SIGINT, &sa, NULL);
    sigaction(SIGTERM, &sa, NULL);

    int status = 0, n = 0;
    int64_t t_first = 0, t_last = 0;
    while (!stop && (frames == 0 || n < frames)) {
        sfm_frame f;
        rc = sfm_capture_acquire(c, timeout_ms, &f);
        if (rc == 0)
            break; /* the replayed recording ended */
        if (rc == SFM_E_FORMAT)
            continue; /* counted in the errors */
        if (rc < 0) {
            if (!stop) {
                fprintf(stderr, "\nsfm-record: capture stopped after %d frames: %s\n", n,
                        sfm_status_str(rc));
                status = 1;
            }
            break;
        }
        int wrc = sfm_recorder_write(r, &f);
        if (n == 0)
            t_first = f.timestamp_ns;
        t_last = f.timestamp_ns;
        sfm_capture_release(c, &f);
        if (wrc != SFM_OK) {
            fprintf(stderr, "\nsfm-record: writing frame %d: %s\n", n, sfm_status_str(wrc));
            status = 1;
            break;
        }
        n++;
        if (!quiet && (n % 10 == 0 || n == frames)) {
            sfm_capture_stats st;
            sfm_capture_get_stats(c, &st);
            double fps = n > 1 && t_last > t_first ? (n - 1) * 1e9 / (double)(t_last - t_first) : 0.0;
            fprintf(stderr, "\rsfm-record: %d frames, %llu drops, %llu errors, %.1f fps   ", n,
                    (unsigned long long)st.drops, (unsigned long long)st.errors, fps);
        }
    }
    sfm_capture_stats st;
    sfm_capture_get_stats(c, &st);
    sfm_capture_close(c);
    if (sfm_recorder_close(r) != SFM_OK) {
        fprintf(stderr, "sfm-record: the manifest of %s is incomplete\n", out);
        status = 1;
    }
    fprintf(stderr, "%ssfm-record: wrote %d frames to %s (%llu drops, %llu errors)\n",
            quiet ? "" : "\n", n, out, (unsigned long long)st.drops,
            (unsigned long long)st.errors);
    return status;
}
