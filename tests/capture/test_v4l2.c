/* The V4L2 source against a simulated driver (no kernel module exists
 * here): normal streaming in every pixel format, a driver that adjusts the
 * request, EINTR and EAGAIN storms, buffers flagged in error, dropped
 * sequence numbers, a device that disappears mid-stream, poll timeouts, and
 * a failure at every step of opening. After each, the simulated kernel must
 * hold no open file, no mapping, and no streaming queue. */
#define _DEFAULT_SOURCE
#include <errno.h>
#include <fcntl.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/mman.h>

#include <linux/videodev2.h>

#include "cap_test.h"
#include "capture/capture_impl.h"
#include "capture/v4l2_sys.h"
#include "sfm_test.h"

enum { SIM_FD = 7, SIM_NBUF_MAX = 8, SIM_BUF_BYTES = 64 * 1024, SIM_FRAME_NS = 33333333 };

typedef struct sim {
    /* what the device is */
    uint32_t formats[4];
    int nformats;
    uint32_t caps;
    int grant_w, grant_h;       /* > 0: the size the driver imposes */
    int bpl_pad;                /* bytes of padding the driver adds per line */
    uint32_t grant_fourcc;      /* != 0: the format the driver imposes */
    int max_buffers;            /* most buffers REQBUFS grants */
    /* faults */
    unsigned long fail_req;     /* this ioctl fails with fail_errno */
    int fail_errno;
    int fail_mmap;
    int open_errno;
    int eintr_left;             /* next ioctls answer EINTR */
    int poll_eintr_left;        /* next polls answer EINTR */
    int eagain_left;            /* next DQBUFs answer EAGAIN */
    int poll_timeouts_left;     /* next polls time out */
    uint32_t error_seq_mask;    /* frames whose sequence bit is set come flagged in error */
    uint32_t skip_after_seq;    /* after this sequence the driver skips skip_count numbers */
    int skip_count;
    int vanish_after;           /* device gone after this many DQBUFs (0: never) */
    int short_seq;              /* frame with this sequence+1 has bytesused too small (0: none) */
    /* state */
    int open_fds, maps, streaming, nbuf;
    int queued[SIM_NBUF_MAX];
    int queue_order[SIM_NBUF_MAX], qhead, qcount;
    uint32_t fourcc;
    int w, h, bpl;
    uint32_t seq;
    int dqbufs;
    int gone;
    int64_t clock;
    int streamoff_calls, reqbufs0_calls;
    const uint8_t *jpeg;
    size_t jpeg_len;
} sim;

static uint8_t sim_mem[SIM_NBUF_MAX][SIM_BUF_BYTES];

static sim *S(void *ctx) { return ctx; }

static int fail(int e)
{
    errno = e;
    return -1;
}

static int sim_open(void *ctx, const char *path, int flags)
{
    sim *s = S(ctx);
    (void)path;
    if (!(flags & O_NONBLOCK))
        return fail(EINVAL); /* the adapter must open non-blocking */
    if (s->open_errno)
        return fail(s->open_errno);
    s->open_fds++;
    return SIM_FD;
}

static int sim_close(void *ctx, int fd)
{
    sim *s = S(ctx);
    if (fd != SIM_FD || s->open_fds == 0)
        return fail(EBADF);
    s->open_fds--;
    s->streaming = 0;
    if (s->maps == 0)
        s->nbuf = 0;
    return 0;
}

static uint8_t pattern(uint32_t seq, int x, int y) { return (uint8_t)(x * 5 + y * 3 + (int)seq * 11); }

static int row_bytes(uint32_t fourcc, int w) { return fourcc == V4L2_PIX_FMT_YUYV ? 2 * w : w; }

/* The driver writes frame `seq` into buffer i. */
static size_t fill(sim *s, int i, uint32_t seq)
{
    uint8_t *m = sim_mem[i];
    if (s->fourcc == V4L2_PIX_FMT_MJPEG) {
        memcpy(m, s->jpeg, s->jpeg_len);
        return s->jpeg_len;
    }
    memset(m, 0xEE, (size_t)s->bpl * (size_t)s->h * 2); /* padding and chroma: noise */
    for (int y = 0; y < s->h; y++)
        for (int x = 0; x < s->w; x++) {
            if (s->fourcc == V4L2_PIX_FMT_YUYV) {
                m[y * s->bpl + 2 * x] = pattern(seq, x, y);
                m[y * s->bpl + 2 * x + 1] = (uint8_t)(x & 1 ? 200 : 50); /* V / U */
            } else {
                m[y * s->bpl + x] = pattern(seq, x, y);
            }
        }
    size_t n = (size_t)s->bpl * (size_t)s->h;
    if (s->fourcc == V4L2_PIX_FMT_NV12)
        n += (size_t)s->bpl * (size_t)s->h / 2;
    return n;
}

