/* Replay: a recorded directory played through the frame-source interface.
 * Everything is allocated at open (manifest rows, one file buffer as large
 * as the largest file, one gray frame); acquire reads and decodes into them. */
#define _POSIX_C_SOURCE 200809L
#define _XOPEN_SOURCE 700 /* realpath */
#include <errno.h>
#include <fcntl.h>
#include <limits.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/stat.h>
#include <unistd.h>

#include "capture/capture_impl.h"

typedef struct replay {
    char dir[SFM_CAPTURE_PATH_MAX];
    char real_dir[PATH_MAX]; /* dir with every symbolic link resolved */
    sfm_manifest_entry *rows;
    unsigned char *in_data; /* per row: the file is under "data/" */
    int n, next;
    uint8_t *file;
    size_t file_cap;
    uint8_t *gray;
    int w, h;
    sfm_jpeg_decoder *jpeg;
    sfm_replay_options opt;
    int started;
    int64_t t0_wall, ts0;
    uint64_t played;     /* frames delivered since the clock started */
    uint64_t loops;
    int have_last;
    uint64_t last_seq;
    int64_t span_ns;     /* last - first timestamp + one mean period */
    uint64_t seq_span;
} replay;

enum { KIND_PNM, KIND_PNG, KIND_JPEG, KIND_UNKNOWN };

static int kind_of(const uint8_t *b, size_t n)
{
    if (n >= 2 && b[0] == 'P' && b[1] >= '2' && b[1] <= '6')
        return KIND_PNM;
    if (n >= 8 && memcmp(b, "\x89PNG\r\n\x1a\n", 8) == 0)
        return KIND_PNG;
    if (n >= 3 && b[0] == 0xff && b[1] == 0xd8 && b[2] == 0xff)
        return KIND_JPEG;
    return KIND_UNKNOWN;
}

static int row_path(const replay *r, int i, char *path, size_t cap)
{
    int k = snprintf(path, cap, "%s/%s%s", r->dir, r->in_data[i] ? "data/" : "",
                     r->rows[i].file);
    return (k < 0 || (size_t)k >= cap) ? SFM_E_ARGUMENT : SFM_OK;
}

/* The resolved path of row i's file in out (PATH_MAX bytes): SFM_E_IO when
 * it does not resolve, SFM_E_FORMAT when it lies outside the recording
 * directory (a symbolic link, or a symlinked "data/", pointing elsewhere). */
static int frame_path(const replay *r, int i, char *out)
{
    char path[2 * SFM_CAPTURE_PATH_MAX + 8];
    int rc = row_path(r, i, path, sizeof path);
    if (rc != SFM_OK)
        return rc;
    if (realpath(path, out) == NULL)
        return SFM_E_IO;
    const size_t k = strlen(r->real_dir);
    const int root = k == 1; /* the directory is "/" */
    if (strncmp(out, r->real_dir, k) != 0 || (!root && out[k] != '/'))
        return SFM_E_FORMAT;
    return SFM_OK;
}

/* Reads path into buf (cap bytes); SFM_E_IO, or SFM_E_FORMAT if larger.
 * nofollow: refuse a final symbolic link (a resolved path that changed). */
static int read_file(const char *path, uint8_t *buf, size_t cap, size_t *len, int nofollow)
{
    int fd = open(path, O_RDONLY | O_CLOEXEC | (nofollow ? O_NOFOLLOW : 0));
    if (fd < 0)
        return SFM_E_IO;
    size_t n = 0;
    for (;;) {
        if (n == cap) { /* full: must be at the end */
            uint8_t extra;
            ssize_t k = read(fd, &extra, 1);
            close(fd);
            if (k != 0)
                return SFM_E_FORMAT;
            break;
        }
        ssize_t k = read(fd, buf + n, cap - n);
        if (k < 0 && errno == EINTR)
            continue;
        if (k < 0) {
            close(fd);
            return SFM_E_IO;
        }
        if (k == 0) {
            close(fd);
            break;
        }
        n += (size_t)k;
    }
    *len = n;
    return SFM_OK;
}

/* Size of an image held in buf. */
static int image_size(replay *r, const uint8_t *buf, size_t n, int *w, int *h)
{
    switch (kind_of(buf, n)) {
    case KIND_PNM: {
        sfm_image_header hd;
        int rc = sfm_pnm_parse_header(buf, n, &hd);
        if (rc != SFM_OK)
            return rc;
        *w = hd.width;
        *h = hd.height;
        return SFM_OK;
    }
    case KIND_PNG: return sfm_png_size(buf, n, w, h);
    case KIND_JPEG:
        return r->jpeg ? sfm_jpeg_size(r->jpeg, buf, n, w, h) : SFM_E_UNSUPPORTED;
    default: return SFM_E_FORMAT;
    }
}

