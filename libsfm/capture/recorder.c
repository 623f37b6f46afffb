/* Recorder: frames to a replay directory (one image per frame plus
 * manifest.csv, each row written as soon as its image is on disk, so a
 * recording cut short still replays up to its last complete frame). */
#define _POSIX_C_SOURCE 200809L
#include <errno.h>
#include <fcntl.h>
#include <inttypes.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/stat.h>
#include <unistd.h>

#include "capture/capture_impl.h"

struct sfm_recorder {
    char dir[SFM_CAPTURE_PATH_MAX];
    int fd; /* manifest */
    int image_format;
    int count;
    int failed;
    int64_t last_ts;
    uint64_t last_seq;
    int width, height, format; /* of the first frame; every later one matches */
};

static int write_all(int fd, const char *p, size_t n)
{
    while (n > 0) {
        ssize_t k = write(fd, p, n);
        if (k < 0) {
            if (errno == EINTR)
                continue;
            return SFM_E_IO;
        }
        p += k;
        n -= (size_t)k;
    }
    return SFM_OK;
}

int sfm_recorder_open(const char *dir, int image_format, sfm_recorder **out)
{
    if (dir == NULL || out == NULL || dir[0] == '\0' ||
        strlen(dir) >= SFM_CAPTURE_PATH_MAX - 32)
        return SFM_E_ARGUMENT;
    if (image_format != SFM_RECORD_PGM && image_format != SFM_RECORD_PNG &&
        image_format != SFM_RECORD_JPEG)
        return SFM_E_ARGUMENT;
#ifndef SFM_HAVE_LIBPNG
    if (image_format == SFM_RECORD_PNG)
        return SFM_E_UNSUPPORTED;
#endif
#ifndef SFM_HAVE_LIBJPEG
    if (image_format == SFM_RECORD_JPEG)
        return SFM_E_UNSUPPORTED;
#endif
    if (mkdir(dir, 0755) != 0 && errno != EEXIST)
        return SFM_E_IO;
    struct stat st;
    if (stat(dir, &st) != 0 || !S_ISDIR(st.st_mode))
        return SFM_E_IO;
    char path[SFM_CAPTURE_PATH_MAX + 32];
    snprintf(path, sizeof path, "%s/manifest.csv", dir);
    int fd = open(path, O_WRONLY | O_CREAT | O_EXCL | O_CLOEXEC, 0644);
    if (fd < 0)
        return errno == EEXIST ? SFM_E_ARGUMENT : SFM_E_IO;
    static const char head[] = "sequence,timestamp_ns,file\n";
    sfm_recorder *r = calloc(1, sizeof *r);
    if (r == NULL || write_all(fd, head, sizeof head - 1) != SFM_OK) {
        free(r);
        close(fd);
        unlink(path);
        return SFM_E_IO;
    }
    sfm_capture_strlcpy(r->dir, sizeof r->dir, dir);
    r->fd = fd;
    r->image_format = image_format;
    *out = r;
    return SFM_OK;
}

int sfm_recorder_write(sfm_recorder *r, const sfm_frame *f)
{
    if (r == NULL || f == NULL || f->data == NULL || f->width <= 0 || f->height <= 0 ||
        f->width > SFM_CAPTURE_MAX_SIDE || f->height > SFM_CAPTURE_MAX_SIDE ||
        (f->format != SFM_PIX_GRAY8 && f->format != SFM_PIX_RGB24) || f->timestamp_ns < 0)
        return SFM_E_ARGUMENT;
    const int ch = f->format == SFM_PIX_RGB24 ? 3 : 1;
    if (f->stride < f->width * ch)
        return SFM_E_ARGUMENT;
    if (r->count > 0 && (f->timestamp_ns < r->last_ts || f->sequence <= r->last_seq))
        return SFM_E_ARGUMENT;
    /* Replay plays frames of one size; one format keeps the files of one
     * recording alike (gray stays gray). */
    if (r->count > 0 && (f->width != r->width || f->height != r->height || f->format != r->format))
        return SFM_E_ARGUMENT;
    if (r->failed)
        return SFM_E_IO;
    static const char *ext[] = {"pgm", "png", "jpg"};
    const char *e = r->image_format == SFM_RECORD_PGM && ch == 3 ? "ppm" : ext[r->image_format];
    char name[48], path[SFM_CAPTURE_PATH_MAX + 64];
    snprintf(name, sizeof name, "%08d.%s", r->count, e);
    snprintf(path, sizeof path, "%s/%s", r->dir, name);
    int rc;
    if (r->image_format == SFM_RECORD_PGM)
        rc = sfm_pnm_write(path, f->data, f->width, f->height, f->stride, ch);
    else if (r->image_format == SFM_RECORD_PNG)
        rc = sfm_png_write(path, f->data, f->width, f->height, f->stride, ch);
    else
        rc = sfm_jpeg_write(path, f->data, f->width, f->height, f->stride, ch, 95);
    if (rc == SFM_OK) {
        char row[128];
        int n = snprintf(row, sizeof row, "%" PRIu64 ",%" PRId64 ",%s\n", f->sequence,
                         f->timestamp_ns, name);
        rc = write_all(r->fd, row, (size_t)n);
        if (rc != SFM_OK)
            r->failed = 1; /* the manifest may now hold half a row */
    }
    if (rc != SFM_OK)
        return SFM_E_IO;
    if (r->count == 0) {
        r->width = f->width;
        r->height = f->height;
        r->format = f->format;
    }
    r->count++;
    r->last_ts = f->timestamp_ns;
    r->last_seq = f->sequence;
    return SFM_OK;
}

int sfm_recorder_count(const sfm_recorder *r) { return r ? r->count : SFM_E_ARGUMENT; }

int sfm_recorder_close(sfm_recorder *r)
{
    if (r == NULL)
        return SFM_OK;
    int rc = r->failed ? SFM_E_IO : SFM_OK;
    if (close(r->fd) != 0)
        rc = SFM_E_IO;
    free(r);
    return rc;
}
