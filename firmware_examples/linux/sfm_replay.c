/* sfm-replay: plays a recording through the replay source and reports what
 * it holds (frames, drops, errors, rate); optionally lists every frame.
 * Exit status: 0 done, 1 the recording cannot be opened or a frame fails,
 * 2 bad usage. */
#define _POSIX_C_SOURCE 200809L
#include <inttypes.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "sfm/sfm_capture.h"

static void usage(FILE *f)
{
    fprintf(f,
            "usage: sfm-replay DIR [options]\n"
            "Plays the recording in DIR (manifest.csv or data.csv plus images) as a\n"
            "camera would deliver it and prints a summary.\n"
            "\n"
            "Options:\n"
            "  --rate R      max (default, as fast as possible), recorded, or a fixed\n"
            "                number of frames per second\n"
            "  --speed X     with --rate recorded: play X times faster\n"
            "  --list        one line per frame: sequence, timestamp_ns, mean gray level\n"
            "  --quiet       no progress line\n"
            "  --help        this text\n");
}

int main(int argc, char **argv)
{
    const char *dir = NULL;
    sfm_replay_options o = {SFM_REPLAY_ASAP, 0.0, 1.0, 0};
    int list = 0, quiet = 0;
    for (int i = 1; i < argc; i++) {
        const char *a = argv[i];
        const char *v = i + 1 < argc ? argv[i + 1] : NULL;
        char *end = NULL;
        if (strcmp(a, "--help") == 0 || strcmp(a, "-h") == 0) {
            usage(stdout);
            return 0;
        } else if (strcmp(a, "--list") == 0) {
            list = 1;
        } else if (strcmp(a, "--quiet") == 0) {
            quiet = 1;
        } else if (strcmp(a, "--rate") == 0 && v) {
            i++;
            if (strcmp(v, "max") == 0) {
                o.rate = SFM_REPLAY_ASAP;
            } else if (strcmp(v, "recorded") == 0) {
                o.rate = SFM_REPLAY_RECORDED;
            } else {
                o.rate = SFM_REPLAY_FIXED;
                o.fixed_fps = strtod(v, &end);
                if (*end != '\0' || !(o.fixed_fps > 0.0 && o.fixed_fps < 1e6)) {
                    fprintf(stderr, "sfm-replay: bad --rate %s (max, recorded or a positive number)\n", v);
                    return 2;
                }
            }
        } else if (strcmp(a, "--speed") == 0 && v) {
            i++;
            o.speed = strtod(v, &end);
            if (*end != '\0' || !(o.speed > 0.0 && o.speed < 1e6)) {
                fprintf(stderr, "sfm-replay: bad --speed %s\n", v);
                return 2;
            }
        } else if (a[0] == '-') {
            fprintf(stderr, "sfm-replay: unknown option or missing value: %s (see --help)\n", a);
            return 2;
        } else if (dir == NULL) {
            dir = a;
        } else {
            fprintf(stderr, "sfm-replay: one directory only (got %s and %s)\n", dir, a);
            return 2;
        }
    }
    if (dir == NULL) {
        usage(stderr);
        return 2;
    }
    sfm_capture *c = NULL;
    int rc = sfm_capture_open_replay(dir, &o, &c);
    if (rc != SFM_OK) {
        fprintf(stderr, "sfm-replay: cannot open %s: %s\n", dir, sfm_status_str(rc));
        return 1;
    }
    sfm_capture_info info;
    sfm_capture_get_info(c, &info);
    long n = 0, bad = 0;
    int64_t t_first = 0, t_last = 0;
    for (;;) {
        sfm_frame f;
        rc = sfm_capture_acquire(c, -1, &f);
        if (rc == 0)
            break;
        if (rc < 0) {
            fprintf(stderr, "sfm-replay: frame %ld: %s\n", n + bad, sfm_status_str(rc));
            bad++;
            if (rc == SFM_E_FORMAT || rc == SFM_E_IO)
                continue;
            break;
        }
        if (n == 0)
            t_first = f.timestamp_ns;
        t_last = f.timestamp_ns;
        if (list) {
            uint64_t sum = 0;
            for (int y = 0; y < f.height; y++)
                for (int x = 0; x < f.width; x++)
                    sum += f.data[(size_t)y * (size_t)f.stride + (size_t)x];
            printf("%" PRIu64 " %" PRId64 " %.3f\n", f.sequence, f.timestamp_ns,
                   (double)sum / ((double)f.width * f.height));
        }
        sfm_capture_release(c, &f);
        n++;
        if (!quiet && !list && n % 25 == 0)
            fprintf(stderr, "\rsfm-replay: %ld frames", n);
    }
    sfm_capture_stats st;
    sfm_capture_get_stats(c, &st);
    sfm_capture_close(c);
    if (!quiet && !list && n >= 25)
        fprintf(stderr, "\n");
    double span = (double)(t_last - t_first) * 1e-9;
    printf("%s: %ld frames %dx%d, %llu drops, %llu errors, span %.3f s", dir, n, info.width,
           info.height, (unsigned long long)st.drops, (unsigned long long)st.errors, span);
    if (n > 1 && span > 0.0)
        printf(", %.2f fps recorded", (double)(n - 1) / span);
    printf("\n");
    return bad ? 1 : 0;
}