static int supported(const sim *s, uint32_t f)
{
    for (int i = 0; i < s->nformats; i++)
        if (s->formats[i] == f)
            return 1;
    return 0;
}

static int sim_ioctl(void *ctx, int fd, unsigned long req, void *arg)
{
    sim *s = S(ctx);
    if (fd != SIM_FD || s->open_fds == 0)
        return fail(EBADF);
    if (s->eintr_left > 0) {
        s->eintr_left--;
        return fail(EINTR);
    }
    if (s->gone)
        return fail(ENODEV);
    if (req == s->fail_req) {
        if (req != VIDIOC_REQBUFS || ((struct v4l2_requestbuffers *)arg)->count != 0)
            return fail(s->fail_errno);
    }
    switch (req) {
    case VIDIOC_QUERYCAP: {
        struct v4l2_capability *c = arg;
        memset(c, 0, sizeof *c);
        memcpy(c->driver, "simdrv", 7);
        memcpy(c->card, "Simulated camera", 17);
        c->capabilities = s->caps | V4L2_CAP_DEVICE_CAPS;
        c->device_caps = s->caps;
        return 0;
    }
    case VIDIOC_ENUM_FMT: {
        struct v4l2_fmtdesc *d = arg;
        if (d->type != V4L2_BUF_TYPE_VIDEO_CAPTURE || d->index >= (uint32_t)s->nformats)
            return fail(EINVAL);
        d->pixelformat = s->formats[d->index];
        return 0;
    }
    case VIDIOC_G_FMT:
    case VIDIOC_S_FMT: {
        struct v4l2_format *f = arg;
        if (f->type != V4L2_BUF_TYPE_VIDEO_CAPTURE)
            return fail(EINVAL);
        if (req == VIDIOC_S_FMT) {
            if (s->nbuf > 0)
                return fail(EBUSY);
            uint32_t fc = f->fmt.pix.pixelformat;
            if (s->grant_fourcc)
                fc = s->grant_fourcc;
            else if (!supported(s, fc))
                fc = s->formats[0];
            s->fourcc = fc;
            s->w = s->grant_w > 0 ? s->grant_w : (int)f->fmt.pix.width;
            s->h = s->grant_h > 0 ? s->grant_h : (int)f->fmt.pix.height;
            s->w &= ~1;
            s->h &= ~1;
            s->bpl = row_bytes(fc, s->w) + s->bpl_pad;
        }
        f->fmt.pix.width = (uint32_t)s->w;
        f->fmt.pix.height = (uint32_t)s->h;
        f->fmt.pix.pixelformat = s->fourcc;
        f->fmt.pix.bytesperline = s->fourcc == V4L2_PIX_FMT_MJPEG ? 0 : (uint32_t)s->bpl;
        f->fmt.pix.sizeimage = (uint32_t)(s->bpl * s->h * 2);
        f->fmt.pix.field = V4L2_FIELD_NONE;
        return 0;
    }
    case VIDIOC_G_PARM: {
        struct v4l2_streamparm *p = arg;
        p->parm.capture.capability = V4L2_CAP_TIMEPERFRAME;
        p->parm.capture.timeperframe.numerator = 1;
        p->parm.capture.timeperframe.denominator = 30;
        return 0;
    }
    case VIDIOC_S_PARM:
        return 0;
    case VIDIOC_REQBUFS: {
        struct v4l2_requestbuffers *r = arg;
        if (r->memory != V4L2_MEMORY_MMAP)
            return fail(EINVAL);
        if (r->count == 0) {
            if (s->maps > 0)
                return fail(EBUSY);
            s->reqbufs0_calls++;
            s->nbuf = 0;
            return 0;
        }
        if (s->nbuf > 0)
            return fail(EBUSY);
        int n = (int)r->count;
        if (n > s->max_buffers)
            n = s->max_buffers;
        s->nbuf = n;
        r->count = (uint32_t)n;
        memset(s->queued, 0, sizeof s->queued);
        s->qhead = s->qcount = 0;
        return 0;
    }
    case VIDIOC_QUERYBUF: {
        struct v4l2_buffer *b = arg;
        if (b->index >= (uint32_t)s->nbuf)
            return fail(EINVAL);
        b->length = SIM_BUF_BYTES;
        b->m.offset = b->index * SIM_BUF_BYTES;
        return 0;
    }
    case VIDIOC_QBUF: {
        struct v4l2_buffer *b = arg;
        if (b->index >= (uint32_t)s->nbuf || s->queued[b->index])
            return fail(EINVAL);
        s->queued[b->index] = 1;
        s->queue_order[(s->qhead + s->qcount) % SIM_NBUF_MAX] = (int)b->index;
        s->qcount++;
        return 0;
    }
    case VIDIOC_DQBUF: {
        struct v4l2_buffer *b = arg;
        if (!s->streaming)
            return fail(EINVAL);
        if (s->eagain_left > 0) {
            s->eagain_left--;
            return fail(EAGAIN);
        }
        if (s->qcount == 0)
            return fail(EAGAIN);
        int i = s->queue_order[s->qhead];
        s->qhead = (s->qhead + 1) % SIM_NBUF_MAX;
        s->qcount--;
        s->queued[i] = 0;
        uint32_t seq = s->seq++;
        if (s->skip_count && seq == s->skip_after_seq)
            s->seq += (uint32_t)s->skip_count;
        memset(b, 0, sizeof *b);
        b->type = V4L2_BUF_TYPE_VIDEO_CAPTURE;
        b->memory = V4L2_MEMORY_MMAP;
        b->index = (uint32_t)i;
        b->sequence = seq;
        b->bytesused = (uint32_t)fill(s, i, seq);
        if (s->short_seq && seq + 1 == (uint32_t)s->short_seq)
            b->bytesused = 10;
        b->length = SIM_BUF_BYTES;
        if (seq < 32 && (s->error_seq_mask >> seq) & 1)
            b->flags |= V4L2_BUF_FLAG_ERROR;
        b->timestamp.tv_sec = (time_t)(s->clock / 1000000000);
        b->timestamp.tv_usec = (suseconds_t)(s->clock % 1000000000 / 1000);
        if (s->vanish_after && ++s->dqbufs >= s->vanish_after)
            s->gone = 1; /* this frame made it; the next call finds no device */
        return 0;
    }
    case VIDIOC_STREAMON:
        if (s->nbuf == 0)
            return fail(EINVAL);
        s->streaming = 1;
        return 0;
    case VIDIOC_STREAMOFF:
        s->streamoff_calls++;
        s->streaming = 0;
        s->qcount = 0;
        memset(s->queued, 0, sizeof s->queued);
        return 0;
    default:
        return fail(ENOTTY);
    }
}

