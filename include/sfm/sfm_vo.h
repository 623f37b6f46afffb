/*
 * libsfm vo: monocular visual odometry over a frame sequence, in fixed
 * caller memory.
 *
 * Per frame (sfm_vo_push_frame):
 *   1. features: FAST-9 + steered BRIEF (sfm_features_detect), every pixel
 *      mapped once through the camera model (sfm_camera: pinhole, Brown or
 *      fisheye) to its ideal pinhole pixel (fx, fy, cx, cy without
 *      distortion); all geometry below works on those;
 *   2. tracking: the map points of the window are projected with the pose
 *      predicted by constant velocity and matched to the keypoints of a
 *      small search window around each prediction (a grid over the image,
 *      Hamming distance, ratio test): no brute-force matching;
 *   3. absolute pose: P3P RANSAC (sfm_ransac_abspose) on those 2D-3D matches;
 *   4. keyframe selection: a new keyframe when the share of the last
 *      keyframe's points still tracked falls, or after a maximum gap;
 *      new points are triangulated from guided matches between the new and
 *      the previous keyframe (search window plus epipolar distance);
 *   5. trifocal RANSAC (sfm_ransac_trifocal) over the tracks seen by the
 *      last three keyframes drops the observations no consistent three-view
 *      geometry explains;
 *   6. windowed bundle adjustment (sfm_ba_solve) over the last `window`
 *      keyframes, the two oldest held (they fix the gauge and the scale).
 * Initialisation: relative pose between a reference frame and the current
 * one by 5-point RANSAC (sfm_ransac_relpose), or by the upright 3-point
 * solver (sfm_ransac_relpose_upright) when both frames carry a gravity
 * direction; accepted when the inliers have enough parallax and do not come
 * from a pure rotation. The first baseline has length 1: the scale of the
 * whole trajectory is that of the first pair, carried on by the map.
 * Unknown intrinsics (params.calibrated = 0): a pinhole camera with unit
 * aspect ratio and the principal point at the image centre. The
 * initialisation's relative-pose test runs with the focal guess
 * params.camera.fx; the first frame passing it becomes the middle keyframe
 * of a triple, the first later frame with twice its parallax the third, and
 * their triplets go through sfm_recon_three_view_uncalibrated (at most 256,
 * evenly spread), answered when the focal length's relative standard
 * deviation is 2.5 % or less (5 % at two sigma: the BA refines it). A
 * refusal (too little baseline for three views, a focal length the motion
 * does not determine) moves the middle keyframe on to the next frame with a
 * quarter more parallax, so both baselines grow; when the parallax to the
 * reference falls instead (to 0.8 of its peak since the middle keyframe or
 * the refusal: a camera turning back), the triple starts over with this
 * frame as the reference. On success the ordinary initialisation runs on
 * that frame with the focal length found, which the windowed BA then
 * refines (one focal shared by the window) over its first `window`
 * adjustments and holds afterwards (a
 * single window's estimate wanders by a few percent; refined in every
 * window the errors accumulate). No frame is tracked before the focal
 * length is known; sfm_vo_frame_result.focal reports it (0 until then).
 * sfm_vo_reset forgets it.
 * After a loss (VO_LOST_RESET = 3 lost frames in a row) the map is dropped
 * and the pipeline re-initialises from the next frames: a new segment
 * (sfm_vo_frame_result.segment + 1). Its reference frame is placed where the
 * last tracked motion, continued, puts it, and its first baseline is the
 * speed of that motion (units per frame) times the frames between the pair:
 * scale and origin are carried over only as far as the motion stayed steady
 * through the gap, nothing measured ties the two segments. A caller that
 * needs one scale aligns each segment on its own (or fuses another sensor).
 * Frames of the gap are LOST, with no pose.
 *
 * Poses. world-to-camera T_cw: x_cam = R_cw X_world + t_cw (the library's
 * convention); camera-to-world T_wc: X_world = R_wc x_cam + c_w, with
 * R_wc = R_cw^T and c_w = -R_cw^T t_cw the camera centre (what a TUM file
 * stores). The world frame is the first frame's camera frame. Both are in
 * sfm_vo_frame_result.
 *
 * Honest state: a pose is reported with SFM_VO_TRACKING only when the
 * absolute pose has at least params.min_inliers inliers and an inlier
 * share of at least params.min_inlier_ratio; otherwise the frame is LOST and
 * carries no pose.
 *
 * Time budget: with params.clock set and params.frame_budget > 0, the
 * pipeline reads the clock between stages; when a frame overruns, the next
 * frames detect fewer features (down to a quarter of max_features, recovering
 * by 10 % a frame while under 80 % of the budget); a keyframe that has spent
 * 60 % of its frame's budget before the trifocal check skips it, and one that
 * has spent 70 % before the bundle adjustment skips that (result.degraded
 * says which); RANSAC runs get what is left of the budget.
 *
 * Memory: one caller buffer of sfm_vo_workspace_size(dims) bytes holds the
 * whole state (keyframes, map, scratch of every stage); nothing is allocated.
 * Reentrant: distinct sfm_vo objects are independent. Deterministic: the same
 * frames and parameters give the same poses bit for bit on one build (no
 * clock: with a clock and a budget, degradation depends on timing).
 */
