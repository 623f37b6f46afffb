/* PNG through libpng's simplified API (libpng >= 1.6): it reports errors in
 * the image structure instead of printing. Gray PNGs come back unchanged;
 * colour PNGs are reduced to gray by libpng (its sRGB-aware luminance). */
#include <string.h>

#include "capture/capture_impl.h"

#ifdef SFM_HAVE_LIBPNG
#include <png.h>

int sfm_png_size(const uint8_t *src, size_t len, int *w, int *h)
{
    png_image im;
    memset(&im, 0, sizeof im);
    im.version = PNG_IMAGE_VERSION;
    if (!png_image_begin_read_from_memory(&im, src, len))
        return SFM_E_FORMAT;
    *w = (int)im.width;
    *h = (int)im.height;
    png_image_free(&im);
    return SFM_OK;
}

int sfm_png_decode_gray(const uint8_t *src, size_t len, int w, int h, uint8_t *dst,
                        int dst_stride)
{
    png_image im;
    memset(&im, 0, sizeof im);
    im.version = PNG_IMAGE_VERSION;
    if (!png_image_begin_read_from_memory(&im, src, len))
        return SFM_E_FORMAT;
    if (im.width != (png_uint_32)w || im.height != (png_uint_32)h) {
        png_image_free(&im);
        return SFM_E_FORMAT;
    }
    im.format = PNG_FORMAT_GRAY;
    if (!png_image_finish_read(&im, NULL, dst, dst_stride, NULL)) {
        png_image_free(&im);
        return SFM_E_FORMAT;
    }
    return SFM_OK;
}

int sfm_png_write(const char *path, const uint8_t *src, int w, int h, int stride,
                  int channels)
{
    png_image im;
    memset(&im, 0, sizeof im);
    im.version = PNG_IMAGE_VERSION;
    im.width = (png_uint_32)w;
    im.height = (png_uint_32)h;
    im.format = channels == 3 ? PNG_FORMAT_RGB : PNG_FORMAT_GRAY;
    if (!png_image_write_to_file(&im, path, 0, src, stride, NULL))
        return SFM_E_IO;
    return SFM_OK;
}

#else /* no libpng in this build */

int sfm_png_size(const uint8_t *src, size_t len, int *w, int *h)
{
    (void)src; (void)len; (void)w; (void)h;
    return SFM_E_UNSUPPORTED;
}
int sfm_png_decode_gray(const uint8_t *src, size_t len, int w, int h, uint8_t *dst,
                        int dst_stride)
{
    (void)src; (void)len; (void)w; (void)h; (void)dst; (void)dst_stride;
    return SFM_E_UNSUPPORTED;
}
int sfm_png_write(const char *path, const uint8_t *src, int w, int h, int stride,
                  int channels)
{
    (void)path; (void)src; (void)w; (void)h; (void)stride; (void)channels;
    return SFM_E_UNSUPPORTED;
}
#endif
