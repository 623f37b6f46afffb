/*
 * libsfm capture: frame sources (file replay, V4L2, libcamera), a recorder,
 * and the image parsers and pixel-format converters behind them.
 *
 * This is a separate library, libsfm_capture.{a,so}, built on the core only
 * (status codes of sfm_common.h). Unlike the core it allocates, but only when
 * a source or recorder is opened; acquire/release never allocate in libsfm's
 * own code (decoding PNG or JPEG runs libpng/libjpeg, which manage their own
 * memory per image).
 *
 * One interface for every source:
 *
 *   sfm_capture *c;
 *   sfm_capture_open_replay("run1", NULL, &c);       (or _v4l2, _libcamera)
 *   sfm_frame f;
 *   while (sfm_capture_acquire(c, 1000, &f) == 1) {  (0: end of stream)
 *       ... f.data, f.width, f.height, f.stride, f.timestamp_ns ...
 *       sfm_capture_release(c, &f);                  (requeues the buffer)
 *   }
 *   sfm_capture_close(c);
 *
 * A frame is a borrowed view, valid until it is released; one frame may be
 * held at a time. Frames are delivered as 8-bit gray (SFM_PIX_GRAY8) whatever
 * the source format: GREY and NV12 are handed out without a copy (the luma
 * plane of the driver's buffer), YUYV, RGB24 and MJPEG are converted into a
 * buffer owned by the source.
 *
 * A source is not thread-safe: one thread acquires and releases. Distinct
 * sources are independent.
 */
#ifndef SFM_CAPTURE_H
#define SFM_CAPTURE_H

#include "sfm/sfm_common.h"

