/* V4L2 capture, single-planar mmap streaming, after the V4L2 API
 * specification's capture example: non-blocking open, VIDIOC_QUERYCAP,
 * VIDIOC_S_FMT (the driver may adjust size, stride and even the pixel
 * format: what it grants is reported), VIDIOC_REQBUFS (fewer than two
 * buffers is refused: one buffer cannot stream without dropping), mmap and
 * VIDIOC_QBUF of every buffer, VIDIOC_STREAMON; then poll with a timeout and
 * VIDIOC_DQBUF. EINTR is retried, EAGAIN means no frame yet, buffers with
 * V4L2_BUF_FLAG_ERROR are requeued and counted, gaps in the driver's
 * sequence numbers are counted as drops, and ENODEV (the device was
 * unplugged) releases every kernel resource at once and is reported as
 * SFM_E_DEVICE_LOST. Every path out of open undoes what it did.
 *
 * GREY and NV12 frames are handed out in place (the luma plane of the mapped
 * buffer, requeued by release); YUYV and MJPEG are converted into the
 * source's gray buffer and the driver buffer is requeued at once. */
#define _POSIX_C_SOURCE 200809L
#include <errno.h>
#include <fcntl.h>
#include <stdlib.h>
#include <string.h>
#include <sys/ioctl.h>
#include <sys/mman.h>
#include <unistd.h>

#include <linux/videodev2.h>

#include "capture/capture_impl.h"
#include "capture/v4l2_sys.h"

typedef struct vbuf {
    void *start;
    size_t length;
} vbuf;

typedef struct v4l2src {
    sfm_v4l2_sys sys;
    int fd;
    int nbuf;      /* buffers granted by REQBUFS (0: none requested) */
    int nmapped;   /* buffers mapped */
    int streaming;
    vbuf buf[SFM_V4L2_MAX_BUFFERS];
    int format;    /* sfm_pixfmt */
    uint32_t fourcc;
    int w, h, bpl;
    uint8_t *gray;
    sfm_jpeg_decoder *jpeg;
    int held_index; /* buffer handed out in place, -1 none */
    int have_seq;
    uint32_t last_seq;
} v4l2src;

static int xioctl(v4l2src *s, unsigned long req, void *arg)
{
    for (int i = 0; i < SFM_V4L2_EINTR_LIMIT; i++) {
        int r = s->sys.ioctl(s->sys.ctx, s->fd, req, arg);
        if (r != -1 || errno != EINTR)
            return r;
    }
    return -1; /* errno is EINTR */
}

static int is_gone(int e) { return e == ENODEV || e == ENXIO; }

/* STREAMOFF, munmap, free the driver's buffers, close: whatever was done. */
static void teardown(v4l2src *s, int device_gone)
{
    if (s->fd < 0)
        return;
    enum v4l2_buf_type type = V4L2_BUF_TYPE_VIDEO_CAPTURE;
    if (s->streaming)
        (void)xioctl(s, VIDIOC_STREAMOFF, &type);
    s->streaming = 0;
    for (int i = 0; i < s->nmapped; i++)
        s->sys.munmap(s->sys.ctx, s->buf[i].start, s->buf[i].length);
    s->nmapped = 0;
    if (s->nbuf > 0 && !device_gone) {
        struct v4l2_requestbuffers rb;
        memset(&rb, 0, sizeof rb);
        rb.count = 0;
        rb.type = V4L2_BUF_TYPE_VIDEO_CAPTURE;
        rb.memory = V4L2_MEMORY_MMAP;
        (void)xioctl(s, VIDIOC_REQBUFS, &rb);
    }
    s->nbuf = 0;
    s->sys.close(s->sys.ctx, s->fd);
    s->fd = -1;
    s->held_index = -1;
}

static void v4l2_free(v4l2src *s)
{
    if (s == NULL)
        return;
    teardown(s, 0);
    free(s->gray);
    sfm_jpeg_decoder_free(s->jpeg);
    free(s);
}

