/* Record a synthetic sequence, replay it, and get back the same frames,
 * timestamps and sequence numbers; replay's errors and contracts. */
#define _DEFAULT_SOURCE
#include <limits.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/stat.h>
#include <unistd.h>

#include "cap_test.h"
#include "sfm_test.h"

enum { RW = 40, RH = 30, RN = 6 };

static int64_t stamp(int k) { return 1700000000000000000LL + (int64_t)k * 33333333 + k * k; }
static uint64_t seqno(int k) { return (uint64_t)(10 + k + (k >= 3 ? 2 : 0)); } /* a gap of 2 */

static void record(sfm_test_ctx *t, const char *dir, int fmt)
{
    static uint8_t img[RH * (RW + 8)];
    sfm_recorder *r = NULL;
    SFM_CHECK_EQ_INT(sfm_recorder_open(dir, fmt, &r), SFM_OK);
    if (r == NULL)
        return;
    for (int k = 0; k < RN; k++) {
        cap_synth_frame(img, RW, RH, RW + 8, k);
        sfm_frame f = {img, RW, RH, RW + 8, SFM_PIX_GRAY8, stamp(k), seqno(k), 0};
        unsigned long before = cap_alloc_calls;
        SFM_CHECK_EQ_INT(sfm_recorder_write(r, &f), SFM_OK);
        if (fmt == SFM_RECORD_PGM) /* PGM frames are written without allocating */
            SFM_CHECK_EQ_INT(cap_alloc_calls - before, 0);
    }
    SFM_CHECK_EQ_INT(sfm_recorder_count(r), RN);
    SFM_CHECK_EQ_INT(sfm_recorder_close(r), SFM_OK);
}

/* Replays dir and compares with the synthetic frames (max_err 0 = exact). */
static void replay_and_compare(sfm_test_ctx *t, const char *dir, int max_err)
{
    sfm_capture *c = NULL;
    SFM_CHECK_EQ_INT(sfm_capture_open_replay(dir, NULL, &c), SFM_OK);
    if (c == NULL)
        return;
    sfm_capture_info info;
    SFM_CHECK_EQ_INT(sfm_capture_get_info(c, &info), SFM_OK);
    SFM_CHECK_EQ_INT(info.width, RW);
    SFM_CHECK_EQ_INT(info.height, RH);
    SFM_CHECK(strcmp(info.driver, "replay") == 0);
    static uint8_t ref[RH * RW];
    int worst = 0;
    for (int k = 0; k < RN; k++) {
        sfm_frame f;
        SFM_CHECK_EQ_INT(sfm_capture_acquire(c, 100, &f), 1);
        SFM_CHECK_EQ_INT(f.width, RW);
        SFM_CHECK_EQ_INT(f.height, RH);
        SFM_CHECK_EQ_INT(f.format, SFM_PIX_GRAY8);
        SFM_CHECK(f.timestamp_ns == stamp(k));
        SFM_CHECK(f.sequence == seqno(k));
        cap_synth_frame(ref, RW, RH, RW, k);
        for (int y = 0; y < RH; y++)
            for (int x = 0; x < RW; x++) {
                int d = abs(f.data[y * f.stride + x] - ref[y * RW + x]);
                if (d > worst)
                    worst = d;
            }
        SFM_CHECK_EQ_INT(sfm_capture_release(c, &f), SFM_OK);
    }
    SFM_CHECK_MSG(worst <= max_err, "worst pixel error %d > %d", worst, max_err);
    sfm_frame f;
    SFM_CHECK_EQ_INT(sfm_capture_acquire(c, 100, &f), 0); /* end of stream */
    sfm_capture_stats st;
    SFM_CHECK_EQ_INT(sfm_capture_get_stats(c, &st), SFM_OK);
    SFM_CHECK_EQ_INT(st.frames, RN);
    SFM_CHECK_EQ_INT(st.drops, 2);
    SFM_CHECK_EQ_INT(st.errors, 0);
    sfm_capture_close(c);
}

/* Records the sequence in a fresh directory in one format, replays it and
 * compares frame by frame (max_err as replay_and_compare takes it), then
 * removes the directory. */
