/* Fuzz target: one pixel-format converter, chosen at build time with
 * -DFUZZ_FORMAT=SFM_PIX_... . Input: width-1, height-1 (one byte each; for
 * MJPEG two bytes each, little-endian), extra stride (one byte, ignored for
 * MJPEG), then the frame bytes as a device would hand them over. The output
 * is checked against the reference formula where there is one, and the
 * bytes around the destination must stay untouched. */
#include <stdlib.h>
#include <string.h>

#include "sfm/sfm_capture.h"

#ifndef FUZZ_FORMAT
#error "FUZZ_FORMAT must name a pixel format"
#endif

int LLVMFuzzerTestOneInput(const uint8_t *data, size_t size);

int LLVMFuzzerTestOneInput(const uint8_t *data, size_t size)
{
    const int fmt = FUZZ_FORMAT;
    int w, h, extra = 0;
    size_t hdr;
    if (fmt == SFM_PIX_MJPEG) {
        if (size < 4)
            return 0;
        w = (data[0] | data[1] << 8) % 1024 + 1;
        h = (data[2] | data[3] << 8) % 1024 + 1;
        hdr = 4;
    } else {
        if (size < 3)
            return 0;
        w = data[0] + 1;
        h = data[1] + 1;
        extra = data[2];
        hdr = 3;
    }
    const uint8_t *src = data + hdr;
    const size_t len = size - hdr;
    int bpp = fmt == SFM_PIX_YUYV ? 2 : fmt == SFM_PIX_RGB24 ? 3 : 1;
    int stride = fmt == SFM_PIX_MJPEG ? 0 : w * bpp + extra;
    const int ds = w + 3;
    const size_t dn = (size_t)ds * (size_t)h;
    uint8_t *dst = malloc(dn + 32);
    if (dst == NULL)
        return 0;
    memset(dst, 0xA5, dn + 32);
    int rc = sfm_convert_to_gray(fmt, src, len, w, h, stride, dst, ds);
    if (rc == SFM_OK) {
        if (fmt != SFM_PIX_MJPEG && len < sfm_pixfmt_min_size(fmt, w, h, stride))
            abort(); /* read past the source */
        for (int y = 0; y < h; y++) {
            for (int x = 0; x < w; x++) {
                const uint8_t *p = src + (size_t)y * (size_t)stride;
                int ref = -1;
                if (fmt == SFM_PIX_GRAY8 || fmt == SFM_PIX_NV12)
                    ref = p[x];
                else if (fmt == SFM_PIX_YUYV)
                    ref = p[2 * x];
                else if (fmt == SFM_PIX_RGB24)
                    ref = (77 * p[3 * x] + 150 * p[3 * x + 1] + 29 * p[3 * x + 2] + 128) >> 8;
                if (ref >= 0 && dst[(size_t)y * (size_t)ds + (size_t)x] != ref)
                    abort();
            }
            for (int x = w; x < ds; x++) /* row padding untouched */
                if (dst[(size_t)y * (size_t)ds + (size_t)x] != 0xA5)
                    abort();
        }
    } else if (rc != SFM_E_FORMAT && rc != SFM_E_ARGUMENT) {
        abort();
    }
    for (size_t i = dn; i < dn + 32; i++)
        if (dst[i] != 0xA5)
            abort();
    free(dst);
    return 0;
}
