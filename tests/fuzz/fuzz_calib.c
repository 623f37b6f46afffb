/* Fuzz target: the calibration-file reader of the C programs
 * (firmware_examples/linux/calib_file.c). Any input gives SFM_OK with a
 * camera sfm_camera_validate accepts, or one of the statuses the header
 * lists with a message naming the file; nothing is written on failure. */
#define _POSIX_C_SOURCE 200809L
#include <stdlib.h>
#include <string.h>

#include "calib_file.h"

int LLVMFuzzerTestOneInput(const uint8_t *data, size_t size);

int LLVMFuzzerTestOneInput(const uint8_t *data, size_t size)
{
    static const char *const cams[] = {NULL, "cam1", "P2", "00"};
    for (int k = 0; k < 4; k++) {
        sfm_camera cam;
        memset(&cam, 0xA5, sizeof cam);
        const sfm_camera before = cam;
        int w = -7, h = -7;
        char err[256];
        int st = calib_text_read("fuzz.yaml", (const char *)data, size, cams[k], &cam, &w, &h, err, sizeof err);
        if (st == SFM_OK) {
            if (sfm_camera_validate(&cam) != SFM_OK || w < 0 || h < 0 || (w == 0) != (h == 0))
                abort();
        } else {
            if (st != SFM_E_FORMAT && st != SFM_E_UNSUPPORTED && st != SFM_E_CAPACITY)
                abort();
            if (memcmp(&cam, &before, sizeof cam) != 0 || w != -7 || h != -7)
                abort();
            if (strncmp(err, "fuzz.yaml", 9) != 0)
                abort();
        }
    }
    return 0;
}