static void round_trip(sfm_test_ctx *t, int format, int max_err)
{
    char dir[512];
    SFM_CHECK(cap_tmpdir(dir, sizeof dir) == 0);
    record(t, dir, format);
    replay_and_compare(t, dir, max_err);
    cap_rmtree(dir);
}

SFM_TEST(replay_round_trip_pgm)
{
    round_trip(t, SFM_RECORD_PGM, 0);
}

SFM_TEST(replay_round_trip_png)
{
    round_trip(t, SFM_RECORD_PNG, 0);
}

SFM_TEST(replay_round_trip_jpeg_lossy)
{
    round_trip(t, SFM_RECORD_JPEG, 40); /* q95 on a checkered texture: close, not exact */
}

SFM_TEST(replay_acquire_release_never_allocates)
{
    char dir[512];
    SFM_CHECK(cap_tmpdir(dir, sizeof dir) == 0);
    record(t, dir, SFM_RECORD_PGM);
    sfm_replay_options o = {SFM_REPLAY_ASAP, 0.0, 0.0, 1};
    sfm_capture *c = NULL;
    SFM_CHECK_EQ_INT(sfm_capture_open_replay(dir, &o, &c), SFM_OK);
    unsigned long before = cap_alloc_calls;
    uint64_t last_seq = 0;
    int64_t last_ts = 0;
    for (int k = 0; k < 3 * RN && c; k++) { /* loops: timestamps keep increasing */
        sfm_frame f;
        SFM_CHECK_EQ_INT(sfm_capture_acquire(c, 0, &f), 1);
        if (k > 0) {
            SFM_CHECK(f.sequence > last_seq);
            SFM_CHECK(f.timestamp_ns > last_ts);
        }
        last_seq = f.sequence;
        last_ts = f.timestamp_ns;
        SFM_CHECK_EQ_INT(sfm_capture_release(c, &f), SFM_OK);
    }
    SFM_CHECK_EQ_INT(cap_alloc_calls - before, 0);
    sfm_capture_close(c);
    cap_rmtree(dir);
}

SFM_TEST(replay_euroc_layout_and_pnm_variants)
{
    char dir[512], sub[600];
    SFM_CHECK(cap_tmpdir(dir, sizeof dir) == 0);
    snprintf(sub, sizeof sub, "%s/data", dir);
    SFM_CHECK(mkdir(sub, 0755) == 0);
    static const char p2[] = "P2\n2 2\n255\n1 2\n3 4\n";
    static const char p5[] = "P5\n2 2\n255\n\x05\x06\x07\x08";
    SFM_CHECK(cap_write_file(sub, "100.pgm", p2, sizeof p2 - 1) == 0);
    SFM_CHECK(cap_write_file(sub, "200.pgm", p5, sizeof p5 - 1) == 0);
    static const char m[] = "#timestamp [ns],filename\n100,100.pgm\n200,200.pgm\n";
    SFM_CHECK(cap_write_file(dir, "data.csv", m, sizeof m - 1) == 0);
    sfm_capture *c = NULL;
    SFM_CHECK_EQ_INT(sfm_capture_open_replay(dir, NULL, &c), SFM_OK);
    sfm_frame f;
    for (int k = 0; k < 2 && c; k++) {
        SFM_CHECK_EQ_INT(sfm_capture_acquire(c, 0, &f), 1);
        SFM_CHECK(f.timestamp_ns == 100 * (k + 1));
        SFM_CHECK_EQ_INT(f.sequence, k);
        SFM_CHECK_EQ_INT(f.data[3], k == 0 ? 4 : 8);
        SFM_CHECK_EQ_INT(sfm_capture_release(c, &f), SFM_OK);
    }
    sfm_capture_close(c);
    cap_rmtree(dir);
}