static void *sim_mmap(void *ctx, void *addr, size_t len, int prot, int flags, int fd, off_t off)
{
    sim *s = S(ctx);
    (void)addr;
    (void)prot;
    if (fd != SIM_FD || !(flags & MAP_SHARED) || len != SIM_BUF_BYTES || off % SIM_BUF_BYTES ||
        off / SIM_BUF_BYTES >= s->nbuf) {
        errno = EINVAL;
        return MAP_FAILED;
    }
    if (s->fail_mmap && s->maps + 1 >= s->fail_mmap) {
        errno = ENOMEM;
        return MAP_FAILED;
    }
    s->maps++;
    return sim_mem[off / SIM_BUF_BYTES];
}

static int sim_munmap(void *ctx, void *addr, size_t len)
{
    sim *s = S(ctx);
    (void)addr;
    (void)len;
    if (s->maps == 0)
        return fail(EINVAL);
    s->maps--;
    return 0;
}

static int sim_poll(void *ctx, struct pollfd *fds, nfds_t n, int timeout_ms)
{
    sim *s = S(ctx);
    if (n != 1 || fds[0].fd != SIM_FD)
        return fail(EINVAL);
    if (s->poll_eintr_left > 0) {
        s->poll_eintr_left--;
        return fail(EINTR);
    }
    if (s->gone) {
        fds[0].revents = POLLERR | POLLHUP;
        return 1;
    }
    if (s->poll_timeouts_left > 0 && timeout_ms >= 0) {
        s->poll_timeouts_left--;
        s->clock += (int64_t)timeout_ms * 1000000;
        return 0;
    }
    if (!s->streaming || s->qcount == 0) {
        fds[0].revents = POLLERR;
        return 1;
    }
    s->clock += SIM_FRAME_NS;
    fds[0].revents = POLLIN;
    return 1;
}

static int64_t sim_now(void *ctx) { return S(ctx)->clock; }

static sfm_v4l2_sys sim_sys(sim *s)
{
    sfm_v4l2_sys t = {s, sim_open, sim_close, sim_ioctl, sim_mmap, sim_munmap, sim_poll, sim_now};
    return t;
}

static void sim_init(sim *s, uint32_t fourcc)
{
    memset(s, 0, sizeof *s);
    s->formats[0] = fourcc;
    s->nformats = 1;
    s->caps = V4L2_CAP_VIDEO_CAPTURE | V4L2_CAP_STREAMING;
    s->max_buffers = SIM_NBUF_MAX;
    s->clock = 5000000000LL;
    s->w = 64;
    s->h = 48;
    s->fourcc = fourcc;
    s->bpl = row_bytes(fourcc, 64);
}