#ifndef SFM_VO_H
#define SFM_VO_H

#include "sfm/sfm_camera.h"
#include "sfm/sfm_common.h"
#include "sfm/sfm_features.h"

#ifdef __cplusplus
extern "C" {
#endif

/* Capacities. */
#define SFM_VO_MAX_WINDOW 16   /* keyframes in the window */
#define SFM_VO_MIN_WINDOW 3    /* the trifocal check needs three */
#define SFM_VO_MAX_FEATURES 4096

/* Frame states (sfm_vo_frame_result.state). Values pinned. */
#define SFM_VO_INITIALISING 0          /* no map yet (first frame, or after a reset) */
#define SFM_VO_TRACKING 1              /* pose estimated against the map */
#define SFM_VO_LOST 2                  /* too few matches or inliers: no pose */
#define SFM_VO_INSUFFICIENT_PARALLAX 3 /* initialising: baseline too small so far */
#define SFM_VO_PURE_ROTATION 4         /* initialising: rotation explains the motion */

/* Quality (sfm_vo_frame_result.quality). */
#define SFM_VO_QUALITY_NONE 0     /* no pose */
#define SFM_VO_QUALITY_GOOD 1     /* full processing, inliers well above the floor */
#define SFM_VO_QUALITY_DEGRADED 2 /* pose kept, but few inliers or work skipped */

/* sfm_vo_frame_result.degraded bits. */
#define SFM_VO_DEGRADED_FEATURES 1 /* fewer features than max_features (budget) */
#define SFM_VO_DEGRADED_BA_SKIPPED 2 /* keyframe without its bundle adjustment */
#define SFM_VO_DEGRADED_TRIFOCAL_SKIPPED 4

/* Stages timed in sfm_vo_frame_result.stage_seconds (with a clock). */
#define SFM_VO_STAGE_FEATURES 0
#define SFM_VO_STAGE_TRACKING 1 /* guided matching + P3P RANSAC (or init) */
#define SFM_VO_STAGE_MAPPING 2  /* keyframe insertion, triangulation */
#define SFM_VO_STAGE_TRIFOCAL 3
#define SFM_VO_STAGE_BA 4
#define SFM_VO_STAGES 5

/* Sizes the workspace depends on. */
typedef struct sfm_vo_dims {
    int width, height; /* image size, >= 2 * SFM_FEATURES_BORDER + 1 */
    int max_features;  /* 8..SFM_VO_MAX_FEATURES */
    int window;        /* keyframes, SFM_VO_MIN_WINDOW..SFM_VO_MAX_WINDOW */
} sfm_vo_dims;

/* Monotonic clock in seconds (as sfm_ransac_clock_fn). */
typedef double (*sfm_vo_clock_fn)(void *clock_ctx);

typedef struct sfm_vo_params {
    sfm_camera camera;      /* intrinsics of every frame */
    int calibrated;         /* 1: camera is known; 0: self-calibration (camera
                               must be PINHOLE; its fx is only the focal guess,
                               its principal point is replaced by the image
                               centre) */
    int max_features;       /* 8..dims.max_features; default dims.max_features */
    int window;             /* SFM_VO_MIN_WINDOW..dims.window; default dims.window */
    sfm_features_params features; /* max_features is overridden per frame */
    double track_radius;    /* px around each predicted point, default 20 */
    double init_radius;     /* px around a reference keypoint at initialisation
                               and when re-tracking after a miss, default 120 */
    int max_hamming;        /* default 64 */
    double ratio;           /* best < ratio * second best, default 0.9 */
    double threshold;       /* RANSAC and BA inlier threshold, px, default 1.5 */
    int min_iterations;     /* RANSAC sample floor, default 100 */
    int max_iterations;     /* RANSAC cap, default 1000 */
    int min_inliers;        /* floor for a tracked pose, default 25 */
    double min_inlier_ratio;/* floor of inliers / matches, default 0.25 */
    double min_parallax_deg;/* initialisation: median parallax, default 1.0 */
    double keyframe_ratio;  /* new keyframe below this share of the last
                               keyframe's points tracked, default 0.7 */
    int keyframe_max_gap;   /* frames, default 10 */
    double keyframe_min_parallax_deg; /* median parallax of tracked points
                               since the last keyframe, default 0.5 */
    double point_min_parallax_deg; /* new points: smallest angle between the
                               two keyframes' rays, default 0.5 */
    int ba_iterations;      /* windowed BA iterations, 0 disables, default 8 */
    int use_trifocal;       /* default 1 */
    uint64_t seed;          /* RANSAC seeds derive from it and the frame index */
    sfm_vo_clock_fn clock;  /* optional */
    void *clock_ctx;
    double frame_budget;    /* seconds per frame; <= 0: unbounded */
} sfm_vo_params;

typedef struct sfm_vo_frame_result {
    int64_t timestamp_ns;
    int frame_index;      /* frames pushed before this one */
    int state;            /* SFM_VO_* state */
    int quality;          /* SFM_VO_QUALITY_* */
    int has_pose;         /* 1 when the pose fields hold this frame's pose */
    int is_keyframe;
    double R_cw[9], t_cw[3]; /* world-to-camera: x_cam = R_cw X + t_cw */
    double R_wc[9], c_w[3];  /* camera-to-world: X = R_wc x_cam + c_w */
    int has_covariance;   /* 1 when covariance holds the pose covariance */
    double covariance[36];/* 6x6 of (w, dt) in the camera frame, rotation
                             first (sfm_ba_solve's convention), px noise 1 */
    int n_features;       /* keypoints detected */
    int n_matches;        /* 2D-3D (or 2D-2D at initialisation) matches */
    int n_inliers;
    int n_map_points;     /* live points in the window */
    int n_keyframes;      /* keyframes in the window */
    int degraded;         /* SFM_VO_DEGRADED_* bits */
    double stage_seconds[SFM_VO_STAGES]; /* 0 without a clock */
    double median_parallax_deg; /* initialisation: of the relative-pose inliers */
    double focal;         /* px: the focal length (fx) this frame was processed
                             with; self-calibrated runs: 0 until found */
    int segment;          /* the map this pose belongs to: 0 for the first,
                             + 1 at each re-initialisation after a loss (a new
                             segment: its scale and origin are only guessed
                             from the motion before the loss), and at each
                             reference frame that starts over before the
                             first map (it reports the origin of its own
                             segment: nothing ties it to the frame that
                             reported the origin before it) */
} sfm_vo_frame_result;

typedef struct sfm_vo sfm_vo;

/* Defaults for these dimensions (camera: pinhole fx = fy = width, centred;
 * the caller sets camera). Statuses: SFM_OK, SFM_E_ARGUMENT (NULL, dims out
 * of range). */
SFM_API int sfm_vo_default_params(const sfm_vo_dims *dims, sfm_vo_params *p);

/* Bytes of workspace for these dimensions; 0 when dims is NULL or out of
 * range. */
SFM_API size_t sfm_vo_workspace_size(const sfm_vo_dims *dims);

/* Lays the pipeline out in ws and returns it in *vo (a pointer into ws; ws
 * must outlive it and not be moved). The parameters are copied.
 * Statuses: SFM_OK, SFM_E_ARGUMENT (NULL, dims or params out of range,
 * invalid camera, calibrated not 0 or 1), SFM_E_NONFINITE (NaN/Inf
 * parameter), SFM_E_WORKSPACE (ws_size < sfm_vo_workspace_size(dims)),
 * SFM_E_UNSUPPORTED (params->calibrated == 0 with a camera model other than
 * pinhole: self-calibration does not find distortion).
 * Nothing is written on failure. */
SFM_API int sfm_vo_init(const sfm_vo_dims *dims, const sfm_vo_params *params, sfm_vo **vo,
                        void *ws, size_t ws_size);

/* Drops the map and starts over (the next frame becomes the origin again; a
 * self-calibrated focal length is dropped too). */
SFM_API int sfm_vo_reset(sfm_vo *vo);

/* Processes one frame. image: 8-bit gray of the dims' size. gravity: NULL, or
 * the direction of gravity in this frame's camera coordinates (any nonzero
 * length; an IMU's, e.g.); when the reference frame and this one both carry
 * one, initialisation uses the upright 3-point solver. want_covariance:
 * non-zero fills out->covariance for a tracked frame.
 * Returns SFM_OK (the state is in out->state: LOST is not an error), or
 *   SFM_E_ARGUMENT   NULL vo/image/out, image of another size, stride < width,
 *                    timestamp lower than the previous frame's;
 *   SFM_E_NONFINITE  NaN/Inf gravity; zero gravity is SFM_E_ARGUMENT.
 * On these failures nothing is written and the state is unchanged. Any other
 * negative status comes from a stage after those checks (e.g.
 * SFM_E_WORKSPACE; not expected of a pipeline made by sfm_vo_init): out is
 * not written and the pipeline is reset as by sfm_vo_reset (map, keyframes
 * and a self-calibrated focal length gone; the next frame starts a new
 * reference), never left with a half-updated map. */
SFM_API int sfm_vo_push_frame(sfm_vo *vo, const sfm_image_u8 *image, int64_t timestamp_ns,
                              const double *gravity, int want_covariance,
                              sfm_vo_frame_result *out);

/* The live map points (world coordinates), up to capacity, n x 3, and their
 * ids (unique over the run: a point refined by later bundle adjustments
 * keeps its id, so a caller can keep the latest position of every point it
 * ever saw; ids may be NULL). Returns the number written, or SFM_E_ARGUMENT
 * (NULL vo or xyz, capacity < 0). */
SFM_API int sfm_vo_map_points(const sfm_vo *vo, double *xyz, uint32_t *ids, int capacity);

/* Where each live map point was first seen, in the order of
 * sfm_vo_map_points (the same ids): px (n x 2) the image pixel of its first
 * observation (the keypoint, mapped back through the camera model; NaN when
 * the model cannot), frame the index of that frame (frames pushed before it;
 * a keyframe). For a colour map a caller samples its copy of that frame.
 * ids may be NULL. Returns the number written, or SFM_E_ARGUMENT (NULL vo,
 * px or frame, capacity < 0). */
SFM_API int sfm_vo_map_points_first_seen(const sfm_vo *vo, uint32_t *ids, double *px, int *frame,
                                         int capacity);

/* Short constant name of a state ("tracking", ...); never NULL. */
SFM_API const char *sfm_vo_state_str(int state);

#ifdef __cplusplus
}
#endif
#endif
