/* Internal: the state of the visual-odometry pipeline and the helpers its
 * stages share. Everything lives in the caller's workspace, carved once by
 * vo_layout (the same code measures the size). */
#ifndef SFM_VO_INTERNAL_H
#define SFM_VO_INTERNAL_H

#include "core/arena.h"
#include "sfm/sfm_ba.h"
#include "sfm/sfm_camera.h"
#include "sfm/sfm_features.h"
#include "sfm/sfm_ransac.h"
#include "sfm/sfm_vo.h"

/* Search grid cell side, pixels. */
#define VO_GRID_CELL 16

typedef struct vo_keyframe {
    int frame_index;
    int64_t timestamp_ns;
    double R[9], t[3]; /* world-to-camera */
    int n;             /* keypoints */
    double *px;        /* n x 2 ideal pinhole pixels */
    uint8_t *desc;     /* n x 32 */
    int *pid;          /* n map point slots, -1: none */
    int has_gravity;
    double gravity[3];
} vo_keyframe;

/* A uniform grid over the ideal pixels of one keypoint set. */
typedef struct vo_grid {
    int gw, gh;
    int *start; /* gw * gh + 1 */
    int *items; /* keypoint indices, cell-major */
    int *cell;  /* scratch: cell of each keypoint */
} vo_grid;

struct sfm_vo {
    sfm_vo_dims dims;
    sfm_vo_params p;
    sfm_camera pinhole; /* K of the camera, no distortion */
    double K[4];        /* fx, fy, cx, cy of pinhole */

    /* keyframe window, a ring: slot (kf_head + i) % window is the i-th oldest */
    vo_keyframe kf[SFM_VO_MAX_WINDOW];
    int kf_head, kf_count;

    /* map points */
    int cap_points;
    double *X;        /* cap x 3 */
    uint8_t *pdesc;   /* cap x 32, newest keyframe observation */
    int *pobs;        /* keyframe observations in the window; 0: free slot */
    uint32_t *pname;  /* running id, unique over the run */
    double *pfirst_px; /* cap x 2, ideal pixel of the first observation */
    int *pfirst_frame; /* cap, frame index of the first observation */
    int *free_list;
    int n_free;
    uint32_t next_name;

    /* current frame */
    sfm_keypoint *kps;
    uint8_t *desc;
    double *px;      /* ideal pixels */
    uint8_t *valid;  /* pixel mapped through the camera */
    int n;
    int *cur_pid;    /* point matched to each keypoint (inlier), -1 */
    int *best_d;     /* scratch per keypoint */
    int *best_q;     /* scratch per keypoint: query of the best distance */
    vo_grid grid;

    /* match scratch (up to max_features rows) */
    double *m_a;   /* n x 3 (2D-3D: world points; 2D-2D: px of the reference) */
    double *m_b;   /* n x 2 */
    double *m_c;   /* n x 2 (trifocal third view) */
    int *m_i, *m_j;
    uint8_t *mask;

    void *feat_ws;
    size_t feat_ws_size;
    void *ransac_ws;
    size_t ransac_ws_size;

    /* bundle adjustment arrays */
    int ba_max_points, ba_max_obs;
    double *ba_R, *ba_t, *ba_X, *ba_xy;
    sfm_camera *ba_cam; /* the pinhole camera, once per BA camera */
    int *ba_oc, *ba_op, *ba_of; /* camera, point, keypoint index of an observation */
    int *ba_of_slot;            /* window position of the observation's keyframe */
    unsigned char *ba_cf;
    int *ba_of_point;           /* map slot of each BA point */
    int *pt_ba;                 /* map slot -> BA index, -1 */
    int *pt_tmp;                /* map slot -> keypoint scratch, -1 */
    void *ba_ws;
    size_t ba_ws_size;

    /* run state */
    int frame_index;
    int64_t last_ts;
    int started;       /* a frame was pushed */
    int mapped;        /* the map is initialised */
    int have_last, have_prev;
    double R_last[9], t_last[3], R_prev[9], t_prev[3];
    int last_frame_index, prev_frame_index;
    int frames_since_kf;
    int kf_tracked;    /* map points observed by the newest keyframe */
    double base_len;   /* baseline of the first pair (the run's unit) */
    int feat_count;    /* features asked of the detector this frame */
    int lost_frames;
    int ever_mapped;
    int origin_given;  /* a reference frame has reported the origin (before
                          the first map) */
    int segment;       /* maps initialised after the first (re-initialisations) */
    double seg_speed;  /* units per frame of the last tracked motion before a loss */

