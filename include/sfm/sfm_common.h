/*
 * libsfm: common definitions shared by every public header.
 *
 * Conventions (see README):
 *  - scalars are double; matrices are row-major, m[r*cols + c];
 *  - poses map world to camera: x_cam = R * X_world + t; quaternions are w-first;
 *  - every public function returns an int: >= 0 on success (a count where the
 *    function says so, else SFM_OK), or a negative sfm_status;
 *  - outputs come last; a function that fails writes nothing to its outputs.
 *
 * Argument order, the same for every function: first the inputs (each array
 * followed by its count, then options, which may be NULL for the defaults);
 * then the outputs, each array followed by its capacity where it has one
 * (a count written back is the return value, never an extra argument); last
 * the caller's work memory as (void *ws, size_t ws_size), sized by the
 * function's *_workspace_size(). Optional outputs (inlier masks, statistics,
 * covariances) may be NULL. Two outputs that share one capacity (keypoints
 * and their descriptors, matches and their distances) sit together before it.
 *
 * Types: a 3x3 model (essential E, fundamental F, homography H) is an
 * sfm_mat3, in and out, in solvers and estimators alike; a solver writes an
 * array of them. Rotations stay double[9] inside sfm_pose.
 *
 * Names: sfm_<module>_<verb> for the API; minimal solvers name the problem and
 * the sample size (sfm_relpose_5pt, sfm_fundamental_8pt, sfm_p3p), capacities
 * are SFM_<SOLVER>_MAX_SOLUTIONS. The library's internal symbols carry sfmi_
 * and are not API.
 */
#ifndef SFM_COMMON_H
#define SFM_COMMON_H

#ifndef SFM_FFI
#include <stddef.h>
#include <stdint.h>
#endif

#if defined(SFM_FFI)
#define SFM_API
#elif defined(__GNUC__)
#define SFM_API __attribute__((visibility("default")))
#else
#define SFM_API
#endif

#ifdef __cplusplus
extern "C" {
#endif

/* Status codes. The values are pinned: they are part of the ABI and are never
 * renumbered; new codes take the next free negative value. */
typedef enum sfm_status {
    SFM_OK = 0,
    SFM_E_ARGUMENT = -1,       /* NULL pointer, bad count or size, bad option */
    SFM_E_NONFINITE = -2,      /* NaN or Inf in an input */
    SFM_E_WORKSPACE = -3,      /* caller workspace too small */
    SFM_E_CAPACITY = -4,       /* a compile-time capacity would be exceeded */
    SFM_E_SINGULAR = -5,       /* singular or degenerate configuration */
    SFM_E_NO_CONVERGENCE = -6, /* an iteration did not converge */
    SFM_E_IO = -7,             /* file or device I/O failed */
    SFM_E_TIMEOUT = -8,        /* no result within the time allowed */
    SFM_E_UNSUPPORTED = -9,    /* valid request this build or device cannot do */
    SFM_E_DEVICE_LOST = -10,   /* a device disappeared while in use */
    SFM_E_NO_DEVICE = -11,     /* no such device */
    SFM_E_FORMAT = -12,        /* malformed input data (file, manifest, frame) */
    SFM_E_DEGENERATE = -13,    /* an estimator's support does not determine its
                                  model (points on a line, one cluster, no
                                  parallax, one plane for F or T) */
    SFM_E_NO_MODEL = -14       /* an estimator's best model has no more support
                                  than random matches would give */
} sfm_status;

/* A short constant English description of a status code; never NULL. */
SFM_API const char *sfm_status_str(int status);

/* Library version as MAJOR*10000 + MINOR*100 + PATCH. Before 1.0 a new
 * MINOR changes the API (and the ABI of libsfm.so.0): callers built for
 * another minor must be rebuilt. */
#define SFM_VERSION_MAJOR 0
#define SFM_VERSION_MINOR 3
#define SFM_VERSION_PATCH 0
SFM_API int sfm_version(void);

/* Fixed small types: structs around arrays, row-major. */
typedef struct sfm_vec2 { double v[2]; } sfm_vec2;
typedef struct sfm_vec3 { double v[3]; } sfm_vec3;
typedef struct sfm_mat3 { double m[9]; } sfm_mat3;
typedef struct sfm_mat34 { double m[12]; } sfm_mat34;

/* A rigid transform x_cam = R * X_world + t. */
typedef struct sfm_pose { double R[9]; double t[3]; } sfm_pose;

/* Every workspace size reported by a *_workspace_size() function already
 * includes the slack needed to align an arbitrary caller pointer, so callers
 * may pass any buffer of that many bytes. */
#define SFM_WS_ALIGN 16

#ifdef __cplusplus
}
#endif
#endif