SFM_TEST(replay_bad_frame_is_an_error_then_continues)
{
    char dir[512];
    SFM_CHECK(cap_tmpdir(dir, sizeof dir) == 0);
    static const char a[] = "P5\n2 2\n255\n\1\2\3\4";
    static const char b[] = "P5\n3 2\n255\n\1\2\3\4\5\6"; /* changes size */
    static const char d[] = "garbage!";
    SFM_CHECK(cap_write_file(dir, "a.pgm", a, sizeof a - 1) == 0);
    SFM_CHECK(cap_write_file(dir, "b.pgm", b, sizeof b - 1) == 0);
    SFM_CHECK(cap_write_file(dir, "d.pgm", d, sizeof d - 1) == 0);
    static const char m[] = "0,1,a.pgm\n1,2,b.pgm\n2,3,d.pgm\n3,4,a.pgm\n";
    SFM_CHECK(cap_write_file(dir, "manifest.csv", m, sizeof m - 1) == 0);
    sfm_capture *c = NULL;
    SFM_CHECK_EQ_INT(sfm_capture_open_replay(dir, NULL, &c), SFM_OK);
    if (c) {
        sfm_frame f;
        SFM_CHECK_EQ_INT(sfm_capture_acquire(c, 0, &f), 1);
        /* one frame held: a second acquire and a wrong release are refused */
        sfm_frame g;
        sfm_test_fill_canary(&g, sizeof g);
        SFM_CHECK_EQ_INT(sfm_capture_acquire(c, 0, &g), SFM_E_ARGUMENT);
        SFM_CHECK(sfm_test_canary_intact(&g, sizeof g));
        sfm_frame wrong = f;
        wrong.sequence++;
        SFM_CHECK_EQ_INT(sfm_capture_release(c, &wrong), SFM_E_ARGUMENT);
        SFM_CHECK_EQ_INT(sfm_capture_release(c, &f), SFM_OK);
        SFM_CHECK_EQ_INT(sfm_capture_release(c, &f), SFM_E_ARGUMENT); /* twice */
        sfm_test_fill_canary(&g, sizeof g);
        SFM_CHECK_EQ_INT(sfm_capture_acquire(c, 0, &g), SFM_E_FORMAT);
        SFM_CHECK(sfm_test_canary_intact(&g, sizeof g));
        SFM_CHECK_EQ_INT(sfm_capture_acquire(c, 0, &g), SFM_E_FORMAT);
        SFM_CHECK_EQ_INT(sfm_capture_acquire(c, 0, &f), 1);
        SFM_CHECK_EQ_INT(f.sequence, 3);
        SFM_CHECK_EQ_INT(sfm_capture_release(c, &f), SFM_OK);
        SFM_CHECK_EQ_INT(sfm_capture_acquire(c, 0, &f), 0);
        sfm_capture_stats st;
        sfm_capture_get_stats(c, &st);
        SFM_CHECK_EQ_INT(st.frames, 2);
        SFM_CHECK_EQ_INT(st.errors, 2);
        SFM_CHECK_EQ_INT(st.drops, 0); /* a frame we failed to read is not a drop */
    }
    sfm_capture_close(c);
    cap_rmtree(dir);
}