static int decode(replay *r, const uint8_t *buf, size_t n)
{
    switch (kind_of(buf, n)) {
    case KIND_PNM: return sfm_pnm_decode_gray(buf, n, r->gray, r->w, r->h, r->w);
    case KIND_PNG: return sfm_png_decode_gray(buf, n, r->w, r->h, r->gray, r->w);
    case KIND_JPEG:
        return r->jpeg ? sfm_jpeg_decode_gray(r->jpeg, buf, n, r->w, r->h, r->gray, r->w)
                       : SFM_E_UNSUPPORTED;
    default: return SFM_E_FORMAT;
    }
}

static void replay_free(replay *r)
{
    if (r == NULL)
        return;
    free(r->rows);
    free(r->in_data);
    free(r->file);
    free(r->gray);
    sfm_jpeg_decoder_free(r->jpeg);
    free(r);
}

static int replay_acquire(sfm_capture *c, int timeout_ms, sfm_frame *frame)
{
    replay *r = c->impl;
    if (r->next >= r->n) {
        if (!r->opt.loop)
            return 0;
        r->next = 0;
        r->loops++;
    }
    const sfm_manifest_entry *e = &r->rows[r->next];
    const int64_t ts = e->timestamp_ns + (int64_t)r->loops * r->span_ns;
    if (r->opt.rate != SFM_REPLAY_ASAP) {
        int64_t now = sfm_capture_now_ns();
        if (!r->started) {
            r->started = 1;
            r->t0_wall = now;
            r->ts0 = ts;
        }
        int64_t due;
        if (r->opt.rate == SFM_REPLAY_RECORDED)
            due = r->t0_wall + (int64_t)((double)(ts - r->ts0) / r->opt.speed);
        else
            due = r->t0_wall + (int64_t)((double)r->played * 1e9 / r->opt.fixed_fps);
        if (due > now) {
            if (timeout_ms >= 0 && due - now > (int64_t)timeout_ms * 1000000) {
                sfm_capture_sleep_ns((int64_t)timeout_ms * 1000000);
                return SFM_E_TIMEOUT;
            }
            sfm_capture_sleep_ns(due - now);
        }
    }
    char path[PATH_MAX];
    const int i = r->next++;
    size_t len = 0;
    int rc = frame_path(r, i, path);
    if (rc == SFM_OK)
        rc = read_file(path, r->file, r->file_cap, &len, 1);
    if (rc == SFM_OK)
        rc = decode(r, r->file, len);
    /* A frame that fails to decode is an error, not a drop: the sequence
     * moves on either way. */
    const uint64_t seq = e->sequence + r->loops * r->seq_span;
    if (r->have_last && seq > r->last_seq + 1)
        c->stats.drops += seq - r->last_seq - 1;
    r->have_last = 1;
    r->last_seq = seq;
    if (rc != SFM_OK) {
        c->stats.errors++;
        return rc == SFM_E_ARGUMENT ? SFM_E_IO : rc;
    }
    r->played++;
    frame->data = r->gray;
    frame->width = r->w;
    frame->height = r->h;
    frame->stride = r->w;
    frame->format = SFM_PIX_GRAY8;
    frame->timestamp_ns = ts;
    frame->sequence = seq;
    frame->slot = 0;
    return 1;
}

static int replay_release(sfm_capture *c, const sfm_frame *frame)
{
    (void)c;
    (void)frame;
    return SFM_OK;
}

static void replay_destroy(sfm_capture *c) { replay_free(c->impl); }

static const sfm_capture_vtbl replay_vt = {replay_acquire, replay_release, replay_destroy};

/* Reads a whole small text file into a fresh NUL-terminated buffer. */
static int slurp(const char *path, char **out, size_t *len)
{
    struct stat st;
    if (stat(path, &st) != 0 || !S_ISREG(st.st_mode))
        return SFM_E_NO_DEVICE;
    if (st.st_size > (off_t)1 << 30)
        return SFM_E_CAPACITY;
    char *buf = malloc((size_t)st.st_size + 1);
    if (buf == NULL)
        return SFM_E_IO;
    size_t n = 0;
    int rc = read_file(path, (uint8_t *)buf, (size_t)st.st_size, &n, 0);
    if (rc != SFM_OK) {
        free(buf);
        return SFM_E_IO;
    }
    buf[n] = '\0';
    *out = buf;
    *len = n;
    return SFM_OK;
}

