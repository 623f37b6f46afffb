/* Pixel-format converters to 8-bit gray. The luma of YUYV and NV12 is the
 * Y sample itself (ITU-R BT.601 studio swing, as the sensor delivered it);
 * RGB uses the BT.601 weights 0.299, 0.587, 0.114 in 8-bit fixed point
 * (77, 150, 29; sum 256), rounded. */
#include <string.h>

#include "capture/capture_impl.h"

void sfm_gray_copy(const uint8_t *src, int src_stride, int w, int h, uint8_t *dst,
                   int dst_stride)
{
    for (int y = 0; y < h; y++)
        memcpy(dst + (size_t)y * (size_t)dst_stride, src + (size_t)y * (size_t)src_stride,
               (size_t)w);
}

void sfm_gray_from_yuyv(const uint8_t *src, int src_stride, int w, int h, uint8_t *dst,
                        int dst_stride)
{
    for (int y = 0; y < h; y++) {
        const uint8_t *s = src + (size_t)y * (size_t)src_stride;
        uint8_t *d = dst + (size_t)y * (size_t)dst_stride;
        for (int x = 0; x < w; x++)
            d[x] = s[2 * x];
    }
}

void sfm_gray_from_rgb24(const uint8_t *src, int src_stride, int w, int h, uint8_t *dst,
                         int dst_stride)
{
    for (int y = 0; y < h; y++) {
        const uint8_t *s = src + (size_t)y * (size_t)src_stride;
        uint8_t *d = dst + (size_t)y * (size_t)dst_stride;
        for (int x = 0; x < w; x++) {
            unsigned v = 77u * s[3 * x] + 150u * s[3 * x + 1] + 29u * s[3 * x + 2] + 128u;
            d[x] = (uint8_t)(v >> 8);
        }
    }
}

static int bytes_per_pixel_row(int format, int w)
{
    switch (format) {
    case SFM_PIX_GRAY8: return w;
    case SFM_PIX_NV12: return w;
    case SFM_PIX_YUYV: return 2 * w;
    case SFM_PIX_RGB24: return 3 * w;
    default: return 0;
    }
}

size_t sfm_pixfmt_min_size(int format, int width, int height, int src_stride)
{
    if (width <= 0 || height <= 0 || width > SFM_CAPTURE_MAX_SIDE ||
        height > SFM_CAPTURE_MAX_SIDE || src_stride < 0 ||
        src_stride > 4 * SFM_CAPTURE_MAX_SIDE)
        return 0;
    int row = bytes_per_pixel_row(format, width);
    if (row == 0)
        return 0;
    if ((format == SFM_PIX_YUYV || format == SFM_PIX_NV12) && (width & 1))
        return 0;
    if (format == SFM_PIX_NV12 && (height & 1))
        return 0;
    size_t stride = src_stride ? (size_t)src_stride : (size_t)row;
    if (stride < (size_t)row)
        return 0;
    size_t n = stride * (size_t)(height - 1) + (size_t)row;
    if (format == SFM_PIX_NV12) /* luma plane, then height/2 rows of UV */
        n = stride * (size_t)height + stride * (size_t)(height / 2 - 1) + (size_t)width;
    return n;
}

int sfm_convert_to_gray(int format, const uint8_t *src, size_t src_len, int width,
                        int height, int src_stride, uint8_t *dst, int dst_stride)
{
    if (src == NULL || dst == NULL || width <= 0 || height <= 0 || dst_stride < width ||
        width > SFM_CAPTURE_MAX_SIDE || height > SFM_CAPTURE_MAX_SIDE || src_stride < 0)
        return SFM_E_ARGUMENT;
    if (format == SFM_PIX_MJPEG) {
        sfm_jpeg_decoder *d = sfm_jpeg_decoder_new();
        if (d == NULL)
            return SFM_E_UNSUPPORTED;
        int rc = sfm_jpeg_decode_gray(d, src, src_len, width, height, dst, dst_stride);
        sfm_jpeg_decoder_free(d);
        return rc;
    }
    int row = bytes_per_pixel_row(format, width);
    if (row == 0)
        return SFM_E_ARGUMENT;
    int stride = src_stride ? src_stride : row;
    size_t need = sfm_pixfmt_min_size(format, width, height, stride);
    if (need == 0)
        return SFM_E_ARGUMENT;
    if (src_len < need)
        return SFM_E_FORMAT;
    switch (format) {
    case SFM_PIX_GRAY8:
    case SFM_PIX_NV12:
        sfm_gray_copy(src, stride, width, height, dst, dst_stride);
        break;
    case SFM_PIX_YUYV:
        sfm_gray_from_yuyv(src, stride, width, height, dst, dst_stride);
        break;
    default:
        sfm_gray_from_rgb24(src, stride, width, height, dst, dst_stride);
        break;
    }
    return SFM_OK;
}