/* Status for an errno from a call on an open device. */
static int status_of(int e) { return is_gone(e) ? SFM_E_DEVICE_LOST : SFM_E_IO; }

static int queue(v4l2src *s, int index)
{
    struct v4l2_buffer b;
    memset(&b, 0, sizeof b);
    b.type = V4L2_BUF_TYPE_VIDEO_CAPTURE;
    b.memory = V4L2_MEMORY_MMAP;
    b.index = (uint32_t)index;
    return xioctl(s, VIDIOC_QBUF, &b) == 0 ? SFM_OK : status_of(errno);
}

static int lost(v4l2src *s)
{
    teardown(s, 1);
    return SFM_E_DEVICE_LOST;
}

static int v4l2_acquire(sfm_capture *c, int timeout_ms, sfm_frame *frame)
{
    v4l2src *s = c->impl;
    if (s->fd < 0)
        return SFM_E_DEVICE_LOST;
    const int64_t deadline =
        timeout_ms < 0 ? INT64_MAX : s->sys.now_ns(s->sys.ctx) + (int64_t)timeout_ms * 1000000;
    int eintr = 0;
    for (;;) {
        int wait_ms = -1;
        if (timeout_ms >= 0) {
            int64_t left = deadline - s->sys.now_ns(s->sys.ctx);
            wait_ms = left <= 0 ? 0 : (int)((left + 999999) / 1000000);
        }
        struct pollfd pfd = {s->fd, POLLIN, 0};
        int r = s->sys.poll(s->sys.ctx, &pfd, 1, wait_ms);
        if (r < 0) {
            if (errno == EINTR && ++eintr < SFM_V4L2_EINTR_LIMIT)
                continue;
            return SFM_E_IO;
        }
        if (r == 0)
            return SFM_E_TIMEOUT;
        struct v4l2_buffer b;
        memset(&b, 0, sizeof b);
        b.type = V4L2_BUF_TYPE_VIDEO_CAPTURE;
        b.memory = V4L2_MEMORY_MMAP;
        if (xioctl(s, VIDIOC_DQBUF, &b) != 0) {
            int e = errno;
            if (is_gone(e))
                return lost(s);
            if (e == EAGAIN) {
                /* No frame yet. POLLERR without a frame means the queue is
                 * empty or the device failed: nothing will come. */
                if (pfd.revents & (POLLERR | POLLHUP | POLLNVAL))
                    return SFM_E_IO;
                if (timeout_ms == 0 || s->sys.now_ns(s->sys.ctx) >= deadline)
                    return SFM_E_TIMEOUT;
                continue;
            }
            if (e == EIO) { /* a transient failure of one frame */
                c->stats.errors++;
                continue;
            }
            return SFM_E_IO;
        }
        if (b.index >= (uint32_t)s->nmapped)
            return SFM_E_IO;
        if (s->have_seq && b.sequence - s->last_seq > 1u && b.sequence - s->last_seq < 0x80000000u)
            c->stats.drops += b.sequence - s->last_seq - 1u;
        s->have_seq = 1;
        s->last_seq = b.sequence;
        const vbuf *vb = &s->buf[b.index];
        size_t used = b.bytesused ? b.bytesused : vb->length;
        if (used > vb->length)
            used = vb->length;
        int bad = (b.flags & V4L2_BUF_FLAG_ERROR) != 0;
        if (!bad && s->format != SFM_PIX_MJPEG)
            bad = used < sfm_pixfmt_min_size(s->format, s->w, s->h, s->bpl);
        const uint8_t *data = vb->start;
        int stride = s->w, in_place = 0;
        if (!bad) {
            switch (s->format) {
            case SFM_PIX_GRAY8:
            case SFM_PIX_NV12:
                stride = s->bpl;
                in_place = 1;
                break;
            case SFM_PIX_YUYV:
                sfm_gray_from_yuyv(vb->start, s->bpl, s->w, s->h, s->gray, s->w);
                data = s->gray;
                break;
            default:
                bad = sfm_jpeg_decode_gray(s->jpeg, vb->start, used, s->w, s->h, s->gray,
                                           s->w) != SFM_OK;
                data = s->gray;
                break;
            }
        }
        if (bad || !in_place) {
            int rc = queue(s, (int)b.index);
            if (rc == SFM_E_DEVICE_LOST) {
                /* A converted frame is already in our buffer: deliver it;
                 * the loss is reported by the next call. */
                teardown(s, 1);
                if (bad)
                    return SFM_E_DEVICE_LOST;
            } else if (rc != SFM_OK) {
                return rc;
            }
        }
        if (bad) {
            c->stats.errors++;
            if (timeout_ms == 0 || s->sys.now_ns(s->sys.ctx) >= deadline)
                return SFM_E_TIMEOUT;
            continue;
        }
        s->held_index = in_place ? (int)b.index : -1;
        frame->data = data;
        frame->width = s->w;
        frame->height = s->h;
        frame->stride = stride;
        frame->format = SFM_PIX_GRAY8;
        frame->timestamp_ns = (int64_t)b.timestamp.tv_sec * 1000000000 +
                              (int64_t)b.timestamp.tv_usec * 1000;
        frame->sequence = b.sequence;
        frame->slot = (int)b.index;
        return 1;
    }
}

