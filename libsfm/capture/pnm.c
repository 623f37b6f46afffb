/* PGM/PPM (Netpbm) reading and writing. Format as specified by Netpbm:
 * magic P2/P3 (ASCII) or P5/P6 (binary), then width, height and maxval as
 * decimal tokens separated by whitespace with '#' comments up to the end of
 * a line, then exactly one whitespace byte and the raster; samples wider
 * than 8 bits (maxval > 255) are two bytes, most significant first. */
#define _POSIX_C_SOURCE 200809L
#include <errno.h>
#include <fcntl.h>
#include <stdio.h>
#include <string.h>
#include <unistd.h>

#include "capture/capture_impl.h"

static int is_space(uint8_t c)
{
    return c == ' ' || c == '\t' || c == '\n' || c == '\r' || c == '\v' || c == '\f';
}

/* Skips whitespace and comments; reads one unsigned decimal token of at most
 * `limit`. Returns SFM_OK, SFM_E_FORMAT (none, not a number, over limit). */
static int read_uint(const uint8_t *buf, size_t len, size_t *pos, unsigned long limit,
                     unsigned long *out)
{
    size_t p = *pos;
    for (;;) {
        while (p < len && is_space(buf[p]))
            p++;
        if (p < len && buf[p] == '#') {
            while (p < len && buf[p] != '\n' && buf[p] != '\r')
                p++;
            continue;
        }
        break;
    }
    if (p >= len || buf[p] < '0' || buf[p] > '9')
        return SFM_E_FORMAT;
    unsigned long v = 0;
    while (p < len && buf[p] >= '0' && buf[p] <= '9') {
        v = v * 10 + (unsigned long)(buf[p] - '0');
        if (v > limit)
            return SFM_E_FORMAT;
        p++;
    }
    *pos = p;
    *out = v;
    return SFM_OK;
}

int sfm_pnm_parse_header(const uint8_t *buf, size_t len, sfm_image_header *out)
{
    if (buf == NULL || out == NULL)
        return SFM_E_ARGUMENT;
    if (len < 3 || buf[0] != 'P')
        return SFM_E_FORMAT;
    int channels, binary;
    switch (buf[1]) {
    case '2': channels = 1; binary = 0; break;
    case '3': channels = 3; binary = 0; break;
    case '5': channels = 1; binary = 1; break;
    case '6': channels = 3; binary = 1; break;
    default: return SFM_E_FORMAT;
    }
    size_t p = 2;
    if (!is_space(buf[p]) && buf[p] != '#')
        return SFM_E_FORMAT;
    unsigned long w, h, maxval;
    /* Sides are read up to a large bound so that "too big" (capacity) and
     * "not a number" (format) are told apart. */
    if (read_uint(buf, len, &p, 1000000000ul, &w) != SFM_OK ||
        read_uint(buf, len, &p, 1000000000ul, &h) != SFM_OK ||
        read_uint(buf, len, &p, 65535ul, &maxval) != SFM_OK)
        return SFM_E_FORMAT;
    if (w == 0 || h == 0 || maxval == 0)
        return SFM_E_FORMAT;
    if (w > SFM_CAPTURE_MAX_SIDE || h > SFM_CAPTURE_MAX_SIDE)
        return SFM_E_CAPACITY;
    if (p >= len || !is_space(buf[p]))
        return SFM_E_FORMAT; /* the single whitespace before the raster */
    p++;
    if (binary) {
        size_t bps = maxval > 255 ? 2 : 1;
        size_t need = (size_t)w * (size_t)h * (size_t)channels * bps;
        if (len - p < need)
            return SFM_E_FORMAT;
    }
    out->width = (int)w;
    out->height = (int)h;
    out->channels = channels;
    out->maxval = (int)maxval;
    out->binary = binary;
    out->data_offset = p;
    return SFM_OK;
}

static uint8_t scale8(unsigned v, unsigned maxval)
{
    if (v > maxval)
        v = maxval; /* out-of-range samples saturate */
    if (maxval == 255)
        return (uint8_t)v;
    return (uint8_t)((v * 255u + maxval / 2u) / maxval);
}

int sfm_pnm_decode_gray(const uint8_t *buf, size_t len, uint8_t *dst, int dst_width,
                        int dst_height, int dst_stride)
{
    if (buf == NULL || dst == NULL || dst_width <= 0 || dst_height <= 0 ||
        dst_stride < dst_width)
        return SFM_E_ARGUMENT;
    sfm_image_header hd;
    int rc = sfm_pnm_parse_header(buf, len, &hd);
    if (rc != SFM_OK)
        return rc;
    if (hd.width != dst_width || hd.height != dst_height)
        return SFM_E_FORMAT;
    const unsigned maxval = (unsigned)hd.maxval;
    const int ch = hd.channels;
    size_t p = hd.data_offset;
    if (hd.binary && maxval == 255 && ch == 1) {
        sfm_gray_copy(buf + p, hd.width, hd.width, hd.height, dst, dst_stride);
        return SFM_OK;
    }
    if (hd.binary && maxval == 255 && ch == 3) {
        sfm_gray_from_rgb24(buf + p, 3 * hd.width, hd.width, hd.height, dst, dst_stride);
        return SFM_OK;
    }
    const size_t bps = maxval > 255 ? 2 : 1;
    for (int y = 0; y < hd.height; y++) {
        uint8_t *d = dst + (size_t)y * (size_t)dst_stride;
        for (int x = 0; x < hd.width; x++) {
            unsigned s[3];
            for (int k = 0; k < ch; k++) {
                if (hd.binary) {
                    s[k] = bps == 2 ? ((unsigned)buf[p] << 8 | buf[p + 1]) : buf[p];
                    p += bps;
                } else {
                    unsigned long v;
                    if (read_uint(buf, len, &p, 65535ul, &v) != SFM_OK)
                        return SFM_E_FORMAT;
                    s[k] = (unsigned)v;
                }
            }
            if (ch == 1) {
                d[x] = scale8(s[0], maxval);
            } else {
                unsigned v = 77u * scale8(s[0], maxval) + 150u * scale8(s[1], maxval) +
                             29u * scale8(s[2], maxval) + 128u;
                d[x] = (uint8_t)(v >> 8);
            }
        }
    }
    return SFM_OK;
}

static int write_all(int fd, const uint8_t *p, size_t n)
{
    while (n > 0) {
        ssize_t k = write(fd, p, n);
        if (k < 0) {
            if (errno == EINTR)
                continue;
            return -1;
        }
        p += k;
        n -= (size_t)k;
    }
    return 0;
}

int sfm_pnm_write(const char *path, const uint8_t *src, int w, int h, int stride,
                  int channels)
{
    char head[64];
    int n = snprintf(head, sizeof head, "P%c\n%d %d\n255\n", channels == 3 ? '6' : '5', w, h);
    int fd = open(path, O_WRONLY | O_CREAT | O_TRUNC | O_CLOEXEC, 0644);
    if (fd < 0)
        return SFM_E_IO;
    int bad = write_all(fd, (const uint8_t *)head, (size_t)n);
    size_t row = (size_t)w * (size_t)channels;
    if (!bad && (size_t)stride == row) {
        bad = write_all(fd, src, row * (size_t)h);
    } else {
        for (int y = 0; y < h && !bad; y++)
            bad = write_all(fd, src + (size_t)y * (size_t)stride, row);
    }
    if (close(fd) != 0)
        bad = 1;
    return bad ? SFM_E_IO : SFM_OK;
}
