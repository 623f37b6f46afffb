/*
 * Bundle adjustment: the pose covariance at the solution.
 *
 * The inverse of the undamped normal matrix J^T W J (robust weights
 * included), taken in the update coordinates of the free parameters: with
 * the points eliminated, the camera block of the inverse is the inverse of
 * the reduced camera system S (the Schur complement of V; Triggs et al.
 * 2000, section 6.1), so S^-1 is formed column by column from its Cholesky
 * factor. Held coordinates (the gauge, held cameras) have no rows; a gauge
 * left free makes S singular (sfmi_lm_factor_full_rank also catches the
 * factorisations that survive it by rounding).
 */
#include <string.h>

#include "core/lm.h"
#include "refine/ba_internal.h"
#include "sfm/sfm_linalg.h"

int sfmi_ba_covariance(sfmi_ba_ctx *c)
{
    sfmi_ba_ws *w = &c->w;
    const int nc = c->nc;
    if (nc == 0)
        return SFM_OK;
    if (!sfmi_ba_form_reduced(c, 0.0))
        return SFM_E_SINGULAR;
    for (int i = 0; i < nc; i++)
        w->Dc[i] = w->S[(size_t)i * nc + i];
    if (sfm_cholesky_factor(w->S, nc) != SFM_OK || !sfmi_lm_factor_full_rank(w->S, w->Dc, nc))
        return SFM_E_SINGULAR;
    /* U is not needed any more: it receives the inverse */
    memset(w->U, 0, sizeof(double) * (size_t)nc * (size_t)nc);
    for (int i = 0; i < nc; i++)
        w->U[(size_t)i * nc + i] = 1.0;
    if (sfm_cholesky_solve(w->S, nc, w->U, nc) != SFM_OK)
        return SFM_E_SINGULAR;
    return SFM_OK;
}

void sfmi_ba_write_covariance(const sfmi_ba_ctx *c, double *pose_covariance)
{
    const sfmi_ba_ws *w = &c->w;
    const int nc = c->nc, qmax = c->qmax;
    memset(pose_covariance, 0, sizeof(double) * 36 * (size_t)c->m);
    for (int ci = 0; ci < c->m; ci++) {
        const int *col = w->cam_col + (size_t)ci * qmax;
        const int *gi = w->cam_gi + (size_t)ci * qmax;
        double *C = pose_covariance + 36 * (size_t)ci;
        for (int a = 0; a < w->cam_q[ci]; a++) {
            if (col[a] >= 6)
                continue;
            for (int b = 0; b < w->cam_q[ci]; b++) {
                if (col[b] >= 6)
                    continue;
                C[6 * col[a] + col[b]] = w->U[(size_t)gi[a] * nc + gi[b]];
            }
        }
    }
}