/* Nothing left in the simulated kernel. */
static void check_released(sfm_test_ctx *t, const sim *s)
{
    SFM_CHECK_EQ_INT(s->open_fds, 0);
    SFM_CHECK_EQ_INT(s->maps, 0);
    SFM_CHECK_EQ_INT(s->streaming, 0);
}

static int frame_matches(const sfm_frame *f, uint32_t seq)
{
    for (int y = 0; y < f->height; y++)
        for (int x = 0; x < f->width; x++)
            if (f->data[y * f->stride + x] != pattern(seq, x, y))
                return 0;
    return 1;
}

static void stream_format(sfm_test_ctx *t, uint32_t fourcc, int fmt, int pad)
{
    sim s;
    sim_init(&s, fourcc);
    s.bpl_pad = pad;
    sfm_v4l2_sys sys = sim_sys(&s);
    sfm_v4l2_options o = {.width = 64, .height = 48, .format = fmt, .buffers = 3, .fps = 30};
    sfm_capture *c = NULL;
    SFM_CHECK_EQ_INT(sfm_v4l2_open_sys("/dev/video9", &o, &sys, &c), SFM_OK);
    if (c == NULL)
        return;
    sfm_capture_info info;
    sfm_capture_get_info(c, &info);
    SFM_CHECK_EQ_INT(info.width, 64);
    SFM_CHECK_EQ_INT(info.height, 48);
    SFM_CHECK_EQ_INT(info.buffers, 3);
    SFM_CHECK_EQ_INT(info.adjusted, 0);
    SFM_CHECK_EQ_INT(info.fourcc, fourcc);
    SFM_CHECK_EQ_INT(info.fps_num, 30);
    SFM_CHECK_EQ_INT(info.fps_den, 1);
    SFM_CHECK(strcmp(info.driver, "v4l2:simdrv") == 0);
    SFM_CHECK(strcmp(info.card, "Simulated camera") == 0);
    SFM_CHECK_EQ_INT(s.maps, 3);
    SFM_CHECK_EQ_INT(s.streaming, 1);
    unsigned long allocs = cap_alloc_calls;
    int64_t last_ts = 0;
    for (uint32_t k = 0; k < 20; k++) { /* wraps the 3 buffers several times */
        sfm_frame f;
        SFM_CHECK_EQ_INT(sfm_capture_acquire(c, 100, &f), 1);
        SFM_CHECK_EQ_INT(f.format, SFM_PIX_GRAY8);
        SFM_CHECK_EQ_INT(f.width, 64);
        SFM_CHECK_EQ_INT(f.sequence, k);
        SFM_CHECK(f.timestamp_ns > last_ts);
        last_ts = f.timestamp_ns;
        SFM_CHECK_MSG(frame_matches(&f, k), "frame %u differs from the driver's luma", k);
        SFM_CHECK_EQ_INT(sfm_capture_release(c, &f), SFM_OK);
    }
    SFM_CHECK_EQ_INT(cap_alloc_calls - allocs, 0); /* nothing allocated per frame */
    sfm_capture_stats st;
    sfm_capture_get_stats(c, &st);
    SFM_CHECK_EQ_INT(st.frames, 20);
    SFM_CHECK_EQ_INT(st.drops, 0);
    SFM_CHECK_EQ_INT(st.errors, 0);
    sfm_capture_close(c);
    check_released(t, &s);
    SFM_CHECK_EQ_INT(s.streamoff_calls, 1);
    SFM_CHECK_EQ_INT(s.reqbufs0_calls, 1);
}

SFM_TEST(v4l2_streams_grey)
{
    stream_format(t, V4L2_PIX_FMT_GREY, SFM_PIX_GRAY8, 0);
    stream_format(t, V4L2_PIX_FMT_GREY, SFM_PIX_GRAY8, 16); /* padded lines */
}

SFM_TEST(v4l2_streams_yuyv)
{
    stream_format(t, V4L2_PIX_FMT_YUYV, SFM_PIX_YUYV, 0);
    stream_format(t, V4L2_PIX_FMT_YUYV, SFM_PIX_YUYV, 32);
}

SFM_TEST(v4l2_streams_nv12)
{
    stream_format(t, V4L2_PIX_FMT_NV12, SFM_PIX_NV12, 0);
    stream_format(t, V4L2_PIX_FMT_NV12, SFM_PIX_NV12, 64);
}

