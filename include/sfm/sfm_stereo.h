/*
 * Dense stereo: rectification of a pair, disparity, disparity to 3D.
 *
 * Conventions (as the rest of the library):
 *  - poses are world-to-camera, x_cam = R * X_world + t; for a pair the
 *    world is camera 1, so camera 2 is x_cam2 = R * x_cam1 + t and its
 *    centre is c2 = -R^T t in camera 1's frame;
 *  - pixel origin at the centre of the top-left pixel, y down; images are
 *    8-bit gray, row-major with a stride in bytes;
 *  - rectified frames: x_rect_i = R_i * x_cam_i. Both rectified cameras
 *    share one rotation of the world, so their x axes lie along the
 *    baseline c2 - c1 and rectified image 1 is always the left one: a
 *    point at depth Z (rectified frame) has disparity
 *    d = u1 - u2 = f B / Z + (cx1 - cx2), B = |c2 - c1| > 0.
 *    When camera 2 lies left of or below camera 1 the rectified images are
 *    turned accordingly (Fusiello, Trucco, Verri, "A compact algorithm for
 *    rectification of stereo pairs", MVA 2000, take the new x axis along
 *    the baseline whatever its direction);
 *  - disparities are float, NaN where invalid (occluded, not unique,
 *    failed the left-right check, or outside the searchable range).
 *
 * Results are bit-identical across targets: the remap is integer
 * arithmetic on fixed-point maps, the matchers use integer costs, and the
 * few floating-point steps are IEEE + - * / only.
 */
#ifndef SFM_STEREO_H
#define SFM_STEREO_H

#include "sfm/sfm_camera.h"
#include "sfm/sfm_common.h"