#ifdef __cplusplus
extern "C" {
#endif

/* Longest path (bytes, with the terminating NUL) a manifest entry, a replay
 * directory or a device name may have. */
#define SFM_CAPTURE_PATH_MAX 512

/* Largest frame side accepted from any file or device. */
#define SFM_CAPTURE_MAX_SIDE 16384

/* Pixel formats (values pinned). */
typedef enum sfm_pixfmt {
    SFM_PIX_GRAY8 = 1, /* 8-bit luma, one byte per pixel (V4L2 GREY) */
    SFM_PIX_YUYV = 2,  /* packed 4:2:2, Y0 U Y1 V (V4L2 YUYV) */
    SFM_PIX_NV12 = 3,  /* Y plane then interleaved UV plane at half size */
    SFM_PIX_MJPEG = 4, /* one JPEG image per frame (V4L2 MJPG / JPEG) */
    SFM_PIX_RGB24 = 5  /* packed R G B, one byte each (PPM) */
} sfm_pixfmt;

/* A borrowed view of one frame. Valid until sfm_capture_release(). */
typedef struct sfm_frame {
    const uint8_t *data; /* first byte of row 0 */
    int width;
    int height;
    int stride;          /* bytes from one row to the next (>= width) */
    int format;          /* sfm_pixfmt; SFM_PIX_GRAY8 for every source */
    int64_t timestamp_ns; /* capture time (device clock, or the manifest) */
    uint64_t sequence;   /* source sequence number: gaps are drops */
    int slot;            /* internal: which buffer this view belongs to */
} sfm_frame;

/* Counters since open. */
typedef struct sfm_capture_stats {
    uint64_t frames; /* frames delivered by acquire */
    uint64_t drops;  /* frames missing from the sequence numbers */
    uint64_t errors; /* frames discarded: flagged in error, short, undecodable */
} sfm_capture_stats;

/* What a source granted when it was opened. */
typedef struct sfm_capture_info {
    int width;
    int height;
    int source_format;     /* sfm_pixfmt the source produces */
    uint32_t fourcc;       /* V4L2 fourcc where there is one, else 0 */
    int source_stride;     /* bytes per line of the source buffer (0: n/a) */
    int buffers;           /* driver buffers in use (0 for replay) */
    int fps_num, fps_den;  /* frame interval den/num seconds; 0/0 unknown */
    char driver[32];       /* "replay", "v4l2:<driver>", "libcamera" */
    char card[64];         /* device or camera name, or the directory */
    int adjusted;          /* 1 when the device changed what was asked (V4L2
                              S_FMT, libcamera validate() "Adjusted") */
} sfm_capture_info;

typedef struct sfm_capture sfm_capture;

/* ----------------------------------------------------------------------- */
/* The frame-source interface. */

/* Waits up to timeout_ms (< 0: forever, 0: poll once) for the next frame.
 * Returns 1 and fills *frame, 0 at the end of a finite stream (replay),
 * or SFM_E_ARGUMENT (NULL, or a frame is still held), SFM_E_TIMEOUT,
 * SFM_E_DEVICE_LOST (the device went away: every kernel resource is already
 * released; only sfm_capture_close() remains to do), SFM_E_IO, SFM_E_FORMAT
 * (replay: a file that does not decode or changes size). On failure *frame
 * is untouched. */
SFM_API int sfm_capture_acquire(sfm_capture *c, int timeout_ms, sfm_frame *frame);

/* Gives the frame back (requeues the driver buffer). Returns SFM_OK,
 * SFM_E_ARGUMENT (NULL, or not the frame held), SFM_E_DEVICE_LOST, SFM_E_IO. */
SFM_API int sfm_capture_release(sfm_capture *c, const sfm_frame *frame);

/* Stops streaming and frees everything; NULL is accepted. A frame still held
 * becomes invalid. */
SFM_API void sfm_capture_close(sfm_capture *c);

/* Returns SFM_OK or SFM_E_ARGUMENT. */
SFM_API int sfm_capture_get_stats(const sfm_capture *c, sfm_capture_stats *out);
SFM_API int sfm_capture_get_info(const sfm_capture *c, sfm_capture_info *out);

/* ----------------------------------------------------------------------- */
/* Replay: a directory with a manifest and one image file per frame.
 *
 * The manifest is "manifest.csv" (else "data.csv", the EuRoC layout): lines
 * starting with '#' are comments; an optional header line names the columns;
 * each row is either "sequence,timestamp_ns,file" or "timestamp_ns,file"
 * (sequence = row index). Timestamps are integers in nanoseconds and never
 * decrease. Files are relative to the directory (else to its "data/"
 * subdirectory); absolute names and ".." are refused, and so is a file whose
 * resolved path (symbolic links followed, the directory's own path resolved
 * first) lies outside the directory: SFM_E_FORMAT at open, or from acquire
 * for a file replaced after open. Images are PGM/PPM
 * (P2, P3, P5, P6; 8 or 16 bits), PNG or JPEG; every frame has the size of
 * the first. */

#define SFM_REPLAY_ASAP 0     /* deliver as fast as acquire is called */
#define SFM_REPLAY_RECORDED 1 /* at the recorded pace (timestamp differences) */
#define SFM_REPLAY_FIXED 2    /* at fixed_fps */

typedef struct sfm_replay_options {
    int rate;         /* SFM_REPLAY_* */
    double fixed_fps; /* > 0 with SFM_REPLAY_FIXED */
    double speed;     /* SFM_REPLAY_RECORDED: 2.0 plays twice as fast; 0 = 1.0 */
    int loop;         /* nonzero: start again after the last frame */
} sfm_replay_options;

/* opt may be NULL (as fast as possible, no loop). Returns SFM_OK,
 * SFM_E_ARGUMENT, SFM_E_NO_DEVICE (no directory or no manifest), SFM_E_IO,
 * SFM_E_FORMAT (bad manifest, empty manifest, first image unreadable, a
 * file resolving outside the directory),
 * SFM_E_UNSUPPORTED (PNG/JPEG file in a build without that library),
 * SFM_E_CAPACITY (image larger than SFM_CAPTURE_MAX_SIDE). */
SFM_API int sfm_capture_open_replay(const char *dir, const sfm_replay_options *opt,
                                    sfm_capture **out);

/* ----------------------------------------------------------------------- */
/* V4L2 (Linux). Non-blocking open, mmap streaming, poll with timeout. */

typedef struct sfm_v4l2_options {
    int width, height; /* requested size; 0 = the driver's current size */
    int format;        /* sfm_pixfmt to request; 0 = the first the device
                          offers of GREY, NV12, YUYV, MJPEG */
    int buffers;       /* driver buffers to request; 0 = 4; fewer than 2
                          granted is refused */
    int fps;           /* requested frame rate; 0 = leave as is */
} sfm_v4l2_options;

/* device: a path such as "/dev/video0". opt may be NULL. Returns SFM_OK,
 * SFM_E_ARGUMENT, SFM_E_NO_DEVICE (no such device node), SFM_E_UNSUPPORTED
 * (not a streaming capture device, no usable pixel format, fewer than 2
 * buffers), SFM_E_DEVICE_LOST, SFM_E_IO. Nothing stays open on failure. */
SFM_API int sfm_capture_open_v4l2(const char *device, const sfm_v4l2_options *opt,
                                  sfm_capture **out);

/* ----------------------------------------------------------------------- */
/* libcamera (Raspberry Pi cameras and others). */

typedef struct sfm_libcamera_options {
    int width, height; /* 0 = the camera's default for the viewfinder role */
    int buffers;       /* 0 = 4 */
} sfm_libcamera_options;

/* Number of cameras libcamera reports (>= 0), SFM_E_UNSUPPORTED when this
 * build has no libcamera, SFM_E_IO when the camera manager does not start.
 * When ids is not NULL, copies up to max_ids camera ids of id_len bytes each
 * (truncated, NUL-terminated). */
SFM_API int sfm_libcamera_list(char *ids, int max_ids, int id_len);

/* camera_id: an id from sfm_libcamera_list, or NULL for the first camera.
 * Returns SFM_OK, SFM_E_ARGUMENT, SFM_E_NO_DEVICE (no such camera),
 * SFM_E_UNSUPPORTED (no libcamera in this build, or the configuration was
 * invalid), SFM_E_IO. */
SFM_API int sfm_capture_open_libcamera(const char *camera_id,
                                       const sfm_libcamera_options *opt,
                                       sfm_capture **out);

/* ----------------------------------------------------------------------- */
/* Recorder: frames from any source to a replay directory. */

#define SFM_RECORD_PGM 0 /* lossless, no library needed */
#define SFM_RECORD_PNG 1 /* lossless, libpng */
#define SFM_RECORD_JPEG 2 /* lossy, libjpeg (quality 95) */

typedef struct sfm_recorder sfm_recorder;

/* Creates dir if needed (one level) and its manifest.csv; refuses a directory
 * that already has a manifest. image_format: SFM_RECORD_*. Returns SFM_OK,
 * SFM_E_ARGUMENT, SFM_E_IO, SFM_E_UNSUPPORTED. */
SFM_API int sfm_recorder_open(const char *dir, int image_format, sfm_recorder **out);

/* Writes one SFM_PIX_GRAY8 or SFM_PIX_RGB24 frame as the next file and adds
 * its manifest row (sequence, timestamp_ns, file), flushed at once. Every
 * frame must have the width, height and format of the first (a replay plays
 * frames of one size). Returns SFM_OK, SFM_E_ARGUMENT (NULL, bad size or
 * format, a size or format other than the first frame's, timestamp going
 * back, sequence not increasing; nothing is written), SFM_E_IO. */
SFM_API int sfm_recorder_write(sfm_recorder *r, const sfm_frame *frame);

/* Frames written so far, or SFM_E_ARGUMENT. */
SFM_API int sfm_recorder_count(const sfm_recorder *r);

/* Closes the manifest; returns SFM_OK or SFM_E_IO (last write failed). NULL
 * is accepted. */
SFM_API int sfm_recorder_close(sfm_recorder *r);

/* ----------------------------------------------------------------------- */
/* Parsers and converters (byte buffers in, no allocation; fuzzed). */

typedef struct sfm_image_header {
    int width, height;
    int channels;      /* 1 (gray) or 3 (RGB) */
    int maxval;        /* PNM: 1..65535 (> 255 means two bytes per sample) */
    int binary;        /* PNM: 1 for P5/P6, 0 for P2/P3 */
    size_t data_offset; /* PNM: first byte after the header */
} sfm_image_header;

/* Parses a PGM/PPM header (P2, P3, P5, P6; comments allowed). Returns SFM_OK,
 * SFM_E_ARGUMENT, SFM_E_FORMAT (not PNM, bad or truncated header, binary data
 * shorter than the header promises), SFM_E_CAPACITY (side over
 * SFM_CAPTURE_MAX_SIDE). */
SFM_API int sfm_pnm_parse_header(const uint8_t *buf, size_t len, sfm_image_header *out);

/* Decodes a whole PGM/PPM into 8-bit gray (PPM: BT.601 luma; 16-bit and
 * maxval != 255 scaled to 0..255, rounded). dst holds height rows of
 * dst_stride >= width bytes. Returns SFM_OK or the statuses of
 * sfm_pnm_parse_header; on failure dst may be partly written for ASCII
 * files only. */
SFM_API int sfm_pnm_decode_gray(const uint8_t *buf, size_t len, uint8_t *dst,
                                int dst_width, int dst_height, int dst_stride);

/* One manifest row. */
typedef struct sfm_manifest_entry {
    uint64_t sequence;
    int64_t timestamp_ns;
    char file[SFM_CAPTURE_PATH_MAX];
} sfm_manifest_entry;

/* Parses a manifest (see replay above) held in text[0..len). With out NULL
 * and capacity 0 it only counts. Returns the number of rows (>= 0),
 * SFM_E_ARGUMENT, SFM_E_FORMAT (bad row, decreasing timestamp, unsafe or
 * too long file name), SFM_E_CAPACITY (more rows than capacity). On failure
 * nothing is written to out. */
SFM_API int sfm_manifest_parse(const char *text, size_t len, sfm_manifest_entry *out,
                               int capacity);

/* Bytes a source frame of this format and size needs at least (for NV12 and
 * YUYV with the given source stride; 0 = tightly packed), or 0 when the
 * format has no fixed size (MJPEG) or the arguments are bad. */
SFM_API size_t sfm_pixfmt_min_size(int format, int width, int height, int src_stride);

/* Converts one frame of src_len bytes to 8-bit gray: GRAY8 copy; YUYV and
 * NV12 take the luma; RGB24 uses BT.601 luma, (77 R + 150 G + 29 B + 128)
 * >> 8; MJPEG decodes the JPEG (its size must be width x height). src_stride
 * 0 means tightly packed. Returns SFM_OK, SFM_E_ARGUMENT, SFM_E_FORMAT (src
 * too short, undecodable or wrong-size JPEG), SFM_E_UNSUPPORTED (MJPEG in a
 * build without libjpeg). On failure dst is untouched, except after a JPEG
 * that fails part way through decoding. */
SFM_API int sfm_convert_to_gray(int format, const uint8_t *src, size_t src_len,
                                int width, int height, int src_stride, uint8_t *dst,
                                int dst_stride);

/* Name of a pixel format ("GRAY8", "YUYV", ...); "?" when unknown. */
SFM_API const char *sfm_pixfmt_name(int format);

#ifdef __cplusplus
}
#endif
#endif