SFM_TEST(replay_open_errors)
{
    char dir[512];
    SFM_CHECK(cap_tmpdir(dir, sizeof dir) == 0);
    sfm_capture *c = (sfm_capture *)&c;
    sfm_capture *const sentinel = c;
    SFM_CHECK_EQ_INT(sfm_capture_open_replay(dir, NULL, &c), SFM_E_NO_DEVICE); /* no manifest */
    SFM_CHECK_EQ_INT(sfm_capture_open_replay("/nonexistent/sfm", NULL, &c), SFM_E_NO_DEVICE);
    SFM_CHECK(cap_write_file(dir, "manifest.csv", "# empty\n", 8) == 0);
    SFM_CHECK_EQ_INT(sfm_capture_open_replay(dir, NULL, &c), SFM_E_FORMAT);
    SFM_CHECK(cap_write_file(dir, "manifest.csv", "0,1,missing.pgm\n", 16) == 0);
    SFM_CHECK_EQ_INT(sfm_capture_open_replay(dir, NULL, &c), SFM_E_IO);
    SFM_CHECK(cap_write_file(dir, "manifest.csv", "0,1,../x.pgm\n", 13) == 0);
    SFM_CHECK_EQ_INT(sfm_capture_open_replay(dir, NULL, &c), SFM_E_FORMAT);
    SFM_CHECK(cap_write_file(dir, "x.pgm", "P5\n1 1\n25", 9) == 0);
    SFM_CHECK(cap_write_file(dir, "manifest.csv", "0,1,x.pgm\n", 10) == 0);
    SFM_CHECK_EQ_INT(sfm_capture_open_replay(dir, NULL, &c), SFM_E_FORMAT); /* truncated */
    SFM_CHECK_EQ_INT(sfm_capture_open_replay(NULL, NULL, &c), SFM_E_ARGUMENT);
    SFM_CHECK_EQ_INT(sfm_capture_open_replay(dir, NULL, NULL), SFM_E_ARGUMENT);
    sfm_replay_options bad = {SFM_REPLAY_FIXED, 0.0, 1.0, 0};
    SFM_CHECK_EQ_INT(sfm_capture_open_replay(dir, &bad, &c), SFM_E_ARGUMENT);
    bad.rate = 7;
    SFM_CHECK_EQ_INT(sfm_capture_open_replay(dir, &bad, &c), SFM_E_ARGUMENT);
    SFM_CHECK(c == sentinel); /* never written on failure */
    SFM_CHECK_EQ_INT(sfm_capture_acquire(NULL, 0, NULL), SFM_E_ARGUMENT);
    SFM_CHECK_EQ_INT(sfm_capture_release(NULL, NULL), SFM_E_ARGUMENT);
    SFM_CHECK_EQ_INT(sfm_capture_get_stats(NULL, NULL), SFM_E_ARGUMENT);
    sfm_capture_close(NULL);
    cap_rmtree(dir);
}

SFM_TEST(replay_recorded_rate_waits_for_the_next_frame)
{
    /* Frames ten seconds apart at the recorded rate: the first comes at once,
     * the second is not due within a zero or 1 ms timeout. */
    char dir[512];
    SFM_CHECK(cap_tmpdir(dir, sizeof dir) == 0);
    static const char a[] = "P5\n1 1\n255\n\1";
    SFM_CHECK(cap_write_file(dir, "a.pgm", a, sizeof a - 1) == 0);
    static const char m[] = "0,0,a.pgm\n1,10000000000,a.pgm\n";
    SFM_CHECK(cap_write_file(dir, "manifest.csv", m, sizeof m - 1) == 0);
    sfm_replay_options o = {SFM_REPLAY_RECORDED, 0.0, 1.0, 0};
    sfm_capture *c = NULL;
    SFM_CHECK_EQ_INT(sfm_capture_open_replay(dir, &o, &c), SFM_OK);
    if (c) {
        sfm_frame f;
        SFM_CHECK_EQ_INT(sfm_capture_acquire(c, 0, &f), 1);
        SFM_CHECK_EQ_INT(sfm_capture_release(c, &f), SFM_OK);
        SFM_CHECK_EQ_INT(sfm_capture_acquire(c, 0, &f), SFM_E_TIMEOUT);
        SFM_CHECK_EQ_INT(sfm_capture_acquire(c, 1, &f), SFM_E_TIMEOUT);
    }
    sfm_capture_close(c);
    /* Fixed rate likewise: 0.1 frame per second. */
    o.rate = SFM_REPLAY_FIXED;
    o.fixed_fps = 0.1;
    SFM_CHECK_EQ_INT(sfm_capture_open_replay(dir, &o, &c), SFM_OK);
    if (c) {
        sfm_frame f;
        SFM_CHECK_EQ_INT(sfm_capture_acquire(c, 0, &f), 1);
        SFM_CHECK_EQ_INT(sfm_capture_release(c, &f), SFM_OK);
        SFM_CHECK_EQ_INT(sfm_capture_acquire(c, 0, &f), SFM_E_TIMEOUT);
    }
    sfm_capture_close(c);
    cap_rmtree(dir);
}