    /* self-calibration (params.calibrated == 0) */
    double K_guess[4];  /* the focal guess before self-calibration */
    int cal_done;       /* the focal length is known (self-calibrated) */
    int cal_attempts;   /* self-calibrations tried */
    int *cal_mid;       /* reference keypoint -> its match in the middle
                           keyframe of the calibration triple, -1 */
    double cal_mid_parallax; /* median parallax (deg) reference -> middle */
    double cal_next_parallax; /* parallax of the next calibration attempt */
    int cal_refinements; /* windowed BAs that refined the focal length */
    int cal_retry;      /* the last attempt failed: the next frame past
                           cal_next_parallax becomes the middle keyframe */
    double cal_peak_parallax; /* largest median parallax (deg) to the reference
                                 since the middle keyframe or the last failure */
};

/* ---- geometry helpers (vo_geom.c) ---- */
void sfmi_vo_compose(const double Ra[9], const double ta[3], const double Rb[9],
                     const double tb[3], double R[9], double t[3]); /* T = Ta * Tb */
void sfmi_vo_inverse(const double R[9], const double t[3], double Ri[9], double ti[3]);
void sfmi_vo_transform(const double R[9], const double t[3], const double X[3], double x[3]);
/* Projects a world point with K and a pose; 0 when behind the camera. */
int sfmi_vo_project(const double K[4], const double R[9], const double t[3], const double X[3],
                    double uv[2]);
void sfmi_vo_centre(const double R[9], const double t[3], double c[3]);
/* Angle (radians) at X between the rays from two centres. */
double sfmi_vo_ray_angle(const double c1[3], const double c2[3], const double X[3]);
/* Median of v[0..n) by partial sort in place (n >= 1). */
double sfmi_vo_median(double *v, int n);

/* ---- grid and guided matching (vo_match.c) ---- */
void sfmi_vo_grid_build(vo_grid *g, const double *px, const uint8_t *valid, int n);
/* Best keypoint of the grid's set within radius of uv whose descriptor is
 * nearest to d (distance <= max_d, best < ratio * second); -1 when none.
 * skip (may be NULL): keypoints with skip[i] >= 0 are not candidates.
 * line (may be NULL): also demand |line . (x, y, 1)| <= line_tol. */
int sfmi_vo_grid_search(const vo_grid *g, const double *px, const uint8_t *desc,
                        const double uv[2], double radius, const uint8_t *d, int max_d,
                        double ratio, const int *skip, const double *line, double line_tol,
                        int *dist);

/* Keeps, per keypoint j of the searched set, the query that found it with
 * the smallest distance (a one-to-one assignment). */
static inline void sfmi_vo_best_reset(int *best_d, int *best_q, int n)
{
    for (int j = 0; j < n; j++) {
        best_d[j] = 1 << 20;
        best_q[j] = -1;
    }
}

static inline void sfmi_vo_best_offer(int *best_d, int *best_q, int j, int d, int q)
{
    if (j >= 0 && d < best_d[j]) {
        best_d[j] = d;
        best_q[j] = q;
    }
}

/* Points a BA problem at the workspace's BA arrays (pose, intrinsics,
 * points, observations); camera_flags left NULL. */
void sfmi_vo_ba_problem(sfm_vo *vo, int m, int np, int no, sfm_ba_problem *pr);

/* ---- map and keyframes (vo_map.c) ---- */
vo_keyframe *sfmi_vo_kf_at(sfm_vo *vo, int i); /* i-th oldest, 0 <= i < kf_count */
/* A new point; px (ideal pixels) and frame: its first observation. */
int sfmi_vo_point_new(sfm_vo *vo, const double X[3], const uint8_t *desc, const double px[2],
                      int frame);
void sfmi_vo_point_unref(sfm_vo *vo, int pid);
/* Appends the current frame as a keyframe (evicting the oldest when full);
 * its observations are the current frame's cur_pid. */
vo_keyframe *sfmi_vo_kf_push(sfm_vo *vo, const double R[9], const double t[3],
                             int64_t ts, const double *gravity);
void sfmi_vo_map_clear(sfm_vo *vo);
/* Triangulates new points between the two newest keyframes. Returns the
 * number created. */
int sfmi_vo_triangulate_new(sfm_vo *vo);
/* Trifocal check over the three newest keyframes; returns observations
 * removed (>= 0) or a negative status of the estimator. */
int sfmi_vo_trifocal_check(sfm_vo *vo);
/* Windowed BA; fixed: how many of the oldest keyframes are held. Returns
 * SFM_OK or the solver's status. */
int sfmi_vo_window_ba(sfm_vo *vo, int fixed, int scale_gauge);
/* Pose covariance of the current frame from its inlier matches
 * (vo->m_a / m_b rows flagged in vo->mask). */
int sfmi_vo_pose_covariance(sfm_vo *vo, int nm, const double R[9], const double t[3],
                            double cov[36]);

#endif
