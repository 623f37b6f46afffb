/* Fuzz target: the PGM/PPM parser and decoder. Any input must either be
 * refused with a status or decode within the image the header announced. */
#include <stdlib.h>
#include <string.h>

#include "sfm/sfm_capture.h"

int LLVMFuzzerTestOneInput(const uint8_t *data, size_t size);

int LLVMFuzzerTestOneInput(const uint8_t *data, size_t size)
{
    sfm_image_header h;
    int rc = sfm_pnm_parse_header(data, size, &h);
    if (rc != SFM_OK)
        return 0;
    if (h.width <= 0 || h.height <= 0 || h.width > SFM_CAPTURE_MAX_SIDE ||
        h.height > SFM_CAPTURE_MAX_SIDE || h.data_offset > size ||
        (h.channels != 1 && h.channels != 3) || h.maxval < 1 || h.maxval > 65535)
        abort();
    /* ASCII headers may announce more than the input holds: stay in memory. */
    if ((size_t)h.width * (size_t)h.height > (size_t)1 << 22)
        return 0;
    size_t n = (size_t)h.width * (size_t)h.height;
    uint8_t *dst = malloc(n + 1);
    if (dst == NULL)
        return 0;
    dst[n] = 0x5A; /* a byte past the image that must survive */
    rc = sfm_pnm_decode_gray(data, size, dst, h.width, h.height, h.width);
    if (rc != SFM_OK && rc != SFM_E_FORMAT)
        abort();
    if (dst[n] != 0x5A)
        abort();
    free(dst);
    return 0;
}