SFM_TEST(v4l2_streams_mjpeg)
{
#ifndef SFM_HAVE_LIBJPEG
    (void)t;
    printf("SKIP: built without libjpeg\n");
#else
    static uint8_t img[48 * 64], jpg[32768];
    for (int y = 0; y < 48; y++)
        for (int x = 0; x < 64; x++)
            img[y * 64 + x] = (uint8_t)(60 + x + y);
    char dir[512], path[600];
    SFM_CHECK(cap_tmpdir(dir, sizeof dir) == 0);
    snprintf(path, sizeof path, "%s/f.jpg", dir);
    SFM_CHECK_EQ_INT(sfm_jpeg_write(path, img, 64, 48, 64, 1, 95), SFM_OK);
    long n = cap_read_file(path, jpg, sizeof jpg);
    cap_rmtree(dir);
    SFM_CHECK(n > 0);
    sim s;
    sim_init(&s, V4L2_PIX_FMT_MJPEG);
    s.jpeg = jpg;
    s.jpeg_len = (size_t)n;
    sfm_v4l2_sys sys = sim_sys(&s);
    sfm_v4l2_options o = {.width = 64, .height = 48, .format = SFM_PIX_MJPEG};
    sfm_capture *c = NULL;
    SFM_CHECK_EQ_INT(sfm_v4l2_open_sys("/dev/video9", &o, &sys, &c), SFM_OK);
    for (int k = 0; k < 5 && c; k++) {
        sfm_frame f;
        SFM_CHECK_EQ_INT(sfm_capture_acquire(c, 100, &f), 1);
        int worst = 0;
        for (int i = 0; i < 64 * 48; i++) {
            int d = abs(f.data[(i / 64) * f.stride + i % 64] - img[i]);
            worst = d > worst ? d : worst;
        }
        SFM_CHECK_MSG(worst <= 3, "MJPEG frame off by %d", worst);
        SFM_CHECK_EQ_INT(sfm_capture_release(c, &f), SFM_OK);
    }
    /* A corrupt frame is an error, requeued; streaming goes on. */
    jpg[n / 2] ^= 0xFF;
    s.jpeg_len = (size_t)n / 2;
    sfm_frame f;
    SFM_CHECK_EQ_INT(sfm_capture_acquire(c, 0, &f), SFM_E_TIMEOUT);
    s.jpeg_len = (size_t)n;
    jpg[n / 2] ^= 0xFF;
    SFM_CHECK_EQ_INT(sfm_capture_acquire(c, 100, &f), 1);
    sfm_capture_release(c, &f);
    sfm_capture_stats st;
    sfm_capture_get_stats(c, &st);
    SFM_CHECK_EQ_INT(st.frames, 6);
    SFM_CHECK_EQ_INT(st.errors, 1);
    sfm_capture_close(c);
    check_released(t, &s);
#endif
}

SFM_TEST(v4l2_auto_format_and_driver_adjustments_are_reported)
{
    sim s;
    sim_init(&s, V4L2_PIX_FMT_MJPEG);
    s.formats[1] = V4L2_PIX_FMT_YUYV;
    s.formats[2] = v4l2_fourcc('R', 'G', 'B', '3'); /* not one of ours */
    s.nformats = 3;
    s.grant_w = 80; /* asked 641 x 479: the driver gives 80 x 60 */
    s.grant_h = 60;
    sfm_v4l2_sys sys = sim_sys(&s);
    sfm_v4l2_options o = {.width = 641, .height = 479};
    sfm_capture *c = NULL;
    SFM_CHECK_EQ_INT(sfm_v4l2_open_sys("/dev/video9", &o, &sys, &c), SFM_OK);
    sfm_capture_info info;
    sfm_capture_get_info(c, &info);
    SFM_CHECK_EQ_INT(info.fourcc, V4L2_PIX_FMT_YUYV); /* preferred over MJPEG */
    SFM_CHECK_EQ_INT(info.source_format, SFM_PIX_YUYV);
    SFM_CHECK_EQ_INT(info.width, 80);
    SFM_CHECK_EQ_INT(info.height, 60);
    SFM_CHECK_EQ_INT(info.source_stride, 160);
    SFM_CHECK_EQ_INT(info.buffers, 4); /* the default */
    SFM_CHECK_EQ_INT(info.adjusted, 1);
    sfm_frame f;
    SFM_CHECK_EQ_INT(sfm_capture_acquire(c, 100, &f), 1);
    SFM_CHECK_EQ_INT(f.width, 80);
    SFM_CHECK(frame_matches(&f, 0));
    sfm_capture_release(c, &f);
    sfm_capture_close(c);
    check_released(t, &s);

    /* Asked for NV12; the driver imposes GREY: accepted and reported. */
    sim_init(&s, V4L2_PIX_FMT_GREY);
    s.grant_fourcc = V4L2_PIX_FMT_GREY;
    sys = sim_sys(&s);
    sfm_v4l2_options o2 = {.width = 64, .height = 48, .format = SFM_PIX_NV12, .buffers = 2};
    SFM_CHECK_EQ_INT(sfm_v4l2_open_sys("/dev/video9", &o2, &sys, &c), SFM_OK);
    sfm_capture_get_info(c, &info);
    SFM_CHECK_EQ_INT(info.source_format, SFM_PIX_GRAY8);
    SFM_CHECK_EQ_INT(info.buffers, 2);
    sfm_capture_close(c);
    check_released(t, &s);

    /* A device offering nothing we convert. */
    sim_init(&s, v4l2_fourcc('R', 'G', 'B', '3'));
    sys = sim_sys(&s);
    SFM_CHECK_EQ_INT(sfm_v4l2_open_sys("/dev/video9", NULL, &sys, &c), SFM_E_UNSUPPORTED);
    check_released(t, &s);
}