static int v4l2_release(sfm_capture *c, const sfm_frame *frame)
{
    (void)frame;
    v4l2src *s = c->impl;
    if (s->fd < 0)
        return SFM_E_DEVICE_LOST;
    if (s->held_index < 0)
        return SFM_OK;
    int idx = s->held_index;
    s->held_index = -1;
    int rc = queue(s, idx);
    if (rc == SFM_E_DEVICE_LOST)
        return lost(s);
    return rc;
}

static void v4l2_destroy(sfm_capture *c) { v4l2_free(c->impl); }

static const sfm_capture_vtbl v4l2_vt = {v4l2_acquire, v4l2_release, v4l2_destroy};

static int pixfmt_of(uint32_t fourcc)
{
    switch (fourcc) {
    case V4L2_PIX_FMT_GREY: return SFM_PIX_GRAY8;
    case V4L2_PIX_FMT_YUYV: return SFM_PIX_YUYV;
    case V4L2_PIX_FMT_NV12: return SFM_PIX_NV12;
    case V4L2_PIX_FMT_MJPEG:
    case V4L2_PIX_FMT_JPEG: return SFM_PIX_MJPEG;
    default: return 0;
    }
}

static uint32_t fourcc_of(int format)
{
    switch (format) {
    case SFM_PIX_GRAY8: return V4L2_PIX_FMT_GREY;
    case SFM_PIX_YUYV: return V4L2_PIX_FMT_YUYV;
    case SFM_PIX_NV12: return V4L2_PIX_FMT_NV12;
    case SFM_PIX_MJPEG: return V4L2_PIX_FMT_MJPEG;
    default: return 0;
    }
}

/* The first format the device offers, in the order GREY, NV12, YUYV, MJPEG
 * (least work per frame first). */
static int pick_format(v4l2src *s, uint32_t *fourcc)
{
    static const int pref[] = {SFM_PIX_GRAY8, SFM_PIX_NV12, SFM_PIX_YUYV, SFM_PIX_MJPEG};
    int best = 99;
    for (uint32_t i = 0; i < 256; i++) {
        struct v4l2_fmtdesc d;
        memset(&d, 0, sizeof d);
        d.index = i;
        d.type = V4L2_BUF_TYPE_VIDEO_CAPTURE;
        if (xioctl(s, VIDIOC_ENUM_FMT, &d) != 0) {
            if (errno == EINVAL)
                break;
            return status_of(errno);
        }
        int f = pixfmt_of(d.pixelformat);
        for (int k = 0; k < 4; k++)
            if (f == pref[k] && k < best) {
                best = k;
                *fourcc = d.pixelformat;
            }
    }
    return best < 4 ? SFM_OK : SFM_E_UNSUPPORTED;
}

