/* The command-line tools: --help, clear errors with exit status 2 for bad
 * usage, and a recording copied by sfm-record from a replay source that
 * sfm-replay then reads back. Needs $SFM_TEST_BIN (make test-capture sets
 * it); prints SKIP otherwise. */
#define _DEFAULT_SOURCE
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/wait.h>

#include "cap_test.h"
#include "sfm_test.h"

static int run(const char *cmd)
{
    int st = system(cmd);
    return WIFEXITED(st) ? WEXITSTATUS(st) : -1;
}

SFM_TEST(tools_record_and_replay)
{
    const char *bin = getenv("SFM_TEST_BIN");
    if (bin == NULL) {
        (void)t;
        printf("SKIP: SFM_TEST_BIN not set\n");
        return;
    }
    char src[512], dst[600], cmd[2048], out[700];
    SFM_CHECK(cap_tmpdir(src, sizeof src) == 0);
    static uint8_t img[20 * 16];
    sfm_recorder *r = NULL;
    SFM_CHECK_EQ_INT(sfm_recorder_open(src, SFM_RECORD_PGM, &r), SFM_OK);
    for (int k = 0; k < 5 && r; k++) {
        cap_synth_frame(img, 20, 16, 20, k);
        sfm_frame f = {img, 20, 16, 20, SFM_PIX_GRAY8, 1000 + 40000000LL * k, (uint64_t)k, 0};
        SFM_CHECK_EQ_INT(sfm_recorder_write(r, &f), SFM_OK);
    }
    sfm_recorder_close(r);
    snprintf(dst, sizeof dst, "%s/copy", src);
    snprintf(out, sizeof out, "%s/out.txt", src);

    snprintf(cmd, sizeof cmd, "%s/sfm-record --help > /dev/null", bin);
    SFM_CHECK_EQ_INT(run(cmd), 0);
    snprintf(cmd, sizeof cmd, "%s/sfm-replay --help > /dev/null", bin);
    SFM_CHECK_EQ_INT(run(cmd), 0);
    snprintf(cmd, sizeof cmd, "%s/sfm-record --bogus 2> /dev/null", bin);
    SFM_CHECK_EQ_INT(run(cmd), 2);
    snprintf(cmd, sizeof cmd, "%s/sfm-record --replay %s 2> /dev/null", bin, src); /* no --out */
    SFM_CHECK_EQ_INT(run(cmd), 2);
    snprintf(cmd, sizeof cmd, "%s/sfm-replay %s/none 2> %s", bin, src, out);
    SFM_CHECK_EQ_INT(run(cmd), 1);
    char text[512] = {0};
    SFM_CHECK(cap_read_file(out, text, sizeof text - 1) > 0);
    SFM_CHECK_MSG(strstr(text, "cannot open") != NULL, "stderr: %s", text);

    snprintf(cmd, sizeof cmd, "%s/sfm-record --replay %s --out %s --image png --quiet 2> /dev/null",
             bin, src, dst);
    SFM_CHECK_EQ_INT(run(cmd), 0);
    snprintf(cmd, sizeof cmd, "%s/sfm-replay %s --list > %s", bin, dst, out);
    SFM_CHECK_EQ_INT(run(cmd), 0);
    memset(text, 0, sizeof text);
    SFM_CHECK(cap_read_file(out, text, sizeof text - 1) > 0);
    /* five "sequence timestamp mean" lines then the summary */
    unsigned long long seq;
    long long ts;
    double mean;
    const char *p = text;
    for (int k = 0; k < 5; k++) {
        SFM_CHECK(sscanf(p, "%llu %lld %lf", &seq, &ts, &mean) == 3);
        SFM_CHECK_EQ_INT(seq, k);
        SFM_CHECK(ts == 1000 + 40000000LL * k);
        p = strchr(p, '\n');
        if (p == NULL)
            break;
        p++;
    }
    SFM_CHECK_MSG(p && strstr(p, "5 frames 20x16, 0 drops, 0 errors") != NULL, "summary: %s", p ? p : "");
    /* Recording into a directory that already holds a manifest is refused. */
    snprintf(cmd, sizeof cmd, "%s/sfm-record --replay %s --out %s --quiet 2> /dev/null", bin, src, dst);
    SFM_CHECK_EQ_INT(run(cmd), 1);
    cap_rmtree(src);
}