SFM_TEST(v4l2_refuses_fewer_than_two_buffers)
{
    sim s;
    sim_init(&s, V4L2_PIX_FMT_GREY);
    s.max_buffers = 1;
    sfm_v4l2_sys sys = sim_sys(&s);
    sfm_capture *c = NULL;
    SFM_CHECK_EQ_INT(sfm_v4l2_open_sys("/dev/video9", NULL, &sys, &c), SFM_E_UNSUPPORTED);
    SFM_CHECK(c == NULL);
    check_released(t, &s);
    SFM_CHECK_EQ_INT(s.nbuf, 0); /* the one buffer was given back */
    sfm_v4l2_options one = {.buffers = 1};
    SFM_CHECK_EQ_INT(sfm_v4l2_open_sys("/dev/video9", &one, &sys, &c), SFM_E_ARGUMENT);
}

SFM_TEST(v4l2_eintr_and_eagain_storms)
{
    sim s;
    sim_init(&s, V4L2_PIX_FMT_GREY);
    s.eintr_left = 1000; /* every ioctl of open is interrupted many times */
    sfm_v4l2_sys sys = sim_sys(&s);
    sfm_capture *c = NULL;
    SFM_CHECK_EQ_INT(sfm_v4l2_open_sys("/dev/video9", NULL, &sys, &c), SFM_OK);
    SFM_CHECK_EQ_INT(s.eintr_left, 0);
    for (int k = 0; k < 4 && c; k++) {
        s.eintr_left = 500;
        s.poll_eintr_left = 300;
        s.eagain_left = 700;
        sfm_frame f;
        SFM_CHECK_EQ_INT(sfm_capture_acquire(c, -1, &f), 1);
        SFM_CHECK_EQ_INT(f.sequence, k);
        SFM_CHECK(frame_matches(&f, (uint32_t)k));
        SFM_CHECK_EQ_INT(sfm_capture_release(c, &f), SFM_OK);
    }
    /* EAGAIN within a bounded timeout: the adapter polls again (each poll
     * of the simulated driver takes a frame period, 33 ms) until the frame
     * comes, without error; beyond the timeout it is a timeout. */
    s.eagain_left = 20;
    sfm_frame f;
    SFM_CHECK_EQ_INT(sfm_capture_acquire(c, 1000, &f), 1);
    sfm_capture_release(c, &f);
    s.eagain_left = 40;
    SFM_CHECK_EQ_INT(sfm_capture_acquire(c, 1000, &f), SFM_E_TIMEOUT);
    s.eagain_left = 0;
    SFM_CHECK_EQ_INT(sfm_capture_acquire(c, 1000, &f), 1);
    sfm_capture_release(c, &f);
    sfm_capture_stats st;
    sfm_capture_get_stats(c, &st);
    SFM_CHECK_EQ_INT(st.errors, 0);
    SFM_CHECK_EQ_INT(st.drops, 0);
    /* An endless EINTR answer is a failure, not a hang. */
    s.eintr_left = 2 * SFM_V4L2_EINTR_LIMIT;
    SFM_CHECK_EQ_INT(sfm_capture_acquire(c, 100, &f), SFM_E_IO);
    s.eintr_left = 0;
    sfm_capture_close(c);
    check_released(t, &s);
}

SFM_TEST(v4l2_error_buffers_requeued_and_drops_counted)
{
    sim s;
    sim_init(&s, V4L2_PIX_FMT_YUYV);
    s.error_seq_mask = (1u << 2) | (1u << 3) | (1u << 9);
    s.skip_after_seq = 5; /* after 5 comes 9: 3 frames dropped */
    s.skip_count = 3;
    s.short_seq = 12;     /* sequence 11 arrives truncated */
    sfm_v4l2_sys sys = sim_sys(&s);
    sfm_capture *c = NULL;
    SFM_CHECK_EQ_INT(sfm_v4l2_open_sys("/dev/video9", NULL, &sys, &c), SFM_OK);
    const uint32_t expect[] = {0, 1, 4, 5, 10, 12, 13};
    for (int k = 0; k < 7 && c; k++) {
        sfm_frame f;
        SFM_CHECK_EQ_INT(sfm_capture_acquire(c, 100, &f), 1);
        SFM_CHECK_EQ_INT(f.sequence, expect[k]);
        SFM_CHECK(frame_matches(&f, expect[k]));
        SFM_CHECK_EQ_INT(sfm_capture_release(c, &f), SFM_OK);
    }
    sfm_capture_stats st;
    sfm_capture_get_stats(c, &st);
    SFM_CHECK_EQ_INT(st.frames, 7);
    SFM_CHECK_EQ_INT(st.errors, 4); /* 2, 3, 9 flagged, 11 short */
    SFM_CHECK_EQ_INT(st.drops, 3);  /* 6, 7, 8 never came */
    /* every buffer is back with the driver (none lost to the error path) */
    SFM_CHECK_EQ_INT(s.qcount, 4);
    sfm_capture_close(c);
    check_released(t, &s);
}