static int v4l2_setup(v4l2src *s, const char *device, const sfm_v4l2_options *o,
                      sfm_capture_info *info)
{
    s->fd = s->sys.open(s->sys.ctx, device, O_RDWR | O_NONBLOCK | O_CLOEXEC);
    if (s->fd < 0) {
        int e = errno;
        return (e == ENOENT || e == ENODEV || e == ENXIO || e == ENOTDIR) ? SFM_E_NO_DEVICE
                                                                          : SFM_E_IO;
    }
    struct v4l2_capability cap;
    memset(&cap, 0, sizeof cap);
    if (xioctl(s, VIDIOC_QUERYCAP, &cap) != 0)
        return errno == ENOTTY || errno == EINVAL ? SFM_E_UNSUPPORTED : status_of(errno);
    uint32_t caps = (cap.capabilities & V4L2_CAP_DEVICE_CAPS) ? cap.device_caps : cap.capabilities;
    if (!(caps & V4L2_CAP_VIDEO_CAPTURE) || !(caps & V4L2_CAP_STREAMING))
        return SFM_E_UNSUPPORTED;
    char drv[sizeof cap.driver + 1];
    memcpy(drv, cap.driver, sizeof cap.driver);
    drv[sizeof cap.driver] = '\0';
    sfm_capture_strlcpy(info->driver, sizeof info->driver, "v4l2:");
    sfm_capture_strlcpy(info->driver + 5, sizeof info->driver - 5, drv);
    char card[sizeof cap.card + 1];
    memcpy(card, cap.card, sizeof cap.card);
    card[sizeof cap.card] = '\0';
    sfm_capture_strlcpy(info->card, sizeof info->card, card);

    /* Format: what was asked, or the best the device lists; then what the
     * driver grants. */
    uint32_t want = fourcc_of(o->format);
    if (want == 0) {
        int rc = pick_format(s, &want);
        if (rc != SFM_OK)
            return rc;
    }
    struct v4l2_format fmt;
    memset(&fmt, 0, sizeof fmt);
    fmt.type = V4L2_BUF_TYPE_VIDEO_CAPTURE;
    if (xioctl(s, VIDIOC_G_FMT, &fmt) != 0)
        return status_of(errno);
    if (o->width > 0)
        fmt.fmt.pix.width = (uint32_t)o->width;
    if (o->height > 0)
        fmt.fmt.pix.height = (uint32_t)o->height;
    fmt.fmt.pix.pixelformat = want;
    fmt.fmt.pix.field = V4L2_FIELD_NONE;
    fmt.fmt.pix.bytesperline = 0; /* let the driver choose */
    if (xioctl(s, VIDIOC_S_FMT, &fmt) != 0)
        return errno == EINVAL ? SFM_E_UNSUPPORTED : status_of(errno);
    s->fourcc = fmt.fmt.pix.pixelformat;
    s->format = pixfmt_of(s->fourcc);
    info->adjusted = s->fourcc != want || (o->width > 0 && fmt.fmt.pix.width != (uint32_t)o->width) ||
                     (o->height > 0 && fmt.fmt.pix.height != (uint32_t)o->height);
    if (s->format == 0)
        return SFM_E_UNSUPPORTED;
    if (fmt.fmt.pix.width == 0 || fmt.fmt.pix.height == 0 ||
        fmt.fmt.pix.width > SFM_CAPTURE_MAX_SIDE || fmt.fmt.pix.height > SFM_CAPTURE_MAX_SIDE)
        return SFM_E_UNSUPPORTED;
    s->w = (int)fmt.fmt.pix.width;
    s->h = (int)fmt.fmt.pix.height;
    int row = s->format == SFM_PIX_YUYV ? 2 * s->w : s->w;
    s->bpl = fmt.fmt.pix.bytesperline ? (int)fmt.fmt.pix.bytesperline : row;
    if (s->format != SFM_PIX_MJPEG &&
        (s->bpl < row || s->bpl > 4 * SFM_CAPTURE_MAX_SIDE ||
         sfm_pixfmt_min_size(s->format, s->w, s->h, s->bpl) == 0))
        return SFM_E_UNSUPPORTED;
    if (s->format == SFM_PIX_MJPEG) {
        s->jpeg = sfm_jpeg_decoder_new();
        if (s->jpeg == NULL)
            return SFM_E_UNSUPPORTED; /* no libjpeg in this build */
    }

    /* Frame rate: asked for if given; reported when the driver tells. */
    struct v4l2_streamparm parm;
    memset(&parm, 0, sizeof parm);
    parm.type = V4L2_BUF_TYPE_VIDEO_CAPTURE;
    if (o->fps > 0 && xioctl(s, VIDIOC_G_PARM, &parm) == 0 &&
        (parm.parm.capture.capability & V4L2_CAP_TIMEPERFRAME)) {
        parm.parm.capture.timeperframe.numerator = 1;
        parm.parm.capture.timeperframe.denominator = (uint32_t)o->fps;
        (void)xioctl(s, VIDIOC_S_PARM, &parm);
    }
    memset(&parm, 0, sizeof parm);
    parm.type = V4L2_BUF_TYPE_VIDEO_CAPTURE;
    if (xioctl(s, VIDIOC_G_PARM, &parm) == 0 && parm.parm.capture.timeperframe.numerator > 0 &&
        parm.parm.capture.timeperframe.denominator <= 0x7fffffffu &&
        parm.parm.capture.timeperframe.numerator <= 0x7fffffffu) {
        info->fps_num = (int)parm.parm.capture.timeperframe.denominator;
        info->fps_den = (int)parm.parm.capture.timeperframe.numerator;
    } else if (errno == ENODEV) {
        return SFM_E_DEVICE_LOST;
    }

    /* Buffers. */
    struct v4l2_requestbuffers rb;
    memset(&rb, 0, sizeof rb);
    rb.count = (uint32_t)(o->buffers > 0 ? o->buffers : 4);
    if (rb.count > SFM_V4L2_MAX_BUFFERS)
        rb.count = SFM_V4L2_MAX_BUFFERS;
    rb.type = V4L2_BUF_TYPE_VIDEO_CAPTURE;
    rb.memory = V4L2_MEMORY_MMAP;
    if (xioctl(s, VIDIOC_REQBUFS, &rb) != 0)
        return errno == EINVAL ? SFM_E_UNSUPPORTED : status_of(errno);
    s->nbuf = rb.count > SFM_V4L2_MAX_BUFFERS ? SFM_V4L2_MAX_BUFFERS : (int)rb.count;
    if (rb.count > 0 && s->nbuf == 0)
        s->nbuf = 1;
    if (rb.count < 2)
        return SFM_E_UNSUPPORTED;
    const size_t need = s->format == SFM_PIX_MJPEG ? 1 : sfm_pixfmt_min_size(s->format, s->w, s->h, s->bpl);
    for (int i = 0; i < s->nbuf; i++) {
        struct v4l2_buffer b;
        memset(&b, 0, sizeof b);
        b.type = V4L2_BUF_TYPE_VIDEO_CAPTURE;
        b.memory = V4L2_MEMORY_MMAP;
        b.index = (uint32_t)i;
        if (xioctl(s, VIDIOC_QUERYBUF, &b) != 0)
            return status_of(errno);
        if (b.length < need)
            return SFM_E_UNSUPPORTED;
        void *p = s->sys.mmap(s->sys.ctx, NULL, b.length, PROT_READ | PROT_WRITE, MAP_SHARED,
                              s->fd, (off_t)b.m.offset);
        if (p == MAP_FAILED)
            return status_of(errno);
        s->buf[i].start = p;
        s->buf[i].length = b.length;
        s->nmapped = i + 1;
    }
    for (int i = 0; i < s->nbuf; i++) {
        int rc = queue(s, i);
        if (rc != SFM_OK)
            return rc;
    }
    s->gray = malloc((size_t)s->w * (size_t)s->h);
    if (s->gray == NULL)
        return SFM_E_IO;
    enum v4l2_buf_type type = V4L2_BUF_TYPE_VIDEO_CAPTURE;
    if (xioctl(s, VIDIOC_STREAMON, &type) != 0)
        return status_of(errno);
    s->streaming = 1;
    info->width = s->w;
    info->height = s->h;
    info->source_format = s->format;
    info->fourcc = s->fourcc;
    info->source_stride = s->format == SFM_PIX_MJPEG ? 0 : s->bpl;
    info->buffers = s->nbuf;
    return SFM_OK;
}

