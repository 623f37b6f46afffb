/* Internal: the frame-source object behind sfm_capture and the helpers the
 * sources share. Not part of the public API. */
#ifndef SFM_CAPTURE_IMPL_H
#define SFM_CAPTURE_IMPL_H

#include <stddef.h>
#include <stdint.h>

#include "sfm/sfm_capture.h"

/* What each kind of source implements. acquire() is called only when no
 * frame is held and the source is not lost; release() only with the frame
 * that is held. */
typedef struct sfm_capture_vtbl {
    int (*acquire)(sfm_capture *c, int timeout_ms, sfm_frame *frame);
    int (*release)(sfm_capture *c, const sfm_frame *frame);
    void (*destroy)(sfm_capture *c); /* releases everything, frees impl */
} sfm_capture_vtbl;

struct sfm_capture {
    const sfm_capture_vtbl *vt;
    void *impl;
    sfm_capture_stats stats;
    sfm_capture_info info;
    int held;       /* a frame is out */
    int held_slot;  /* its slot */
    uint64_t held_sequence;
    int lost;       /* the device went away: acquire reports it again */
};

/* Allocates a source with its vtable and implementation (owned). */
sfm_capture *sfm_capture_new(const sfm_capture_vtbl *vt, void *impl);

/* Monotonic clock in nanoseconds. */
int64_t sfm_capture_now_ns(void);
/* Sleeps for ns nanoseconds (restarting after signals). */
void sfm_capture_sleep_ns(int64_t ns);

/* Copies src to dst info strings, truncating, always NUL-terminated. */
void sfm_capture_strlcpy(char *dst, size_t cap, const char *src);

/* --- Converters (convert.c) --- */
void sfm_gray_from_yuyv(const uint8_t *src, int src_stride, int w, int h, uint8_t *dst,
                        int dst_stride);
void sfm_gray_from_rgb24(const uint8_t *src, int src_stride, int w, int h, uint8_t *dst,
                         int dst_stride);
void sfm_gray_copy(const uint8_t *src, int src_stride, int w, int h, uint8_t *dst,
                   int dst_stride);

/* --- JPEG (jpeg_io.c). A decoder made once and reused for every frame. --- */
typedef struct sfm_jpeg_decoder sfm_jpeg_decoder;
sfm_jpeg_decoder *sfm_jpeg_decoder_new(void);
void sfm_jpeg_decoder_free(sfm_jpeg_decoder *d);
/* Reads the size without decoding. SFM_OK, SFM_E_FORMAT, SFM_E_UNSUPPORTED. */
int sfm_jpeg_size(sfm_jpeg_decoder *d, const uint8_t *src, size_t len, int *w, int *h);
/* Decodes to gray; the image must be exactly w x h. SFM_OK, SFM_E_FORMAT,
 * SFM_E_UNSUPPORTED. */
int sfm_jpeg_decode_gray(sfm_jpeg_decoder *d, const uint8_t *src, size_t len, int w, int h,
                         uint8_t *dst, int dst_stride);
/* Writes a gray (channels 1) or RGB (3) image to path. SFM_OK, SFM_E_IO,
 * SFM_E_UNSUPPORTED. */
int sfm_jpeg_write(const char *path, const uint8_t *src, int w, int h, int stride,
                   int channels, int quality);

/* --- PNG (png_io.c) --- */
int sfm_png_size(const uint8_t *src, size_t len, int *w, int *h);
int sfm_png_decode_gray(const uint8_t *src, size_t len, int w, int h, uint8_t *dst,
                        int dst_stride);
int sfm_png_write(const char *path, const uint8_t *src, int w, int h, int stride,
                  int channels);

/* --- Whole files --- */
/* Writes a binary PGM (channels 1) or PPM (3), 8-bit, without allocating. */
int sfm_pnm_write(const char *path, const uint8_t *src, int w, int h, int stride,
                  int channels);

#endif