int sfm_capture_open_replay(const char *dir, const sfm_replay_options *opt, sfm_capture **out)
{
    if (dir == NULL || out == NULL || dir[0] == '\0' ||
        strlen(dir) >= SFM_CAPTURE_PATH_MAX)
        return SFM_E_ARGUMENT;
    sfm_replay_options o = {SFM_REPLAY_ASAP, 0.0, 1.0, 0};
    if (opt) {
        o = *opt;
        if (o.speed == 0.0)
            o.speed = 1.0;
        if ((o.rate != SFM_REPLAY_ASAP && o.rate != SFM_REPLAY_RECORDED &&
             o.rate != SFM_REPLAY_FIXED) ||
            !(o.speed > 0.0 && o.speed < 1e6) ||
            (o.rate == SFM_REPLAY_FIXED && !(o.fixed_fps > 0.0 && o.fixed_fps < 1e6)))
            return SFM_E_ARGUMENT;
    }
    struct stat st;
    if (stat(dir, &st) != 0 || !S_ISDIR(st.st_mode))
        return SFM_E_NO_DEVICE;

    replay *r = calloc(1, sizeof *r);
    if (r == NULL)
        return SFM_E_IO;
    sfm_capture_strlcpy(r->dir, sizeof r->dir, dir);
    r->opt = o;
    char path[2 * SFM_CAPTURE_PATH_MAX + 8], resolved[PATH_MAX];
    int rc;
    char *text = NULL;
    size_t tlen = 0;
    if (realpath(dir, r->real_dir) == NULL) {
        rc = SFM_E_IO;
        goto fail;
    }
    snprintf(path, sizeof path, "%s/manifest.csv", dir);
    rc = slurp(path, &text, &tlen);
    if (rc == SFM_E_NO_DEVICE) {
        snprintf(path, sizeof path, "%s/data.csv", dir);
        rc = slurp(path, &text, &tlen);
    }
    if (rc != SFM_OK)
        goto fail;
    rc = sfm_manifest_parse(text, tlen, NULL, 0);
    if (rc == 0)
        rc = SFM_E_FORMAT; /* nothing to play */
    if (rc < 0)
        goto fail;
    r->n = rc;
    r->rows = calloc((size_t)r->n, sizeof *r->rows);
    r->in_data = calloc((size_t)r->n, 1);
    if (r->rows == NULL || r->in_data == NULL) {
        rc = SFM_E_IO;
        goto fail;
    }
    rc = sfm_manifest_parse(text, tlen, r->rows, r->n);
    if (rc < 0)
        goto fail;
    free(text);
    text = NULL;

    /* Every file must exist now; the largest sizes the read buffer. */
    size_t biggest = 0;
    for (int i = 0; i < r->n; i++) {
        int found = 0;
        for (int in_data = 0; in_data < 2 && !found; in_data++) {
            r->in_data[i] = (unsigned char)in_data;
            if (row_path(r, i, path, sizeof path) == SFM_OK && stat(path, &st) == 0 &&
                S_ISREG(st.st_mode))
                found = 1;
        }
        if (!found) {
            rc = SFM_E_IO;
            goto fail;
        }
        rc = frame_path(r, i, resolved);
        if (rc != SFM_OK)
            goto fail;
        if (st.st_size > (off_t)1 << 30) {
            rc = SFM_E_CAPACITY;
            goto fail;
        }
        if ((size_t)st.st_size > biggest)
            biggest = (size_t)st.st_size;
    }
    r->file_cap = biggest ? biggest : 1;
    r->file = malloc(r->file_cap);
    r->jpeg = sfm_jpeg_decoder_new(); /* NULL without libjpeg: JPEG unsupported */
    if (r->file == NULL) {
        rc = SFM_E_IO;
        goto fail;
    }
    size_t len = 0;
    rc = frame_path(r, 0, resolved);
    if (rc == SFM_OK)
        rc = read_file(resolved, r->file, r->file_cap, &len, 1);
    if (rc == SFM_OK)
        rc = image_size(r, r->file, len, &r->w, &r->h);
    if (rc != SFM_OK)
        goto fail;
    if (r->w <= 0 || r->h <= 0 || r->w > SFM_CAPTURE_MAX_SIDE || r->h > SFM_CAPTURE_MAX_SIDE) {
        rc = (r->w > 0 && r->h > 0) ? SFM_E_CAPACITY : SFM_E_FORMAT;
        goto fail;
    }
    r->gray = malloc((size_t)r->w * (size_t)r->h);
    if (r->gray == NULL) {
        rc = SFM_E_IO;
        goto fail;
    }
    const int64_t first = r->rows[0].timestamp_ns, last = r->rows[r->n - 1].timestamp_ns;
    r->span_ns = last - first + (r->n > 1 ? (last - first) / (r->n - 1) : 1);
    if (r->span_ns <= 0)
        r->span_ns = 1;
    r->seq_span = r->rows[r->n - 1].sequence + 1;

    sfm_capture *c = sfm_capture_new(&replay_vt, r);
    if (c == NULL) {
        rc = SFM_E_IO;
        goto fail;
    }
    c->info.width = r->w;
    c->info.height = r->h;
    c->info.source_format = SFM_PIX_GRAY8;
    if (r->n > 1 && last > first) {
        /* mean frame interval as a rational (n-1) frames per (last-first) ns */
        double fps = (double)(r->n - 1) * 1e9 / (double)(last - first);
        c->info.fps_num = (int)(fps * 1000.0 + 0.5);
        c->info.fps_den = 1000;
    }
    sfm_capture_strlcpy(c->info.driver, sizeof c->info.driver, "replay");
    sfm_capture_strlcpy(c->info.card, sizeof c->info.card, dir);
    *out = c;
    return SFM_OK;
fail:
    free(text);
    replay_free(r);
    return rc;
}