SFM_TEST(recorder_contracts)
{
    char dir[512];
    SFM_CHECK(cap_tmpdir(dir, sizeof dir) == 0);
    sfm_recorder *r = NULL;
    SFM_CHECK_EQ_INT(sfm_recorder_open(dir, 9, &r), SFM_E_ARGUMENT);
    SFM_CHECK_EQ_INT(sfm_recorder_open(NULL, SFM_RECORD_PGM, &r), SFM_E_ARGUMENT);
    SFM_CHECK_EQ_INT(sfm_recorder_open(dir, SFM_RECORD_PGM, &r), SFM_OK);
    sfm_recorder *r2 = NULL;
    SFM_CHECK_EQ_INT(sfm_recorder_open(dir, SFM_RECORD_PGM, &r2), SFM_E_ARGUMENT); /* exists */
    uint8_t px[12] = {0};
    sfm_frame f = {px, 2, 2, 2, SFM_PIX_GRAY8, 100, 5, 0};
    SFM_CHECK_EQ_INT(sfm_recorder_write(r, &f), SFM_OK);
    f.timestamp_ns = 99;
    f.sequence = 6;
    SFM_CHECK_EQ_INT(sfm_recorder_write(r, &f), SFM_E_ARGUMENT); /* time going back */
    f.timestamp_ns = 100;
    f.sequence = 5;
    SFM_CHECK_EQ_INT(sfm_recorder_write(r, &f), SFM_E_ARGUMENT); /* same sequence */
    f.sequence = 6;
    f.format = SFM_PIX_YUYV;
    SFM_CHECK_EQ_INT(sfm_recorder_write(r, &f), SFM_E_ARGUMENT);
    f.format = SFM_PIX_RGB24;
    SFM_CHECK_EQ_INT(sfm_recorder_write(r, &f), SFM_E_ARGUMENT); /* stride < 3w */
    f.stride = 6;
    SFM_CHECK_EQ_INT(sfm_recorder_write(r, &f), SFM_E_ARGUMENT); /* not the first's format */
    f.format = SFM_PIX_GRAY8;
    f.width = 3;
    SFM_CHECK_EQ_INT(sfm_recorder_write(r, &f), SFM_E_ARGUMENT); /* not the first's size */
    f.width = 2;
    f.height = 3;
    SFM_CHECK_EQ_INT(sfm_recorder_write(r, &f), SFM_E_ARGUMENT);
    f.height = 2;
    SFM_CHECK_EQ_INT(sfm_recorder_count(r), 1);
    char path[600];
    snprintf(path, sizeof path, "%s/00000001.ppm", dir);
    struct stat st;
    SFM_CHECK(stat(path, &st) != 0); /* nothing written for a refused frame */
    snprintf(path, sizeof path, "%s/00000001.pgm", dir);
    SFM_CHECK(stat(path, &st) != 0);
    SFM_CHECK_EQ_INT(sfm_recorder_write(r, &f), SFM_OK);
    SFM_CHECK_EQ_INT(sfm_recorder_count(r), 2);
    SFM_CHECK_EQ_INT(sfm_recorder_close(r), SFM_OK);
    SFM_CHECK_EQ_INT(sfm_recorder_close(NULL), SFM_OK);
    SFM_CHECK(stat(path, &st) == 0);
    /* the manifest holds the header and the two accepted rows only, and the
     * recording replays */
    char man[256];
    snprintf(path, sizeof path, "%s/manifest.csv", dir);
    long n = cap_read_file(path, man, sizeof man - 1);
    SFM_CHECK(n > 0);
    man[n > 0 ? n : 0] = '\0';
    SFM_CHECK(strcmp(man, "sequence,timestamp_ns,file\n5,100,00000000.pgm\n6,100,00000001.pgm\n") == 0);
    sfm_capture *c = NULL;
    SFM_CHECK_EQ_INT(sfm_capture_open_replay(dir, NULL, &c), SFM_OK);
    sfm_capture_close(c);
    cap_rmtree(dir);
}

/* A frame whose file is a symbolic link to a file outside the recording, or
 * sits under a "data/" that links elsewhere, is refused; links that stay
 * inside, and a recording directory reached through a link, play. */
