/* Internal: the system calls the V4L2 source makes, as a table, so tests run
 * the adapter against a simulated driver. Each entry behaves as the system
 * call of the same name: -1 (MAP_FAILED for mmap) with errno set on failure.
 * now_ns is the clock poll timeouts are measured on (CLOCK_MONOTONIC). */
#ifndef SFM_CAPTURE_V4L2_SYS_H
#define SFM_CAPTURE_V4L2_SYS_H

#include <poll.h>
#include <stddef.h>
#include <stdint.h>
#include <sys/types.h>

#include "sfm/sfm_capture.h"

typedef struct sfm_v4l2_sys {
    void *ctx;
    int (*open)(void *ctx, const char *path, int flags);
    int (*close)(void *ctx, int fd);
    int (*ioctl)(void *ctx, int fd, unsigned long request, void *arg);
    void *(*mmap)(void *ctx, void *addr, size_t len, int prot, int flags, int fd, off_t off);
    int (*munmap)(void *ctx, void *addr, size_t len);
    int (*poll)(void *ctx, struct pollfd *fds, nfds_t nfds, int timeout_ms);
    int64_t (*now_ns)(void *ctx);
} sfm_v4l2_sys;

/* The real system calls. */
const sfm_v4l2_sys *sfm_v4l2_sys_default(void);

/* sfm_capture_open_v4l2 with the given table (copied). */
int sfm_v4l2_open_sys(const char *device, const sfm_v4l2_options *opt, const sfm_v4l2_sys *sys,
                      sfm_capture **out);

/* Most driver buffers used. */
#define SFM_V4L2_MAX_BUFFERS 32
/* Consecutive EINTR answers after which a call is reported as failed. */
#define SFM_V4L2_EINTR_LIMIT 100000

#endif