int sfm_v4l2_open_sys(const char *device, const sfm_v4l2_options *opt, const sfm_v4l2_sys *sys,
                      sfm_capture **out)
{
    if (device == NULL || out == NULL || sys == NULL || device[0] == '\0' ||
        strlen(device) >= SFM_CAPTURE_PATH_MAX)
        return SFM_E_ARGUMENT;
    sfm_v4l2_options o = {0, 0, 0, 0, 0};
    if (opt)
        o = *opt;
    if (o.width < 0 || o.height < 0 || o.width > SFM_CAPTURE_MAX_SIDE ||
        o.height > SFM_CAPTURE_MAX_SIDE || o.buffers < 0 || o.buffers > SFM_V4L2_MAX_BUFFERS ||
        o.fps < 0 || o.fps > 100000 || (o.buffers == 1) ||
        (o.format != 0 && fourcc_of(o.format) == 0))
        return SFM_E_ARGUMENT;
    v4l2src *s = calloc(1, sizeof *s);
    if (s == NULL)
        return SFM_E_IO;
    s->sys = *sys;
    s->fd = -1;
    s->held_index = -1;
    sfm_capture_info info;
    memset(&info, 0, sizeof info);
    int rc = v4l2_setup(s, device, &o, &info);
    sfm_capture *c = NULL;
    if (rc == SFM_OK) {
        c = sfm_capture_new(&v4l2_vt, s);
        if (c == NULL)
            rc = SFM_E_IO;
    }
    if (rc != SFM_OK) {
        teardown(s, rc == SFM_E_DEVICE_LOST);
        v4l2_free(s);
        return rc;
    }
    c->info = info;
    *out = c;
    return SFM_OK;
}