SFM_TEST(replay_refuses_files_resolving_outside_the_directory)
{
    char rel_dir[512], rel_out[512], dir[PATH_MAX], out[PATH_MAX], p1[PATH_MAX + 64], p2[PATH_MAX + 64];
    SFM_CHECK(cap_tmpdir(rel_dir, sizeof rel_dir) == 0);
    SFM_CHECK(cap_tmpdir(rel_out, sizeof rel_out) == 0);
    /* absolute, so that the links' targets do not depend on where they sit */
    SFM_CHECK(realpath(rel_dir, dir) != NULL);
    SFM_CHECK(realpath(rel_out, out) != NULL);
    static const char a[] = "P5\n1 1\n255\n\1";
    SFM_CHECK(cap_write_file(out, "secret.pgm", a, sizeof a - 1) == 0);
    SFM_CHECK(cap_write_file(dir, "in.pgm", a, sizeof a - 1) == 0);
    snprintf(p1, sizeof p1, "%s/secret.pgm", out);
    snprintf(p2, sizeof p2, "%s/link.pgm", dir);
    SFM_CHECK(symlink(p1, p2) == 0);
    sfm_capture *c = (sfm_capture *)&c;
    sfm_capture *const sentinel = c;
    static const char m1[] = "0,0,in.pgm\n1,1,link.pgm\n";
    SFM_CHECK(cap_write_file(dir, "manifest.csv", m1, sizeof m1 - 1) == 0);
    SFM_CHECK_EQ_INT(sfm_capture_open_replay(dir, NULL, &c), SFM_E_FORMAT);
    SFM_CHECK(c == sentinel);
    /* "data/" itself a link out of the directory */
    snprintf(p2, sizeof p2, "%s/data", dir);
    SFM_CHECK(symlink(out, p2) == 0);
    static const char m2[] = "0,0,secret.pgm\n";
    SFM_CHECK(cap_write_file(dir, "manifest.csv", m2, sizeof m2 - 1) == 0);
    SFM_CHECK_EQ_INT(sfm_capture_open_replay(dir, NULL, &c), SFM_E_FORMAT);
    SFM_CHECK(c == sentinel);
    /* a link inside the directory is fine, and so is reaching it by a link */
    snprintf(p1, sizeof p1, "%s/in.pgm", dir);
    snprintf(p2, sizeof p2, "%s/alias.pgm", dir);
    SFM_CHECK(symlink(p1, p2) == 0);
    static const char m3[] = "0,0,in.pgm\n1,1,alias.pgm\n";
    SFM_CHECK(cap_write_file(dir, "manifest.csv", m3, sizeof m3 - 1) == 0);
    snprintf(p2, sizeof p2, "%s/via", out);
    SFM_CHECK(symlink(dir, p2) == 0);
    c = NULL;
    SFM_CHECK_EQ_INT(sfm_capture_open_replay(p2, NULL, &c), SFM_OK);
    if (c) {
        sfm_frame f;
        for (int k = 0; k < 2; k++) {
            SFM_CHECK_EQ_INT(sfm_capture_acquire(c, 0, &f), 1);
            SFM_CHECK_EQ_INT(sfm_capture_release(c, &f), SFM_OK);
        }
        /* a file swapped for an outside link after open: refused at acquire */
        sfm_capture_close(c);
        c = NULL;
        SFM_CHECK_EQ_INT(sfm_capture_open_replay(dir, NULL, &c), SFM_OK);
        snprintf(p1, sizeof p1, "%s/alias.pgm", dir);
        unlink(p1);
        snprintf(p2, sizeof p2, "%s/secret.pgm", out);
        SFM_CHECK(symlink(p2, p1) == 0);
        SFM_CHECK_EQ_INT(sfm_capture_acquire(c, 0, &f), 1);
        SFM_CHECK_EQ_INT(sfm_capture_release(c, &f), SFM_OK);
        SFM_CHECK_EQ_INT(sfm_capture_acquire(c, 0, &f), SFM_E_FORMAT);
    }
    sfm_capture_close(c);
    snprintf(p2, sizeof p2, "%s/data", dir);
    unlink(p2); /* the links, not what they point to */
    snprintf(p2, sizeof p2, "%s/via", out);
    unlink(p2);
    cap_rmtree(dir);
    cap_rmtree(out);
}
