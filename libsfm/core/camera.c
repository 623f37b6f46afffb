/*
 * Camera model dispatcher: argument checks, the intrinsics (focal lengths,
 * principal point), batch forms. The distortion models live in
 * camera_brown.c (pinhole is Brown with zero coefficients) and
 * camera_fisheye.c.
 */
#include <math.h>
#include <string.h>

#include "core/camera_internal.h"

static const double zero_dist[5] = {0.0, 0.0, 0.0, 0.0, 0.0};

static int n_dist(int model)
{
    return model == SFM_CAMERA_BROWN ? 5 : model == SFM_CAMERA_FISHEYE ? 4 : 0;
}

int sfm_camera_validate(const sfm_camera *cam)
{
    if (!cam)
        return SFM_E_ARGUMENT;
    if (cam->model != SFM_CAMERA_PINHOLE && cam->model != SFM_CAMERA_BROWN &&
        cam->model != SFM_CAMERA_FISHEYE)
        return SFM_E_ARGUMENT;
    if (!isfinite(cam->fx) || !isfinite(cam->fy) || !isfinite(cam->cx) || !isfinite(cam->cy))
        return SFM_E_NONFINITE;
    for (int i = 0; i < n_dist(cam->model); i++)
        if (!isfinite(cam->dist[i]))
            return SFM_E_NONFINITE;
    if (cam->fx == 0.0 || cam->fy == 0.0)
        return SFM_E_ARGUMENT;
    return SFM_OK;
}

static int project_one(const sfm_camera *cam, const double X[3], double px[2], double *J)
{
    if (!isfinite(X[0]) || !isfinite(X[1]) || !isfinite(X[2]))
        return SFM_E_NONFINITE;
    double xd[2], D[6];
    int st;
    if (cam->model == SFM_CAMERA_FISHEYE)
        st = sfmi_cam_fisheye_project(cam->dist, X, xd, J ? D : NULL);
    else
        st = sfmi_cam_brown_project(cam->model == SFM_CAMERA_BROWN ? cam->dist : zero_dist, X,
                                    xd, J ? D : NULL);
    if (st < 0)
        return st;
    const double u = cam->fx * xd[0] + cam->cx, v = cam->fy * xd[1] + cam->cy;
    if (!isfinite(u) || !isfinite(v))
        return SFM_E_SINGULAR; /* overflow: too close to the camera plane */
    if (J) {
        double Jt[6];
        for (int j = 0; j < 3; j++) {
            Jt[j] = cam->fx * D[j];
            Jt[3 + j] = cam->fy * D[3 + j];
        }
        for (int j = 0; j < 6; j++)
            if (!isfinite(Jt[j]))
                return SFM_E_SINGULAR;
        memcpy(J, Jt, sizeof Jt);
    }
    px[0] = u;
    px[1] = v;
    return SFM_OK;
}

static int unproject_one(const sfm_camera *cam, const double px[2], double bearing[3])
{
    if (!isfinite(px[0]) || !isfinite(px[1]))
        return SFM_E_NONFINITE;
    const double xd[2] = {(px[0] - cam->cx) / cam->fx, (px[1] - cam->cy) / cam->fy};
    double b[3];
    int st;
    if (cam->model == SFM_CAMERA_FISHEYE)
        st = sfmi_cam_fisheye_unproject(cam->dist, xd, b);
    else
        st = sfmi_cam_brown_unproject(cam->model == SFM_CAMERA_BROWN ? cam->dist : zero_dist, xd,
                                      b);
    if (st < 0)
        return st;
    memcpy(bearing, b, sizeof b);
    return SFM_OK;
}

int sfm_camera_project(const sfm_camera *cam, const double X[3], double px[2], double *J)
{
    if (!X || !px)
        return SFM_E_ARGUMENT;
    int st = sfm_camera_validate(cam);
    if (st < 0)
        return st;
    return project_one(cam, X, px, J);
}

int sfm_camera_unproject(const sfm_camera *cam, const double px[2], double bearing[3])
{
    if (!px || !bearing)
        return SFM_E_ARGUMENT;
    int st = sfm_camera_validate(cam);
    if (st < 0)
        return st;
    return unproject_one(cam, px, bearing);
}

int sfm_camera_project_many(const sfm_camera *cam, const double *X, int n, double *px)
{
    if (!X || !px || n < 0)
        return SFM_E_ARGUMENT;
    int st = sfm_camera_validate(cam);
    if (st < 0)
        return st;
    for (int i = 0; i < n; i++) {
        st = project_one(cam, X + 3 * (size_t)i, px + 2 * (size_t)i, NULL);
        if (st < 0)
            return st;
    }
    return SFM_OK;
}

int sfm_camera_unproject_many(const sfm_camera *cam, const double *px, int n, double *bearings)
{
    if (!px || !bearings || n < 0)
        return SFM_E_ARGUMENT;
    int st = sfm_camera_validate(cam);
    if (st < 0)
        return st;
    for (int i = 0; i < n; i++) {
        st = unproject_one(cam, px + 2 * (size_t)i, bearings + 3 * (size_t)i);
        if (st < 0)
            return st;
    }
    return SFM_OK;
}
