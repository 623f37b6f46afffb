/* libcamera here: the adapter is built and linked (this runner would not
 * link otherwise), the camera manager starts, enumeration finds no camera
 * (none exists on this machine), and opening one is SFM_E_NO_DEVICE, not a
 * crash or a hang. Streaming is only exercised on a board (see README). */
#include <stdio.h>
#include <string.h>

#include "cap_test.h"
#include "sfm_test.h"

SFM_TEST(libcamera_enumerates_and_reports_no_device)
{
#ifndef SFM_HAVE_LIBCAMERA
    sfm_capture *c = NULL;
    SFM_CHECK_EQ_INT(sfm_libcamera_list(NULL, 0, 0), SFM_E_UNSUPPORTED);
    SFM_CHECK_EQ_INT(sfm_capture_open_libcamera(NULL, NULL, &c), SFM_E_UNSUPPORTED);
    printf("SKIP: built without libcamera\n");
#else
    char ids[4][64];
    memset(ids, 0, sizeof ids);
    int n = sfm_libcamera_list(&ids[0][0], 4, 64);
    SFM_TEST_LOG("libcamera reports %d camera(s)", n);
    if (n > 0) {
        printf("SKIP: a camera is attached (%s); the no-camera checks do not apply\n", ids[0]);
        return;
    }
    SFM_CHECK_EQ_INT(n, 0);
    SFM_CHECK_EQ_INT(sfm_libcamera_list(NULL, 0, 0), 0);
    sfm_capture *c = NULL;
    SFM_CHECK_EQ_INT(sfm_capture_open_libcamera(NULL, NULL, &c), SFM_E_NO_DEVICE);
    SFM_CHECK_EQ_INT(sfm_capture_open_libcamera("/base/soc/i2c0mux/i2c@1/imx219@10", NULL, &c),
                     SFM_E_NO_DEVICE);
    SFM_CHECK(c == NULL);
    /* twice in a row: the shared camera manager stops and starts again */
    SFM_CHECK_EQ_INT(sfm_capture_open_libcamera(NULL, NULL, &c), SFM_E_NO_DEVICE);
    sfm_libcamera_options bad = {-1, 0, 0};
    SFM_CHECK_EQ_INT(sfm_capture_open_libcamera(NULL, &bad, &c), SFM_E_ARGUMENT);
    SFM_CHECK_EQ_INT(sfm_capture_open_libcamera(NULL, NULL, NULL), SFM_E_ARGUMENT);
    SFM_CHECK_EQ_INT(sfm_libcamera_list(NULL, 3, 0), SFM_E_ARGUMENT);
#endif
}
