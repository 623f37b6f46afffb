/* JPEG through libjpeg(-turbo): a decompressor made once per source and
 * reused for every frame (Motion-JPEG frames from UVC cameras often omit the
 * Huffman tables; libjpeg-turbo supplies the standard ones of ITU T.81 K.3).
 * Errors longjmp back here; the library's messages are never printed. A
 * frame that decodes only with warnings (truncated data) is refused. */
#include <stdlib.h>

#include "capture/capture_impl.h"

#ifdef SFM_HAVE_LIBJPEG
#include <setjmp.h>
#include <stdio.h>

#include <jpeglib.h>

typedef struct jerr {
    struct jpeg_error_mgr pub;
    jmp_buf jb;
} jerr;

struct sfm_jpeg_decoder {
    struct jpeg_decompress_struct cinfo;
    jerr err;
};

static void on_error(j_common_ptr ci)
{
    jerr *e = (jerr *)ci->err;
    longjmp(e->jb, 1);
}

static void on_message(j_common_ptr ci) { (void)ci; }

sfm_jpeg_decoder *sfm_jpeg_decoder_new(void)
{
    sfm_jpeg_decoder *volatile d = calloc(1, sizeof *d);
    if (d == NULL)
        return NULL;
    d->cinfo.err = jpeg_std_error(&d->err.pub);
    d->err.pub.error_exit = on_error;
    d->err.pub.output_message = on_message;
    if (setjmp(d->err.jb)) {
        free(d);
        return NULL;
    }
    jpeg_create_decompress(&d->cinfo);
    return d;
}

void sfm_jpeg_decoder_free(sfm_jpeg_decoder *d)
{
    if (d == NULL)
        return;
    jpeg_destroy_decompress(&d->cinfo);
    free(d);
}

int sfm_jpeg_size(sfm_jpeg_decoder *d, const uint8_t *src, size_t len, int *w, int *h)
{
    if (d == NULL || src == NULL || len == 0 || len > 0x7fffffff)
        return SFM_E_FORMAT;
    if (setjmp(d->err.jb)) {
        jpeg_abort_decompress(&d->cinfo);
        return SFM_E_FORMAT;
    }
    jpeg_mem_src(&d->cinfo, src, (unsigned long)len);
    if (jpeg_read_header(&d->cinfo, TRUE) != JPEG_HEADER_OK) {
        jpeg_abort_decompress(&d->cinfo);
        return SFM_E_FORMAT;
    }
    *w = (int)d->cinfo.image_width;
    *h = (int)d->cinfo.image_height;
    jpeg_abort_decompress(&d->cinfo);
    return SFM_OK;
}

int sfm_jpeg_decode_gray(sfm_jpeg_decoder *d, const uint8_t *src, size_t len, int w, int h,
                         uint8_t *dst, int dst_stride)
{
    if (d == NULL || src == NULL || len == 0 || len > 0x7fffffff)
        return SFM_E_FORMAT;
    if (setjmp(d->err.jb)) {
        jpeg_abort_decompress(&d->cinfo);
        return SFM_E_FORMAT;
    }
    d->err.pub.num_warnings = 0;
    jpeg_mem_src(&d->cinfo, src, (unsigned long)len);
    if (jpeg_read_header(&d->cinfo, TRUE) != JPEG_HEADER_OK ||
        d->cinfo.image_width != (JDIMENSION)w || d->cinfo.image_height != (JDIMENSION)h) {
        jpeg_abort_decompress(&d->cinfo);
        return SFM_E_FORMAT;
    }
    d->cinfo.out_color_space = JCS_GRAYSCALE;
    d->cinfo.dct_method = JDCT_ISLOW; /* exact, the same on every machine */
    jpeg_start_decompress(&d->cinfo);
    if (d->cinfo.output_components != 1) {
        jpeg_abort_decompress(&d->cinfo);
        return SFM_E_FORMAT;
    }
    while (d->cinfo.output_scanline < d->cinfo.output_height) {
        JSAMPROW row = dst + (size_t)d->cinfo.output_scanline * (size_t)dst_stride;
        jpeg_read_scanlines(&d->cinfo, &row, 1);
    }
    jpeg_finish_decompress(&d->cinfo);
    return d->err.pub.num_warnings ? SFM_E_FORMAT : SFM_OK;
}

int sfm_jpeg_write(const char *path, const uint8_t *src, int w, int h, int stride,
                   int channels, int quality)
{
    struct jpeg_compress_struct ci;
    jerr err;
    FILE *volatile f = NULL;
    ci.err = jpeg_std_error(&err.pub);
    err.pub.error_exit = on_error;
    err.pub.output_message = on_message;
    if (setjmp(err.jb)) {
        jpeg_destroy_compress(&ci);
        if (f)
            fclose(f);
        return SFM_E_IO;
    }
    jpeg_create_compress(&ci);
    f = fopen(path, "wb");
    if (f == NULL) {
        jpeg_destroy_compress(&ci);
        return SFM_E_IO;
    }
    jpeg_stdio_dest(&ci, f);
    ci.image_width = (JDIMENSION)w;
    ci.image_height = (JDIMENSION)h;
    ci.input_components = channels;
    ci.in_color_space = channels == 3 ? JCS_RGB : JCS_GRAYSCALE;
    jpeg_set_defaults(&ci);
    jpeg_set_quality(&ci, quality, TRUE);
    jpeg_start_compress(&ci, TRUE);
    while (ci.next_scanline < ci.image_height) {
        JSAMPROW row = (JSAMPROW)(src + (size_t)ci.next_scanline * (size_t)stride);
        jpeg_write_scanlines(&ci, &row, 1);
    }
    jpeg_finish_compress(&ci);
    jpeg_destroy_compress(&ci);
    int bad = ferror(f);
    if (fclose(f) != 0)
        bad = 1;
    return bad ? SFM_E_IO : SFM_OK;
}

#else /* no libjpeg in this build */

sfm_jpeg_decoder *sfm_jpeg_decoder_new(void) { return NULL; }
void sfm_jpeg_decoder_free(sfm_jpeg_decoder *d) { (void)d; }
int sfm_jpeg_size(sfm_jpeg_decoder *d, const uint8_t *src, size_t len, int *w, int *h)
{
    (void)d; (void)src; (void)len; (void)w; (void)h;
    return SFM_E_UNSUPPORTED;
}
int sfm_jpeg_decode_gray(sfm_jpeg_decoder *d, const uint8_t *src, size_t len, int w, int h,
                         uint8_t *dst, int dst_stride)
{
    (void)d; (void)src; (void)len; (void)w; (void)h; (void)dst; (void)dst_stride;
    return SFM_E_UNSUPPORTED;
}
int sfm_jpeg_write(const char *path, const uint8_t *src, int w, int h, int stride,
                   int channels, int quality)
{
    (void)path; (void)src; (void)w; (void)h; (void)stride; (void)channels; (void)quality;
    return SFM_E_UNSUPPORTED;
}
#endif