#ifdef __cplusplus
extern "C" {
#endif

/* ---- Rectification -------------------------------------------------- */

typedef struct sfm_stereo_rectification {
    double R1[9], R2[9]; /* x_rect_i = R_i x_cam_i (row-major) */
    double K1[9], K2[9]; /* rectified pinhole intrinsics: same f and cy,
                            cx1 and cx2 may differ (each image centred) */
    double baseline;     /* B = |c2 - c1|, in the units of t */
    double Q[16];        /* (u1, v, d, 1) -> homogeneous point in rectified
                            camera 1's frame, as OpenCV's Q */
    int width, height;   /* size of the rectified images */
    int roi1[4], roi2[4]; /* x, y, w, h of the region where every rectified
                            pixel has a source pixel (inner rectangle) */
} sfm_stereo_rectification;

/* Rectifying rotations and new intrinsics for a calibrated pair (pinhole,
 * Brown-Conrady or Kannala-Brandt cameras). The new y axis is normal to the
 * baseline and to the mean optical axis of the two cameras, so the
 * rectified views turn as little as they can. One focal length f serves
 * both images; alpha chooses it as OpenCV's stereoRectify does: alpha = 0
 * scales so that every rectified pixel of the inner rectangles has a source
 * pixel, alpha = 1 so that every source pixel lands in the rectified image,
 * values between interpolate; alpha = -1 keeps the mean focal length of
 * the two cameras and centres the valid regions. out_width/out_height <= 0
 * mean the size of image 1.
 * Statuses: SFM_OK; SFM_E_ARGUMENT (NULL, sizes < 8 or > 32767, alpha
 * outside [0, 1] and not -1, R not a rotation to 1e-4: within that, the
 * nearest rotation is used); SFM_E_NONFINITE; SFM_E_SINGULAR
 * (baseline below 1e-9 of the camera distance scale, or the baseline along
 * the mean optical axis within 1 degree: the epipoles lie inside the images
 * and a planar rectification does not exist; or no part of the images is
 * visible after rectification). Nothing is written on failure. */
SFM_API int sfm_stereo_rectify(const sfm_camera *cam1, const sfm_camera *cam2, int width,
                               int height, const double R[9], const double t[3], double alpha,
                               int out_width, int out_height, sfm_stereo_rectification *out);

/* Map entries are source coordinates in 1/256 pixel (SFM_STEREO_MAP_ONE),
 * two int32 per rectified pixel (x then y), row-major; an entry whose x is
 * negative has no source pixel (its bilinear footprint leaves the image). */
#define SFM_STEREO_MAP_ONE 256

/* The remap table from rectified pixels of view i (rotation R_i, rectified
 * intrinsics K_i of `rect`, view 1 or 2) back to the source image of
 * camera `cam` (with its distortion), built once per camera pair. map holds
 * 2 * rect->width * rect->height int32.
 * Statuses: SFM_OK; SFM_E_ARGUMENT (NULL, view not 1 or 2, bad sizes);
 * SFM_E_NONFINITE. Nothing is written on failure. */
SFM_API int sfm_stereo_rectify_map(const sfm_camera *cam, int src_width, int src_height,
                                   const sfm_stereo_rectification *rect, int view,
                                   int32_t *map, size_t map_len);

/* The same table for a plane homography H (3x3, rectified pixel ->
 * source pixel is H^-1; give H as it maps source to rectified), for the
 * uncalibrated rectification below. Statuses as sfm_stereo_rectify_map,
 * and SFM_E_SINGULAR for a singular H. */
SFM_API int sfm_stereo_homography_map(const sfm_mat3 *H, int src_width, int src_height,
                                      int out_width, int out_height, int32_t *map,
                                      size_t map_len);

/* dst(x, y) = src(map(x, y)) with bilinear interpolation in 8-bit fixed
 * point (identical on every target); pixels without a source get `fill`.
 * Statuses: SFM_OK; SFM_E_ARGUMENT (NULL, sizes < 1, strides < widths). */
SFM_API int sfm_stereo_remap(const uint8_t *src, int src_width, int src_height, int src_stride,
                             const int32_t *map, int out_width, int out_height, uint8_t fill,
                             uint8_t *dst, int dst_stride);

/* Uncalibrated rectification from the fundamental matrix (x2^T F x1 = 0, in
 * pixels) and n >= 8 matches (pixels, n x 2), by Hartley's method
 * (Hartley & Zisserman, 2nd ed., section 11.12): H2 sends the epipole of
 * image 2 to infinity along x with the least distortion at the image
 * centre, H1 is the matching projective transform that minimises the sum of
 * squared horizontal disparities of the matches. Both map source pixels to
 * rectified pixels of the same size as the input. As above, rectified
 * image 1 is the left one.
 * Statuses: SFM_OK; SFM_E_ARGUMENT; SFM_E_NONFINITE; SFM_E_SINGULAR (F not
 * of rank 2, an epipole inside image 2's bounds enlarged by half, or
 * degenerate matches). Nothing is written on failure. */
SFM_API int sfm_stereo_rectify_uncalibrated(const sfm_mat3 *F, const double *x1,
                                            const double *x2, int n, int width, int height,
                                            sfm_mat3 *H1, sfm_mat3 *H2);

/* Rectify matched pixels of the source images (n x 2 each) and report the
 * vertical disparity after rectification: median and maximum |v1 - v2| in
 * rectified pixels over the matches that rectify. With `rect` NULL, H1 and
 * H2 (source -> rectified) are used instead. Returns the number of matches
 * used (>= 0) or a status (SFM_E_ARGUMENT, SFM_E_NONFINITE: a NaN/Inf match,
 * camera, rect rotation or intrinsic, or H). */
SFM_API int sfm_stereo_rectification_error(const sfm_camera *cam1, const sfm_camera *cam2,
                                           const sfm_stereo_rectification *rect,
                                           const sfm_mat3 *H1, const sfm_mat3 *H2,
                                           const double *x1, const double *x2, int n,
                                           double *median_dy, double *max_dy);

/* ---- Disparity --------------------------------------------------------- */

/* Largest disparity range (multiple of 8) and image width the matchers
 * accept; cost counters are 16-bit. */
#define SFM_STEREO_MAX_DISPARITIES 256
#define SFM_STEREO_MAX_WIDTH 8192

typedef enum sfm_stereo_paths {
    SFM_STEREO_PATHS_5 = 5, /* one top-down pass: left, right, up, up-left,
                               up-right (row memory only) */
    SFM_STEREO_PATHS_4 = 4, /* left, right, up, down: two passes */
    SFM_STEREO_PATHS_8 = 8  /* the eight directions: two passes */
} sfm_stereo_paths;

/* Semi-global matching (Hirschmüller, "Stereo processing by semiglobal
 * matching and mutual information", PAMI 2008) on a 9x7 census transform
 * with Hamming costs (0..63). P1 penalises a disparity change of one
 * between neighbours, P2 (> P1) a larger one. */
typedef struct sfm_stereo_sgm_options {
    int min_disparity;   /* smallest disparity searched (may be negative) */
    int num_disparities; /* 8..SFM_STEREO_MAX_DISPARITIES, multiple of 8 */
    int p1, p2;          /* 1 <= p1 < p2 <= 1000 */
    int paths;           /* an sfm_stereo_paths */
    int uniqueness;      /* percent: the best cost must beat every cost more
                            than one disparity away by this margin; 0 off */
    int lr_max_diff;     /* left-right check tolerance in pixels; < 0 off */
    int subpixel;        /* 1: parabola through the best cost's neighbours */
} sfm_stereo_sgm_options;

/* min 0, 64 disparities, p1 5, p2 60, 5 paths, uniqueness 10, lr 1,
 * subpixel 1. */
SFM_API void sfm_stereo_sgm_default_options(sfm_stereo_sgm_options *opt);

/* Workspace for a width x height pair with opt's disparity range and
 * paths (5 paths need rows only; 4 and 8 paths a full cost volume of
 * 2 * width * height * num_disparities bytes). 0 for invalid options. */
SFM_API size_t sfm_stereo_sgm_workspace_size(int width, int height,
                                             const sfm_stereo_sgm_options *opt);

/* Disparity of every pixel of `left` (rectified image 1) against `right`
 * (rectified image 2, same size), written to disp (width x height floats,
 * row-major, NaN invalid). Returns the number of valid pixels.
 * Statuses: SFM_E_ARGUMENT (NULL, sizes < 16 or width > MAX_WIDTH, strides,
 * options out of range, a disparity range wider than the image);
 * SFM_E_WORKSPACE. Nothing is written on failure. */
SFM_API int sfm_stereo_sgm(const uint8_t *left, const uint8_t *right, int width, int height,
                           int stride, const sfm_stereo_sgm_options *opt, float *disp,
                           void *ws, size_t ws_size);

/* Correlation matching with multiple supporting windows and a left-right
 * consistency check (Hirschmüller, Innocent, Garibaldi, "Real-time
 * correlation-based stereo vision with reduced border errors", IJCV 2002):
 * the SAD over a (2 r + 1) x (2 r + 1) window plus the two best of its
 * four corner neighbours (windows shifted by 2 r diagonally), which keeps
 * the support on the object's side of a depth edge. */
typedef struct sfm_stereo_block_options {
    int min_disparity;
    int num_disparities; /* 8..SFM_STEREO_MAX_DISPARITIES, multiple of 8 */
    int radius;          /* 1..5: window (2 r + 1)^2; SFM_E_ARGUMENT outside */
    int uniqueness;      /* percent, as SGM; 0 off */
    int lr_max_diff;     /* < 0 off */
    int texture;         /* minimum mean |dI/dx| of the left image over the
                            window, in 1/16 gray level (0 off): flat
                            regions are marked invalid */
    int subpixel;
} sfm_stereo_block_options;

/* min 0, 64 disparities, radius 2, uniqueness 15, lr 1, texture 8,
 * subpixel 1. */
SFM_API void sfm_stereo_block_default_options(sfm_stereo_block_options *opt);
SFM_API size_t sfm_stereo_block_workspace_size(int width, int height,
                                               const sfm_stereo_block_options *opt);
/* As sfm_stereo_sgm. */
SFM_API int sfm_stereo_block(const uint8_t *left, const uint8_t *right, int width, int height,
                             int stride, const sfm_stereo_block_options *opt, float *disp,
                             void *ws, size_t ws_size);

/* ---- Disparity to 3D ------------------------------------------------- */

/* Depth image (rectified camera 1's z, in the units of the baseline) from a
 * disparity image and the rectification: Z = f B / (d - (cx1 - cx2)); NaN
 * where the disparity is invalid or the depth not positive. Returns the
 * number of valid pixels; SFM_E_ARGUMENT, SFM_E_NONFINITE (rect). */
SFM_API int sfm_stereo_depth(const float *disp, int width, int height,
                             const sfm_stereo_rectification *rect, float *depth);

/* Points (capacity x 3 doubles) in camera 1's original frame (R1^T applied)
 * for every valid pixel with a depth in (0, max_depth] (max_depth <= 0: no
 * limit), in row-major pixel order; pixel_index (may be NULL) receives
 * y * width + x of each. With points NULL only counts. Returns the number
 * of points; SFM_E_CAPACITY (nothing written) when more exist than
 * capacity; SFM_E_ARGUMENT, SFM_E_NONFINITE (rect, NaN max_depth). */
SFM_API int sfm_stereo_points(const float *disp, int width, int height,
                              const sfm_stereo_rectification *rect, double max_depth,
                              double *points, int32_t *pixel_index, int capacity);

#ifdef __cplusplus
}
#endif
#endif
