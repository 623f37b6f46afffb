/*
 * Camera models: map a point in camera coordinates (z forward, x right, y
 * down) to pixels and a pixel back to a unit bearing.
 *
 *  SFM_CAMERA_PINHOLE   params: none (fx, fy, cx, cy only)
 *  SFM_CAMERA_BROWN     pinhole + radial-tangential (Brown-Conrady) distortion,
 *                       dist = {k1, k2, p1, p2, k3}, as OpenCV's 5-vector
 *  SFM_CAMERA_FISHEYE   equidistant Kannala-Brandt, dist = {k1, k2, k3, k4}:
 *                       theta_d = theta (1 + k1 t^2 + k2 t^4 + k3 t^6 + k4 t^8),
 *                       as OpenCV's fisheye model
 *
 * Pixel coordinates: origin at the centre of the top-left pixel, y down.
 */
#ifndef SFM_CAMERA_H
#define SFM_CAMERA_H

#include "sfm/sfm_common.h"

#ifdef __cplusplus
extern "C" {
#endif

typedef enum sfm_camera_model {
    SFM_CAMERA_PINHOLE = 0,
    SFM_CAMERA_BROWN = 1,
    SFM_CAMERA_FISHEYE = 2
} sfm_camera_model;

typedef struct sfm_camera {
    int model;       /* an sfm_camera_model */
    double fx, fy;   /* focal lengths in pixels, non-zero */
    double cx, cy;   /* principal point in pixels */
    double dist[5];  /* model parameters, unused entries ignored */
} sfm_camera;

/* Statuses: SFM_OK, SFM_E_ARGUMENT (NULL, unknown model, zero focal length),
 * SFM_E_NONFINITE (NaN/Inf in fx, fy, cx, cy or a dist entry the model
 * uses; unused entries are ignored). Every function below validates the
 * camera the same way first. */
SFM_API int sfm_camera_validate(const sfm_camera *cam);

/* Project X (camera frame) to px. J (2x3, row-major, may be NULL) receives
 * d(px)/d(X). Pinhole and Brown need X[2] > 0; the fisheye model accepts any
 * direction except the optical axis' negative half (theta < pi).
 * Statuses: SFM_OK, SFM_E_ARGUMENT, SFM_E_NONFINITE, SFM_E_SINGULAR (point not
 * projectable: at or behind the camera plane, at the origin, or so close to
 * the plane that the pixel or J overflows). */
SFM_API int sfm_camera_project(const sfm_camera *cam, const double X[3], double px[2], double *J);

/* Unit bearing for a pixel. Distortion is inverted iteratively (Gauss-Newton
 * on the distortion map); failing to reach 1e-10 normalized units within the
 * iteration limit is SFM_E_NO_CONVERGENCE, never a silent inexact answer.
 * The answer is the preimage inside the region where the distortion map is
 * invertible: Brown, the disc inside the first radius where
 * r (1 + k1 r^2 + k2 r^4 + k3 r^6) stops increasing, with a positive Jacobian
 * determinant at the answer (strong tangential terms fold the map too);
 * fisheye, angles below the first where theta_d(theta) stops increasing (and
 * below pi). Pixels outside the image of that region are
 * SFM_E_NO_CONVERGENCE. Pinhole and Brown bearings have z > 0; fisheye
 * bearings may point behind the camera plane (theta > pi/2).
 * Statuses: SFM_OK, SFM_E_ARGUMENT, SFM_E_NONFINITE, SFM_E_NO_CONVERGENCE. */
SFM_API int sfm_camera_unproject(const sfm_camera *cam, const double px[2], double bearing[3]);

/* Batch forms over n points (px n x 2, X / bearings n x 3), n >= 0. Stop at
 * the first failure and return its status; entries before it are written,
 * entries from it on are not (an exception to "nothing written on failure").
 * Statuses: as the single-point forms; n < 0 is SFM_E_ARGUMENT. */
SFM_API int sfm_camera_project_many(const sfm_camera *cam, const double *X, int n, double *px);
SFM_API int sfm_camera_unproject_many(const sfm_camera *cam, const double *px, int n,
                                      double *bearings);

#ifdef __cplusplus
}
#endif
#endif