SFM_TEST(v4l2_poll_timeout)
{
    sim s;
    sim_init(&s, V4L2_PIX_FMT_GREY);
    sfm_v4l2_sys sys = sim_sys(&s);
    sfm_capture *c = NULL;
    SFM_CHECK_EQ_INT(sfm_v4l2_open_sys("/dev/video9", NULL, &sys, &c), SFM_OK);
    s.poll_timeouts_left = 1;
    sfm_frame f;
    sfm_test_fill_canary(&f, sizeof f);
    int64_t t0 = s.clock;
    SFM_CHECK_EQ_INT(sfm_capture_acquire(c, 250, &f), SFM_E_TIMEOUT);
    SFM_CHECK(sfm_test_canary_intact(&f, sizeof f));
    SFM_CHECK_EQ_INT((s.clock - t0) / 1000000, 250); /* waited in poll, as asked */
    SFM_CHECK_EQ_INT(sfm_capture_acquire(c, 250, &f), 1); /* then streams on */
    SFM_CHECK_EQ_INT(f.sequence, 0);
    sfm_capture_release(c, &f);
    /* All buffers held by nobody and none queued: POLLERR, not a hang. */
    s.streaming = 0;
    SFM_CHECK_EQ_INT(sfm_capture_acquire(c, -1, &f), SFM_E_IO);
    sfm_capture_close(c);
    check_released(t, &s);
}

SFM_TEST(v4l2_device_disappears_mid_stream)
{
    for (int held = 0; held < 2; held++) {
        sim s;
        /* GREY frames are lent in place (requeued at release); YUYV frames
         * are converted and requeued at acquire. */
        sim_init(&s, held ? V4L2_PIX_FMT_GREY : V4L2_PIX_FMT_YUYV);
        s.vanish_after = 3;
        sfm_v4l2_sys sys = sim_sys(&s);
        sfm_capture *c = NULL;
        SFM_CHECK_EQ_INT(sfm_v4l2_open_sys("/dev/video9", NULL, &sys, &c), SFM_OK);
        sfm_frame f;
        for (int k = 0; k < 2; k++) {
            SFM_CHECK_EQ_INT(sfm_capture_acquire(c, 100, &f), 1);
            SFM_CHECK_EQ_INT(sfm_capture_release(c, &f), SFM_OK);
        }
        SFM_CHECK_EQ_INT(sfm_capture_acquire(c, 100, &f), 1); /* the last frame */
        SFM_CHECK(frame_matches(&f, 2));
        /* In place: the requeue at release finds the device gone. Converted:
         * the requeue at acquire did, the frame was still delivered, and
         * release reports the loss. */
        SFM_CHECK_EQ_INT(sfm_capture_release(c, &f), SFM_E_DEVICE_LOST);
        /* Everything is released before close, and it stays lost. */
        check_released(t, &s);
        SFM_CHECK_EQ_INT(sfm_capture_acquire(c, -1, &f), SFM_E_DEVICE_LOST);
        SFM_CHECK_EQ_INT(sfm_capture_acquire(c, 100, &f), SFM_E_DEVICE_LOST);
        sfm_capture_close(c);
        check_released(t, &s);
    }
    /* Gone between two frames: acquire (forever) reports it at once. */
    sim s;
    sim_init(&s, V4L2_PIX_FMT_YUYV);
    sfm_v4l2_sys sys = sim_sys(&s);
    sfm_capture *c = NULL;
    SFM_CHECK_EQ_INT(sfm_v4l2_open_sys("/dev/video9", NULL, &sys, &c), SFM_OK);
    sfm_frame f;
    SFM_CHECK_EQ_INT(sfm_capture_acquire(c, 100, &f), 1);
    SFM_CHECK_EQ_INT(sfm_capture_release(c, &f), SFM_OK);
    s.gone = 1;
    SFM_CHECK_EQ_INT(sfm_capture_acquire(c, -1, &f), SFM_E_DEVICE_LOST);
    check_released(t, &s);
    sfm_capture_close(c);
}