/* The real system calls. */
static int sys_open(void *ctx, const char *path, int flags)
{
    (void)ctx;
    return open(path, flags);
}
static int sys_close(void *ctx, int fd)
{
    (void)ctx;
    return close(fd);
}
static int sys_ioctl(void *ctx, int fd, unsigned long request, void *arg)
{
    (void)ctx;
    return ioctl(fd, request, arg);
}
static void *sys_mmap(void *ctx, void *addr, size_t len, int prot, int flags, int fd, off_t off)
{
    (void)ctx;
    return mmap(addr, len, prot, flags, fd, off);
}
static int sys_munmap(void *ctx, void *addr, size_t len)
{
    (void)ctx;
    return munmap(addr, len);
}
static int sys_poll(void *ctx, struct pollfd *fds, nfds_t nfds, int timeout_ms)
{
    (void)ctx;
    return poll(fds, nfds, timeout_ms);
}
static int64_t sys_now(void *ctx)
{
    (void)ctx;
    return sfm_capture_now_ns();
}

static const sfm_v4l2_sys real_sys = {NULL,      sys_open,   sys_close, sys_ioctl,
                                      sys_mmap,  sys_munmap, sys_poll,  sys_now};

const sfm_v4l2_sys *sfm_v4l2_sys_default(void) { return &real_sys; }

int sfm_capture_open_v4l2(const char *device, const sfm_v4l2_options *opt, sfm_capture **out)
{
    return sfm_v4l2_open_sys(device, opt, &real_sys, out);
}
