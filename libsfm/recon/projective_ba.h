/*
 * Internal: projective bundle adjustment over every observation (11-DOF
 * cameras and homogeneous points on their unit spheres, Schur complement on
 * the points, the core LM driver). Not API.
 */
#ifndef SFM_RECON_PROJECTIVE_BA_H
#define SFM_RECON_PROJECTIVE_BA_H

#include <stddef.h>

#include "core/lm.h"

/* Workspace bytes for m cameras, n points, nobs observations. */
size_t sfmi_projective_ba_workspace_size(int m, int n, int nobs);

/* Observations grouped by point: those of point j are first[j] ..
 * first[j + 1] - 1 (first has n + 1 entries; a point without observations
 * is held). obs_xy in each camera's normalized coordinates, iscale[i] the
 * pixels per normalized unit of camera i (the cost is in pixels). P (m x 12)
 * and X (n x 4, non-zero) are refined in place (scaled to unit norm). */
int sfmi_projective_ba(int m, int n, int nobs, const int *obs_cam, const int *obs_pt, const int *first,
                       const double *obs_xy, const double *iscale, double *P, double *X, int max_iterations,
                       sfmi_lm_summary *summary, void *ws, size_t ws_size);

#endif
