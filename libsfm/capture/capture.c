/* The frame-source interface shared by every source: argument checks, the
 * one-frame-held rule, statistics and closing. */
#define _POSIX_C_SOURCE 200809L
#include <errno.h>
#include <stdlib.h>
#include <string.h>
#include <time.h>

#include "capture/capture_impl.h"

sfm_capture *sfm_capture_new(const sfm_capture_vtbl *vt, void *impl)
{
    sfm_capture *c = calloc(1, sizeof *c);
    if (c == NULL)
        return NULL;
    c->vt = vt;
    c->impl = impl;
    c->held_slot = -1;
    return c;
}

int64_t sfm_capture_now_ns(void)
{
    struct timespec ts;
    clock_gettime(CLOCK_MONOTONIC, &ts);
    return (int64_t)ts.tv_sec * 1000000000 + ts.tv_nsec;
}

void sfm_capture_sleep_ns(int64_t ns)
{
    if (ns <= 0)
        return;
    struct timespec req = {(time_t)(ns / 1000000000), (long)(ns % 1000000000)}, rem;
    while (nanosleep(&req, &rem) != 0 && errno == EINTR)
        req = rem;
}

void sfm_capture_strlcpy(char *dst, size_t cap, const char *src)
{
    if (cap == 0)
        return;
    size_t n = src ? strlen(src) : 0;
    if (n >= cap)
        n = cap - 1;
    if (n)
        memcpy(dst, src, n);
    dst[n] = '\0';
}

int sfm_capture_acquire(sfm_capture *c, int timeout_ms, sfm_frame *frame)
{
    if (c == NULL || frame == NULL || c->held)
        return SFM_E_ARGUMENT;
    if (c->lost)
        return SFM_E_DEVICE_LOST;
    sfm_frame f;
    memset(&f, 0, sizeof f);
    int rc = c->vt->acquire(c, timeout_ms, &f);
    if (rc == SFM_E_DEVICE_LOST)
        c->lost = 1;
    if (rc != 1)
        return rc;
    c->held = 1;
    c->held_slot = f.slot;
    c->held_sequence = f.sequence;
    c->stats.frames++;
    *frame = f;
    return 1;
}

int sfm_capture_release(sfm_capture *c, const sfm_frame *frame)
{
    if (c == NULL || frame == NULL || !c->held || frame->slot != c->held_slot ||
        frame->sequence != c->held_sequence)
        return SFM_E_ARGUMENT;
    c->held = 0;
    c->held_slot = -1;
    if (c->lost)
        return SFM_E_DEVICE_LOST;
    int rc = c->vt->release(c, frame);
    if (rc == SFM_E_DEVICE_LOST)
        c->lost = 1;
    return rc;
}

void sfm_capture_close(sfm_capture *c)
{
    if (c == NULL)
        return;
    c->vt->destroy(c);
    free(c);
}

int sfm_capture_get_stats(const sfm_capture *c, sfm_capture_stats *out)
{
    if (c == NULL || out == NULL)
        return SFM_E_ARGUMENT;
    *out = c->stats;
    return SFM_OK;
}

int sfm_capture_get_info(const sfm_capture *c, sfm_capture_info *out)
{
    if (c == NULL || out == NULL)
        return SFM_E_ARGUMENT;
    *out = c->info;
    return SFM_OK;
}

const char *sfm_pixfmt_name(int format)
{
    switch (format) {
    case SFM_PIX_GRAY8: return "GRAY8";
    case SFM_PIX_YUYV: return "YUYV";
    case SFM_PIX_NV12: return "NV12";
    case SFM_PIX_MJPEG: return "MJPEG";
    case SFM_PIX_RGB24: return "RGB24";
    default: return "?";
    }
}