SFM_TEST(v4l2_every_open_failure_releases_everything)
{
    const unsigned long reqs[] = {VIDIOC_QUERYCAP, VIDIOC_ENUM_FMT, VIDIOC_G_FMT, VIDIOC_S_FMT,
                                  VIDIOC_REQBUFS, VIDIOC_QUERYBUF, VIDIOC_QBUF, VIDIOC_STREAMON};
    const int errs[] = {EIO, ENODEV, EINVAL};
    for (size_t i = 0; i < sizeof reqs / sizeof reqs[0]; i++)
        for (size_t e = 0; e < 3; e++) {
            sim s;
            sim_init(&s, V4L2_PIX_FMT_GREY);
            s.fail_req = reqs[i];
            s.fail_errno = errs[e];
            sfm_v4l2_sys sys = sim_sys(&s);
            sfm_capture *c = NULL;
            int rc = sfm_v4l2_open_sys("/dev/video9", NULL, &sys, &c);
            SFM_CHECK_MSG(rc < 0 && c == NULL, "ioctl %zu errno %d: %d", i, errs[e], rc);
            if (errs[e] == ENODEV)
                SFM_CHECK_MSG(rc == SFM_E_DEVICE_LOST, "ioctl %zu: %d", i, rc);
            SFM_CHECK_MSG(s.open_fds == 0 && s.maps == 0 && s.streaming == 0,
                          "ioctl %zu errno %d left fds %d maps %d streaming %d", i, errs[e],
                          s.open_fds, s.maps, s.streaming);
        }
    /* mmap failing at the first, second, third buffer */
    for (int k = 1; k <= 3; k++) {
        sim s;
        sim_init(&s, V4L2_PIX_FMT_GREY);
        s.fail_mmap = k;
        sfm_v4l2_sys sys = sim_sys(&s);
        sfm_capture *c = NULL;
        SFM_CHECK_EQ_INT(sfm_v4l2_open_sys("/dev/video9", NULL, &sys, &c), SFM_E_IO);
        check_released(t, &s);
        SFM_CHECK_EQ_INT(s.nbuf, 0);
    }
    /* no device node, a node that is not a capture device */
    sim s;
    sim_init(&s, V4L2_PIX_FMT_GREY);
    s.open_errno = ENOENT;
    sfm_v4l2_sys sys = sim_sys(&s);
    sfm_capture *c = NULL;
    SFM_CHECK_EQ_INT(sfm_v4l2_open_sys("/dev/video9", NULL, &sys, &c), SFM_E_NO_DEVICE);
    s.open_errno = EACCES;
    SFM_CHECK_EQ_INT(sfm_v4l2_open_sys("/dev/video9", NULL, &sys, &c), SFM_E_IO);
    s.open_errno = 0;
    s.caps = V4L2_CAP_VIDEO_OUTPUT | V4L2_CAP_STREAMING;
    SFM_CHECK_EQ_INT(sfm_v4l2_open_sys("/dev/video9", NULL, &sys, &c), SFM_E_UNSUPPORTED);
    s.caps = V4L2_CAP_VIDEO_CAPTURE | V4L2_CAP_READWRITE;
    SFM_CHECK_EQ_INT(sfm_v4l2_open_sys("/dev/video9", NULL, &sys, &c), SFM_E_UNSUPPORTED);
    check_released(t, &s);
    SFM_CHECK(c == NULL);
    /* argument checks */
    SFM_CHECK_EQ_INT(sfm_v4l2_open_sys(NULL, NULL, &sys, &c), SFM_E_ARGUMENT);
    SFM_CHECK_EQ_INT(sfm_v4l2_open_sys("/dev/video9", NULL, &sys, NULL), SFM_E_ARGUMENT);
    sfm_v4l2_options bad = {.width = -1};
    SFM_CHECK_EQ_INT(sfm_v4l2_open_sys("/dev/video9", &bad, &sys, &c), SFM_E_ARGUMENT);
    sfm_v4l2_options badfmt = {.format = SFM_PIX_RGB24};
    SFM_CHECK_EQ_INT(sfm_v4l2_open_sys("/dev/video9", &badfmt, &sys, &c), SFM_E_ARGUMENT);
    SFM_CHECK_EQ_INT(s.open_fds, 0);
}

SFM_TEST(v4l2_real_device_node_absent)
{
    /* Through the real system calls: a missing node is SFM_E_NO_DEVICE, and
     * a file that is not a device is refused without hanging. */
    sfm_capture *c = NULL;
    SFM_CHECK_EQ_INT(sfm_capture_open_v4l2("/dev/sfm-no-such-video", NULL, &c), SFM_E_NO_DEVICE);
    int rc = sfm_capture_open_v4l2("/dev/null", NULL, &c);
    SFM_CHECK_MSG(rc == SFM_E_UNSUPPORTED || rc == SFM_E_IO, "/dev/null: %d", rc);
    SFM_CHECK(c == NULL);
}
