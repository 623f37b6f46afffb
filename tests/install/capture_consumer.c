/* A program built against an installed libsfm_capture: records a 4x3 frame
 * into the directory given, replays it, and checks every pixel and the
 * timestamp came back. */
#include <stdio.h>
#include <string.h>

#include <sfm/sfm_capture.h>

int main(int argc, char **argv)
{
    if (argc != 2)
        return 2;
    uint8_t px[12];
    for (int i = 0; i < 12; i++)
        px[i] = (uint8_t)(20 * i + 7);
    const sfm_frame f = {.data = px, .width = 4, .height = 3, .stride = 4,
                         .format = SFM_PIX_GRAY8, .timestamp_ns = 123456789};
    sfm_recorder *r = NULL;
    int st = sfm_recorder_open(argv[1], SFM_RECORD_PGM, &r);
    if (st == SFM_OK)
        st = sfm_recorder_write(r, &f);
    if (sfm_recorder_close(r) != SFM_OK || st != SFM_OK) {
        printf("record: %s\n", sfm_status_str(st));
        return 1;
    }
    sfm_capture *c = NULL;
    st = sfm_capture_open_replay(argv[1], NULL, &c);
    if (st != SFM_OK) {
        printf("replay: %s\n", sfm_status_str(st));
        return 1;
    }
    sfm_frame g;
    int ok = sfm_capture_acquire(c, 0, &g) == 1 && g.width == 4 && g.height == 3 &&
             g.timestamp_ns == 123456789;
    for (int y = 0; ok && y < 3; y++)
        ok = memcmp(g.data + (size_t)y * (size_t)g.stride, px + 4 * y, 4) == 0;
    if (ok)
        sfm_capture_release(c, &g);
    sfm_capture_close(c);
    printf("capture consumer: %s, frame %s\n", sfm_pixfmt_name(SFM_PIX_GRAY8), ok ? "round-tripped" : "DIFFERS");
    return ok ? 0 : 1;
}
